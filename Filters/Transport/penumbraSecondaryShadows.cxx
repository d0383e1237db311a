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
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace penumbra
{

namespace
{

/**
 * Secondary shadows: a fast single shot evaluates a receiver by the exact
 * method instead when occluders stand between them (AnyRayBlocked), the
 * shot brings at least this share of the receiver's reflected light, and
 * the fast method's shadows there are not accurate enough
 * (SecondaryShadowTolerance), within ExactPairBudget. The fast method's
 * visibility per node of the shooter's hierarchy shows as blocky shadows:
 * a floor lit only by a half-lit panel over a baffle was 127% RMS off.
 */
constexpr double SecondaryShadowShare = 0.05;
/**
 * The fast method's shadows suffice on a receiver when, at PilotPoints of
 * its points, the RMS difference between the radiance the shot adds by
 * the fast and by the exact method is at most this fraction of the
 * receiver's radiance. Measured (Documentation/design/transport.md,
 * "Secondary shadows"): the half-lit panel's floor (pilot difference
 * 150%) stays exact; on the Cornell box 0.01 keeps one pair (the back wall
 * onto a side of the short box: 1.2%) and spares the others (up to 0.9%):
 * every surface's RMS error within 0.21% of that with all of them exact,
 * in 2.5 s instead of 3.4 s; 0.02 spares that pair too, the back wall is
 * then shot only through the sweeps, and the ceiling's largest error rises
 * from 3% to 14%.
 */
constexpr double SecondaryShadowTolerance = 0.01;
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

/// Points of a receiver at which the fast method is compared with the
/// exact one (FastShadowsSuffice), spread over its evaluation points.
constexpr int PilotPoints = 32;

} // namespace

/// The exact shot of `shooter` for its secondary shadows: its radiance
/// merged to fewer triangles (ShooterCoarseningTolerance), as the shooter's
/// mesh is as fine as its own light needed.
static Shot SecondaryExactShot(const SampleSet& samples, int shooter, double openingAngle,
  double leafSize)
{
  Shot shot;
  PrepareShot(samples, shooter, ShotMethod::Exact, openingAngle, leafSize, shot);
  shot.Radiance = CoarsenShooterRadiance(
    shot.Radiance, samples.Surfaces[shooter].Creases, ShooterCoarseningTolerance);
  return shot;
}

/**
 * Whether the fast method's shadows on `receiver` are as accurate as the
 * exact method's where it matters: at PilotPoints of its points, spread
 * by area, the radiance that the shot adds by each method. The fast
 * method suffices when the RMS of their difference is within
 * SecondaryShadowTolerance of the receiver's radiance there (what it has
 * received so far plus this shot).
 */
bool ProgressiveShooter::Internals::FastShadowsSuffice(
  const Receiver& receiver, const Shot& fast, const Shot& exact)
{
  // Systematic sampling by the lumped weights: the refined parts of the
  // mesh get no more pilots than their area.
  const std::vector<double>& weights = this->Samples.LumpedWeights[receiver.Id];
  double area = 0.0;
  for (const double w : weights)
  {
    area += w;
  }
  std::vector<int> points;
  double cumulative = 0.0;
  int next = 0;
  for (std::size_t k = 0; k < weights.size() && next < PilotPoints; ++k)
  {
    cumulative += weights[k];
    if (cumulative >= (next + 0.5) / PilotPoints * area)
    {
      points.push_back(static_cast<int>(k));
      while (next < PilotPoints && cumulative >= (next + 0.5) / PilotPoints * area)
      {
        ++next;
      }
    }
  }
  if (points.empty())
  {
    return true;
  }
  const std::vector<RGB> exactIrradiance = this->PilotIrradiance(exact, receiver, points);
  const std::vector<RGB> fastIrradiance = this->PilotIrradiance(fast, receiver, points);
  const SurfaceSamples& s = this->Samples.Surfaces[receiver.Id];
  const double factor = this->SceneCopy.Surfaces[receiver.Id].Reflectance.Mean() / Pi;
  double level = 0.0;
  double squares = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    level += s.Total[points[k]].Mean() + factor * exactIrradiance[k].Mean();
    const double difference = factor * (fastIrradiance[k].Mean() - exactIrradiance[k].Mean());
    squares += difference * difference;
  }
  const double count = static_cast<double>(points.size());
  return std::sqrt(squares / count) <= SecondaryShadowTolerance * (level / count);
}

/**
 * The receivers (surface ids) of a fast single shot of `shooter` to
 * evaluate exactly for their secondary shadows: those to which the shot
 * brings at least SecondaryShadowShare of their reflected light, with
 * occluders between them (AnyRayBlocked), where the fast method's shadows
 * are not accurate enough (FastShadowsSuffice); largest share first within
 * ExactPairBudget. The share of a receiver of reflectance rho is
 * rho P / (R + rho P), P the power the shot brings it by the form factor
 * of two discs about the centroids, R its reflected power.
 */
std::vector<int> ProgressiveShooter::Internals::SecondaryShadowSurfaces(int shooter)
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
  Shot probe;
  probe.Empty = false;
  probe.Shooter = shooter;
  std::size_t items = 0;
  const std::vector<Receiver> receivers =
    this->FindReceivers(probe, std::vector<char>(this->Samples.Surfaces.size(), 0), false, items);
  const PreparedPolygon& from = this->Samples.Polygon(shooter);
  const double power = this->Samples.UnshotPower[shooter].Mean();
  std::vector<std::pair<double, int>> shares;
  for (std::size_t r = 0; r < receivers.size(); ++r)
  {
    const int i = receivers[r].Id;
    const SurfaceSamples& s = this->Samples.Surfaces[i];
    const double rho = this->SceneCopy.Surfaces[i].Reflectance.Mean();
    if (rho <= 0.0 || s.Uniform || s.LinearPower || receivers[r].Candidates.empty())
    {
      continue; // (the candidates: FindReceivers' shaft query for this single shot)
    }
    const double added = rho * power * DiscTransferFraction(from, this->Samples.Polygon(i));
    const RGB reflected = this->Samples.ReflectedPower(i, this->SceneCopy.Surfaces[i].Emission);
    const double share = added / (reflected.Mean() + added);
    // The share first: the rays cost more, the pilot points more still.
    if (share >= SecondaryShadowShare && AnyRayBlocked(this->Samples, this->Caster(), shooter, i))
    {
      shares.emplace_back(share, static_cast<int>(r));
    }
  }
  std::sort(shares.begin(), shares.end(),
    [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
  Shot exact;
  Shot fast;
  double cost = 0.0;
  for (const auto& entry : shares)
  {
    const Receiver& receiver = receivers[entry.second];
    const double pairs = static_cast<double>(triangles) *
      static_cast<double>(this->Samples.EvaluationPoints[receiver.Id].size());
    // A receiver whose light comes mostly from this shot is taken within a
    // larger budget: finer samples on both sides must not drop it back to
    // the fast method's blocky shadows (where its light is mostly from
    // elsewhere, those would show much less).
    const double budget = chosen.empty() && entry.first >= DominatedShare ? LargestShareBudget
                                                                           : ExactPairBudget;
    if (cost + pairs > budget)
    {
      continue;
    }
    if (exact.Empty)
    {
      exact =
        SecondaryExactShot(this->Samples, shooter, this->Settings.OpeningAngle, this->Settings.LeafSize);
      PrepareShot(this->Samples, shooter, ShotMethod::Fast, this->Settings.OpeningAngle,
        this->Settings.LeafSize, fast);
    }
    if (!this->FastShadowsSuffice(receiver, fast, exact))
    {
      cost += pairs;
      chosen.push_back(receiver.Id);
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
  const Shot shot =
    SecondaryExactShot(this->Samples, shooter, this->Settings.OpeningAngle, this->Settings.LeafSize);
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
