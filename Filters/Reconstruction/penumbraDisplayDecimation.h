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

#include <vector>

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
  /// Largest |removed value - display| over the points tested (removed
  /// points, and edge midpoints with TestEdgeMidpoints) and channels,
  /// relative to that channel's tolerance (at most 1).
  double LargestError = 0.0;
};

/// Settings of DecimateDisplay. Each channel's tolerance at a point is the
/// larger of Tolerance times the mesh's area-mean |value| of that channel and
/// AbsoluteTolerance's entry (limited by LocalFraction); both 0 leave the
/// mesh as it is.
struct DecimationOptions
{
  /// Tolerance relative to the mesh's area-mean |value|, per channel. [0],
  /// in [0, 1]
  double Tolerance = 0.0;
  /// Per channel, a tolerance in the units of the values (empty: none). [],
  /// each >= 0
  std::vector<double> AbsoluteTolerance;
  /// When > 0, AbsoluteTolerance applies at a point only up to this
  /// fraction of its own |value| (per channel), so that dark places keep
  /// what light they have; Tolerance's part is not limited. [0], >= 0
  double LocalFraction = 0.0;
  /// Also test the display between the input points: the midpoint of every
  /// input edge that is no feature keeps its input value (the mean of its
  /// ends') as a test point. Two piecewise-linear displays differ most at
  /// the points of either or where their edges cross; without these points
  /// only the former are tested, and a merged triangle whose edge crosses a
  /// fold of the input display can be off by many times the tolerance
  /// there. [false]
  bool TestEdgeMidpoints = false;
  /// Per line of the mesh (LineOffsets), a group: where two lines of the
  /// same group meet end to end in a straight run, and no other line ends
  /// there, the point between them may move along the run, and the two
  /// become one polyline, kept by the lower-numbered line (the other's
  /// is left empty). Empty: every line end stays. []
  std::vector<int> LineGroups;
  /// Further test points, held like removed points (e.g. points of a finer
  /// display that the mesh leaves out): (u, v) pairs, NumberOfChannels values
  /// each, and for each the mesh triangle that holds it. []
  std::vector<double> TestPoints;
  std::vector<double> TestValues;
  std::vector<int> TestTriangles;
};

/**
 * Remove points of `mesh` (in place: Points, Values, Triangles,
 * SourceTriangle, SourcePoint, ErrorEstimate and the line polylines are
 * updated; kept points keep their order) while the linear display over the
 * remaining triangles stays within each channel's tolerance (see
 * DecimationOptions) of every removed point's value. Throws InputError for
 * settings out of range or a LineGroups of the wrong size.
 */
PENUMBRARECONSTRUCTION_EXPORT DecimationStatistics DecimateDisplay(
  ResampledMesh& mesh, const DecimationOptions& options);

/// The same with Tolerance `tolerance` and nothing else (removed points
/// tested, every line end kept). Throws InputError for a tolerance outside
/// [0, 1].
PENUMBRARECONSTRUCTION_EXPORT DecimationStatistics DecimateDisplay(
  ResampledMesh& mesh, double tolerance);

} // namespace penumbra

#endif
