// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraWedgeTracer.h
 * @brief Tracing one wedge (the surface swept by the lines through an apex
 * and a generator edge) onto a receiver: the parts of it that are really a
 * boundary there, solved exactly along the whole wedge. In the wedge plane
 * each blocker is a chord whose central projection from the apex is an
 * interval of the generator parameter t; the visible t-intervals are mapped
 * to the receiver's plane. Private (not installed).
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraWedgeTracer_h
#define penumbraWedgeTracer_h

#include "penumbraSceneTopology.h"

#include <utility>
#include <vector>

namespace penumbra
{
class OccluderSet;

namespace detail
{

/// Everything the wedge tracer needs about one (shooter, receiver) pair.
struct PairContext
{
  const std::vector<PolygonData>* Polygons = nullptr;
  const PolygonData* Shooter = nullptr;
  const PolygonData* Receiver = nullptr;
  const OccluderSet* Occluders = nullptr;
  int ShooterId = -1;
  int ReceiverId = -1;
  std::vector<int>* Scratch = nullptr; ///< blocker candidates of the current wedge
  const std::vector<int>* Candidates = nullptr; ///< the pair's shaft candidates
  bool Cull = true;      ///< DiscontinuityMeshSettings::CullWedges
  double Tol = 0.0;      ///< linear tolerance
  Vec3 ReceiverCentre;   ///< for bounding the wedge's reach
  double ReceiverRadius = 0.0;
  double Margin = 0.0;   ///< lengthening of the receiver's chords (far above Tol)
};

enum class WedgeKind
{
  EV, ///< apex: shooter vertex; generator: occluder edge
  VE, ///< apex: occluder vertex; generator: shooter edge
  OO  ///< apex: occluder vertex; generator: another occluder's edge
};

struct Wedge
{
  WedgeKind Kind = WedgeKind::EV;
  Vec3 P;  ///< apex
  Vec3 G0; ///< generator edge
  Vec3 G1;
  Vec3 M;  ///< unit normal of the wedge plane
  std::vector<int> Exclude; ///< polygons sharing the features (sorted)
};

/// Chords of polygon p with the plane (m, through point o): pairs of 3D points.
void PlaneChords(const PolygonData& p, const Vec3& m, const Vec3& o, double tol,
  std::vector<std::pair<Vec3, Vec3>>& chords);

/**
 * Trace one wedge: the visible t-intervals of the generator, mapped to 3D
 * segments on the receiver's plane (not yet clipped to the receiver). Returns
 * false when the wedge was culled before the visibility test. All conditions
 * on t except blocking are linear in t; blocking chords map to t-intervals
 * by central projection from the apex.
 */
bool TraceWedge(const PairContext& ctx, const Wedge& w, std::vector<std::pair<Vec3, Vec3>>& out);

} // namespace detail
} // namespace penumbra

#endif
