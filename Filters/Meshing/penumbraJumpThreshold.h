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

/// An upper bound, over every point of `receiver`, of the form factor of the
/// part of `shooter` that an occluder inside the sphere (`occluderCentre`,
/// `occluderRadius`) hides: the largest jump (over Ls) its shadow
/// boundaries can carry. Every hidden ray runs from the receiver's plane
/// through the occluder's sphere to the shooter, so its length is at least
/// the sphere's height above the plane plus the gap between the sphere and
/// the shooter's, its direction lies in the cone between the two spheres
/// (which bounds both cosines), and its solid angle is within the sphere's
/// as seen from the plane. The sphere is the whole connected object's (a
/// finely triangulated object hides as much as one big polygon would).
/// Unlike FormFactorBound it stays tight for receivers much larger than the
/// distances involved (a floor under many lights). 1 when the sphere
/// reaches the receiver's plane.
double HiddenFormFactorBound(const PolygonData& shooter, const Vec3& occluderCentre,
  double occluderRadius, const PolygonData& receiver);

} // namespace detail
} // namespace penumbra

#endif
