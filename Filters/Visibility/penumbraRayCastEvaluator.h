// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraRayCastEvaluator.h
 * @brief Contributed irradiance by ray casting (Lischinski, Tampieri and
 * Greenberg 1991, section 5, Eq. 6, after Wallace, Elmquist and Haines 1989):
 * adaptive subdivision of the shooter, each piece weighted by the shooter's
 * radiance at its centre, visibility by Embree occlusion rays.
 *
 * For a point x with unit normal n and a shooter j with front normal m,
 *
 *   E(x) = sum_k L_j(y_k) V(x, y_k) cos(theta_x) cos(theta_y) pi A_k / (pi r_k^2 + A_k),
 *
 * over pieces A_k of the shooter with centres y_k (Eq. 6 without rho / pi:
 * the contributed radiance is rho_i E / pi). The factor A / (pi r^2 + A) is
 * the form factor of a coaxial disc of area A: it stays bounded when r is
 * small, and E tends to pi L F for a constant unoccluded shooter as the
 * pieces shrink. Because each piece is weighted by L at its centre, a
 * non-uniform (piecewise-linear) shooter is integrated as such: the centroid
 * rule is exact wherever L is linear over a piece.
 *
 * Subdivision. The initial pieces are the shooter polygon's triangles clipped
 * to x's front half-space, whatever the radiance (a mesh radiance is looked up
 * at each sample through its grid, so the cost does not grow with the mesh,
 * and the domain is the shooter polygon, as for the exact evaluator). Each
 * piece is split 4 ways at its edge midpoints; the recursion continues into
 * all four children while the piece's estimate differs from the sum of its
 * children's by more than the threshold (and always down to MinDepth, never
 * beyond MaxDepth), and otherwise only into a child
 * - whose visibility samples (its corners and centre) disagree, while its
 *   unoccluded estimate exceeds the threshold: without this, a piece whose
 *   centre and children's centres all fall in shadow stops although a shadow
 *   edge crosses it (15 % of a penumbra was lost that way in the test);
 * - whose centre radiance departs from the mean of its corners' (zero for a
 *   linear radiance: a kink or step of the mesh crosses it) by more than the
 *   threshold once weighted (the same failure for radiance steps).
 * A split costs 6 rays, traced as one Embree packet: the 3 edge midpoints and
 * the centres of the 3 outer children (the middle child has the parent's
 * centroid and reuses its ray). The threshold is
 * max(Tolerance * U, AbsoluteTolerance) where U is the unoccluded estimate of
 * the whole shooter from x (one sample per initial triangle, no rays): the
 * same absolute error target in light, penumbra and umbra, which a running
 * total would not give (in the umbra it is 0). RGB values are compared
 * through the mean of the channels' absolute values. The sampling depends
 * only on x, n and the geometry: no random numbers, no state, so results do
 * not depend on the thread count or on the order of queries.
 *
 * Accuracy (measured by the tests). Unoccluded, the error falls roughly like
 * Tolerance (6e-4 relative at the default 1e-3, 1.6e-5 at 1e-6; the disc term
 * biases each piece by about -A / (pi r^2)). In a penumbra, pieces crossed by
 * the shadow edge carry an error of the order of their size, so the error
 * falls like the square root of Tolerance (0.5 % at 1e-3, 1.6e-4 at 1e-7).
 * Occluders, and features of a mesh radiance, smaller than the pieces at
 * MinDepth can still be missed by all samples (the paper's aliasing); the
 * exact evaluator has no such failure.
 *
 * Visibility. One Embree scene of every surface (triangulated), built once,
 * robust (watertight) traversal, queried concurrently by all threads. A ray
 * tests the segment from x to y_k shortened by RelativeRayOffset of its length
 * at both ends; hits on the receiver and the shooter themselves are ignored
 * (an intersection filter), so neither can shadow itself even at grazing
 * angles. Embree works in single precision: geometry closer than about 1e-7
 * of the scene's size to a ray may or may not block it.
 */
#ifndef penumbraRayCastEvaluator_h
#define penumbraRayCastEvaluator_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraRayCaster.h"
#include "penumbraScene.h"
#include "penumbraShooterRadiance.h"
#include "penumbraVector.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{

/// Counters of one ray-cast evaluation (optional output).
struct RayCastStatistics
{
  long long Rays = 0;        ///< occlusion rays traced
  long long Pieces = 0;      ///< shooter pieces whose estimate was computed
  int DeepestLevel = 0;      ///< deepest subdivision level reached
};

/// Settings of RayCastEvaluator: the member initialisers are the defaults.
struct RayCastSettings
{
  /// Subdivision tolerance, relative to the unoccluded estimate of the
  /// shooter seen from x (see the file comment). [1e-3], in (0, 1]
  double Tolerance = 1e-3;
  /// Absolute floor of the subdivision threshold, in irradiance units
  /// (W m^-2 for radiance in W sr^-1 m^-2). [0], in [0, inf)
  double AbsoluteTolerance = 0.0;
  /// Level down to which every piece is split whatever the estimates say.
  /// [1], in [0, 16]
  int MinDepth = 1;
  /// Deepest subdivision level. [8], in [0, 16]
  int MaxDepth = 8;
};

/**
 * Ray-cast evaluator of contributed irradiance (paper Eq. 6). Construct once
 * per scene; configure (the setters are not thread-safe), then query from any
 * number of threads (queries are const, use no shared mutable state and only
 * small per-query buffers).
 */
class PENUMBRAVISIBILITY_EXPORT RayCastEvaluator
{
public:
  /// Prepare `scene` (its geometry and materials are copied).
  explicit RayCastEvaluator(const Scene& scene);
  ~RayCastEvaluator();
  RayCastEvaluator(const RayCastEvaluator&) = delete;
  RayCastEvaluator& operator=(const RayCastEvaluator&) = delete;

  /**
   * Subdivision tolerance, relative to the unoccluded estimate of the
   * shooter seen from x (see the file comment). Default
   * RayCastSettings::Tolerance, valid range (0, 1]; throws InputError outside.
   */
  void SetTolerance(double tolerance);
  double GetTolerance() const { return this->Settings.Tolerance; }

  /**
   * Absolute floor of the subdivision threshold, in irradiance units
   * (W m^-2 for radiance in W sr^-1 m^-2). Valid range [0, inf).
   */
  void SetAbsoluteTolerance(double tolerance);
  double GetAbsoluteTolerance() const { return this->Settings.AbsoluteTolerance; }

  /**
   * Level down to which every piece is split whatever the estimates say (a
   * guard against small occluders missed by all samples; level k has 4^k
   * pieces per initial triangle). Valid range [0, 16]; must not
   * exceed MaxDepth at query time. 0 and 1 behave alike: the error estimate
   * of an initial piece needs its level-1 children anyway.
   */
  void SetMinDepth(int depth);
  int GetMinDepth() const { return this->Settings.MinDepth; }

  /**
   * Deepest subdivision level (each level divides a piece's area by 4).
   * Valid range [0, 16]; 0 means one sample per initial triangle.
   */
  void SetMaxDepth(int depth);
  int GetMaxDepth() const { return this->Settings.MaxDepth; }

  /// Forwarded to RayCaster::SetRelativeOffset (default 1e-5, range [0, 0.01]).
  void SetRelativeRayOffset(double offset);
  double GetRelativeRayOffset() const;

  /// The Embree scene (for raw occlusion queries).
  const RayCaster& GetRayCaster() const { return *this->Caster; }

  /**
   * Irradiance (W m^-2 per channel) at x (unit normal n; on receiver
   * `receiverId`, or -1 for a free point) due to shooter `shooterId` emitting
   * `radiance` from its front, integrated over the shooter polygon (a mesh
   * radiance is zero where the mesh does not cover the shooter). Zero when x
   * is behind the shooter. Throws InputError for a bad shooter id or
   * MinDepth > MaxDepth.
   */
  RGB Irradiance(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    const ShooterRadiance& radiance, RayCastStatistics* statistics = nullptr) const;

  /// Form factor with visibility: the irradiance of a unit constant radiance, over pi.
  double FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    RayCastStatistics* statistics = nullptr) const;

  /**
   * Radiance contributed at x by shooter `shooterId` emitting its scene
   * Emission, reflected by receiver `receiverId` (its scene Reflectance):
   * rho E / pi per channel. Zero for receiverId -1.
   */
  RGB ContributedRadiance(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    RayCastStatistics* statistics = nullptr) const;

private:
  void CheckQuery(int shooterId) const;

  std::unique_ptr<RayCaster> Caster;
  std::vector<Vec3> Normals;       // per surface, unit front normal (zero if degenerate)
  std::vector<RGB> Reflectance;
  std::vector<RGB> Emission;
  RayCastSettings Settings;
};

} // namespace penumbra

#endif
