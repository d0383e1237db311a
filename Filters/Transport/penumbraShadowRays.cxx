// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraShadowRays.h"

#include "penumbraOccluderSet.h"
#include "penumbraRayCaster.h"
#include "penumbraSampleSet.h"
#include "penumbraMath.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace penumbra
{

namespace
{

constexpr int ShadowTestRays = 64;

} // namespace

double DiscTransferFraction(const PreparedPolygon& from, const PreparedPolygon& to)
{
  const Vec3 d = to.Centroid - from.Centroid;
  const double r2 = Dot(d, d);
  const double cosines = std::max(0.0, Dot(from.Normal, d)) * std::max(0.0, -Dot(to.Normal, d));
  return r2 > 0.0 ? to.Area * cosines / (r2 * (Pi * r2 + to.Area)) : 0.0;
}

bool AnyRayBlocked(const SampleSet& samples, const RayCaster& caster, int shooter, int receiver)
{
  const SurfaceSamples& s = samples.Surfaces[shooter];
  const std::vector<Vec3>& targets = samples.EvaluationPoints[receiver];
  if (s.Triangles.empty() || targets.empty())
  {
    return false;
  }
  const PreparedPolygon& to = samples.Polygon(receiver);
  for (int k = 0; k < ShadowTestRays; ++k)
  {
    // Two coprime strides through the lists, so that pairs do not repeat.
    const std::array<int, 3>& tri =
      s.Triangles[(static_cast<std::size_t>(k) * 7919u) % s.Triangles.size()];
    const Vec3 from = (s.Points[tri[0]] + s.Points[tri[1]] + s.Points[tri[2]]) * (1.0 / 3.0);
    const Vec3& target = targets[(static_cast<std::size_t>(k) * 104729u) % targets.size()];
    if (Dot(to.Normal, from - target) > 0.0 &&
      caster.IsOccluded(from, target, shooter, receiver))
    {
      return true;
    }
  }
  return false;
}

} // namespace penumbra
