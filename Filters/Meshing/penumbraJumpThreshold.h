// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraJumpThreshold.h
 * @brief The importance of a shadow boundary for DiscontinuityMeshSettings::
 * JumpThreshold: its estimated radiance jump Ls min(F_occluder, F_shooter)
 * relative to the receiver's largest unoccluded direct radiance, and the
 * bound that skips whole wedges which cannot reach the threshold. Private.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraJumpThreshold_h
#define penumbraJumpThreshold_h

#include "penumbraConstraintMerging.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraSceneTopology.h"

#include <cstddef>
#include <vector>

namespace penumbra
{
namespace detail
{

/// The radiance (mean of RGB) of a shooter used by the jump threshold.
double JumpRadiance(const Scene& scene, const DiscontinuityMeshSettings& settings, int shooter);

/// The jump below which shadows on receiver `receiverId` are dropped:
/// JumpThreshold times the largest unoccluded direct radiance over the
/// receiver from `shooters` (infinite when that is 0); -1 without threshold.
double MinimumJump(const SceneTopology& topology, const Scene& scene, int receiverId,
  const std::vector<int>& shooters, const DiscontinuityMeshSettings& settings);

/// Remove from segments[first, end) the shadow boundaries whose estimated
/// jump at their midpoint is below `minimumJump` (nothing when it is < 0).
void DropFaintShadows(const SceneTopology& topology, const Scene& scene, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame, double minimumJump,
  std::size_t first, std::vector<Segment2>& segments);

/// An upper bound of the form factor from any point of `receiver` (of
/// radius `receiverRadius` about its centroid) to polygon p: c A / (pi d^2),
/// at most 1, with d the distance between the two (bounded below by their
/// centres' distance minus their radii) and c the largest cosine at the
/// receiver's normal over the directions towards p, times the largest at p's
/// normal when p emits from its front only (a shooter; not an occluder).
double FormFactorBound(const PolygonData& p, const PolygonData& receiver, double receiverRadius,
  bool emitsFromFront);

} // namespace detail
} // namespace penumbra

#endif
