// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraExactShot.h"

#include "penumbraExactEvaluator.h"
#include "penumbraLinearSource.h"

#include <utility>

namespace penumbra
{

ShooterRadiance ExactShooterRadiance(
  const SurfaceSamples& s, std::vector<Vec3> points, std::vector<std::array<int, 3>> kept)
{
  bool uniform = kept.size() == s.Triangles.size();
  for (std::size_t k = 1; k < s.Unshot.size() && uniform; ++k)
  {
    uniform = s.Unshot[k].R == s.Unshot[0].R && s.Unshot[k].G == s.Unshot[0].G &&
      s.Unshot[k].B == s.Unshot[0].B;
  }
  return uniform ? ShooterRadiance(s.Unshot[0])
                 : ShooterRadiance(std::move(points), std::move(kept), s.Unshot);
}

RGB ExactIrradiance(const Shot& shot, const ExactEvaluator& exact, const Vec3& x, const Vec3& n,
  int receiver, const std::vector<int>* candidates, LinearSourceWorkspace& ws)
{
  VisibleRegion& region = ws.Region;
  if (candidates)
  {
    exact.FormFactor(x, n, receiver, shot.Shooter, *candidates, ws.Visibility, &region);
  }
  else
  {
    exact.FormFactor(x, n, receiver, shot.Shooter, ws.Visibility, &region);
  }
  return VisibleShooterIrradiance(x, n, shot.Radiance, region, shot.Normal, ws);
}

} // namespace penumbra
