// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraConvexHull.h"

#include <algorithm>
#include <cstddef>

namespace penumbra
{

void ConvexHull2(const std::vector<P2>& p, std::vector<int>& hull)
{
  thread_local std::vector<int> idx;
  idx.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    idx[i] = static_cast<int>(i);
  }
  std::sort(idx.begin(), idx.end(), [&p](int a, int b) { return p[a] < p[b]; });
  hull.resize(2 * idx.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < idx.size(); ++i)
  {
    while (k >= 2 && Cross2(p[hull[k - 2]], p[hull[k - 1]], p[idx[i]]) <= 0.0)
    {
      --k;
    }
    hull[k++] = idx[i];
  }
  for (std::size_t i = idx.size() - 1, t = k + 1; i > 0; --i)
  {
    while (k >= t && Cross2(p[hull[k - 2]], p[hull[k - 1]], p[idx[i - 1]]) <= 0.0)
    {
      --k;
    }
    hull[k++] = idx[i - 1];
  }
  hull.resize(k > 1 ? k - 1 : k);
}

} // namespace penumbra
