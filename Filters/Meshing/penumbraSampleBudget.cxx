// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSampleBudget.h"

#include <algorithm>

namespace penumbra
{

std::vector<int> ShareSampleBudget(const std::vector<const ReceiverMesh*>& receivers,
  int maximumSamplesPerSurface, long long maximumSamples)
{
  std::vector<int> budgets(receivers.size(), maximumSamplesPerSurface);
  if (maximumSamples <= 0)
  {
    return budgets;
  }
  std::vector<double> areas(receivers.size(), 0.0);
  double totalArea = 0.0;
  for (std::size_t w = 0; w < receivers.size(); ++w)
  {
    const ReceiverMesh& mesh = *receivers[w];
    for (const auto& t : mesh.Triangles)
    {
      areas[w] += 0.5 *
        Length(Cross(mesh.Points[t[1]] - mesh.Points[t[0]], mesh.Points[t[2]] - mesh.Points[t[0]]));
    }
    totalArea += areas[w];
  }
  const double budget = static_cast<double>(maximumSamples);
  const double equalShare =
    budget / static_cast<double>(std::max<std::size_t>(1, receivers.size()));
  for (std::size_t w = 0; w < receivers.size() && totalArea > 0.0; ++w)
  {
    const double share = std::max(equalShare, budget * areas[w] / totalArea);
    budgets[w] = static_cast<int>(std::max(3.0, std::min<double>(share, budgets[w])));
  }
  return budgets;
}

} // namespace penumbra
