// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraIndirectSampling.h"

#include <utility>
#include <vector>

namespace penumbra
{

void IndirectSampling::Assign(const Scene& scene,
  std::unordered_map<int, SurfaceSamples>& samples, std::size_t maximumIndirectSamples,
  const RayCaster& caster, const ParallelFor& loop, ProgressiveShooter& shooter)
{
  this->SeparatePoints = 0;
  std::vector<std::size_t> finePoints(scene.Surfaces.size(), 0);
  for (const auto& entry : samples)
  {
    finePoints[entry.first] = entry.second.Points.size();
  }
  this->Spacing =
    maximumIndirectSamples > 0 ? IndirectSpacing(scene, finePoints, maximumIndirectSamples) : 0.0;
  for (auto& entry : samples)
  {
    if (this->Spacing > 0.0 &&
      IndirectLevel::CountPoints(scene.Surfaces[entry.first], this->Spacing) <
        entry.second.Points.size())
    {
      auto level =
        std::make_shared<IndirectLevel>(scene.Surfaces[entry.first], this->Spacing, entry.second);
      // A polygon within one lattice cell receives one value (Uniform
      // below): it has nothing to separate.
      if (level->GetResolution() > 1)
      {
        this->SeparatePoints += level->SeparateOccluded(entry.second, entry.first, caster, loop);
      }
      this->Coarse[entry.first] = { level, level->Restrict(entry.second) };
      // A polygon within one lattice cell receives one value, as the
      // lattice resolves nothing finer.
      this->Coarse[entry.first].Before.Uniform = level->GetResolution() == 1;
      this->Fine[entry.first] = std::move(entry.second);
      shooter.SetSurfaceSamples(entry.first, this->Coarse[entry.first].Before);
    }
    else
    {
      shooter.SetSurfaceSamples(entry.first, std::move(entry.second));
    }
  }
}

void IndirectSampling::Prolong(const ProgressiveShooter& shooter)
{
  for (auto& entry : this->Coarse)
  {
    entry.second.Level->Prolong(
      entry.second.Before, shooter.GetSurfaceSamples(entry.first), this->Fine[entry.first]);
  }
}

const SurfaceSamples& IndirectSampling::GetSamples(
  int surface, const ProgressiveShooter& shooter) const
{
  const auto refined = this->Fine.find(surface);
  return refined != this->Fine.end() ? refined->second : shooter.GetSurfaceSamples(surface);
}

double IndirectSampling::GetSpacing() const
{
  return this->Coarse.empty() ? 0.0 : this->Spacing;
}

} // namespace penumbra
