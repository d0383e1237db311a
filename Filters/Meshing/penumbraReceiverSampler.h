// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverSampler.h
 * @brief The refinement passes of SampleReceiver on one receiver: build the
 * interpolant (around the last insertions only, when that is enough), probe
 * the candidates, score them against the tolerance, insert the failing ones
 * by decreasing score. Private to Penumbra::Meshing.
 *
 * Members are defined in penumbraReceiverSampler.cxx (passes, interpolant,
 * insertions) and penumbraCandidateProbes.cxx (candidates and residuals).
 * Design notes: Documentation/design/sampling.md
 */
#ifndef penumbraReceiverSampler_h
#define penumbraReceiverSampler_h

#include "penumbraAdaptiveSampler.h"
#include "penumbraCandidateProbes.h"
#include "penumbraReconstruction.h"
#include "penumbraSamplingReceiver.h"

#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace penumbra
{
namespace detail
{

/// An insertion request of one pass.
struct Request
{
  double Score = 0.0;
  int Order = 0;          // creation order (tie break)
  bool Edge = false;
  int A = -1, B = -1;     // edge vertex ids, or the hint vertex of a centroid
  double U = 0.0, V = 0.0;
  bool Constrained = false;
  double FeatureSize = HUGE_VAL; // feature size the new vertex inherits
  std::vector<const CandidateValue*> Values; // the new point's samples
};

/**
 * Adaptive sampling of one receiver (SampleReceiver without its argument
 * checks and timing): Run refines pass after pass and fills the result.
 */
class ReceiverSampler
{
public:
  ReceiverSampler(const ReceiverMesh& mesh, const RadianceBatchFunction& evaluate,
    const AdaptiveSamplingSettings& settings, AdaptiveSamplingResult& result);

  /// Sample the receiver: initial mesh, refinement passes, final state.
  void Run();

private:
  // The candidates and residuals a triangle keeps from one pass to the next.
  struct TriangleState
  {
    std::array<CandidateValue*, 4> Candidates;
    std::array<RGB, 4> Residuals;
  };
  using CandidateMap = std::unordered_map<CandidateKey, CandidateValue, CandidateKeyHash>;

  // penumbraReceiverSampler.cxx
  void Initialize();
  void ComputeFloors();
  bool Pass(int pass);
  bool MarkRescoredTriangles(int nt);
  void BuildLocalInterpolant(int nt);
  void UpdateTolerance();
  std::vector<Request> CollectRequests(int nt, bool canInsert, int& failing);
  void AddOtherSides(std::vector<Request>& requests);
  void StopConverged(int nt, bool canInsert, int current);
  int InsertRequests(std::vector<Request>& requests, int nt, int current);
  void KeepProbes(int nt);

  // penumbraCandidateProbes.cxx
  CandidateKey KeyOf(int t) const;
  void ProbeCandidates(int nt);
  void ScoreCandidates(int nt);
  void ForgetStaleCandidates();

  const ReceiverMesh& Mesh;
  const RadianceBatchFunction& Evaluate;
  const AdaptiveSamplingSettings& Settings;
  AdaptiveSamplingResult& Result;
  AdaptiveSamplingStatistics& Stats;
  Receiver Rec;
  // Refinement floors (see ComputeFloors).
  double MinimumSize = 0.0;
  double MaximumLength = 0.0;
  double MinimumWidth = 0.0;
  double RoundingWidth = 0.0;
  // Candidate 0 is the centroid, 1..3 the edge midpoints.
  int FirstCandidate = 1;
  CandidateMap Cache;
  Reconstruction Interpolant;
  ReconstructionOptions PassInterpolant;
  // Per triangle: its four candidates (centroid, edges 0..2), their scores
  // and residuals.
  std::vector<std::array<CandidateValue*, 4>> Candidates;
  std::vector<std::array<double, 4>> Scores;
  std::vector<std::array<RGB, 4>> Residuals;
  RGB Tolerance;
  std::unordered_map<CandidateKey, TriangleState, CandidateKeyHash> Previous;
  std::vector<int> NewVertices;
  std::vector<int> Hops;        // per vertex: rings from the nearest new vertex (capped)
  std::vector<int> SubTriangle; // per triangle: index in the built mesh, or -1
  std::vector<char> Scored;     // per triangle: scored this pass
};

} // namespace detail
} // namespace penumbra

#endif
