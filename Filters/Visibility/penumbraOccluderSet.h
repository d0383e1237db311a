// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraOccluderSet.h
 * @brief A scene prepared for visibility queries: per-polygon planes, frames,
 * bounds and convex decompositions, a BVH over the polygons, and the two
 * culling queries of exact visibility.
 *
 * Query A (once per shooter-receiver pair): the polygons that may intersect
 * the shaft between a shooter and a receiver, i.e. the convex hull of both
 * polygons cut by the shooter's and the receiver's front half-spaces (every
 * segment from a receiving point to a visible shooter point lies in it).
 * Query B (per receiving point): the polygons that may intersect the pyramid
 * from the point to the part of the shooter in front of it, restricted to the
 * slab between the point and the shooter's plane.
 * Both are conservative: a polygon that can block a ray is never dropped; a
 * polygon that is kept may still cast no shadow. Both traverse the BVH and do
 * not touch every polygon of the scene.
 */
#ifndef penumbraOccluderSet_h
#define penumbraOccluderSet_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <cstdint>
#include <vector>

namespace penumbra
{

/// A closed half-space Dot(Normal, p) >= Offset (Normal is a unit vector).
struct Plane
{
  Vec3 Normal;         ///< unit normal, pointing inside
  double Offset = 0.0; ///< Dot(Normal, p) on the plane
};

/**
 * A convex culling volume: an axis-aligned box intersected with half-spaces.
 * A polygon lies outside when it is outside the box or entirely on the outer
 * side of one plane (Dot(Normal, p) < Offset for all its points). A long
 * thin volume (a pyramid from a point to a distant shooter) may also give a
 * capsule that holds it, the points within CapsuleRadius of the segment
 * CapsuleStart -> CapsuleStart + CapsuleAxis: boxes far from that segment
 * are rejected by one distance instead of every plane.
 */
struct CullingVolume
{
  Vec3 BoxMin;               ///< lower corner of the box
  Vec3 BoxMax;               ///< upper corner of the box
  std::vector<Plane> Planes; ///< inner sides Dot(Normal, p) >= Offset
  Vec3 CapsuleStart;
  Vec3 CapsuleAxis;
  double CapsuleRadius = -1.0; ///< negative: no capsule
};

/**
 * Sutherland-Hodgman clip of a 2D polygon (x, y pairs) to the closed
 * half-plane a*x + b*y + c >= 0. `out` needs room for 2 * count points (count
 * + 1 for a convex polygon); returns the number of points written (0 if
 * fewer than 3 remain). Vertices on the line are never duplicated.
 */
PENUMBRAVISIBILITY_EXPORT int ClipPolygon2D(
  const double* xy, int count, double a, double b, double c, double* out);

/// A convex piece of a polygon: a range of vertices in OccluderSet's piece arrays.
struct ConvexPiece
{
  int First = 0; ///< index of the first vertex
  int Count = 0; ///< number of vertices (counter-clockwise seen from the front)
};

/// One scene polygon prepared for visibility queries.
struct PreparedPolygon
{
  Vec3 Normal;           ///< unit front normal
  double Offset = 0.0;   ///< plane: Dot(Normal, p) == Offset
  double Area = 0.0;     ///< area
  double Diameter = 0.0; ///< largest vertex distance
  double Radius = 0.0;   ///< largest distance from Centroid to a vertex
  Vec3 Centroid;         ///< origin of the in-plane frame
  Vec3 AxisU;            ///< in-plane unit axis
  Vec3 AxisV;            ///< Cross(Normal, AxisU): (AxisU, AxisV, Normal) is right-handed
  Vec3 BoundsMin;        ///< axis-aligned bounds
  Vec3 BoundsMax;
  int FirstPiece = 0;     ///< first convex piece (index into GetPieces())
  int NumberOfPieces = 0; ///< 0 for a degenerate polygon
  int FirstHullPoint = 0; ///< convex hull, counter-clockwise (index into hull arrays)
  int NumberOfHullPoints = 0;
  bool Valid = false; ///< false for a degenerate (zero-area) polygon, ignored by all queries
};

/**
 * The scene prepared once for visibility: every polygon's plane, in-plane
 * frame, bounds, convex hull and convex decomposition (ear clipping followed
 * by a Hertel-Mehlhorn merge, so convex polygons stay one piece), plus a BVH
 * over the polygons' bounds. Immutable after construction; all queries are
 * const and thread-safe.
 */
class PENUMBRAVISIBILITY_EXPORT OccluderSet
{
public:
  OccluderSet() = default;
  /// Prepare `scene` (see Build).
  explicit OccluderSet(const Scene& scene);

  /**
   * Prepare the polygons of `scene`. Degenerate polygons are kept (ids stay
   * the scene's) but marked invalid and ignored by every query.
   */
  void Build(const Scene& scene);

  /// Number of polygons (the scene's surface count).
  int GetNumberOfPolygons() const { return static_cast<int>(this->Polygons.size()); }
  /// Prepared data of polygon `id`.
  const PreparedPolygon& GetPolygon(int id) const { return this->Polygons[id]; }
  /// All convex pieces; polygon p owns [FirstPiece, FirstPiece + NumberOfPieces).
  const std::vector<ConvexPiece>& GetPieces() const { return this->Pieces; }
  /// Piece vertices in world coordinates.
  const std::vector<Vec3>& GetPieceVertices() const { return this->PieceVertices; }
  /// Piece vertices in their polygon's frame (u, v pairs), same indices as GetPieceVertices.
  const std::vector<double>& GetPiecePoints2D() const { return this->PiecePoints2D; }
  /// Convex hull vertices in world coordinates.
  const std::vector<Vec3>& GetHullVertices() const { return this->HullVertices; }
  /// Convex hull vertices in their polygon's frame (u, v pairs).
  const std::vector<double>& GetHullPoints2D() const { return this->HullPoints2D; }

  /**
   * A number that no other Build of any set has had (0 for a set never
   * built): caches of query results key on it, since another set may later
   * live at the same address. Copies share it, as they share the contents.
   */
  std::uint64_t GetIdentity() const { return this->Identity; }

  /// Largest extent of the scene's bounding box.
  double GetExtent() const { return this->Extent; }
  /**
   * Distance below which geometry is considered touching by the culling
   * tests and coplanar by the visibility code: 1e-12 of the extent plus a few
   * ulps of the largest coordinate.
   */
  double GetTolerance() const { return this->Tolerance; }
  /**
   * Distance below which a point is considered to lie in an occluder's plane
   * (the occluder then casts no shadow from it): 1e-15 of the extent plus a
   * few ulps of the largest coordinate, i.e. rounding level.
   */
  double GetPlaneTolerance() const { return this->PlaneTolerance; }

  /**
   * Query A. Build the culling volume of the shaft between shooter and
   * receiver. Returns false (and leaves `shaft` unspecified) when no point of
   * the receiver can receive light from the shooter's front, i.e. the pair
   * exchanges nothing.
   */
  bool BuildShaft(int shooterId, int receiverId, CullingVolume& shaft) const;

  /**
   * Query A. The polygons that may block a ray from a point of the receiver
   * to a point of the shooter, excluding both; sorted by id. Returns false
   * (with no candidates) when the pair exchanges nothing. Allocates only the
   * output and a small plane list: call it once per pair. When `shaft` is
   * given it receives the culling volume used (see BuildShaft).
   */
  bool ShaftCandidates(int shooterId, int receiverId, std::vector<int>& candidates,
    CullingVolume* shaft = nullptr) const;

  /**
   * Query B, first step. Build the pyramid from x to the part of the shooter
   * in front of x's tangent plane (unit normal n, or the zero vector for no
   * tangent plane), cut by the slab between x and the shooter's plane.
   * Returns false when nothing of the shooter's front is visible from x's
   * front half-space (the form factor is then 0).
   * `frustum` is reused: its vectors keep their capacity. When
   * `clippedHull` is given it receives the clipped convex hull of the shooter,
   * counter-clockwise (u, v) pairs in the shooter's frame.
   */
  bool BuildFrustum(const Vec3& x, const Vec3& n, int shooterId, CullingVolume& frustum,
    std::vector<double>* clippedHull = nullptr) const;

  /**
   * Query C. The polygons, except the shooter and the receiver, that may
   * meet the pyramid of any point of `tile` (a convex quadrilateral in the
   * receiver's plane, counter-clockwise seen from its front) with the
   * shooter (BuildFrustum): a list to filter point by point instead of a
   * traversal per point. Sorted by id; `shaft` receives the volume used.
   * False (no candidates) when either polygon is invalid.
   */
  bool TileCandidates(const Vec3 tile[4], int shooterId, int receiverId,
    std::vector<int>& candidates, CullingVolume& shaft) const;

  /// Query B by BVH traversal: every polygon except `excludeA`/`excludeB` that may meet `volume`.
  void VolumeCandidates(
    const CullingVolume& volume, int excludeA, int excludeB, std::vector<int>& candidates) const;

  /// Query B on a given list (e.g. shaft candidates): appends the ones that may meet `volume`.
  void FilterCandidates(const CullingVolume& volume, const int* ids, int count, int excludeA,
    int excludeB, std::vector<int>& candidates) const;

  /// Whether polygon `id` may meet `volume` (bounds, then hull vertices against every plane).
  bool MayIntersect(const CullingVolume& volume, int id) const;

private:
  struct Node
  {
    Vec3 Min;
    Vec3 Max;
    int First = 0; ///< leaf: first item; inner: index of the right child
    int Count = 0; ///< leaf: number of items; inner: 0 (left child is the next node)
  };

  int BuildNode(int first, int count, std::vector<Vec3>& centres);

  std::vector<PreparedPolygon> Polygons;
  std::vector<ConvexPiece> Pieces;
  std::vector<Vec3> PieceVertices;
  std::vector<double> PiecePoints2D;
  std::vector<Vec3> HullVertices;
  std::vector<double> HullPoints2D;
  std::vector<Node> Nodes;
  std::vector<int> Items;
  double Extent = 0.0;
  std::uint64_t Identity = 0;
  double Tolerance = 0.0;
  double PlaneTolerance = 0.0;
};

} // namespace penumbra

#endif
