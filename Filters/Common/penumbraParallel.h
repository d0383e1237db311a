// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraParallel.h
 * @brief The parallel loop the core's solvers run their per-sample work
 * through, supplied by the caller (the VTK filters pass vtkSMPTools::For).
 *
 * The core has no thread pool of its own: a solver takes a ParallelFor and
 * runs each of its parallel loops through it. Results must not depend on
 * how the range is cut, so every body writes to its own slots only and all
 * sums are formed afterwards in a fixed order.
 */
#ifndef penumbraParallel_h
#define penumbraParallel_h

#include <cstddef>
#include <functional>

namespace penumbra
{

/**
 * Runs body(b, e) over disjoint sub-ranges [b, e) covering [begin, end),
 * possibly concurrently, and returns when all are done (the contract of
 * vtkSMPTools::For). An empty function means serial: body(begin, end).
 */
using ParallelFor = std::function<void(
  std::size_t begin, std::size_t end, const std::function<void(std::size_t, std::size_t)>& body)>;

/// body over [0, count) through `loop`, or serially (body(0, count)) when it is empty.
inline void RunParallel(const ParallelFor& loop, std::size_t count,
  const std::function<void(std::size_t, std::size_t)>& body)
{
  if (loop)
  {
    loop(0, count, body);
  }
  else
  {
    body(0, count);
  }
}

} // namespace penumbra

#endif
