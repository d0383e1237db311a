// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSliverRepair.h
 * @brief Repair of sample-mesh slivers that projection turned clockwise.
 *
 * A sampler triangulates each receiver in its own plane with exact
 * predicates, so its triangles are counter-clockwise there. A consumer that
 * lifts the points to 3D and projects them into another frame rounds twice;
 * a triangle whose apex lies within rounding of its longest edge can then
 * come out with zero or negative area. Such a sliver covers no area: it is
 * removed and its apex is inserted into the edge instead (the neighbour
 * across the edge is split in two; on the outline the sliver is dropped).
 * A constrained edge through the apex is split with it.
 */
#ifndef penumbraSliverRepair_h
#define penumbraSliverRepair_h

#include "penumbraReconstructionModule.h" // for export macro
#include "penumbraReconstruction.h" // SampleMesh

#include <vector>

namespace penumbra
{

/// What RepairSlivers changed.
struct SliverRepairResult
{
  int Split = 0;      ///< slivers merged into the neighbour across their longest edge
  int Dropped = 0;    ///< slivers on the mesh's outline removed
  int Unrepaired = 0; ///< slivers left as they were (apex not inside the edge)
  /// New id of every input triangle, -1 for a dropped one.
  std::vector<int> TriangleMap;
  /// For every constrained edge of the repaired mesh, the input edge it is
  /// (part of); pieces of a split edge are appended after the input edges.
  std::vector<int> EdgeOrigin;

  int GetNumberOfRepairs() const { return this->Split + this->Dropped; }
};

/**
 * Remove the triangles of @p mesh with zero or negative area whose apex lies
 * strictly inside their longest edge, as described in the file comment; the
 * points and their values do not change. Triangles that cannot be repaired
 * this way are left in place (Reconstruction::Build then rejects them).
 */
PENUMBRARECONSTRUCTION_EXPORT SliverRepairResult RepairSlivers(SampleMesh& mesh);

} // namespace penumbra

#endif
