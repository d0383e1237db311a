// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraFormFactor.h
 * @brief Point-to-polygon form factors by Lambert's formula, and polygon
 * clipping against a half-space.
 *
 * The form factor from a differential area at x (unit normal n) to a polygon
 * is the cosine-weighted solid angle of the polygon divided by pi. Lambert's
 * contour formula gives it exactly:
 *
 *   F = 1/(2 pi) sum_k gamma_k n . (R_{k+1} x R_k) / |R_{k+1} x R_k|,
 *
 * with R_k = v_k - x and gamma_k the angle between R_k and R_{k+1}, computed as
 * atan2(|R_k x R_{k+1}|, R_k . R_{k+1}) (see LambertEdgeAngle), which is
 * accurate to a few ulps at every angle (acos of a normalised dot product
 * loses half the digits near 0).
 * The polygon must lie in the closed half-space in front of x's tangent plane;
 * PointPolygonFormFactorClipped clips it there first.
 *
 * Orientation: vertices are counter-clockwise seen from the polygon's front.
 * The result is positive when the front faces x; a polygon whose front does
 * not face x gets 0 (surfaces emit from the front only).
 */
#ifndef penumbraFormFactor_h
#define penumbraFormFactor_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraVector.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace penumbra
{

/**
 * Angle in [0, pi] between two vectors, from s = |cross product| > 0 and
 * c = dot product: atan2(s, c), evaluated as atan(s / |c|) folded about
 * pi/2, which is the same angle to an ulp (s / |c| = inf gives pi/2) and
 * about a third cheaper than atan2 with glibc.
 */
inline double LambertEdgeAngle(double s, double c)
{
  const double a = std::atan(s / std::abs(c));
  return c >= 0.0 ? a : M_PI - a;
}

/**
 * One edge term of Lambert's formula, without the 1/(2 pi) factor:
 * gamma * n.(r1 x r0)/|r1 x r0| for the edge from r0 to r1 (both relative to
 * the receiving point). Returns 0 for a degenerate edge (r0, r1 parallel),
 * whose contribution vanishes. Shared by every integrator of the core.
 */
inline double LambertEdgeTerm(const Vec3& r0, const Vec3& r1, const Vec3& n)
{
  Vec3 c = Cross(r1, r0);
  double s2 = Dot(c, c);
  if (!(s2 > 1e-280))
  {
    // Rescale before squaring: for a point almost on the edge's line the
    // squares underflow, yet the edge's term (up to pi) still matters.
    const double m = std::max(std::abs(c.X), std::max(std::abs(c.Y), std::abs(c.Z)));
    if (!(m > 0.0))
    {
      return 0.0;
    }
    const double s = m * Length(c / m);
    return LambertEdgeAngle(s, Dot(r0, r1)) * (Dot(n, c / m) / (s / m));
  }
  const double s = std::sqrt(s2);
  return LambertEdgeAngle(s, Dot(r0, r1)) * (Dot(n, c) / s);
}

/**
 * Signed Lambert sum for a polygon (no clipping, no clamping): positive when
 * the front faces x, negative when the back does. `n` must be a unit vector
 * and the polygon must lie in front of x's tangent plane for the value to be
 * a form factor.
 */
PENUMBRAVISIBILITY_EXPORT double PointPolygonFormFactorSigned(
  const Vec3& x, const Vec3& n, const Vec3* vertices, int count);

/**
 * Form factor from a differential area at x with unit normal n to a polygon
 * that already lies in front of x's tangent plane (Dot(n, v - x) >= 0 for every
 * vertex). Returns 0 when the polygon's front does not face x, or for fewer
 * than three vertices. Works for concave polygons too.
 */
PENUMBRAVISIBILITY_EXPORT double PointPolygonFormFactor(
  const Vec3& x, const Vec3& n, const Vec3* vertices, int count);

/**
 * Sutherland-Hodgman clip of a polygon to the closed half-space
 * Dot(normal, p) >= offset. Writes the result to `out`, which must have room
 * for 2 * count vertices (count + 1 suffice for a convex polygon), and returns
 * its vertex count (0 when nothing remains). For a concave polygon the result
 * may contain zero-width bridges, which contour integrals such as Lambert's
 * formula traverse twice in opposite directions and so cancel exactly.
 */
PENUMBRAVISIBILITY_EXPORT int ClipPolygonToHalfSpace(
  const Vec3* vertices, int count, const Vec3& normal, double offset, Vec3* out);

/// Convenience overload of ClipPolygonToHalfSpace on vectors (`out` is resized).
PENUMBRAVISIBILITY_EXPORT void ClipPolygonToHalfSpace(
  const std::vector<Vec3>& vertices, const Vec3& normal, double offset, std::vector<Vec3>& out);

/**
 * Form factor from a differential area at x (unit normal n) to an arbitrary
 * planar polygon: the polygon is first clipped to x's front half-space
 * Dot(n, p - x) >= 0. No heap allocation for polygons of up to 32 vertices.
 */
PENUMBRAVISIBILITY_EXPORT double PointPolygonFormFactorClipped(
  const Vec3& x, const Vec3& n, const Vec3* vertices, int count);

/// Convenience overload of PointPolygonFormFactorClipped on a vector.
inline double PointPolygonFormFactorClipped(
  const Vec3& x, const Vec3& n, const std::vector<Vec3>& vertices)
{
  return PointPolygonFormFactorClipped(x, n, vertices.data(), static_cast<int>(vertices.size()));
}

} // namespace penumbra

#endif
