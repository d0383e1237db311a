// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraJumpThreshold.h
 * @brief The importance of a shadow boundary for DiscontinuityMeshSettings::
 * JumpThreshold: its estimated radiance jump Ls min(F_shooter, F_hidden)
 * relative to the receiver's largest unoccluded direct radiance, and the
 * bounds that skip whole wedges which cannot reach the threshold. Private.
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
class ExactEvaluator;

namespace detail
{

/// The radiance (mean of RGB) of a shooter used by the jump threshold.
double JumpRadiance(const Scene& scene, const DiscontinuityMeshSettings& settings, int shooter);

/// The jump below which shadows on receiver `receiverId` are dropped:
/// JumpThreshold times the largest direct radiance from `shooters` with
/// visibility (exact form factors) at sample points of the receiver (its
/// centroid, points near its vertices and halfway to them); infinite when
/// the receiver gets no unoccluded light; -1 without threshold. Not the
/// unoccluded radiance: a light hidden by a baffle would make the shadows
/// of the light the receiver does get look faint.
double MinimumJump(const SceneTopology& topology, const Scene& scene,
  const ExactEvaluator& evaluator, int receiverId, const std::vector<int>& shooters,
  const DiscontinuityMeshSettings& settings);

/// Remove from segments[first, end) the shadow boundaries whose estimated
/// jump at their midpoint, Ls min(F_S, HiddenFormFactor of each occluding
/// object), is below `minimumJump` (nothing when it is < 0).
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

/// An upper bound of the form factor of the part of `shooter` that an
/// object inside the sphere (`centre`, `radius`) can hide from a point at
/// distance `reach` from the centre whose normal is `receiverNormal`: the
/// sphere's projected solid angle over pi, (radius / reach)^2, and the
/// shooter's form factor over rays at least reach - radius + gap long (gap:
/// between the sphere and the shooter's bounding sphere) whose directions
/// lie in the cone between the two spheres, which bounds both cosines. It
/// is the object's, not one face's: a face seen edge-on may bound a large
/// object's shadow. 1 when the point is inside the sphere.
double HiddenFormFactor(const PolygonData& shooter, const Vec3& centre, double radius,
  const Vec3& receiverNormal, double reach);

/// HiddenFormFactor bounded over every point of `receiver`'s plane (whose
/// distance from the centre is at least the centre's height over it).
/// Unlike FormFactorBound it stays tight for receivers much larger than the
/// distances involved (a floor under many lights).
double HiddenFormFactorBound(const PolygonData& shooter, const Vec3& centre, double radius,
  const PolygonData& receiver);

} // namespace detail
} // namespace penumbra

#endif
