// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSampleBudget.h
 * @brief The scene's adaptive-sampling budget shared among its receivers.
 */
#ifndef penumbraSampleBudget_h
#define penumbraSampleBudget_h

#include "penumbraMeshingModule.h" // for export macro
#include "penumbraDiscontinuityMesher.h"

#include <vector>

namespace penumbra
{

/**
 * The sample budget of each receiver (same order as `receivers`): with
 * `maximumSamples` > 0, the larger of its share of `maximumSamples` by area
 * and an equal share, at most `maximumSamplesPerSurface` and at least 3;
 * `maximumSamplesPerSurface` for every receiver otherwise (or when the
 * receivers have no area). The equal share keeps for slivers and small parts
 * the samples they may still need, so the total is at most twice the budget.
 */
PENUMBRAMESHING_EXPORT std::vector<int> ShareSampleBudget(
  const std::vector<const ReceiverMesh*>& receivers, int maximumSamplesPerSurface,
  long long maximumSamples);

} // namespace penumbra

#endif
