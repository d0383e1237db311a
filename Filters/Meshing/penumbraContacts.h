// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraContacts.h
 * @brief Contacts on a receiver: edges of other polygons lying in its plane
 * give order-0 lines, and the footprints of solids standing on it (closed
 * apart from the edges they stand on) are marked for removal. Private.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraContacts_h
#define penumbraContacts_h

#include "penumbraConstraintMerging.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraSceneTopology.h"

#include <vector>

namespace penumbra
{
class OccluderSet;

namespace detail
{

/// The polygons (sorted ids, the receiver left out) that may meet the slab
/// of points at signed distances [nearDistance, farDistance] from receiver
/// `receiverId`'s plane (along its normal), over its bounding box widened by
/// `margin`.
std::vector<int> PolygonsNearPlane(const SceneTopology& topology, const OccluderSet& occluders,
  int receiverId, double nearDistance, double farDistance, double margin);

/// Append receiver `receiverId`'s contact lines (Order 0) and the outlines
/// of the footprints of solids standing on it (Order 0, Removal) to `out`.
void AddContacts(const SceneTopology& topology, const OccluderSet& occluders, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats);

} // namespace detail
} // namespace penumbra

#endif
