// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the exact irradiance from linearly varying sources
// (penumbraLinearSource.h): Clausen's integral against known constants, the
// closed form against an independent adaptive Gauss-Legendre quadrature of the
// irradiance integral (parallel, tilted, near the source plane, far and small,
// cut by the receiver's tangent plane), the constant case against Lambert's
// formula, a piecewise-linear shooter through a visible region, and the paper's
// Fig. 7/8 half-lit shooter (the bump moves toward the bright half).
#include "penumbraFormFactor.h"
#include "penumbraLinearSource.h"
#include "penumbraShooterRadiance.h"
#include "penumbraTesting.h"

#include <cmath>
#include <cstdio>
#include <array>
#include <functional>
#include <vector>

using namespace penumbra;

namespace
{

constexpr double Pi = 3.141592653589793238462643383279502884;

// ---------------------------------------------------------------------------
// Independent reference: adaptive quadrature over triangles. Each triangle is
// integrated with an 8x8 Gauss-Legendre rule mapped by the Duffy (collapsed
// square) transform, then split into 4 by its midpoints until the estimate and
// the sum of the children's agree to an absolute tolerance.

struct GaussRule
{
  double X[8];
  double W[8];
  GaussRule()
  {
    // Nodes and weights of the 8-point rule on [0, 1] by Newton on P_8.
    const int n = 8;
    for (int i = 0; i < n; ++i)
    {
      double z = std::cos(Pi * (i + 0.75) / (n + 0.5));
      double dp = 0.0;
      for (int it = 0; it < 100; ++it)
      {
        double p0 = 1.0;
        double p1 = z;
        for (int k = 2; k <= n; ++k)
        {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-17)
        {
          break;
        }
      }
      this->X[i] = 0.5 * (1.0 - z);
      this->W[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

using Integrand = std::function<double(const Vec3&)>;

double TriangleRule(const Integrand& f, const Vec3& a, const Vec3& b, const Vec3& c)
{
  static const GaussRule rule;
  const double area = 0.5 * Length(Cross(b - a, c - a));
  double sum = 0.0;
  for (int i = 0; i < 8; ++i)
  {
    for (int j = 0; j < 8; ++j)
    {
      // (s, t) in the unit square -> (s, (1 - s) t) in the unit triangle.
      const double s = rule.X[i];
      const double t = rule.X[j] * (1.0 - s);
      const Vec3 y = a + (b - a) * s + (c - a) * t;
      sum += rule.W[i] * rule.W[j] * (1.0 - s) * f(y);
    }
  }
  return sum * 2.0 * area;
}

double AdaptiveTriangle(const Integrand& f, const Vec3& a, const Vec3& b, const Vec3& c,
  double estimate, double tolerance, int depth)
{
  const Vec3 ab = (a + b) * 0.5;
  const Vec3 bc = (b + c) * 0.5;
  const Vec3 ca = (c + a) * 0.5;
  const double q[4] = { TriangleRule(f, a, ab, ca), TriangleRule(f, ab, b, bc),
    TriangleRule(f, ca, bc, c), TriangleRule(f, ab, bc, ca) };
  const double children = q[0] + q[1] + q[2] + q[3];
  // The second bound is the rounding floor: the tolerance halves at each level
  // but the rounding errors of tiny triangles near a peak do not.
  const double magnitude = std::abs(q[0]) + std::abs(q[1]) + std::abs(q[2]) + std::abs(q[3]);
  if (std::abs(children - estimate) <= std::max(tolerance, 1e-14 * magnitude) || depth >= 40)
  {
    return children;
  }
  return AdaptiveTriangle(f, a, ab, ca, q[0], tolerance / 2, depth + 1) +
    AdaptiveTriangle(f, ab, b, bc, q[1], tolerance / 2, depth + 1) +
    AdaptiveTriangle(f, ca, bc, c, q[2], tolerance / 2, depth + 1) +
    AdaptiveTriangle(f, ab, bc, ca, q[3], tolerance / 2, depth + 1);
}

/// Test-local clip to Dot(n, y - x) >= 0 (kept independent of the library's).
std::vector<Vec3> ClipFront(const std::vector<Vec3>& poly, const Vec3& n, const Vec3& x)
{
  if (poly.empty())
  {
    return poly;
  }
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    const Vec3& p = poly[i];
    const Vec3& q = poly[(i + 1) % poly.size()];
    const double dp = Dot(n, p - x);
    const double dq = Dot(n, q - x);
    if (dp >= 0)
    {
      out.push_back(p);
    }
    if ((dp > 0 && dq < 0) || (dp < 0 && dq > 0))
    {
      out.push_back(p + (q - p) * (dp / (dp - dq)));
    }
  }
  return out;
}

/// Reference irradiance from a convex polygon with radiance L(y) (one channel).
double ReferenceIrradiance(const Vec3& x, const Vec3& n, const std::vector<Vec3>& polygon,
  const Vec3& frontNormal, const std::function<double(const Vec3&)>& radiance)
{
  const std::vector<Vec3> clipped = ClipFront(polygon, n, x);
  if (clipped.size() < 3)
  {
    return 0.0;
  }
  // The integrand peaks at the foot of the perpendicular from x, with width
  // the distance h to the plane. Quadrature runs in local coordinates
  // q = y - origin, the origin being the foot when it lies inside the polygon
  // (tiny triangles near the peak keep their relative precision), else the
  // polygon's vertex mean (no digit lost to the distance).
  const double h = -Dot(frontNormal, clipped[0] - x);
  Vec3 foot = x - frontNormal * h;
  std::vector<Vec3> local;
  for (const Vec3& p : clipped)
  {
    local.push_back(p - foot);
  }
  // Fan triangulation from the foot when it lies inside (the peak is then a
  // vertex of every triangle), else from the first vertex.
  const double orientation =
    Dot(Cross(local[1] - local[0], local[2] - local[0]), frontNormal) > 0 ? 1.0 : -1.0;
  bool footInside = true;
  for (std::size_t i = 0; i < local.size(); ++i)
  {
    const Vec3& p = local[i];
    const Vec3& q = local[(i + 1) % local.size()];
    footInside = footInside && orientation * Dot(Cross(q - p, -p), frontNormal) >= 0;
  }
  if (!footInside)
  {
    Vec3 mean;
    for (const Vec3& p : clipped)
    {
      mean += p / static_cast<double>(clipped.size());
    }
    for (std::size_t i = 0; i < clipped.size(); ++i)
    {
      local[i] = clipped[i] - mean;
    }
    foot = mean;
  }
  const Vec3 footFromX = foot - x;
  const Integrand f = [&](const Vec3& q) {
    const Vec3 r = footFromX + q;
    const double r2 = SquaredLength(r);
    const double cx = Dot(n, r);
    const double cy = -Dot(frontNormal, r);
    if (cx <= 0 || cy <= 0)
    {
      return 0.0;
    }
    return radiance(foot + q) * cx * cy / (r2 * r2);
  };
  std::vector<std::array<Vec3, 3>> fan;
  for (std::size_t i = 0; i < local.size(); ++i)
  {
    if (footInside)
    {
      fan.push_back({ Vec3(), local[i], local[(i + 1) % local.size()] });
    }
    else if (i >= 1 && i + 1 < local.size())
    {
      fan.push_back({ local[0], local[i], local[i + 1] });
    }
  }
  // Absolute tolerance from the scale of the answer, pi max|L| F (Lambert's
  // F of the clipped polygon, used only as a scale).
  double maxL = 0.0;
  for (const Vec3& p : clipped)
  {
    maxL = std::max(maxL, std::abs(radiance(p)));
  }
  const double formFactor = std::abs(
    PointPolygonFormFactorSigned(x, n, clipped.data(), static_cast<int>(clipped.size())));
  const double tolerance = 1e-14 * Pi * std::max(maxL, 1e-300) * std::max(formFactor, 1e-300);
  double sum = 0.0;
  for (const auto& t : fan)
  {
    const double q = TriangleRule(f, t[0], t[1], t[2]);
    sum += AdaptiveTriangle(f, t[0], t[1], t[2], q, tolerance, 0);
  }
  return sum;
}

Vec3 Unit(double x, double y, double z)
{
  return Normalized(Vec3(x, y, z));
}

/// Compare the closed form with the quadrature for one configuration.
void CheckConfiguration(const char* name, const Vec3& x, const Vec3& n,
  const std::vector<Vec3>& triangle, const RGB values[3], double tolerance)
{
  const Vec3 front = Normalized(Cross(triangle[1] - triangle[0], triangle[2] - triangle[0]));
  const RGB exact = LinearTriangleIrradiance(x, n, triangle.data(), values, front);
  const LinearRadiance f = LinearRadiance::FromTriangle(triangle.data(), values);
  double worst = 0.0;
  double scale = 0.0;
  double reference[3];
  for (int c = 0; c < 3; ++c)
  {
    reference[c] = ReferenceIrradiance(
      x, n, triangle, front, [&](const Vec3& y) { return f.Evaluate(y)[c]; });
    scale = std::max(scale, std::abs(reference[c]));
  }
  for (int c = 0; c < 3; ++c)
  {
    worst = std::max(worst, std::abs(exact[c] - reference[c]) / scale);
  }
  std::printf("  %-34s E = (%.15g, %.15g, %.15g)  max rel. diff %.2e\n", name, exact.R,
    exact.G, exact.B, worst);
  PENUMBRA_EXPECT(scale > 0.0);
  PENUMBRA_EXPECT(worst <= tolerance);
}

PENUMBRA_TEST(TestClausen)
{
  std::printf("Clausen's integral\n");
  // Catalan's constant G = Cl2(pi/2) and the maximum Cl2(pi/3) (OEIS A006752, A143298).
  PENUMBRA_EXPECT_NEAR(Clausen2(Pi / 2), 0.915965594177219015054603514932, 2e-16);
  PENUMBRA_EXPECT_NEAR(Clausen2(Pi / 3), 1.014941606409653625021202554275, 3e-16);
  // Duplication formula Cl2(2t) = 2 Cl2(t) - 2 Cl2(pi - t) gives Cl2(2 pi/3) = 2/3 Cl2(pi/3).
  PENUMBRA_EXPECT_NEAR(Clausen2(2 * Pi / 3), 2.0 / 3.0 * 1.014941606409653625021202554275, 3e-16);
  PENUMBRA_EXPECT_NEAR(Clausen2(Pi), 0.0, 1e-16);
  PENUMBRA_EXPECT_NEAR(Clausen2(0.0), 0.0, 0.0);
  // Odd, 2 pi periodic, t - t ln t near 0.
  PENUMBRA_EXPECT_NEAR(Clausen2(-1.234), -Clausen2(1.234), 1e-16);
  PENUMBRA_EXPECT_NEAR(Clausen2(1.234 + 6 * Pi), Clausen2(1.234), 1e-14);
  const double t = 1e-8;
  PENUMBRA_EXPECT_NEAR(Clausen2(t), t - t * std::log(t), 1e-22);
  // Against the defining series (partial sum with an Euler-Maclaurin tail).
  for (double theta : { 0.3, 1.1, 2.0, 2.9 })
  {
    long double sum = 0.0L;
    const long terms = 200000;
    for (long k = terms; k >= 1; --k)
    {
      sum += std::sin(static_cast<long double>(k) * theta) / (static_cast<long double>(k) * k);
    }
    // The tail sum_{k > N} sin(k t)/k^2 is below 1/(N^2 |sin(t/2)|).
    PENUMBRA_EXPECT_NEAR(Clausen2(theta), static_cast<double>(sum),
      1.0 / (double(terms) * terms * std::sin(theta / 2)) + 1e-15);
  }
}

PENUMBRA_TEST(TestAgainstQuadrature)
{
  // Required: 1e-9 everywhere; reached: 1e-12 or better except where noted.
  std::printf("closed form vs. adaptive quadrature (relative to the largest channel)\n");
  const RGB values[3] = { { 1.0, 0.2, 3.0 }, { 0.1, 2.0, 3.0 }, { 2.5, 0.7, 0.0 } };
  // Triangle 1 m above the receiver, parallel, facing down.
  // Counter-clockwise seen from below: the front faces the receivers.
  const std::vector<Vec3> parallel = { { -0.5, 1, -0.4 }, { 0.6, 1, -0.5 }, { 0.2, 1, 0.6 } };
  CheckConfiguration("parallel, foot inside", { 0, 0, 0 }, { 0, 1, 0 }, parallel, values, 1e-12);
  CheckConfiguration("parallel, foot outside", { 1.5, 0, 0.7 }, { 0, 1, 0 }, parallel, values, 1e-12);
  // Tilted source and tilted receiver.
  const std::vector<Vec3> tilted = { { -0.3, 1.4, 0.1 }, { 0.5, 0.8, -0.6 }, { 0.4, 1.6, 0.7 } };
  const Vec3 tiltedFront = Normalized(Cross(tilted[1] - tilted[0], tilted[2] - tilted[0]));
  std::vector<Vec3> tiltedFacing = tilted;
  if (Dot(tiltedFront, Vec3(0, 1.2, 0) - tilted[0]) < 0)
  {
    std::swap(tiltedFacing[1], tiltedFacing[2]); // front towards the receivers
  }
  CheckConfiguration("tilted source and receiver", { 0.1, 0.0, -0.2 }, Unit(0.3, 1.0, -0.2),
    tiltedFacing, values, 1e-12);
  // Receiver point 1e-3 below the source plane, foot inside, and beside it.
  CheckConfiguration("1e-3 from the plane, foot inside", { 0.05, 0.999, -0.05 }, { 0, 1, 0 },
    parallel, values, 1e-12);
  // Foot of the perpendicular exactly at a vertex and on an edge (edge lines
  // through the foot: zero-angle terms).
  CheckConfiguration("foot at a vertex, h = 0.01", { -0.5, 0.99, -0.4 }, { 0, 1, 0 }, parallel,
    values, 1e-12);
  CheckConfiguration("foot on an edge, h = 0.01", { 0.05, 0.99, -0.45 }, Unit(0.1, 1, 0.1),
    parallel, values, 1e-12);
  // Outside the footprint near the plane, F is O(h) from O(1) edge terms
  // (Lambert's formula itself): about 1e-16 size / h relative.
  CheckConfiguration("1e-3 from the plane, foot outside", { 0.9, 0.999, 0.1 }, { 0, 1, 0 },
    parallel, values, 1e-9);
  CheckConfiguration("receiver normal along the plane", { 0.9, 0.999, 0.1 }, Unit(-1, 0.001, 0),
    parallel, values, 1e-9);
  // Receiver tangent plane cutting the source: only part of it counts.
  CheckConfiguration("cut by the tangent plane", { 0.0, 0.5, 0.0 }, Unit(1.0, 0.3, 0.2),
    parallel, values, 1e-12);
  CheckConfiguration("cut, tilted", { 0.1, 0.9, 0.0 }, Unit(-0.4, 0.1, 1.0), tiltedFacing,
    values, 1e-12);
  // Small and far (the closed form would lose digits; the Gauss rules are
  // used below 0.15 radius / distance, the 4 x 4 one below 0.02): 100 and
  // 1000 times the size away, and just either side of each switch (the
  // triangle's radius over its distance is 0.665 scale).
  for (const double scale : { 0.01, 0.001, 0.0001, 0.0285, 0.0315, 0.22, 0.23 })
  {
    std::vector<Vec3> small;
    for (const Vec3& p : parallel)
    {
      small.push_back(Vec3(p.X * scale + 0.3, 1.0, p.Z * scale - 0.2));
    }
    char name[64];
    std::snprintf(name, sizeof(name), "small (%g), far", scale);
    CheckConfiguration(name, { 0, 0, 0 }, { 0, 1, 0 }, small, values, 1e-12);
  }
  // Large gradient: one vertex bright, two dark.
  const RGB spike[3] = { { 10, 10, 10 }, { 0, 0, 0 }, { 0, 1e-3, 0 } };
  CheckConfiguration("strong gradient", { 0.3, 0.2, -0.1 }, Unit(0.1, 1, 0), parallel, spike, 1e-12);
}

PENUMBRA_TEST(TestConstantCase)
{
  std::printf("zero gradient equals pi L F (Lambert)\n");
  // Counter-clockwise seen from below (front -y).
  const std::vector<Vec3> quad = { { -0.4, 2, -0.3 }, { 0.6, 2, -0.3 }, { 0.6, 2, 0.5 },
    { -0.4, 2, 0.5 } };
  const Vec3 front(0, -1, 0);
  const RGB l(17, 12, 4);
  const LinearRadiance constant = LinearRadiance::MakeConstant(l);
  for (const Vec3& x : { Vec3(0, 0, 0), Vec3(2, 0.5, 1), Vec3(0.1, 1.999, 0.1) })
  {
    for (const Vec3& n : { Vec3(0, 1, 0), Unit(1, 1, 0), Unit(-0.2, 0.5, 1) })
    {
      const double f = PointPolygonFormFactorClipped(x, n, quad);
      const RGB e = LinearPolygonIrradiance(x, n, quad.data(), 4, front, constant);
      for (int c = 0; c < 3; ++c)
      {
        PENUMBRA_EXPECT_REL(e[c], Pi * l[c] * f, 1e-13);
      }
      // The same through a mesh of equal values (a sum over 2 triangles).
      const ShooterRadiance mesh(quad, { { 0, 1, 2 }, { 0, 2, 3 } }, { l, l, l, l });
      LinearSourceWorkspace workspace;
      const RGB em = UnoccludedShooterIrradiance(x, n, mesh, quad, workspace);
      // A sum of two Lambert sums: the diagonal's terms cancel to rounding
      // of their own size, so compare in units of pi L (F = 1).
      for (int c = 0; c < 3; ++c)
      {
        PENUMBRA_EXPECT_NEAR(em[c], Pi * l[c] * f, 1e-13 * Pi * l[c]);
      }
    }
  }
}

PENUMBRA_TEST(TestShooterMesh)
{
  std::printf("piecewise-linear shooter through a visible region\n");
  // Shooter: square [-1, 1]^2 at y = 1 facing down, a 3 x 3 grid of points
  // (8 triangles) with values from a bumpy function: not one linear function.
  std::vector<Vec3> points;
  std::vector<RGB> values;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      const double u = -1.0 + i;
      const double v = -1.0 + j;
      points.push_back(Vec3(u, 1, v));
      values.push_back(RGB(1 + u * u + 0.5 * v, 2 - u, 1 + (i == 1 && j == 1 ? 3 : 0)));
    }
  }
  std::vector<std::array<int, 3>> triangles;
  for (int j = 0; j < 2; ++j)
  {
    for (int i = 0; i < 2; ++i)
    {
      const int a = j * 3 + i;
      triangles.push_back({ a, a + 1, a + 4 });
      triangles.push_back({ a, a + 4, a + 3 });
    }
  }
  const ShooterRadiance radiance(points, triangles, values);
  PENUMBRA_EXPECT(!radiance.IsConstant());
  PENUMBRA_EXPECT(radiance.GetNumberOfTriangles() == 8);
  // Evaluate: interpolation and the exact integral.
  const RGB centre = radiance.Evaluate(Vec3(0, 1.3, 0)); // projected onto the plane
  PENUMBRA_EXPECT_NEAR(centre.B, 4.0, 1e-14);
  PENUMBRA_EXPECT_NEAR(radiance.Evaluate(Vec3(0.5, 1, 0.5)).G, 1.5, 1e-14);
  PENUMBRA_EXPECT(radiance.Evaluate(Vec3(3, 1, 0)).IsZero());
  PENUMBRA_EXPECT(radiance.FindTriangle(Vec3(1.5, 1, 0)) == -1);
  // int (2 - u) over [-1,1]^2 = 8 exactly; the B channel: 4 plus the hat of
  // height 3 at the centre point, whose support is 6 triangles of area 1/2
  // (the diagonals of two cells miss the centre): volume 3 * 3 / 3.
  PENUMBRA_EXPECT_NEAR(radiance.Integrate(0.0).G, 8.0, 1e-13);
  PENUMBRA_EXPECT_NEAR(radiance.Integrate(0.0).B, 7.0, 1e-13);
  PENUMBRA_EXPECT_NEAR(ShooterRadiance(RGB(2, 3, 4)).Integrate(0.5).B, 2.0, 0.0);

  // Visible region: two convex pieces (the shooter minus a vertical band and a corner).
  VisibleRegion region;
  const std::vector<std::vector<Vec3>> pieces = {
    { { -1, 1, -1 }, { -1, 1, 1 }, { -0.2, 1, 1 }, { -0.35, 1, -1 } },
    { { 0.3, 1, -1 }, { 0.1, 1, 1 }, { 1, 1, 1 }, { 1, 1, 0.2 }, { 0.6, 1, -1 } },
  };
  for (const auto& piece : pieces)
  {
    region.Offsets.push_back(static_cast<int>(region.Points.size()));
    // Counter-clockwise seen from the front (normal -y): reverse the listing.
    for (auto it = piece.rbegin(); it != piece.rend(); ++it)
    {
      region.Points.push_back(*it);
    }
  }
  region.Offsets.push_back(static_cast<int>(region.Points.size()));
  const Vec3 front(0, -1, 0);
  LinearSourceWorkspace workspace;
  for (const Vec3& x : { Vec3(0, 0, 0), Vec3(1.3, 0.2, -0.4), Vec3(0.2, 0.95, 0.1) })
  {
    const Vec3 n = Unit(0.2, 1, -0.1);
    const RGB exact = VisibleShooterIrradiance(x, n, radiance, region, front, workspace);
    // Reference: quadrature over every (piece, mesh triangle) intersection,
    // clipped here by test-local code, where the integrand is smooth.
    double reference[3] = { 0, 0, 0 };
    for (const auto& piece : pieces)
    {
      for (int t = 0; t < radiance.GetNumberOfTriangles(); ++t)
      {
        const RadianceTriangle tri = radiance.GetTriangle(t);
        std::vector<Vec3> part = piece;
        for (int k = 0; k < 3; ++k)
        {
          const Vec3& p = tri.Points[k];
          const Vec3& q = tri.Points[(k + 1) % 3];
          // Every mesh triangle is counter-clockwise about -y: inside is Cross(-y, q - p).
          part = ClipFront(part, Cross(front, q - p), p);
        }
        const LinearRadiance& f = radiance.GetTriangleFunction(t);
        for (int c = 0; c < 3; ++c)
        {
          reference[c] +=
            ReferenceIrradiance(x, n, part, front, [&](const Vec3& y) { return f.Evaluate(y)[c]; });
        }
      }
    }
    for (int c = 0; c < 3; ++c)
    {
      PENUMBRA_EXPECT_REL(exact[c], reference[c], 1e-9);
    }
    std::printf("  x = (%g, %g, %g): E = (%.12g, %.12g, %.12g), quadrature (%.12g, %.12g, %.12g)\n",
      x.X, x.Y, x.Z, exact.R, exact.G, exact.B, reference[0], reference[1], reference[2]);
  }
}

PENUMBRA_TEST(TestInvalidMesh)
{
  const std::vector<Vec3> p = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0.5 } };
  const std::vector<RGB> v(4, RGB(1, 1, 1));
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, { { 0, 1, 5 } }, v), InputError, "triangle 0");
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, { { 0, 1, 2 }, { 1, 3, 2 } }, v), InputError, "off the plane");
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, { { 0, 1, 1 } }, v), InputError, "degenerate");
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, { { 0, 1, 1 }, { 2, 2, 0 } }, v), InputError, "every triangle");
}

/// A sliver beside a real triangle carries nothing: it is dropped and the
/// irradiance is that of the real triangle alone.
PENUMBRA_TEST(TestSliverDropped)
{
  // Unit right triangle at z = 0 facing +z, radiance rising along x, and a
  // sliver of area 1e-14 along its hypotenuse's far side.
  const std::vector<Vec3> p = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0.5, 0.5 + 1e-14, 0 } };
  const std::vector<RGB> v = { RGB(1, 1, 1), RGB(3, 2, 1), RGB(1, 1, 1), RGB(50, 50, 50) };
  const ShooterRadiance withSliver(p, { { 0, 1, 2 }, { 1, 3, 2 } }, v);
  const ShooterRadiance alone(p, { { 0, 1, 2 } }, v);
  PENUMBRA_EXPECT(withSliver.GetNumberOfTriangles() == 1);
  PENUMBRA_EXPECT(withSliver.GetNumberOfDroppedTriangles() == 1);
  PENUMBRA_EXPECT_REL(withSliver.GetTriangleArea(0), 0.5, 1e-12);
  // Exact integral of the linear radiance: area x mean of the corner values.
  PENUMBRA_EXPECT_REL(withSliver.Integrate(0.0).R, 0.5 * (1.0 + 3.0 + 1.0) / 3.0, 1e-12);
  PENUMBRA_EXPECT_REL(withSliver.Integrate(0.0).G, alone.Integrate(0.0).G, 1e-15);
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, { { 0, 1, 2 } }, { RGB() }), InputError, "values");
  PENUMBRA_EXPECT_THROW(ShooterRadiance(p, {}, v), InputError, "no triangle");
}

/// The paper's Fig. 7/8: a shooter bright on one half gives a shifted bump.
PENUMBRA_TEST(TestHalfLitShooter)
{
  std::printf("half-lit shooter (paper Fig. 7/8)\n");
  // Shooter [-1, 1] x [-1, 1] at y = 1 facing down; radiance 0 for u < -0.05,
  // 1 for u > 0.05, a linear ramp in between (a step approximated by a mesh).
  const double us[4] = { -1.0, -0.05, 0.05, 1.0 };
  const double ls[4] = { 0.0, 0.0, 1.0, 1.0 };
  std::vector<Vec3> points;
  std::vector<RGB> values;
  for (int j = 0; j < 2; ++j)
  {
    for (int i = 0; i < 4; ++i)
    {
      points.push_back(Vec3(us[i], 1, j == 0 ? -1.0 : 1.0));
      values.push_back(RGB(ls[i], ls[i], ls[i]));
    }
  }
  std::vector<std::array<int, 3>> triangles;
  for (int i = 0; i < 3; ++i)
  {
    triangles.push_back({ i, i + 1, i + 5 });
    triangles.push_back({ i, i + 5, i + 4 });
  }
  const ShooterRadiance halfLit(points, triangles, values);
  const std::vector<Vec3> shooter = { { -1, 1, -1 }, { 1, 1, -1 }, { 1, 1, 1 }, { -1, 1, 1 } };
  // Constant shooter with the same power (mean 0.5): "standard radiosity".
  const ShooterRadiance uniform(halfLit.Integrate(0.0) * 0.25);
  LinearSourceWorkspace workspace;
  const auto irradiance = [&](const ShooterRadiance& r, double s) {
    return UnoccludedShooterIrradiance(Vec3(s, 0, 0), Vec3(0, 1, 0), r, shooter, workspace).R;
  };
  // Golden-section search for the peak on the receiver line z = 0.
  const auto peak = [&](const ShooterRadiance& r) {
    double a = -1.5;
    double b = 1.5;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a);
    double d = a + g * (b - a);
    while (b - a > 1e-9)
    {
      if (irradiance(r, c) > irradiance(r, d))
      {
        b = d;
      }
      else
      {
        a = c;
      }
      c = b - g * (b - a);
      d = a + g * (b - a);
    }
    return 0.5 * (a + b);
  };
  const double peakUniform = peak(uniform);
  const double peakHalfLit = peak(halfLit);
  std::printf("  peak of the uniform shooter's bump at x = %.6f, half-lit at x = %.6f\n",
    peakUniform, peakHalfLit);
  for (double s = -2.0; s <= 2.001; s += 0.5)
  {
    std::printf("  x = %5.2f  uniform E = %.6f  half-lit E = %.6f\n", s, irradiance(uniform, s),
      irradiance(halfLit, s));
  }
  PENUMBRA_EXPECT_NEAR(peakUniform, 0.0, 1e-6);
  PENUMBRA_EXPECT(peakHalfLit > 0.1); // toward the bright half (+x)
  PENUMBRA_EXPECT(irradiance(halfLit, 0.8) > 2.0 * irradiance(halfLit, -0.8));
  // Same power: the bumps have the same total (checked at symmetric pairs).
  PENUMBRA_EXPECT_REL(irradiance(halfLit, 0.7) + irradiance(halfLit, -0.7),
    2.0 * irradiance(uniform, 0.7), 1e-12);
}

} // namespace

// A receiving point at a vertex of the source, a rounding error above its
// plane (a box's corner on the floor it stands on): the integral is tiny
// and must stay finite (it was NaN, from the moments' centroid 0 / 0).
PENUMBRA_TEST(TestPointAtVertex)
{
  const Vec3 points[3] = { Vec3(0, 0, 0), Vec3(0.05, 0, 0), Vec3(0, 0, 0.05) };
  const RGB values[3] = { RGB(1, 0, 0), RGB(0, 1, 0), RGB(0, 0, 1) };
  for (const double height : { 0.0, 5e-10, 1e-7 })
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const Vec3 x = points[corner] + Vec3(0, height, 0);
      for (const Vec3& n : { Vec3(-1, 0, 0), Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, 1, 0) })
      {
        const RGB e = LinearTriangleIrradiance(x, n, points, values, Vec3(0, 1, 0));
        const bool finite = std::isfinite(e.R) && std::isfinite(e.G) && std::isfinite(e.B);
        if (!finite)
        {
          std::printf("non-finite at corner %d, height %g, n (%g %g %g)\n", corner, height, n.X,
            n.Y, n.Z);
        }
        PENUMBRA_EXPECT(finite);
        PENUMBRA_EXPECT(e.R >= 0.0 && e.G >= 0.0 && e.B >= 0.0);
        // Bounded by the irradiance of a unit radiance over the whole
        // hemisphere seen through the triangle's plane from that height.
        PENUMBRA_EXPECT(e.R + e.G + e.B <= Pi);
      }
    }
  }
}
