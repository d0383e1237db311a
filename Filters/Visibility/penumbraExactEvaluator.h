// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraExactEvaluator.h
 * @brief Exact visible part of a shooting polygon seen from a point, and the
 * exact form factor / contributed radiance of a constant-radiance shooter
 * (Lischinski, Tampieri and Greenberg 1991, section 5, "the more accurate
 * method": resolve the visible regions of the source, then integrate them in
 * closed form).
 *
 * Method. In the shooter's plane, the visible region starts as the shooter's
 * convex pieces clipped to x's front half-space. Each convex piece O of each
 * candidate occluder casts the shadow
 *
 *   { y on the shooter : the ray from x to y crosses O's plane inside O,
 *                        strictly before y },
 *
 * a convex region. When O lies between the shooter's plane and x's level and
 * no closer than 5% of the way to x's level, the shadow is O's central
 * projection from x (magnified at most 20 times). Otherwise it is written
 * as an intersection of half-planes of the shooter's plane: one per edge of O
 * (the plane through x and the edge) and one for "y strictly beyond O's plane
 * as seen from x". That form needs no clipping of O to the slab or to the
 * pyramid and no division by small numbers, so occluders that straddle the
 * shooter's plane or x's tangent plane, touch the shooter or the receiver,
 * or are seen almost edge-on are handled exactly. Shadows are subtracted one
 * at a time (largest solid angle first) from the convex visible pieces: a piece
 * the shadow meets (bounding boxes, then separating axes) is split by the
 * shadow's lines, the parts outside a line are kept and the part inside all
 * lines vanishes; other pieces are kept whole. Pieces smaller than 1e-14 of
 * the shooter's area are dropped. The form factor is the sum of Lambert's
 * formula over the visible pieces.
 *
 * Conventions: an occluder casts no shadow from a point within
 * OccluderSet::GetPlaneTolerance() of its own plane (rays from x then only
 * graze it); occluders within OccluderSet::GetTolerance() of the shooter's
 * plane count as coplanar with it and do not block it. The contributed
 * radiance of a constant shooter of radiance Ls onto a receiver of
 * reflectance rho is rho * Ls * F (E = pi Ls F, L = rho E / pi).
 */
#ifndef penumbraExactEvaluator_h
#define penumbraExactEvaluator_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraOccluderSet.h"
#include "penumbraPreparedScene.h"
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penumbra
{

/**
 * Scratch memory of the exact visibility code. One per thread; reusing it
 * makes every query free of heap allocation once the buffers have grown.
 * The members are internal and meaningless between calls.
 */
struct VisibilityWorkspace
{
  /**
   * The visible pieces (internal): convex 2D polygons in the shooter's frame.
   * Points only grows during a query (pieces that are split leave their old
   * points behind); the alive pieces are [0, Count) of the index arrays.
   */
  struct PieceBuffer
  {
    std::vector<double> Points; ///< (u, v) pairs; the first Used doubles are in use
    int Used = 0;
    std::vector<int> Starts;           ///< first double of each piece in Points
    std::vector<int> Sizes;            ///< vertex count of each piece (0 = removed)
    std::vector<double> Boxes;         ///< umin, umax, vmin, vmax of each piece
    int Count = 0;                     ///< number of pieces
    double Bounds[4] = { 0, 0, 0, 0 }; ///< union of the boxes
  };
  PieceBuffer Pieces;                        ///< the visible region
  std::vector<double> Remainder;             ///< the part of a piece still inside the shadow
  std::vector<double> Split;                 ///< scratch for one split
  std::vector<double> Distances;             ///< signed distances of the remainder to a line
  std::vector<double> Lines;                 ///< shadow half-planes, (a, b, c) triples
  std::vector<double> Shadow;                ///< the current shadow polygon
  std::vector<double> ShadowSwap;            ///< scratch for clipping it
  std::vector<double> Hull;                  ///< the shooter's hull clipped to x's front
  std::vector<Vec3> Local;                   ///< occluder piece vertices relative to x
  std::vector<int> Candidates;               ///< pyramid candidates
  std::vector<std::pair<double, int>> Order; ///< candidates sorted by solid angle
  CullingVolume Frustum;                     ///< pyramid of the current query
  long long ShadowCount = 0;                 ///< statistics: shadows subtracted so far

  /// A square of a receiver's plane seen with one shooter (the tile cache).
  struct TileKey
  {
    std::uint64_t Set; ///< OccluderSet::GetIdentity
    int Receiver;
    int Shooter;
    long long I;
    long long J;
    bool operator==(const TileKey& o) const
    {
      return Set == o.Set && Receiver == o.Receiver && Shooter == o.Shooter && I == o.I &&
        J == o.J;
    }
  };
  struct TileKeyHash
  {
    std::size_t operator()(const TileKey& k) const
    {
      std::size_t h = std::hash<std::uint64_t>()(k.Set);
      for (const long long v : { static_cast<long long>(k.Receiver),
             static_cast<long long>(k.Shooter), k.I, k.J })
      {
        h ^= std::hash<long long>()(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      }
      return h;
    }
  };
  /// The occluders that may meet the pyramid of any point of a tile
  /// (OccluderSet::TileCandidates); Usable is false for a list so long that
  /// the traversal per point is cheaper.
  struct TileEntry
  {
    bool Usable = false;
    std::vector<int> Candidates;
  };
  std::unordered_map<TileKey, TileEntry, TileKeyHash> Tiles; ///< internal
  CullingVolume TileShaft;                                    ///< scratch of TileCandidates
};

/**
 * The visible part of a shooter from a point: convex polygons in the
 * shooter's plane, world coordinates, counter-clockwise seen from the
 * shooter's front. Piece k is Points[Offsets[k]] .. Points[Offsets[k+1] - 1].
 */
struct VisibleRegion
{
  std::vector<Vec3> Points;
  std::vector<int> Offsets; ///< size = number of pieces + 1 (or empty)

  /// Number of convex pieces.
  int GetNumberOfPieces() const
  {
    return this->Offsets.empty() ? 0 : static_cast<int>(this->Offsets.size()) - 1;
  }
  /// Total area of the pieces.
  PENUMBRAVISIBILITY_EXPORT double GetArea() const;
};

/**
 * Exact form factor from the differential area at x (unit normal n) to the
 * part of shooter `shooterId` visible from x, taking as potential occluders
 * the polygons listed in `candidates` (any superset of the real blockers:
 * shaft candidates, all polygons, ...; each is culled again against the
 * pyramid from x). `receiverId` (or -1) and the shooter are skipped. When
 * `region` is given it receives the visible pieces. Returns a finite value
 * in [0, 1]; 0 when x is not in front of the shooter.
 *
 * Pure visibility queries (e.g. "does this occluder vertex see the source")
 * pass n = (0, 0, 0): nothing is clipped by a tangent plane, the return
 * value is 0 and `region` holds the part of the shooter's front visible from
 * x. A point lying on occluders (an occluder vertex or edge) is not hidden
 * by them: a polygon whose plane contains x casts no shadow.
 */
PENUMBRAVISIBILITY_EXPORT double VisibleFormFactor(const OccluderSet& occluders, const Vec3& x,
  const Vec3& n, int shooterId, int receiverId, const int* candidates, int numberOfCandidates,
  VisibilityWorkspace& workspace, VisibleRegion* region = nullptr);

/// Convenience overload taking a vector of candidates.
inline double VisibleFormFactor(const OccluderSet& occluders, const Vec3& x, const Vec3& n,
  int shooterId, int receiverId, const std::vector<int>& candidates, VisibilityWorkspace& workspace,
  VisibleRegion* region = nullptr)
{
  return VisibleFormFactor(occluders, x, n, shooterId, receiverId, candidates.data(),
    static_cast<int>(candidates.size()), workspace, region);
}

/**
 * Exact evaluator of contributed radiance for constant-radiance shooters:
 * culling (BVH + pyramid per point, or shaft per pair), exact visibility and
 * closed-form integration. Construct once per scene; the queries are const
 * and thread-safe given one VisibilityWorkspace per thread.
 */
class PENUMBRAVISIBILITY_EXPORT ExactEvaluator
{
public:
  /// Prepare `scene` (its geometry is copied; the scene may be discarded).
  explicit ExactEvaluator(const Scene& scene);
  /// Share the occluder set of a prepared scene.
  explicit ExactEvaluator(const std::shared_ptr<const PreparedScene>& scene);

  /// The prepared scene.
  const OccluderSet& GetOccluders() const { return *this->Occluders; }

  /**
   * Form factor from the differential area at x (on receiver `receiverId`,
   * or -1 for a free point; unit normal n) to the visible part of shooter
   * `shooterId`. Occluders are found by BVH traversal of the pyramid from x.
   */
  double FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    VisibilityWorkspace& workspace, VisibleRegion* region = nullptr) const;

  /**
   * Query A for a pair: the candidates to pass to the per-pair FormFactor.
   * Returns false when the pair exchanges no light (every FormFactor of the
   * pair is then 0).
   */
  bool ShaftCandidates(int shooterId, int receiverId, std::vector<int>& candidates) const
  {
    return this->Occluders->ShaftCandidates(shooterId, receiverId, candidates);
  }

  /// Per-pair variant of FormFactor: occluders are taken from `shaftCandidates`.
  double FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    const std::vector<int>& shaftCandidates, VisibilityWorkspace& workspace,
    VisibleRegion* region = nullptr) const;

  /**
   * Radiance contributed at x by shooter `shooterId` emitting its scene
   * Emission uniformly, reflected by receiver `receiverId` (its scene
   * Reflectance): rho * Le * F per channel, W sr^-1 m^-2.
   */
  RGB ContributedRadiance(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
    VisibilityWorkspace& workspace) const;

private:
  void CopyMaterials(const Scene& scene);

  std::shared_ptr<const OccluderSet> Occluders;
  std::vector<RGB> Reflectance;
  std::vector<RGB> Emission;
};

} // namespace penumbra

#endif
