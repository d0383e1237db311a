// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCovers.h
 * @brief Covers on a receiver: polygons lying close in front of it, with a
 * gap small next to their width (a fixture hung a few millimetres below a
 * ceiling, a cabinet's back a centimetre from a wall, two books side by
 * side). Light reaches the receiver under a cover only through the gap, so
 * the interreflected light falls steeply inside its outline, where the
 * direct light alone would place no sample (an unlit ceiling, an umbra).
 * The cover's outline projected onto the receiver and loops inset from it
 * at the gap, 4 times the gap, ... become lines of order 1, whose points
 * carry that fall: as the gap closes it becomes a jump, so the
 * reconstruction fits each side on its own (a kink, not a smooth
 * crossing, which overshoots far from so steep a fall). Private.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraCovers_h
#define penumbraCovers_h

#include "penumbraConstraintMerging.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraSceneTopology.h"

#include <vector>

namespace penumbra
{
class OccluderSet;

namespace detail
{

/// A polygon covers a receiver when all its vertices lie in front of it,
/// none farther than this fraction of the width of the pocket (the part of
/// the polygon over the receiver; the width is its smallest extent across
/// an edge).
constexpr double kCoverGapRatio = 0.1;

/// Append receiver `receiverId`'s cover lines (order 1, no source) to `out`.
void AddCovers(const SceneTopology& topology, const OccluderSet& occluders, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats);

} // namespace detail
} // namespace penumbra

#endif
