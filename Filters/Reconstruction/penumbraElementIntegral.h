// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraElementIntegral.h
 * @brief The integral of the reconstruction's Clough-Tocher element as
 * weights of its inputs, for callers that integrate sampled functions the
 * way the reconstruction interpolates them (the progressive shooter's power
 * quadrature).
 */
#ifndef penumbraElementIntegral_h
#define penumbraElementIntegral_h

#include "penumbraReconstructionModule.h" // for export macro

namespace penumbra
{

/**
 * The Clough-Tocher element over the triangle of 2D `corners` (either
 * orientation, non-zero area) integrates to
 *   sum_i valueWeights[i] f_i + sum_i gradientWeights[i] . g_i
 * for corner values f_i and corner gradients g_i (d/du, d/dv). Exact for
 * quadratics when the g_i are their gradients; with zero gradients the values
 * weigh a third of the area each.
 */
PENUMBRARECONSTRUCTION_EXPORT void CloughTocherIntegralWeights(
  const double corners[3][2], double valueWeights[3], double gradientWeights[3][2]);

} // namespace penumbra

#endif
