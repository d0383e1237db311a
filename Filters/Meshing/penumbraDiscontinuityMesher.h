// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDiscontinuityMesher.h
 * @brief Discontinuity meshing of each receiver (Lischinski, Tampieri and
 * Greenberg 1991, section 4, done in 3D): the shadow and contact boundaries
 * cast on a receiving polygon by the selected shooters become constraints of
 * a constrained Delaunay triangulation of that polygon, so that initial
 * samples lie on every cusp of the radiance function.
 *
 * This header holds the public types: the boundary segments and the
 * triangulated receiver, the settings and statistics, and the mesher. The
 * public types carry no CGAL type.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraDiscontinuityMesher_h
#define penumbraDiscontinuityMesher_h

#include "penumbraMeshingModule.h" // for export macro
#include "penumbraPreparedScene.h"
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{

/// One straight discontinuity or boundary segment on a receiver.
struct DiscontinuitySegment
{
  Vec3 A; ///< first end point (in the receiver's plane)
  Vec3 B; ///< second end point
  /// 0 contact (value discontinuity), 1 slope (D1), 2 second derivative (D2),
  /// -1 the receiver's own outline.
  int Order = 2;
  /// The shooting surface whose shadow this is; -1 for outlines and contacts
  /// (which do not depend on the shooter).
  int SourceId = -1;
  /// The receiving surface.
  int ReceiverId = -1;
  /// Indices into ReceiverMesh::Points of the end points as used by a triangle
  /// on the segment's left (seen from the front, going from A to B), or on its
  /// right when there is none; -1 in ComputeBoundaries' output.
  int PointA = -1;
  int PointB = -1;
};

/**
 * The triangulated receiver.
 *
 * Points along order-0 lines are duplicated: around such a point, the
 * triangles are split into sectors by the order-0 edges through it, and each
 * sector gets its own copy of the point. Triangles on different sides of an
 * order-0 line therefore never share a point, and a reconstructor can store a
 * different value on each side. PointVertex maps every point to its geometric
 * vertex (copies share it); at the free end of an order-0 line there is a
 * single copy.
 */
struct ReceiverMesh
{
  int ReceiverId = -1;
  /// Points in 3D, in the receiver's plane (outline vertices are the input's).
  std::vector<Vec3> Points;
  /// Geometric vertex of each point (same size as Points).
  std::vector<int> PointVertex;
  /// Triangles, counter-clockwise seen from the receiver's front; they cover
  /// the receiver minus the footprints of solids standing on it.
  std::vector<std::array<int, 3>> Triangles;
  /// Every constrained edge bordering a triangle: outline pieces (Order -1),
  /// contact lines (0) and shadow boundaries (1, 2), split where they cross.
  std::vector<DiscontinuitySegment> Segments;
};

/// Settings of the discontinuity mesher; defaults in brackets.
struct DiscontinuityMeshSettings
{
  /// Shooting surfaces. Empty [default]: every surface with non-zero emission
  /// whose power is at least ShooterPowerFraction of the total.
  std::vector<int> Shooters;
  /// Optional radiance of each entry of Shooters (same size), used only by
  /// JumpThreshold, e.g. the unshot radiance of a secondary shooter. Empty
  /// [default]: each shooter's Emission.
  std::vector<RGB> ShooterRadiance;
  /// Optional receivers of each entry of Shooters (same size): that shooter's
  /// boundaries are traced on these receivers only (an empty list: on every
  /// receiver), e.g. a secondary shooter on the receivers whose light it
  /// dominates. Empty [default]: every shooter on every receiver.
  std::vector<std::vector<int>> ShooterReceivers;
  /// With an empty Shooters list: skip emitters whose power (mean of the RGB
  /// channels) is below this fraction of the total emitted power. [0], in [0, 1].
  double ShooterPowerFraction = 0.0;
  /// Quality refinement: smallest triangle angle in degrees, keeping every
  /// constraint (CGAL Delaunay_mesher_2). [0] = none; valid range [0, 20.6]
  /// (the largest bound for which refinement is guaranteed to terminate).
  double MinimumAngle = 0.0;
  /// Also trace EV events between a vertex of one occluder and an edge of
  /// another whose wedge cuts the shooter. [true]
  bool OccluderOccluderEvents = true;
  /// Also trace the non-supporting EV/VE wedges (interior D2 boundaries of
  /// the penumbra; see the design notes). [false]
  bool InteriorEvents = false;
  /// Also trace the D1 lines where a plane crosses the receiver: the plane of
  /// an occluder polygon that cuts the shooter (the polygon is seen edge-on
  /// there; see the design notes), and the shooter's own plane. [true]
  bool PlaneEvents = true;
  /// Generate contact lines and remove the footprints of solids standing on
  /// the receiver, and lines under covers (polygons close in front of it:
  /// penumbraCovers.h). [true]
  bool Contacts = true;
  /// Drop shadow boundaries whose estimated radiance jump, relative to the
  /// largest direct radiance the receiver gets (with visibility, at sample
  /// points), is below this. [0] = keep all; in [0, 1]. Contact lines and
  /// the line of a shooter's own plane are always kept.
  double JumpThreshold = 0.0;
  /// Distance (relative to the scene size) within which an edge lying in a
  /// receiver's plane is a contact. [1e-6], in [0, 1e-2].
  double ContactTolerance = 1e-6;
  /// Cull wedges that cannot leave a boundary on the receiver before tracing
  /// them (see "Culling" in the design notes). The result is the same
  /// either way up to rounding; false only to check that, or to measure the
  /// gain. [true]
  bool CullWedges = true;
};

/// Counters of one or more MeshReceiver / ComputeBoundaries calls.
struct DiscontinuityMeshStatistics
{
  std::size_t Receivers = 0;          ///< receivers processed
  std::size_t Pairs = 0;              ///< (shooter, receiver) pairs exchanging light
  std::size_t CandidateOccluders = 0; ///< shaft candidates summed over pairs
  std::size_t Wedges = 0;             ///< wedges traced (that reached the visibility test after culling)
  std::size_t SegmentsGenerated = 0;  ///< shadow-boundary pieces found on receivers (traced wedges)
  std::size_t SegmentsKept = 0;       ///< of those, kept by the jump threshold
  std::size_t ContactSegments = 0;    ///< contact pieces (order 0) on receivers
  std::size_t CoverSegments = 0;      ///< cover pieces (order 1): outlines and loops under covers
  std::size_t Constraints = 0;        ///< constraints inserted (after merging collinear pieces)
  std::size_t ConstraintFailures = 0; ///< constraint insertions that threw (should be 0)
  std::size_t Points = 0;             ///< output points (with order-0 copies)
  std::size_t Triangles = 0;          ///< output triangles
  std::size_t DroppedDegenerate = 0;  ///< triangles of zero area after rounding, dropped (should be 0)
  /// Triangles dropped because two of their corners, a rounding error apart
  /// (closer than 1e-7 of the scene size), were merged into one point.
  std::size_t MergedTriangles = 0;
  double RemovedArea = 0.0;           ///< receiver area under standing solids, not meshed
  double BoundarySeconds = 0.0;       ///< wall time for events, visibility, clipping, merging
  double TriangulationSeconds = 0.0;  ///< wall time for the triangulations

  /// Accumulate another call's counters (e.g. from other threads).
  PENUMBRAMESHING_EXPORT DiscontinuityMeshStatistics& operator+=(
    const DiscontinuityMeshStatistics& other);
};

/**
 * Discontinuity mesher of a scene. Construction validates the scene (throws
 * InputError naming the cell), copies it and prepares the occluder BVH and
 * the shared-feature tables. The queries are const and thread-safe: receivers
 * may be meshed in parallel, and the result does not depend on the order.
 */
class PENUMBRAMESHING_EXPORT DiscontinuityMesher
{
public:
  explicit DiscontinuityMesher(const Scene& scene);
  /// Mesh a prepared scene (already valid), sharing its occluder set.
  explicit DiscontinuityMesher(const std::shared_ptr<const PreparedScene>& scene);
  ~DiscontinuityMesher();
  DiscontinuityMesher(DiscontinuityMesher&&) noexcept;
  DiscontinuityMesher& operator=(DiscontinuityMesher&&) noexcept;
  DiscontinuityMesher(const DiscontinuityMesher&) = delete;
  DiscontinuityMesher& operator=(const DiscontinuityMesher&) = delete;

  /// Number of surfaces of the scene.
  int GetNumberOfSurfaces() const;

  /// The shooters `settings` selects (sorted, unique). Throws InputError for
  /// an id out of range or a ShooterRadiance list of the wrong size.
  std::vector<int> SelectShooters(const DiscontinuityMeshSettings& settings) const;

  /**
   * The boundaries of receiver `receiverId` before triangulation: the merged
   * constraint segments (outline pieces with Order -1, contact and shadow
   * boundaries), in 3D. PointA/PointB are -1. Throws InputError for a bad id
   * or setting.
   */
  std::vector<DiscontinuitySegment> ComputeBoundaries(int receiverId,
    const DiscontinuityMeshSettings& settings,
    DiscontinuityMeshStatistics* statistics = nullptr) const;

  /**
   * Mesh receiver `receiverId`: its boundaries as constraints of a
   * constrained Delaunay triangulation (exact predicates and constructions),
   * the footprints of standing solids removed, optionally refined to
   * MinimumAngle. Throws InputError for a bad id or setting.
   */
  ReceiverMesh MeshReceiver(int receiverId, const DiscontinuityMeshSettings& settings,
    DiscontinuityMeshStatistics* statistics = nullptr) const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace penumbra

#endif
