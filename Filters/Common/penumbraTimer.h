// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraTimer.h
 * @brief The wall-clock time the solvers report in their statistics.
 */
#ifndef penumbraTimer_h
#define penumbraTimer_h

#include "penumbraCommonModule.h" // for export macro

#include <chrono>

namespace penumbra
{

/// Seconds elapsed since `since` (steady clock).
PENUMBRACOMMON_EXPORT double Seconds(std::chrono::steady_clock::time_point since);

} // namespace penumbra

#endif
