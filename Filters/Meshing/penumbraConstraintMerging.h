// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraConstraintMerging.h
 * @brief The boundary segments of one receiver, in its 2D frame, and their
 * merging into the constraints of its triangulation: end points closer than
 * the snapping distance become one point, collinear overlapping pieces become
 * one line split at every end point lying on it, each piece labelled with the
 * lowest order of the segments covering it. Private (not installed).
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraConstraintMerging_h
#define penumbraConstraintMerging_h

#include "penumbraReceiverFrame.h"
#include "penumbraReceiverTriangulation.h"

#include <vector>

namespace penumbra
{
namespace detail
{

/// A boundary segment in the receiver's frame before merging.
struct Segment2
{
  P2 A;
  P2 B;
  int Order = 2;
  int SourceId = -1;
  bool Outline = false;
  bool Removal = false;
  int OccluderA = -1; ///< polygons used by the jump estimate
  int OccluderB = -1;
  int Priority() const { return this->Outline ? 0 : (this->Removal ? 1 : 2); }
};

/**
 * Snap and merge the receiver's segments into non-overlapping constraints:
 * 1. end points closer than `tol` become one point (outline vertices win,
 *    then footprint vertices, so the outline stays bit-exact);
 * 2. collinear segments (within tol) form one line; along it the pieces
 *    between consecutive end points (including end points of other lines
 *    lying on it: T-junctions) get the lowest order of the segments covering
 *    them, and the outline / footprint flags of any of them.
 * Crossings in the interior of two lines are left to the exact CDT. Pieces
 * shorter than `minLength` are dropped unless they are outline or footprint
 * pieces.
 */
std::vector<Constraint2D> MergeSegments(
  std::vector<Segment2> segments, double tol, double minLength);

} // namespace detail
} // namespace penumbra

#endif
