// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraGroupShot.h
 * @brief Group shots (private): the fast method over the pieces of several
 * shooters at once, one hierarchy over all their leaves, members facing one
 * way or, across orientations, several; also the hierarchy of the recorded
 * transport, whose leaves carry their corners' barycentric coordinates
 * (Documentation/design/transport.md, "Group shots").
 */
#ifndef penumbraGroupShot_h
#define penumbraGroupShot_h

#include "penumbraShot.h"
#include "penumbraVector.h"

#include <array>
#include <functional>
#include <vector>

namespace penumbra
{

struct Scene;
struct SampleSet;

/// The weakest members have this fraction of the shooter's power (SelectGroup).
constexpr double GroupPowerFraction = 0.1;

/// Most leaves split to the leaf size (PrepareGroupShot); beyond, the
/// sample triangles themselves are the leaves.
constexpr double MaximumGroupLeaves = 250000.0;

/**
 * The members of a group shot led by surface `j`: j, then in id order every
 * other surface with triangles and positive unshot power that `weak`
 * accepts (its power calls for the fast method) and that faces j's way, or
 * with `acrossOrientations` also has at least GroupPowerFraction of j's
 * power.
 */
std::vector<int> SelectGroup(const SampleSet& samples, int j, bool acrossOrientations,
  const std::function<bool(double power)>& weak);

/**
 * A fast shot of the surfaces `members` at once: one hierarchy over all
 * their leaves (split to `leafSize` times each one's diameter, unless that
 * makes more than MaximumGroupLeaves), so that a far cluster of them costs
 * one expansion and one ray. With `basis` (the recorded transport): every
 * triangle with an area, the hierarchy built on the current unshot
 * radiance (power-weighted centroids), and each leaf's corners'
 * barycentric coordinates in its triangle returned in `basis` and left as
 * its Values.
 */
void PrepareGroupShot(const SampleSet& samples, const std::vector<int>& members,
  double openingAngle, double leafSize, Shot& shot,
  std::vector<std::array<RGB, 3>>* basis = nullptr);

/// The leaf with the unshot radiance of its triangle's corners, from its
/// corners' barycentric coordinates `basis` in that triangle.
Leaf Reweighted(
  const SampleSet& samples, const Leaf& leaf, const std::array<RGB, 3>& basis, const Vec3& origin);

/**
 * Whether a group shot (of one orientation) may light surface `receiver`:
 * some vertex of it is in front of the lowest shooter plane, and some
 * vertex of a member in front of the receiver's plane (conservative, and
 * cheap next to every sample or leaf).
 */
bool GroupMayReach(const Scene& scene, const SampleSet& samples, const Shot& shot, int receiver);

} // namespace penumbra

#endif
