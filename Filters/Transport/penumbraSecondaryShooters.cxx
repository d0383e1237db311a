// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSecondaryShooters.h"

#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraRayCaster.h"
#include "penumbraShadowRays.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra
{

namespace
{

/// A secondary shooter must bring at least this share of a shaded
/// receiver's light.
constexpr double DominantShare = 0.5;
/// ... and reflect at least this fraction of the emitted power more with it
/// (small receivers, such as an emitter's own sides, do not count).
constexpr double SignificantGain = 0.01;
/// Rays of the shading test between a shooter and a receiver.
constexpr int ShadingRays = 64;
/// Receivers with more shaft candidates than this are not meshed for a
/// secondary shooter: each occluder adds its EV and VE events, and behind
/// many (a wall seeing a floor past the boxes of a room) the many small
/// shadows blur into a smooth whole that needs no boundaries, while
/// tracing them would cost more than all of the direct light's.
constexpr std::size_t MaximumSecondaryOccluders = 32;

/// A point of `surface`'s plane within half its radius of its centroid,
/// from 2D Halton coordinates (u, v) in [0, 1), uniform by area: for a
/// shading test, not a quadrature.
Vec3 PointOn(const OccluderSet& occluders, int surface, double u, double v)
{
  const PreparedPolygon& p = occluders.GetPolygon(surface);
  const double radius = 0.5 * p.Radius * std::sqrt(u);
  const double angle = 2.0 * Pi * v;
  return p.Centroid + p.AxisU * (radius * std::cos(angle)) + p.AxisV * (radius * std::sin(angle));
}

bool Shaded(const PreparedScene& scene, int shooter, int receiver)
{
  const OccluderSet& occluders = *scene.GetOccluders();
  const RayCaster& caster = *scene.GetRayCaster();
  for (int k = 1; k <= ShadingRays; ++k)
  {
    const Vec3 a = PointOn(occluders, shooter, RadicalInverse(k, 2), RadicalInverse(k, 3));
    const Vec3 b = PointOn(occluders, receiver, RadicalInverse(k, 5), RadicalInverse(k, 7));
    if (caster.IsOccluded(a, b, shooter, receiver))
    {
      return true;
    }
  }
  return false;
}

} // namespace

std::vector<SecondaryShooter> SelectSecondaryShooters(const PreparedScene& scene,
  const std::vector<double>& reflected, double fraction, int maximum)
{
  std::vector<SecondaryShooter> chosen;
  const Scene& s = scene.GetScene();
  const OccluderSet& occluders = *scene.GetOccluders();
  const double emitted = s.EmittedPower().Mean();
  const int surfaces = static_cast<int>(s.Surfaces.size());
  if (!(emitted > 0.0) || fraction >= 1.0 || static_cast<int>(reflected.size()) != surfaces)
  {
    return chosen;
  }
  std::vector<std::pair<double, int>> strong;
  for (int j = 0; j < surfaces; ++j)
  {
    if (s.Surfaces[j].Emission.IsZero() && reflected[j] >= fraction * emitted &&
      occluders.GetPolygon(j).Valid)
    {
      strong.emplace_back(reflected[j], j);
    }
  }
  std::sort(strong.begin(), strong.end(), [](const std::pair<double, int>& a,
                                            const std::pair<double, int>& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  std::vector<int> candidates;
  for (const auto& entry : strong)
  {
    if (static_cast<int>(chosen.size()) >= maximum)
    {
      break;
    }
    SecondaryShooter shooter;
    shooter.Shooter = entry.second;
    const int j = entry.second;
    const PreparedPolygon& from = occluders.GetPolygon(j);
    for (int i = 0; i < surfaces; ++i)
    {
      const PreparedPolygon& to = occluders.GetPolygon(i);
      const double rho = s.Surfaces[i].Reflectance.Mean();
      if (i == j || !to.Valid || rho <= 0.0)
      {
        continue;
      }
      const double added = rho * entry.first * DiscTransferFraction(from, to);
      // The estimate first: the shaft query costs a search of the scene.
      if (added >= SignificantGain * emitted && added >= DominantShare * (added + reflected[i]) &&
        occluders.ShaftCandidates(j, i, candidates) && !candidates.empty() &&
        candidates.size() <= MaximumSecondaryOccluders && Shaded(scene, j, i))
      {
        shooter.Receivers.push_back(i);
      }
    }
    if (!shooter.Receivers.empty())
    {
      chosen.push_back(std::move(shooter));
    }
  }
  return chosen;
}

} // namespace penumbra
