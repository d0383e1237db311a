// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraParameterIntervals.h
 * @brief Intervals of a line parameter (the wedge parameter t in [0, 1], or
 * the parameter along a segment clipped to a polygon) and the set operations
 * the wedge tracer needs on sorted lists of them. Private (not installed).
 */
#ifndef penumbraParameterIntervals_h
#define penumbraParameterIntervals_h

#include <vector>

namespace penumbra
{
namespace detail
{

/// A parameter interval [Lo, Hi]; empty when !(Hi > Lo).
struct Interval
{
  double Lo;
  double Hi;
};

/// Restrict iv to { t : a + b t >= 0 }.
void Restrict(Interval& iv, double a, double b);

/// Sort and merge a list of intervals in place (empty ones dropped).
void Normalize(std::vector<Interval>& list);

/// The intersection of two normalized lists.
void Intersect(const std::vector<Interval>& a, const std::vector<Interval>& b,
  std::vector<Interval>& out);

/// base minus the union of `blocked` (normalized).
void Subtract(const std::vector<Interval>& base, const std::vector<Interval>& blocked,
  std::vector<Interval>& out);

} // namespace detail
} // namespace penumbra

#endif
