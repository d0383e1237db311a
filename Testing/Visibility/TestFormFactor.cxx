// SPDX-License-Identifier: GPL-3.0-or-later
// Point-to-polygon form factors (Lambert's formula) against closed forms from
// Howell's catalogue, computed here independently of the code under test, and
// area-to-area form factors obtained by integrating the point values.
#include "penumbraFormFactor.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using penumbra::Vec3;

namespace
{

const double Pi = 3.14159265358979323846;

// Differential area to a parallel rectangle a x b at distance c, the normal
// through one corner (Howell B-1). Odd in a and in b, so signed sums of it
// give any axis-aligned rectangle.
double CornerParallel(double a, double b, double c)
{
  const double X = a / c, Y = b / c;
  const double sx = std::sqrt(1.0 + X * X), sy = std::sqrt(1.0 + Y * Y);
  return (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2.0 * Pi);
}

// Parallel axis-aligned rectangle [x0,x1] x [y0,y1] at distance c, coordinates
// relative to the foot of the normal.
double ParallelRectangle(double x0, double x1, double y0, double y1, double c)
{
  return CornerParallel(x1, y1, c) - CornerParallel(x0, y1, c) - CornerParallel(x1, y0, c) +
    CornerParallel(x0, y0, c);
}

// Differential area to a rectangle in a perpendicular plane (Howell B-3): the
// rectangle is b wide and c high, one of its b-edges lies in the element's
// plane and the element faces the rectangle's plane at distance d, on the
// normal to that plane through a corner.
double CornerPerpendicular(double b, double c, double d)
{
  const double X = c / b, Y = d / b;
  const double r = std::sqrt(X * X + Y * Y);
  return (std::atan(1.0 / Y) - Y / r * std::atan(1.0 / r)) / (2.0 * Pi);
}

// Identical parallel directly opposed rectangles a x b at distance c (Howell C-11).
double ParallelPlates(double a, double b, double c)
{
  const double X = a / c, Y = b / c;
  const double x2 = 1.0 + X * X, y2 = 1.0 + Y * Y;
  return 2.0 / (Pi * X * Y) *
    (std::log(std::sqrt(x2 * y2 / (x2 + Y * Y))) +
      X * std::sqrt(y2) * std::atan(X / std::sqrt(y2)) +
      Y * std::sqrt(x2) * std::atan(Y / std::sqrt(x2)) - X * std::atan(X) - Y * std::atan(Y));
}

// Perpendicular rectangles with a common edge of length l (Howell C-14):
// from the rectangle of width w to the one of height h.
double PerpendicularPlates(double h, double w, double l)
{
  const double H = h / l, W = w / l;
  const double H2 = H * H, W2 = W * W, s = std::sqrt(H2 + W2);
  const double a = (1.0 + W2) * (1.0 + H2) / (1.0 + W2 + H2);
  const double b = W2 * (1.0 + W2 + H2) / ((1.0 + W2) * (W2 + H2));
  const double c = H2 * (1.0 + H2 + W2) / ((1.0 + H2) * (W2 + H2));
  return (W * std::atan(1.0 / W) + H * std::atan(1.0 / H) - s * std::atan(1.0 / s) +
           0.25 * (std::log(a) + W2 * std::log(b) + H2 * std::log(c))) /
    (Pi * W);
}

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method.
void GaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights)
{
  nodes.assign(n, 0.0);
  weights.assign(n, 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i)
  {
    double z = std::cos(Pi * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int iter = 0; iter < 100; ++iter)
    {
      double p0 = 1.0, p1 = 0.0;
      for (int k = 1; k <= n; ++k)
      {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      const double dz = p0 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16)
      {
        break;
      }
    }
    nodes[i] = -z;
    nodes[n - 1 - i] = z;
    weights[i] = weights[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

// Composite Gauss rule on the given breakpoints.
void CompositeRule(const std::vector<double>& breaks, int order, std::vector<double>& nodes,
  std::vector<double>& weights)
{
  std::vector<double> gx, gw;
  GaussLegendre(order, gx, gw);
  nodes.clear();
  weights.clear();
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
  {
    const double h = 0.5 * (breaks[i + 1] - breaks[i]), m = 0.5 * (breaks[i + 1] + breaks[i]);
    for (int k = 0; k < order; ++k)
    {
      nodes.push_back(m + h * gx[k]);
      weights.push_back(h * gw[k]);
    }
  }
}

// Breakpoints on [0, L] graded geometrically (ratio q, `levels` layers) towards
// the ends flagged.
std::vector<double> GradedBreaks(double L, double q, int levels, bool toLow, bool toHigh)
{
  std::vector<double> b;
  b.push_back(0.0);
  const double half = (toLow && toHigh) ? 0.5 * L : L;
  if (toLow)
  {
    for (int k = levels; k >= 1; --k)
    {
      b.push_back(half * std::pow(q, k));
    }
  }
  if (toLow && toHigh)
  {
    b.push_back(half);
  }
  if (toHigh)
  {
    const double start = toLow ? half : 0.0;
    const double span = L - start;
    for (int k = 1; k <= levels; ++k)
    {
      b.push_back(L - span * std::pow(q, k));
    }
    std::sort(b.begin(), b.end());
  }
  b.push_back(L);
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

std::vector<double> UniformBreaks(double L, int n)
{
  std::vector<double> b;
  for (int i = 0; i <= n; ++i)
  {
    b.push_back(L * i / n);
  }
  return b;
}

// Area-to-area form factor from the parallel square/rectangle receiver at z=0
// (a x b, facing +z) to the identical one at z=c facing down.
double IntegrateParallel(double a, double b, double c, int order, int panels)
{
  const Vec3 shooter[4] = { { 0, 0, c }, { 0, b, c }, { a, b, c }, { a, 0, c } };
  std::vector<double> xs, xw, ys, yw;
  CompositeRule(UniformBreaks(a, panels), order, xs, xw);
  CompositeRule(UniformBreaks(b, panels), order, ys, yw);
  double sum = 0.0;
  for (std::size_t i = 0; i < xs.size(); ++i)
  {
    for (std::size_t j = 0; j < ys.size(); ++j)
    {
      sum += xw[i] * yw[j] *
        penumbra::PointPolygonFormFactor(Vec3(xs[i], ys[j], 0), Vec3(0, 0, 1), shooter, 4);
    }
  }
  return sum / (a * b);
}

// From the receiver w x l in z=0 (x in [0,w], facing +z) to the shooter
// l x h in x=0 (z in [0,h], facing +x), sharing the edge x=z=0. The point
// form factor is singular along the shared edge and at its ends: geometric
// meshes towards x=0 and towards y=0 and y=l.
double IntegratePerpendicular(double h, double w, double l, int order, int levels)
{
  const Vec3 shooter[4] = { { 0, 0, 0 }, { 0, l, 0 }, { 0, l, h }, { 0, 0, h } };
  std::vector<double> xs, xw, ys, yw;
  CompositeRule(GradedBreaks(w, 0.15, levels, true, false), order, xs, xw);
  CompositeRule(GradedBreaks(l, 0.15, levels, true, true), order, ys, yw);
  double sum = 0.0;
  for (std::size_t i = 0; i < xs.size(); ++i)
  {
    for (std::size_t j = 0; j < ys.size(); ++j)
    {
      sum += xw[i] * yw[j] *
        penumbra::PointPolygonFormFactorClipped(Vec3(xs[i], ys[j], 0), Vec3(0, 0, 1), shooter, 4);
    }
  }
  return sum / (w * l);
}

PENUMBRA_TEST(TestPointParallel)
{
  // Unit square centred at distance 1: four corner rectangles 0.5 x 0.5.
  const double reference = 4.0 * CornerParallel(0.5, 0.5, 1.0);
  PENUMBRA_EXPECT_NEAR(reference, 0.239456, 5e-7); // design.md's 6 digits
  const Vec3 square[4] = { { -0.5, -0.5, 1 }, { -0.5, 0.5, 1 }, { 0.5, 0.5, 1 }, { 0.5, -0.5, 1 } };
  const double f = penumbra::PointPolygonFormFactor(Vec3(0, 0, 0), Vec3(0, 0, 1), square, 4);
  PENUMBRA_EXPECT_REL(f, reference, 1e-12);
  std::printf("parallel unit square at 1: F = %.15f (closed form %.15f)\n", f, reference);

  // Off-centre points, in general position: signed sums of corner rectangles.
  const double points[3][3] = { { 0.2, -0.1, 1.0 }, { 1.3, 0.7, 0.4 }, { -2.0, 3.0, 5.0 } };
  for (const auto& p : points)
  {
    const double c = p[2];
    const Vec3 x(p[0], p[1], 0.0);
    const Vec3 sq[4] = { { -0.5, -0.5, c }, { -0.5, 0.5, c }, { 0.5, 0.5, c }, { 0.5, -0.5, c } };
    const double ref = ParallelRectangle(-0.5 - p[0], 0.5 - p[0], -0.5 - p[1], 0.5 - p[1], c);
    PENUMBRA_EXPECT_REL(penumbra::PointPolygonFormFactor(x, Vec3(0, 0, 1), sq, 4), ref, 1e-12);
  }
}

PENUMBRA_TEST(TestCornellLight)
{
  // Floor point under the Cornell light (mm); the light faces down (-y).
  const Vec3 light[4] = { { 343, 548.8, 227 }, { 343, 548.8, 332 }, { 213, 548.8, 332 },
    { 213, 548.8, 227 } };
  const Vec3 x(278, 0, 279.5);
  const double c = 548.8;
  const double reference = ParallelRectangle(213 - 278, 343 - 278, 227 - 279.5, 332 - 279.5, c);
  PENUMBRA_EXPECT_NEAR(reference, 0.0142070, 5e-8);
  const double f = penumbra::PointPolygonFormFactor(x, Vec3(0, 1, 0), light, 4);
  PENUMBRA_EXPECT_REL(f, reference, 1e-12);
  std::printf("Cornell floor point under the light: F = %.15f (closed form %.15f)\n", f, reference);
  // Irradiance from the light's radiance: E = pi Le F.
  const double le = 17.0;
  PENUMBRA_EXPECT_REL(Pi * le * f, Pi * le * reference, 1e-12);
}

PENUMBRA_TEST(TestPerpendicular)
{
  // Element at the origin facing +z; rectangle in the plane x = d facing -x,
  // y in [y0, y1], z in [0, c].
  struct Case
  {
    double d, y0, y1, c;
  };
  const Case cases[] = { { 1.0, 0.0, 1.0, 1.0 }, { 0.7, 0.0, 2.0, 0.5 }, { 0.3, -0.4, 1.1, 2.5 },
    { 2.0, 0.5, 1.5, 0.2 } };
  for (const Case& k : cases)
  {
    // Front normal -x: counter-clockwise seen from -x.
    const Vec3 rect[4] = { { k.d, k.y0, 0 }, { k.d, k.y0, k.c }, { k.d, k.y1, k.c },
      { k.d, k.y1, 0 } };
    // Signed sum of corner rectangles (B-3 is odd in the width).
    auto corner = [&](double y) {
      return y == 0.0 ? 0.0 : (y > 0 ? 1.0 : -1.0) * CornerPerpendicular(std::abs(y), k.c, k.d);
    };
    const double ref = corner(k.y1) - corner(k.y0);
    const double f = penumbra::PointPolygonFormFactor(Vec3(0, 0, 0), Vec3(0, 0, 1), rect, 4);
    PENUMBRA_EXPECT_REL(f, ref, 1e-12);
  }
}

PENUMBRA_TEST(TestClipping)
{
  const Vec3 x(0, 0, 0), n(0, 0, 1);
  // A rectangle straddling the tangent plane z = 0: only z in [0, 1] counts.
  const Vec3 rect[4] = { { 1, 0, -0.5 }, { 1, 0, 1 }, { 1, 1, 1 }, { 1, 1, -0.5 } };
  const double ref = CornerPerpendicular(1.0, 1.0, 1.0);
  PENUMBRA_EXPECT_REL(penumbra::PointPolygonFormFactorClipped(x, n, rect, 4), ref, 1e-12);

  // A tilted triangle straddling the plane, clipped by hand.
  const Vec3 a(0.3, -0.2, 1.0), b(-0.4, 0.5, -0.6), c(0.8, 0.9, 0.2);
  // Edge a-b crosses z=0 at t = 1/1.6, edge b-c at t = 0.6/0.8.
  const Vec3 ab = a + (b - a) * (1.0 / 1.6);
  const Vec3 bc = b + (c - b) * (0.6 / 0.8);
  // Orient so that the front faces x.
  const penumbra::Vec3 nt = penumbra::Cross(b - a, c - a);
  const bool flip = penumbra::Dot(nt, a - x) > 0.0; // front must face x: normal towards x
  std::vector<Vec3> tri = { a, b, c };
  std::vector<Vec3> clipped = { a, ab, bc, c };
  if (flip)
  {
    tri = { a, c, b };
    clipped = { a, c, bc, ab };
  }
  const double fClipped = penumbra::PointPolygonFormFactor(x, n, clipped.data(), 4);
  PENUMBRA_EXPECT(fClipped > 0.0);
  PENUMBRA_EXPECT_REL(penumbra::PointPolygonFormFactorClipped(x, n, tri), fClipped, 1e-13);

  // ClipPolygonToHalfSpace itself: vertices of the clipped rectangle.
  std::vector<Vec3> out;
  penumbra::ClipPolygonToHalfSpace(std::vector<Vec3>(rect, rect + 4), Vec3(0, 0, 1), 0.0, out);
  PENUMBRA_EXPECT(out.size() == 4);
  double zmin = 1e300, area2 = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    zmin = std::min(zmin, out[i].Z);
    area2 += penumbra::Cross(out[i], out[(i + 1) % out.size()]).X;
  }
  PENUMBRA_EXPECT_NEAR(zmin, 0.0, 0.0);
  PENUMBRA_EXPECT_NEAR(std::abs(area2) * 0.5, 1.0, 1e-15);
  // Entirely behind: nothing.
  const Vec3 below[3] = { { 0, 0, -1 }, { 1, 0, -1 }, { 0, 1, -2 } };
  PENUMBRA_EXPECT(penumbra::PointPolygonFormFactorClipped(x, n, below, 3) == 0.0);
}

PENUMBRA_TEST(TestOrientation)
{
  const Vec3 x(0, 0, 0), n(0, 0, 1);
  // Facing x (normal -z, counter-clockwise seen from below) and reversed.
  const Vec3 front[4] = { { -0.5, -0.5, 1 }, { -0.5, 0.5, 1 }, { 0.5, 0.5, 1 }, { 0.5, -0.5, 1 } };
  const Vec3 back[4] = { { -0.5, -0.5, 1 }, { 0.5, -0.5, 1 }, { 0.5, 0.5, 1 }, { -0.5, 0.5, 1 } };
  const double f = penumbra::PointPolygonFormFactor(x, n, front, 4);
  PENUMBRA_EXPECT(f > 0.2);
  PENUMBRA_EXPECT(penumbra::PointPolygonFormFactor(x, n, back, 4) == 0.0);
  PENUMBRA_EXPECT(penumbra::PointPolygonFormFactorClipped(x, n, back, 4) == 0.0);
  PENUMBRA_EXPECT_REL(penumbra::PointPolygonFormFactorSigned(x, n, back, 4), -f, 1e-14);
  // Degenerate input gives 0, never NaN.
  PENUMBRA_EXPECT(penumbra::PointPolygonFormFactor(x, n, front, 2) == 0.0);
  const Vec3 flat[3] = { { 1, 0, 1 }, { 2, 0, 1 }, { 3, 0, 1 } };
  PENUMBRA_EXPECT(penumbra::PointPolygonFormFactor(x, n, flat, 3) == 0.0);
  // x in the polygon's plane: 0 (up to rounding), finite.
  const Vec3 side[4] = { { 1, -1, 0 }, { 1, 1, 0 }, { 2, 1, 0 }, { 2, -1, 0 } };
  const double fs = penumbra::PointPolygonFormFactorClipped(x, n, side, 4);
  PENUMBRA_EXPECT(std::isfinite(fs) && std::abs(fs) < 1e-15);
  // A huge polygon covering the hemisphere: F -> 1.
  const double L = 1e8;
  const Vec3 sky[4] = { { -L, -L, 1 }, { -L, L, 1 }, { L, L, 1 }, { L, -L, 1 } };
  PENUMBRA_EXPECT_NEAR(penumbra::PointPolygonFormFactor(x, n, sky, 4), 1.0, 1e-7);
}

PENUMBRA_TEST(TestEdgeAngle)
{
  // The edge angle equals atan2(s, c) to an ulp or two, at every angle.
  double worst = 0.0;
  const double cs[] = { 1.0, 0.5, 1e-3, 1e-12, 0.0, -0.0, -1e-12, -1e-3, -0.5, -1.0, -1e12 };
  const double ss[] = { 1e-300, 1e-12, 1e-3, 0.5, 1.0, 7.0, 1e12 };
  for (double c : cs)
  {
    for (double s : ss)
    {
      const double ref = std::atan2(s, c);
      worst = std::max(worst, std::abs(penumbra::LambertEdgeAngle(s, c) - ref) / ref);
    }
  }
  PENUMBRA_EXPECT(worst <= 4.5e-16);
}

PENUMBRA_TEST(TestAreaToArea)
{
  // Parallel directly opposed squares/rectangles: design.md's values, the
  // closed form, and the integral of point values.
  struct Case
  {
    double a, b, c, given, digits;
  };
  const Case cases[] = { { 1, 1, 1, 0.199825, 5e-7 }, { 1, 1, 0.5, 0.415253, 5e-7 },
    { 1, 1, 2, 0.068590, 5e-7 }, { 1, 1.5, 0.5, 0.47558, 5e-6 } };
  for (const Case& k : cases)
  {
    const double closed = ParallelPlates(k.a, k.b, k.c);
    PENUMBRA_EXPECT_NEAR(closed, k.given, k.digits);
    const double integral = IntegrateParallel(k.a, k.b, k.c, 16, 2);
    PENUMBRA_EXPECT_REL(integral, closed, 1e-12); // reaches ~1e-14
    std::printf("parallel %gx%g at %g: closed %.12f integral %.12f rel.err %.2e\n", k.a, k.b, k.c,
      closed, integral, std::abs(integral - closed) / closed);
  }

  // Perpendicular rectangles sharing an edge.
  struct PerpCase
  {
    double h, w, l, given, digits;
  };
  const PerpCase perp[] = { { 1, 1, 1, 0.200044, 5e-7 }, { 2, 1, 1, 0.232853, 5e-7 },
    { 1, 2, 1, 0.116426, 5e-7 } };
  for (const PerpCase& k : perp)
  {
    const double closed = PerpendicularPlates(k.h, k.w, k.l);
    PENUMBRA_EXPECT_NEAR(closed, k.given, k.digits);
    const double integral = IntegratePerpendicular(k.h, k.w, k.l, 16, 30);
    PENUMBRA_EXPECT_REL(integral, closed, 1e-12); // reaches ~1e-14
    std::printf("perpendicular h=%g w=%g: closed %.12f integral %.12f rel.err %.2e\n", k.h, k.w,
      closed, integral, std::abs(integral - closed) / closed);
  }
  // Reciprocity of the closed forms: A1 F12 = A2 F21.
  PENUMBRA_EXPECT_REL(
    1.0 * PerpendicularPlates(2, 1, 1), 2.0 * PerpendicularPlates(1, 2, 1), 1e-13);
}

} // namespace
