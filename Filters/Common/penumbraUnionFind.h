// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraUnionFind.h
 * @brief Disjoint sets over 0 .. n-1 (path halving; the smaller root wins a
 * union, so the representatives do not depend on the order of unions).
 * Private to the core.
 */
#ifndef penumbraUnionFind_h
#define penumbraUnionFind_h

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace penumbra
{
namespace detail
{

struct UnionFind
{
  std::vector<int> Parent;

  explicit UnionFind(std::size_t n)
    : Parent(n)
  {
    std::iota(this->Parent.begin(), this->Parent.end(), 0);
  }

  int Find(int i)
  {
    while (this->Parent[i] != i)
    {
      this->Parent[i] = this->Parent[this->Parent[i]];
      i = this->Parent[i];
    }
    return i;
  }

  void Union(int a, int b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a != b)
    {
      this->Parent[std::max(a, b)] = std::min(a, b);
    }
  }
};

} // namespace detail
} // namespace penumbra

#endif
