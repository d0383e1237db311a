// SPDX-License-Identifier: GPL-3.0-or-later
// Secondary shadows of fast single shots: which receivers to evaluate by the
// exact method, and that evaluation (Documentation/design/transport.md,
// "Secondary shadows").
#include "penumbraProgressiveShooterInternals.h"

#include "penumbraExactShot.h"
#include "penumbraMath.h"
#include "penumbraShadowRays.h"
#include "penumbraShooterCoarsening.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace penumbra
{

namespace
{

/**
 * Secondary shadows: a fast single shot evaluates a receiver by the exact
 * method instead when occluders stand between them (AnyRayBlocked) and the shot brings at
 * least this share of the receiver's reflected light (there the fast
 * method's visibility per node of the shooter's hierarchy would show as
 * blocky shadows: a floor lit only by a half-lit panel over a baffle was
 * 127% RMS off), within ExactPairBudget.
 */
constexpr double SecondaryShadowShare = 0.05;
/// Largest (shooter triangle, receiving point) pairs that one shot
/// evaluates exactly for secondary shadows: about half a second on 2 cores.
constexpr double ExactPairBudget = 2e6;
/// ... and for the receiver with the largest share alone, this many, when
/// that share is at least DominatedShare.
constexpr double LargestShareBudget = 8.0 * ExactPairBudget;
constexpr double DominatedShare = 0.5;
// The shooter's radiance for these receivers is merged to fewer triangles
// within this fraction of its area-mean value: the default sampling
// tolerance, to which its samples were placed. Measured (Cornell box, half-lit
// panel; Documentation/design/transport.md): half the shooter triangles (1.4
// to 2.8 times fewer), the same accuracy; 1e-2 doubles the panel floor's error.
constexpr double ShooterCoarseningTolerance = 2e-3;

} // namespace

/**
 * The receivers (indices into `receivers`) of a fast shot of `shooter` to
 * evaluate exactly for their secondary shadows (SecondaryShadowShare),
 * largest share first within ExactPairBudget. The share of a receiver of
 * reflectance rho: rho P / (R + rho P), P the power the shot brings it (by
 * the fast method's `irradiance`, or without it by the form factor of two
 * discs about the centroids, as a first guess), R its reflected power.
 */
std::vector<int> ProgressiveShooter::Internals::SecondaryShadowReceivers(
  int shooter, const std::vector<Receiver>& receivers, const std::vector<RGB>* irradiance)
{
  std::vector<int> chosen;
  const SurfaceSamples& source = this->Samples.Surfaces[shooter];
  std::size_t triangles = 0;
  for (const std::array<int, 3>& tri : source.Triangles)
  {
    triangles += (source.Unshot[tri[0]].IsZero() && source.Unshot[tri[1]].IsZero() &&
                   source.Unshot[tri[2]].IsZero())
      ? 0
      : 1;
  }
  if (triangles == 0)
  {
    return chosen;
  }
  const PreparedPolygon& from = this->Samples.Polygon(shooter);
  const double power = this->Samples.UnshotPower[shooter].Mean();
  std::vector<std::pair<double, int>> shares;
  std::vector<RGB> e;
  for (std::size_t r = 0; r < receivers.size(); ++r)
  {
    const int i = receivers[r].Id;
    const SurfaceSamples& s = this->Samples.Surfaces[i];
    const double rho = this->SceneCopy.Surfaces[i].Reflectance.Mean();
    if (rho <= 0.0 || s.Uniform || s.LinearPower || receivers[r].Candidates.empty())
    {
      continue; // (the candidates: FindReceivers' shaft query for this single shot)
    }
    double received;
    if (irradiance)
    {
      const std::size_t count = this->Samples.EvaluationPoints[i].size();
      e.assign(irradiance->begin() + static_cast<std::ptrdiff_t>(receivers[r].First),
        irradiance->begin() + static_cast<std::ptrdiff_t>(receivers[r].First + count));
      received = this->Samples.Integral(i, e).Mean();
    }
    else
    {
      received = power * DiscTransferFraction(from, this->Samples.Polygon(i));
    }
    const double added = rho * received;
    const RGB reflected = this->Samples.ReflectedPower(i, this->SceneCopy.Surfaces[i].Emission);
    const double share = added / (reflected.Mean() + added);
    // The share first: the rays cost more.
    if (share >= SecondaryShadowShare && AnyRayBlocked(this->Samples, this->Caster(), shooter, i))
    {
      shares.emplace_back(share, static_cast<int>(r));
    }
  }
  std::sort(shares.begin(), shares.end(),
    [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
  double cost = 0.0;
  for (const auto& entry : shares)
  {
    const double pairs = static_cast<double>(triangles) *
      static_cast<double>(this->Samples.EvaluationPoints[receivers[entry.second].Id].size());
    // A receiver whose light comes mostly from this shot is taken within a
    // larger budget: finer samples on both sides must not drop it back to
    // the fast method's blocky shadows (where its light is mostly from
    // elsewhere, those would show much less).
    const double budget = chosen.empty() && entry.first >= DominatedShare ? LargestShareBudget
                                                                           : ExactPairBudget;
    if (cost + pairs <= budget)
    {
      cost += pairs;
      chosen.push_back(entry.second);
    }
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

/// Overwrite the irradiance of the receivers `which` (indices into
/// `receivers`, with their shaft candidates) with the exact shot of `shooter`.
void ProgressiveShooter::Internals::ExactReceivers(const std::vector<Receiver>& receivers,
  const std::vector<int>& which, int shooter, std::vector<RGB>& irradiance)
{
  Shot shot;
  PrepareShot(this->Samples, shooter, ShotMethod::Exact, this->Settings.OpeningAngle,
    this->Settings.LeafSize, shot);
  // The shooter's mesh is as fine as its own light needed; its shadows on
  // these receivers cost its triangles times their points.
  shot.Radiance = CoarsenShooterRadiance(
    shot.Radiance, this->Samples.Surfaces[shooter].Creases, ShooterCoarseningTolerance);
  std::vector<Receiver> subset;
  std::size_t items = 0;
  for (const int r : which)
  {
    subset.push_back({ receivers[r].Id, items, receivers[r].Candidates });
    items += this->Samples.EvaluationPoints[receivers[r].Id].size();
  }
  std::vector<RGB> exact(items);
  this->PointIrradiance(shot, subset, exact);
  for (std::size_t k = 0; k < which.size(); ++k)
  {
    const std::size_t count = this->Samples.EvaluationPoints[subset[k].Id].size();
    std::copy(exact.begin() + static_cast<std::ptrdiff_t>(subset[k].First),
      exact.begin() + static_cast<std::ptrdiff_t>(subset[k].First + count),
      irradiance.begin() + static_cast<std::ptrdiff_t>(receivers[which[k]].First));
  }
}

} // namespace penumbra
