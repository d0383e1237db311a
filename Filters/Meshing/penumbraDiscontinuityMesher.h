// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDiscontinuityMesher.h
 * @brief Discontinuity meshing of each receiver (Lischinski, Tampieri and
 * Greenberg 1991, section 4, done in 3D): the shadow and contact boundaries
 * cast on a receiving polygon by the selected shooters become constraints of
 * a constrained Delaunay triangulation of that polygon, so that initial
 * samples lie on every cusp of the radiance function.
 *
 * What is computed, per receiver R and selected shooter S (S != R, S's front
 * facing part of R and R's front facing part of S):
 *
 * - Candidate occluders: the polygons that may meet the shaft between S and R
 *   (OccluderSet::ShaftCandidates: conservative, BVH-accelerated).
 * - EV events (vertex v of S, edge e of an occluder): the wedge
 *   { v + s (a + t (b - a) - v) : s >= 1, t in [0, 1] }; VE events (edge pq of
 *   S, vertex w of an occluder): { w + s (w - (p + t (q - p))) : s >= 0 };
 *   optionally (OccluderOccluderEvents) EV events between two occluders
 *   (vertex w of one, edge e of another): the lines through w and e that hit
 *   S beyond both features, continued to R.
 * - Which wedges are used ("supporting" wedges). Let P be the wedge plane.
 *   Polygons are two-sided and the occluders are the scene's polygons, so
 *   the feature of a solid made of several polygons is shared: an edge by the
 *   polygons having it as an edge, a vertex by the polygons having it as a
 *   vertex (matched within 1e-9 of the scene size). A feature is *on the
 *   silhouette* seen along P when every polygon sharing it lies locally on
 *   one side of P (polygons lying in P are ignored; a feature whose polygons
 *   all lie in P is seen edge-on and casts nothing). Locally means: for an
 *   edge, the polygon's inward direction at the edge; for a vertex, the
 *   polygon's corner at it (a reflex corner always straddles P). The exact
 *   criterion used is then:
 *     EV (v, e):  e on the silhouette, and S's corner at v on one side of P;
 *     VE (pq, w): w on the silhouette (S is always on one side of a plane
 *                 through its own edge);
 *     occluder EV (w, e): both on the silhouette and P cuts S.
 *   For convex S and a single convex occluder these are exactly the planes
 *   supporting both S and the occluder (tangent to both): the wedges that
 *   bound umbra and penumbra, the "extremal" boundaries. With InteriorEvents
 *   the corner conditions are relaxed (S's corner at v, and the occluder's
 *   corner at w, may straddle P): those wedges are also true D2 events (the
 *   visible part of the source gains or loses a vertex) that bend the
 *   radiance inside a penumbra. Lines through w that pierce a solid leave
 *   it through another face, which blocks them; from inside an open,
 *   floating box such wedges can give superfluous (harmless) lines.
 * - Each wedge is cut by R's plane and kept only where it is really a
 *   boundary: the line from the receiving point through the features to the
 *   source point (v for EV, the point of pq for VE, the point of S for
 *   occluder EV) must be free of every other polygon (those sharing the
 *   features excepted), must lie in front of S and of R, and must hit S's
 *   front. This is solved exactly along the whole wedge (not by sampling):
 *   in the wedge plane each blocker is a chord whose central projection from
 *   the wedge's apex is an interval of the wedge parameter t; the visible
 *   t-intervals are mapped to R's plane and clipped to R (which may be
 *   concave). Blockers are found per wedge (polygons crossing the wedge
 *   plane inside the hull of the wedge's region), and the generators of
 *   occluder EV events per apex (edges on lines through the apex that hit
 *   both S and R), among the pair's shaft candidates when they are few, else
 *   in the BVH.
 * - Culling (CullWedges), so that the cost follows the boundaries produced
 *   rather than the square of the polygon count: every event line runs from
 *   a point of R to a point of S, so (a) features entirely outside the shaft
 *   (the convex hull of S and R) are skipped, although their polygon may
 *   cross it; (b) a wedge whose plane leaves R's vertices on one side (by
 *   more than the snapping distance) is not traced, and otherwise its
 *   parameter t is restricted to the central projection of R's chords in
 *   the wedge plane (lengthened by 1e-6 of the scene size, so the pieces
 *   still end where the clip against R's outline puts them) before blockers
 *   are looked for; (c) occluder EV generators are looked for only on lines
 *   that also reach R. Each culled wedge would have been clipped away
 *   entirely: the output is the same up to rounding, which the tests check
 *   with the culling switched off.
 * - Contacts: edges of other polygons lying in R's plane (within
 *   ContactTolerance) give order-0 lines. When such polygons belong to a
 *   solid that is closed apart from the edges it stands on (every other edge
 *   shared by exactly two polygons, e.g. a box without bottom standing on a
 *   floor), the area it encloses on R (its footprint) is removed from the
 *   mesh: nothing there is visible.
 * - Plane events (PlaneEvents): from a receiving point in the plane of an
 *   occluder polygon F that cuts S, F is seen edge-on; moving off the plane,
 *   F's image opens into a strip whose two long sides (the two chains of F's
 *   outline, at different depths) recede at different rates, so the hidden
 *   area of S has a kink: a D1 line. This is the degenerate EEE event of F's
 *   coplanar edges, and for solids (every face of a box has it) it is often
 *   the strongest line of a shadow: on the Cornell floor, a tall-block side
 *   plane crossing the light changes the form factor's slope by half. Its
 *   extent is where F's image overlaps S's chord in that plane (lines through
 *   a vertex of F and the chord, or through a chord end and an edge of F,
 *   with the same visibility test). Likewise S's own plane crossing R is a D1
 *   line (the form factor grows linearly from 0 in front of it); that one is
 *   kept whole, without a visibility test.
 * - Orders: 0 contact; 1 when the wedge plane contains an edge of each of
 *   the two features' polygons (a source edge parallel to the occluder edge
 *   being the common case: the visible sliver is a strip growing linearly);
 *   2 otherwise (generic EV/VE: the sliver grows like a triangle).
 *   Collinear pieces from different events are merged; where they overlap
 *   the lowest order wins (-1 for R's own outline, then 0, 1, 2).
 * - The jump threshold estimates each boundary's importance as
 *   Ls * min(F_occluder, F_shooter) at its midpoint (form factors from R's
 *   normal, Ls the mean shooter radiance) relative to the largest
 *   unoccluded direct radiance sum_S Ls F_S over R (sampled at its centroid
 *   and near its vertices); R's reflectance cancels out. With CullWedges, a
 *   wedge whose jump is below the threshold even with the form factors
 *   bounded over all of R (F <= min(1, A / (pi d^2)), d the distance between
 *   R and the polygon of area A) is not traced at all, so faint boundaries
 *   of weak or distant shooters cost nothing.
 *
 * Left out (documented limitations): EEE events (three edges in general
 * position, their quadric surfaces) are not generated (only the degenerate,
 * planar ones above); occluder-occluder events are EV only and supporting
 * only (InteriorEvents does not apply to them); shared features are matched
 * by coincident vertices
 * (not by T-junctions); a polygon lying in a wedge plane does not block that
 * wedge; polygons coplanar with R and solids that cross R's plane are not
 * treated as contacts; overlapping footprints of two solids on the same
 * receiver are not merged.
 *
 * Triangulation: the constraints (after snapping end points closer than
 * 1e-10 of the scene size and merging collinear pieces) go into a CGAL
 * constrained Delaunay triangulation with exact predicates and exact
 * constructions, so crossings are computed exactly and no inverted or flat
 * triangle arises. Faces are classified by flood fill (crossing an outline
 * edge toggles "inside R", crossing a footprint edge toggles "under a
 * solid"). Quality refinement (MinimumAngle) runs on that arrangement
 * rounded to doubles, with exact predicates (refining with exact
 * constructions makes the coordinates' size explode). The public types carry
 * no CGAL type; the CGAL code lives in a private translation unit.
 */
#ifndef penumbraDiscontinuityMesher_h
#define penumbraDiscontinuityMesher_h

#include "penumbraMeshingModule.h" // for export macro
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
  /// the penumbra; see the file documentation). [false]
  bool InteriorEvents = false;
  /// Also trace the D1 lines where a plane crosses the receiver: the plane of
  /// an occluder polygon that cuts the shooter (the polygon is seen edge-on
  /// there; see the file documentation), and the shooter's own plane. [true]
  bool PlaneEvents = true;
  /// Generate contact lines and remove the footprints of solids standing on
  /// the receiver. [true]
  bool Contacts = true;
  /// Drop shadow boundaries whose estimated radiance jump, relative to the
  /// receiver's largest unoccluded direct radiance, is below this. [0] = keep
  /// all; in [0, 1]. Contact lines are always kept.
  double JumpThreshold = 0.0;
  /// Distance (relative to the scene size) within which an edge lying in a
  /// receiver's plane is a contact. [1e-6], in [0, 1e-2].
  double ContactTolerance = 1e-6;
  /// Cull wedges that cannot leave a boundary on the receiver before tracing
  /// them (see "Culling" in the file documentation). The result is the same
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
  std::size_t Constraints = 0;        ///< constraints inserted (after merging collinear pieces)
  std::size_t ConstraintFailures = 0; ///< constraint insertions that threw (should be 0)
  std::size_t Points = 0;             ///< output points (with order-0 copies)
  std::size_t Triangles = 0;          ///< output triangles
  std::size_t DroppedDegenerate = 0;  ///< triangles of zero area after rounding, dropped (should be 0)
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
  struct Internal;
  std::unique_ptr<Internal> Impl;
};

} // namespace penumbra

#endif
