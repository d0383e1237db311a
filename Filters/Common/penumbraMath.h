// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraMath.h
 * @brief The constant pi and the 2D point of the core's in-plane geometry,
 * with its cross products.
 */
#ifndef penumbraMath_h
#define penumbraMath_h

#include <array>

namespace penumbra
{

/// pi, the same double as M_PI (which standard C++ does not define).
constexpr double Pi = 3.141592653589793238462643383279502884;

/// A point or vector in a plane's 2D frame.
using P2 = std::array<double, 2>;

/// z component of the cross product of (ax, ay) and (bx, by).
inline double Cross2(double ax, double ay, double bx, double by)
{
  return ax * by - ay * bx;
}

/// z component of the cross product of a - o and b - o: positive when o, a, b turn left.
inline double Cross2(const P2& o, const P2& a, const P2& b)
{
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/// The radical inverse of `index` in `base`: coordinate `base` of the
/// Halton sequence's point number `index`, in [0, 1).
inline double RadicalInverse(unsigned index, unsigned base)
{
  const double inverse = 1.0 / base;
  double scale = inverse;
  double value = 0.0;
  while (index > 0)
  {
    value += (index % base) * scale;
    index /= base;
    scale *= inverse;
  }
  return value;
}

} // namespace penumbra

#endif
