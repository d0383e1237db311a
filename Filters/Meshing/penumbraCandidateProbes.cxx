// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCandidateProbes.cxx
 * @brief Candidate probing of the adaptive sampler: the candidates of each
 * triangle (cached across passes, new ones evaluated in one batch), their
 * residuals against the interpolant and their scores against the
 * tolerance.
 */
#include "penumbraCandidateProbes.h"

#include "penumbraReceiverSampler.h"
#include "penumbraTimer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>

namespace penumbra
{
namespace detail
{

//------------------------------------------------------------------------------
bool CandidateKey::operator==(const CandidateKey& o) const
{
  return this->A == o.A && this->B == o.B && this->C == o.C;
}

std::size_t CandidateKeyHash::operator()(const CandidateKey& k) const
{
  std::size_t h = static_cast<std::size_t>(k.A) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::size_t>(k.B) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
  h ^= static_cast<std::size_t>(static_cast<long long>(k.C)) + 0x94D049BB133111EBull + (h << 6) +
    (h >> 2);
  return h;
}

//------------------------------------------------------------------------------
// The key of triangle t's centroid, which identifies the triangle.
CandidateKey ReceiverSampler::KeyOf(int t) const
{
  const Receiver& rec = this->Rec;
  const auto& tri = rec.Snap.Triangles[t];
  int v[3] = { rec.Snap.PointVertex[tri[0]], rec.Snap.PointVertex[tri[1]],
    rec.Snap.PointVertex[tri[2]] };
  std::sort(v, v + 3);
  return CandidateKey{ v[0], v[1], v[2] }; // the key of its centroid
}

//------------------------------------------------------------------------------
void ReceiverSampler::ProbeCandidates(int nt)
{
  const Receiver& rec = this->Rec;
  AdaptiveSamplingStatistics& stats = this->Stats;
  CandidateMap& cache = this->Cache;
  std::vector<std::array<CandidateValue*, 4>>& candidates = this->Candidates;
  std::vector<std::array<RGB, 4>>& residuals = this->Residuals;
  std::vector<char>& scored = this->Scored;
  auto& previous = this->Previous;
  const int firstCandidate = this->FirstCandidate;
  // Candidates: cached values of unchanged elements, new ones evaluated in
  // one batch.
  for (auto& entry : cache)
  {
    entry.second.Used = false;
  }
  candidates.assign(nt, { nullptr, nullptr, nullptr, nullptr });
  residuals.assign(nt, {});
  std::vector<Vec3> newPoints;
  std::vector<CandidateValue*> newEntries;
  for (int t = 0; t < nt; ++t)
  {
    if (!scored[t])
    {
      const TriangleState& state = previous.find(this->KeyOf(t))->second;
      candidates[t] = state.Candidates;
      residuals[t] = state.Residuals;
      for (int c = firstCandidate; c < 4; ++c)
      {
        candidates[t][c]->Used = true;
      }
      continue;
    }
    const auto& tri = rec.Snap.Triangles[t];
    const int v[3] = { rec.Snap.PointVertex[tri[0]], rec.Snap.PointVertex[tri[1]],
      rec.Snap.PointVertex[tri[2]] };
    for (int c = firstCandidate; c < 4; ++c)
    {
      CandidateKey key;
      P2 at;
      bool sided = false;
      if (c == 0)
      {
        int s[3] = { v[0], v[1], v[2] };
        std::sort(s, s + 3);
        key = { s[0], s[1], s[2] };
        const P2 a = rec.Vertex(v[0]), b = rec.Vertex(v[1]), d = rec.Vertex(v[2]);
        at = { (a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0 };
      }
      else
      {
        const int k = c - 1, a = v[k], b = v[(k + 1) % 3];
        const int segment = rec.Snap.TriangleSegments[t][k];
        sided = segment >= 0 && rec.Snap.Segments[segment].Order <= 0;
        // The triangle is on the left of a -> b (counter-clockwise).
        key = { std::min(a, b), std::max(a, b), sided ? (a < b ? -2 : -3) : -1 };
        const P2 pa = rec.Vertex(a), pb = rec.Vertex(b);
        at = { 0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]) };
      }
      CandidateValue& entry = cache[key];
      entry.Used = true;
      candidates[t][c] = &entry;
      if (!entry.Evaluated)
      {
        entry.Evaluated = true;
        Vec3 x = rec.F.To3D(at[0], at[1]);
        if (sided)
        {
          double du, dv, distance;
          rec.SideDirection(t, at, du, dv, distance);
          entry.Du = du;
          entry.Dv = dv;
          entry.Sided = true;
          x += distance * (du * rec.F.U + dv * rec.F.V);
        }
        newPoints.push_back(x);
        newEntries.push_back(&entry);
      }
    }
  }
  if (!newPoints.empty())
  {
    std::vector<RGB> values(newPoints.size());
    const auto evalStart = std::chrono::steady_clock::now();
    this->Evaluate(newPoints.data(), static_cast<int>(newPoints.size()), values.data());
    stats.EvaluationSeconds += Seconds(evalStart);
    stats.Evaluations += static_cast<long long>(newPoints.size());
    for (std::size_t k = 0; k < newEntries.size(); ++k)
    {
      newEntries[k]->Value = values[k];
    }
  }
}

//------------------------------------------------------------------------------
void ReceiverSampler::ScoreCandidates(int nt)
{
  std::vector<std::array<CandidateValue*, 4>>& candidates = this->Candidates;
  std::vector<std::array<double, 4>>& scores = this->Scores;
  std::vector<std::array<RGB, 4>>& residuals = this->Residuals;
  std::vector<char>& scored = this->Scored;
  std::vector<int>& subTriangle = this->SubTriangle;
  const int firstCandidate = this->FirstCandidate;
  const RGB& tolerance = this->Tolerance;
  // Residuals against the interpolant, scores = max over channels of
  // |residual| / tolerance.
  scores.assign(nt, { 0.0, 0.0, 0.0, 0.0 });
  const double tol[3] = { tolerance.R, tolerance.G, tolerance.B };
  static const double bary[4][3] = { { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 }, { 0.5, 0.5, 0.0 },
    { 0.0, 0.5, 0.5 }, { 0.5, 0.0, 0.5 } };
  for (int t = 0; t < nt; ++t)
  {
    for (int c = firstCandidate; c < 4; ++c)
    {
      if (scored[t])
      {
        double value[3];
        this->Interpolant.Evaluate(subTriangle[t], bary[c], value);
        const RGB& exact = candidates[t][c]->Value;
        residuals[t][c] = RGB(exact.R - value[0], exact.G - value[1], exact.B - value[2]);
      }
      const RGB& r = residuals[t][c];
      double score = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const double a = std::abs(Channel(r, k));
        score = std::max(score, tol[k] > 0.0 ? a / tol[k] : (a > 0.0 ? HUGE_VAL : 0.0));
      }
      scores[t][c] = score;
    }
  }
}

//------------------------------------------------------------------------------
// Forget candidates of elements that no longer exist.
void ReceiverSampler::ForgetStaleCandidates()
{
  CandidateMap& cache = this->Cache;
  for (auto it = cache.begin(); it != cache.end();)
  {
    it = it->second.Used ? std::next(it) : cache.erase(it);
  }
}

} // namespace detail
} // namespace penumbra
