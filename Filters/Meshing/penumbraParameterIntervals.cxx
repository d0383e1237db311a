// SPDX-License-Identifier: GPL-3.0-or-later
// Set operations on sorted lists of parameter intervals.
#include "penumbraParameterIntervals.h"

#include <algorithm>

namespace penumbra
{
namespace detail
{

void Restrict(Interval& iv, double a, double b)
{
  if (b == 0.0)
  {
    if (a < 0.0)
    {
      iv.Hi = iv.Lo - 1.0;
    }
    return;
  }
  const double root = -a / b;
  if (b > 0.0)
  {
    iv.Lo = std::max(iv.Lo, root);
  }
  else
  {
    iv.Hi = std::min(iv.Hi, root);
  }
}

// Sort and merge a list of intervals in place.
void Normalize(std::vector<Interval>& list)
{
  std::sort(list.begin(), list.end(),
    [](const Interval& x, const Interval& y) { return x.Lo < y.Lo; });
  std::size_t n = 0;
  for (const Interval& iv : list)
  {
    if (!(iv.Hi > iv.Lo))
    {
      continue;
    }
    if (n > 0 && iv.Lo <= list[n - 1].Hi)
    {
      list[n - 1].Hi = std::max(list[n - 1].Hi, iv.Hi);
    }
    else
    {
      list[n++] = iv;
    }
  }
  list.resize(n);
}

// The intersection of two normalized lists.
void Intersect(const std::vector<Interval>& a, const std::vector<Interval>& b,
  std::vector<Interval>& out)
{
  out.clear();
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size())
  {
    const double lo = std::max(a[i].Lo, b[j].Lo), hi = std::min(a[i].Hi, b[j].Hi);
    if (hi > lo)
    {
      out.push_back({ lo, hi });
    }
    if (a[i].Hi < b[j].Hi)
    {
      ++i;
    }
    else
    {
      ++j;
    }
  }
}

// base minus the union of `blocked` (normalized).
void Subtract(const std::vector<Interval>& base, const std::vector<Interval>& blocked,
  std::vector<Interval>& out)
{
  out.clear();
  for (Interval iv : base)
  {
    double lo = iv.Lo;
    for (const Interval& b : blocked)
    {
      if (b.Hi <= lo)
      {
        continue;
      }
      if (b.Lo >= iv.Hi)
      {
        break;
      }
      if (b.Lo > lo)
      {
        out.push_back({ lo, b.Lo });
      }
      lo = std::max(lo, b.Hi);
    }
    if (iv.Hi > lo)
    {
      out.push_back({ lo, iv.Hi });
    }
  }
}

} // namespace detail
} // namespace penumbra
