// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDisplayDecimation.h
 * @brief Compact display: merge a resampled receiver's output triangles
 * wherever the linear display stays within a tolerance of the values it
 * replaces.
 *
 * The display resampling cuts every sample triangle into pieces so that the
 * linear display follows the cubic interpolant; where the interpolant is
 * nearly linear over many of them (most of a smoothly lit wall), the pieces
 * carry nothing. DecimateDisplay removes output points by half-edge
 * collapses, cheapest first, while every removed point's value stays within
 * the tolerance of the display that replaces it, per channel. The outline,
 * the discontinuity lines and the surface's holes keep their shape: points
 * on them move only along straight runs of them, into a neighbour on the
 * same run. No triangle is flipped or made degenerate, and the mesh stays
 * conforming (no T-junction). See Documentation/design/reconstruction.md,
 * "Compact display".
 */
#ifndef penumbraDisplayDecimation_h
#define penumbraDisplayDecimation_h

#include "penumbraReconstructionModule.h" // for export macro

namespace penumbra
{

struct ResampledMesh;

/// What DecimateDisplay did.
struct DecimationStatistics
{
  int PointsBefore = 0;
  int PointsAfter = 0;
  int TrianglesBefore = 0;
  int TrianglesAfter = 0;
  /// Largest |removed value - display| over removed points and channels,
  /// relative to that channel's tolerance (at most 1).
  double LargestError = 0.0;
};

/**
 * Remove points of `mesh` (in place: Points, Values, Triangles,
 * SourceTriangle, SourcePoint, ErrorEstimate and the line polylines are
 * updated; kept points keep their order) while the linear display over the
 * remaining triangles stays within `tolerance` times the mesh's area-mean
 * |value| of every removed point's value, per channel. `tolerance` 0 leaves
 * the mesh as it is. Throws InputError for a tolerance outside [0, 1].
 */
PENUMBRARECONSTRUCTION_EXPORT DecimationStatistics DecimateDisplay(
  ResampledMesh& mesh, double tolerance);

} // namespace penumbra

#endif
