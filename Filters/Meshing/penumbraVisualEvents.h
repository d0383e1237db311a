// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraVisualEvents.h
 * @brief The shadow boundaries one shooter casts on one receiver: the visual
 * events of the pair (EV and VE wedges between the shooter and the
 * occluders' silhouette features, EV wedges between two occluders, and the
 * D1 lines of planes seen edge-on), each traced onto the receiver and
 * clipped to it. Private (not installed).
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraVisualEvents_h
#define penumbraVisualEvents_h

#include "penumbraConstraintMerging.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraSceneTopology.h"
#include "penumbraScreens.h"
#include "penumbraWedgeTracer.h"

#include <utility>
#include <vector>

namespace penumbra
{
class OccluderSet;
struct CullingVolume;

namespace detail
{

/**
 * The events of one (shooter, receiver) pair. Run() appends the pair's
 * boundary pieces (in the receiver's frame) to the output and counts them.
 * The plane events are in penumbraPlaneEvents.cxx.
 */
class ShadowEvents
{
public:
  /// `minimumJump`: the jump below which shadows are dropped (< 0: none).
  ShadowEvents(const SceneTopology& topology, const OccluderSet& occluders, const Scene& scene,
    const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame, int receiverId,
    int shooterId, double minimumJump, std::vector<Segment2>& out,
    DiscontinuityMeshStatistics& stats);
  ShadowEvents(const ShadowEvents&) = delete;
  ShadowEvents& operator=(const ShadowEvents&) = delete;

  void Run();

private:
  /// The candidates' edges and vertices usable as occluders of the pair.
  void SelectFeatures(const CullingVolume& shaft);
  bool OutsideShaft(const CullingVolume& shaft, const Vec3* points, int count) const;
  /// EV: shooter vertex x occluder edge.
  void AddEdgeVertexEvents();
  /// VE: shooter edge x occluder vertex.
  void AddVertexEdgeEvents();
  /// Occluder EV: vertex of one occluder x edge of another.
  void AddOccluderEvents();
  /// The edges of the polygons that may hold generators for apex `c`.
  void FindGenerators(int c, std::vector<int>& found, std::vector<int>& generators) const;
  /// The shooter's own plane crossing the receiver.
  void AddShooterPlaneEvent();
  /// The planes of occluder polygons cutting the shooter.
  void AddFacePlaneEvents();

  /// Whether a wedge's jump is below the threshold even bounded over R.
  bool Faint(int occluderA, int occluderB) const;
  /// Trace wedge w and append its pieces on the receiver.
  void Emit(const Wedge& w, int order, int occluderA, int occluderB);
  /// The polygons sharing edge e / vertex cluster c do not block the wedge.
  void ExcludeEdge(int e, std::vector<int>& exclude) const;
  void ExcludeVertex(int c, std::vector<int>& exclude) const;
  /// Sort and deduplicate an exclusion list.
  static void FinishExclude(std::vector<int>& exclude);
  double DistR(const Vec3& p) const { return Dot(this->Rec.N, p) - this->Rec.D; }
  double DistS(const Vec3& p) const { return Dot(this->Sh.N, p) - this->Sh.D; }

  const SceneTopology& Topology;
  const OccluderSet& Occluders;
  const Scene& SceneRef;
  const DiscontinuityMeshSettings& Settings;
  const ReceiverFrame& Frame;
  const int ReceiverId;
  const int ShooterId;
  const double MinimumJump;
  std::vector<Segment2>& Out;
  DiscontinuityMeshStatistics& Stats;
  const PolygonData& Rec;
  const PolygonData& Sh;
  const double Tol;        ///< linear tolerance
  const double ContactTol; ///< features within this of R's plane are contacts
  const double Snap;
  const double MinPiece;
  double ShooterRadiance = 0.0;
  std::vector<int> Candidates;     ///< the pair's shaft candidates
  std::vector<int> Scratch;        ///< blocker candidates of the current wedge
  std::vector<int> UsableEdges;    ///< sorted
  std::vector<int> UsableVertices; ///< sorted
  PairContext Ctx;
  ScreenSet Screens; ///< polygons hiding whole features from the receiver
  std::vector<std::pair<Vec3, Vec3>> Traced;
  std::vector<Interval> ClipScratch;
  std::vector<std::pair<P2, P2>> Pieces;
};

} // namespace detail
} // namespace penumbra

#endif
