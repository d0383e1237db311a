// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraTimer.h"

namespace penumbra
{

double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

} // namespace penumbra
