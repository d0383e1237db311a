// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSensorIrradiance.h"

#include "penumbraMath.h"

namespace penumbra
{

SensorIrradiance EvaluateSensor(const ExactEvaluator& evaluator, const Scene& scene,
  const std::map<int, ShooterRadiance>& reflected, const Vec3& x, const Vec3& n,
  VisibilityWorkspace& visibility, LinearSourceWorkspace& linear)
{
  SensorIrradiance result;
  const int numberOfSurfaces = static_cast<int>(scene.Surfaces.size());
  for (int j = 0; j < numberOfSurfaces; ++j)
  {
    const RGB& emission = scene.Surfaces[j].Emission;
    if (!emission.IsZero())
    {
      result.Direct += emission * (Pi * evaluator.FormFactor(x, n, -1, j, visibility));
    }
  }
  for (const auto& entry : reflected)
  {
    if (entry.first >= 0 && entry.first < numberOfSurfaces)
    {
      result.Indirect += ExactShooterIrradiance(evaluator, x, n, -1, entry.first, entry.second, linear);
    }
  }
  return result;
}

} // namespace penumbra
