// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverTriangulation.h
 * @brief Private interface between the discontinuity mesher (and the
 * adaptive sampler) and their CGAL translation unit: the constrained
 * Delaunay triangulation of one receiver in its plane, and its refinement by
 * point insertion. Not installed; carries no CGAL type.
 */
#ifndef penumbraReceiverTriangulation_h
#define penumbraReceiverTriangulation_h

#include "penumbraDiscontinuityMesher.h"
#include "penumbraMath.h"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{
namespace detail
{

/// A constraint in the receiver's 2D frame, with its label.
struct Constraint2D
{
  double A[2];
  double B[2];
  int Order = 2;        ///< -1 outline, 0 contact, 1, 2
  int SourceId = -1;    ///< shooter, or -1
  bool Outline = false; ///< part of the receiver's outline (toggles "inside receiver")
  bool Removal = false; ///< part of a footprint outline (toggles "under a solid")
};

/// Input of TriangulateReceiver.
struct TriangulationInput
{
  int ReceiverId = -1;
  /// Constraints; collinear overlaps already merged, end points snapped.
  std::vector<Constraint2D> Constraints;
  /// The frame: a 2D point (x, y) is Origin + x AxisU + y AxisV in 3D.
  Vec3 Origin;
  Vec3 AxisU;
  Vec3 AxisV;
  /// 2D points that stand for known 3D points (the receiver's vertices):
  /// output exactly as given instead of being mapped back through the frame.
  std::vector<P2> Known2D;
  std::vector<Vec3> Known3D;
  /// Minimum angle in degrees (0 = no refinement).
  double MinimumAngle = 0.0;
};

/// Output of TriangulateReceiver.
struct TriangulationOutput
{
  ReceiverMesh Mesh;
  std::size_t Failures = 0;          ///< constraint insertions that threw
  std::size_t DroppedDegenerate = 0; ///< zero-area triangles after rounding
  double RemovedArea = 0.0;          ///< area inside the outline and inside a footprint
};

/**
 * Triangulate: insert every constraint (exact intersections where they
 * cross), classify faces by flood fill (crossing an Outline edge toggles
 * "inside the receiver", crossing a Removal edge toggles "under a solid"),
 * refine when asked, then emit the kept triangles, their points (duplicated
 * across order-0 edges, see ReceiverMesh) and the constrained edges that
 * border them, labelled with the lowest order of the constraints through them.
 */
TriangulationOutput TriangulateReceiver(const TriangulationInput& input);

/// A constrained segment of a RefinableTriangulation, between two vertex ids.
struct RefinableSegment
{
  int A = -1;
  int B = -1;
  int Order = 2;     ///< -1 outline, 0, 1, 2
  int SourceId = -1; ///< shooter, or -1
};

/**
 * The current mesh of a RefinableTriangulation (its kept faces), in the same
 * layout as ReceiverMesh but 2D: points are duplicated across order-0 edges
 * (one copy per sector of kept faces around a vertex, sectors being separated
 * by order-0 edges and by non-kept faces), so triangles on the two sides of
 * an order-0 line never share a point.
 */
struct RefinableSnapshot
{
  /// (u, v) of every vertex id (stable across insertions; ids in [0, n)).
  std::vector<P2> Vertices;
  /// Vertex id of each point (copy).
  std::vector<int> PointVertex;
  /// Kept triangles: point ids, counter-clockwise.
  std::vector<std::array<int, 3>> Triangles;
  /// Per triangle and edge k (from corner k to corner k + 1): index into
  /// Segments of the constrained edge there, or -1 (unconstrained).
  std::vector<std::array<int, 3>> TriangleSegments;
  /// One constrained edge bordering kept faces.
  struct Segment
  {
    int VertexA = -1, VertexB = -1; ///< vertex ids
    int LeftA = -1, LeftB = -1;     ///< point ids on the left of A->B, or -1 (not kept)
    int RightA = -1, RightB = -1;   ///< point ids on the right, or -1 (not kept)
    int Order = 2;                  ///< lowest order of the constraints through it (-1 first)
    int SourceId = -1;              ///< its source (lowest id among those of that order)
  };
  std::vector<Segment> Segments;
};

/**
 * A constrained Delaunay triangulation of one receiver mesh in its plane
 * (double coordinates, exact predicates) that accepts point insertions
 * keeping every constraint and its label: the adaptive sampler's. A point
 * inserted on a constrained edge splits it and both pieces keep the labels
 * of every constraint through it. The triangulation is enclosed in a far
 * bounding square (never part of the output), so receiver edges are never
 * convex-hull edges and may be split by points rounded slightly off them.
 * Deterministic: the same calls give the same output.
 */
class RefinableTriangulation
{
public:
  /**
   * Build from `vertices` (2D, ids = indices), constrained `segments`
   * (between vertex ids) and seed points of the region to keep: a face is
   * kept when its cell (connected across unconstrained edges) contains one
   * of `keptSeeds` (e.g. the centroids of the triangles of a mesh of that
   * region; seeds on an edge or a vertex are ignored). Vertices that
   * coincide after rounding, or segments that cross or pass through a
   * vertex, are resolved by the triangulation (crossings add vertices with
   * new ids) and counted in GetIrregularities().
   */
  RefinableTriangulation(const std::vector<P2>& vertices,
    const std::vector<RefinableSegment>& segments,
    const std::vector<P2>& keptSeeds);
  ~RefinableTriangulation();
  RefinableTriangulation(const RefinableTriangulation&) = delete;
  RefinableTriangulation& operator=(const RefinableTriangulation&) = delete;

  /// Number of vertex ids (input vertices, then inserted ones).
  int GetNumberOfVertices() const;
  /// (u, v) of vertex `id`.
  P2 GetVertex(int id) const;
  /// Input vertices merged with another, failed segment insertions and
  /// vertices created where segments cross (0 for a valid planar input).
  std::size_t GetIrregularities() const;

  /**
   * Insert (u, v) into the kept face containing it, located from vertex
   * `hintVertex`. Returns the new vertex id, or -1 (nothing inserted) when the
   * point is on a vertex or a constrained edge, or not in a kept face.
   */
  int InsertInFace(double u, double v, int hintVertex);

  /**
   * Split the edge between vertices `a` and `b` at (u, v), a point on (or
   * within rounding of) the segment: a constrained edge is split into two
   * constrained pieces with its labels. Returns the new vertex id, or -1
   * when a-b is no longer an edge or the split would give a triangle that is
   * not counter-clockwise (exact predicate).
   */
  int InsertOnEdge(int a, int b, double u, double v);

  /// The current kept mesh (uses per-face scratch data, hence not const).
  void Extract(RefinableSnapshot& snapshot);

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace detail
} // namespace penumbra

#endif
