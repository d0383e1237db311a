// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraResampler.h
 * @brief The state of one Reconstruction::Resample call, shared by the
 * display's level choice (penumbraDisplayLevels.cxx: how many pieces each
 * edge gets) and its subdivision (penumbraResampling.cxx).
 */
#ifndef penumbraResampler_h
#define penumbraResampler_h

#include "penumbraReconstructionInternals.h"
#include "penumbraErrorModel.h"

#include <array>
#include <vector>

namespace penumbra
{

/**
 * One Resample call: the output under construction, the points already
 * created (input points, edge points) so that shared edges are shared, and
 * the current triangle's lattice and error contributions.
 */
class Reconstruction::Internals::Resampler
{
public:
  Resampler(const Internals& in, const ResampleOptions& options,
    const ErrorEstimateOptions& errorOptions, ResampledMesh& output)
    : In(in)
    , Options(options)
    , ErrorOptions(errorOptions)
    , Output(output)
    , NC(in.NC)
    , Estimate(options.ComputeErrorEstimate)
    , Cubic(in.Options.Mode == ReconstructionMode::CloughTocher)
  {
  }

  /// Per triangle and channel, filled by the caller before Run when
  /// estimating: the probe bounds and model scales of CalibrateWithProbes,
  /// or the per-triangle bounds with PerTriangle.
  std::vector<double> ProbeBounds, ModelScale, TriangleBounds;
  /// Per channel, the compact display's tolerance (value units), set by the
  /// caller before Run; empty: the dense display.
  std::vector<double> CompactTolerances;
  /// After Run with the compact base: the midpoints of the edges left
  /// whole, as test points for the merging ((u, v), NC values of the
  /// interpolant, an output triangle holding each).
  std::vector<double> LeftOutPoints, LeftOutValues;
  std::vector<int> LeftOutTriangles;

  void Run();

private:
  // Output points of the current triangle with their barycentrics in it,
  // for the error estimate.
  struct Contribution
  {
    int Id;
    double B[3];
  };

  void CountSegments();
  void ChooseCompactEdges();
  void SubdivideGreen(const int n[3]);
  void KeepLeftOut(int firstTriangle);
  void ChooseAdaptiveLevels();
  void CountEdgesFromLevels();
  double Deviation(int t, int n);
  double PieceDeviation(int t, const double (&b)[3][3], const std::array<const double*, 3>& p);
  bool RaiseFailingLevels();
  int InnerLevel(int t, const int n[3], bool& regular) const;
  void Reserve();
  int NewPoint(int t, const double b[3], int source);
  int EdgePoint(int t, int k, int i, int n);
  int LatticeIndex(int a, int b) const { return a * (this->S + 1) - a * (a - 1) / 2 + b; }
  int LatticePoint(int a, int b);
  void AddTriangle(int p0, int p1, int p2);
  void SubdivideTriangle(int t);
  void SubdivideRegular();
  void SubdivideIrregular(const int n[3]);
  void Zip(int k, int nk);
  void SpreadErrors();
  void TraceLines();

  const Internals& In;
  const ResampleOptions& Options;
  const ErrorEstimateOptions& ErrorOptions;
  ResampledMesh& Output;
  const int NC;
  const bool Estimate;
  const bool Cubic;
  // Segments per unique edge; with DisplayTolerance the level each triangle
  // needs (empty otherwise); output ids of input points and of edge points
  // (first id of each edge).
  std::vector<int> Segments;
  std::vector<int> Needed;
  // Compact base: the interpolant at each edge's midpoint (NC per edge), and
  // whether an edge left whole has its test point yet.
  bool Green = false;
  std::vector<double> MidValues;
  std::vector<char> LeftOutDone;
  std::vector<int> PointId;
  std::vector<int> EdgeFirst;
  std::vector<Net> Nets;
  std::vector<double> Value, Error;
  // Adaptive levels: 1 / tolerance per channel (0: channel ignored), and the
  // interpolant on the lattice being tested.
  std::vector<double> InverseTolerance;
  std::vector<double> LatticeValues;
  std::vector<Contribution> Contributions;
  // The current triangle, its lattice level and lattice point ids.
  int T = -1;
  int S = 0;
  std::vector<int> Lattice;
};

} // namespace penumbra

#endif
