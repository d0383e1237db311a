// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraIndirectLevel.h
 * @brief The coarse level on which large scenes compute their
 * interreflections.
 *
 * The progressive shooter evaluates every shot at every sample it is given
 * (penumbraProgressiveShooter.h), so a shot costs samples times the
 * shooter's hierarchy. The direct light needs thousands of samples per
 * surface to follow its shadows; a room of thousands of polygons cannot
 * afford to shoot hundreds of times onto all of them. When the samples
 * exceed a budget, the interreflections run on a coarse level instead:
 *
 * - Mesh. Each surface's polygon is cut into its ear triangles
 *   (TriangulatePolygon), and each ear into an n x n lattice of triangles,
 *   one n per polygon (n = ceil(longest ear edge / spacing)), points on
 *   shared ear edges made once. One spacing serves the whole scene
 *   (IndirectSpacing), so the level is uniform in world units.
 * - Restriction (fine -> coarse). The coarse values are the lumped L2
 *   projection of the fine piecewise-linear function f:
 *   v_k = int f phi_k dA / int phi_k dA (phi_k the coarse hat functions),
 *   both integrals by the same midpoint rule on sub-triangles of each fine
 *   triangle (at most half a lattice triangle's height across), so that
 *   constants are kept; points the quadrature misses take their
 *   neighbours' mean. Each channel is then scaled so that the integral of
 *   the coarse interpolant, sum_k v_k int phi_k, equals the integral of f
 *   (up to rounding): the power each surface has to shoot is the same on
 *   both levels, and non-negative values stay non-negative.
 * - Prolongation (coarse -> fine). What the shots added on the coarse level
 *   (its Total after minus before) is interpolated linearly at the fine
 *   points and added to their totals, so the direct light keeps its fine
 *   shadows and the interreflections are as smooth as the lattice.
 *
 * - Occluders (SeparateOccluded). Interpolating across an occluder would
 *   leak light: into the thin gap behind a cabinet standing near a wall,
 *   onto the ceiling behind a fixture hung just below it, round a table
 *   leg. A lattice corner lends its light to a fine point only if the two
 *   see each other at a height above the surface (half the spacing) and are
 *   both covered or both uncovered within that height. A fine point that
 *   loses a corner lies near an occluder, whose shadow of the interreflected
 *   light (a contact, a pocket narrower than the spacing) the lattice cannot
 *   follow: it is evaluated on its own. It joins the coarse samples as a
 *   point outside every triangle, which receives the shots but carries no
 *   power (evaluated a little inside its fine triangles, as boundary
 *   samples are). A surface with more such points than lattice points and a
 *   quarter of its fine points (clutter everywhere) interpolates them from
 *   the corners they keep (all, if none).
 *
 * What is lost: the indirect light is resolved to the spacing (contact
 * shadows of secondary sources narrower than it are blurred), and the
 * first bounce leaves from the restricted, not the exact, reflected direct
 * light (same power per surface, blurred to the spacing).
 */
#ifndef penumbraIndirectLevel_h
#define penumbraIndirectLevel_h

#include "penumbraTransportModule.h" // for export macro
#include "penumbraParallel.h"
#include "penumbraProgressiveShooter.h"
#include "penumbraScene.h"

#include <array>
#include <cstddef>
#include <vector>

namespace penumbra
{

class RayCaster;

/// The coarse level of one surface and the transfer to and from its fine samples.
class PENUMBRATRANSPORT_EXPORT IndirectLevel
{
public:
  /**
   * The lattice mesh of `surface` at `spacing` (> 0, scene units), and the
   * location of the points of `fine` (which must lie in the surface's
   * plane) in it.
   */
  IndirectLevel(const Surface& surface, double spacing, const SurfaceSamples& fine);

  /// The lattice resolution n of each ear (see the file comment).
  int GetResolution() const { return this->Resolution; }

  /// Number of points of the coarse mesh (the lattice's, without the points evaluated on their own).
  std::size_t GetNumberOfPoints() const { return this->Points.size(); }

  /**
   * Keep interpolation from crossing occluders (see the file comment):
   * `fine` are the samples given to the constructor, `surfaceId` their
   * surface in `caster`'s scene. Returns the number of fine points that
   * are evaluated on their own from now on. Call before Restrict.
   */
  std::size_t SeparateOccluded(const SurfaceSamples& fine, int surfaceId, const RayCaster& caster,
    const ParallelFor& loop);

  /// Number of fine points evaluated on their own (SeparateOccluded).
  std::size_t GetNumberOfSeparatePoints() const { return this->Separate.size(); }

  /// Number of coarse points `surface` would get at `spacing`, without building them.
  static std::size_t CountPoints(const Surface& surface, double spacing);

  /**
   * The coarse samples: the lattice's points and triangles, with Total and
   * Unshot the restrictions of `fine`'s (the samples given to the
   * constructor, with their current values), then the fine points evaluated
   * on their own with their fine values.
   */
  SurfaceSamples Restrict(const SurfaceSamples& fine) const;

  /**
   * Add to every fine total the coarse increment after.Total - before.Total
   * interpolated at that fine point; `before` and `after` are coarse
   * samples of this level (as returned by Restrict, and after shooting).
   */
  void Prolong(const SurfaceSamples& before, const SurfaceSamples& after, SurfaceSamples& fine) const;

private:
  /// A point of the plane located in the coarse mesh: corners and weights.
  struct Location
  {
    std::array<int, 3> Corners;
    std::array<double, 3> Weights;
  };
  Location Locate(const Vec3& p) const;

  double Spacing = 0.0;
  Vec3 Normal;                                ///< the surface's front normal
  double QuadratureSize = 0.0;               ///< restriction: largest quadrature triangle
  int Resolution = 1;
  Vec3 AxisU, AxisV;                          ///< the plane's frame
  std::vector<std::array<int, 3>> Ears;       ///< polygon vertex indices
  std::vector<std::array<double, 2>> Corners; ///< polygon vertices in the frame
  std::vector<std::vector<int>> LatticeIds;   ///< per ear: lattice (i, j) -> point id
  std::vector<Vec3> Points;
  std::vector<std::array<int, 3>> Triangles;
  std::vector<double> Mass;                   ///< int phi_k dA per coarse point
  std::vector<Location> FineLocations;
  /// Fine points evaluated on their own; the k-th is coarse sample Points.size() + k.
  std::vector<int> Separate;
  std::vector<int> SeparateIndex; ///< per fine point: its place in Separate, or -1
  std::vector<Vec3> SeparatePoints; ///< where each is evaluated (moved off contact lines)
};

/**
 * The lattice spacing at which the surfaces' sample counts total about
 * `budget`, each surface counting min(its coarse points, finePoints[i])
 * (a surface with fewer fine samples than coarse points keeps its fine
 * samples). finePoints has one count per surface (0: the surface takes no
 * part). Returns 0 when the fine samples already fit the budget.
 */
PENUMBRATRANSPORT_EXPORT double IndirectSpacing(
  const Scene& scene, const std::vector<std::size_t>& finePoints, std::size_t budget);

} // namespace penumbra

#endif
