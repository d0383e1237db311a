// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShortEdges.h
 * @brief Merging of the points of a receiver mesh that rounding left too
 * close together. Private (not installed).
 *
 * Shadow boundaries that meet at one point in theory (the lines of several
 * lights through the foot of an occluder's edge) cross the exact
 * triangulation in a cluster of vertices a rounding error apart. Rounded to
 * doubles such triangles may turn clockwise, and a gradient fitted over
 * them divides a value difference by a rounding-error distance, which the
 * reconstruction spreads over every triangle around the point.
 */
#ifndef penumbraShortEdges_h
#define penumbraShortEdges_h

#include "penumbraDiscontinuityMesher.h"

#include <cstddef>
#include <vector>

namespace penumbra
{
namespace detail
{

/// What MergeShortEdges dropped.
struct MergeCounts
{
  std::size_t Collapsed = 0; ///< triangles with two corners merged
  std::size_t Inverted = 0;  ///< triangles not counter-clockwise (after merging)
};

/**
 * Merge the points of `mesh` joined by a triangle edge shorter than
 * `length` into one (a point of `keep`, such as the receiver's vertices,
 * when the group holds one; points across an order-0 line stay apart, as
 * no triangle joins them), drop the triangles that collapse or that are not
 * counter-clockwise about `normal` after it, and the segments and points
 * left without a triangle.
 */
MergeCounts MergeShortEdges(
  ReceiverMesh& mesh, const Vec3& normal, double length, const std::vector<Vec3>& keep);

} // namespace detail
} // namespace penumbra

#endif
