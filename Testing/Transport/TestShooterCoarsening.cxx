// SPDX-License-Identifier: GPL-3.0-or-later
// CoarsenShooterRadiance: a secondary shooter's radiance on fewer triangles,
// within the tolerance of the values it drops, its creases kept.
#include "penumbraShooterCoarsening.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <set>
#include <vector>

using namespace penumbra;

namespace
{

using Field = std::function<RGB(double x, double z)>;

// A jittered n x n grid on [0, 1]^2 in the plane y = 1 (normal -y), values
// of `field`; the column x = 0.5 straight when `crease` is set, its edges
// returned in `creases`.
ShooterRadiance Grid(int n, const Field& field, bool crease,
  std::vector<std::array<int, 2>>* creases = nullptr)
{
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2); // no triangle folds
  std::vector<Vec3> points;
  std::vector<RGB> values;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      double x = static_cast<double>(i) / n, z = static_cast<double>(j) / n;
      const bool straight = crease && 2 * i == n;
      if (i > 0 && i < n && !straight)
      {
        x += jitter(rng) / n;
      }
      if (j > 0 && j < n)
      {
        z += jitter(rng) / n;
      }
      points.emplace_back(x, 1.0, z);
      values.push_back(field(x, z));
    }
  }
  std::vector<std::array<int, 3>> triangles;
  const auto id = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < n; ++j)
    {
      triangles.push_back({ id(i, j), id(i + 1, j), id(i + 1, j + 1) });
      triangles.push_back({ id(i, j), id(i + 1, j + 1), id(i, j + 1) });
      if (creases && crease && 2 * i == n)
      {
        creases->push_back({ id(i, j), id(i, j + 1) });
      }
    }
  }
  return ShooterRadiance(points, triangles, values);
}

double AreaMean(const ShooterRadiance& r, int channel)
{
  const RGB integral = r.Integrate(0.0);
  double area = 0.0;
  for (int t = 0; t < r.GetNumberOfTriangles(); ++t)
  {
    area += r.GetTriangleArea(t);
  }
  return integral[channel] / area;
}

} // namespace

PENUMBRA_TEST(TestLinearRadianceMergesExactly)
{
  const Field linear = [](double x, double z) {
    return RGB(1.0 + 2.0 * x - 0.5 * z, 3.0 - x, 0.2 + z);
  };
  const ShooterRadiance fine = Grid(24, linear, false);
  const ShooterRadiance coarse = CoarsenShooterRadiance(fine, {}, 1e-3);
  std::printf("linear radiance: %d triangles -> %d\n", fine.GetNumberOfTriangles(),
    coarse.GetNumberOfTriangles());
  PENUMBRA_EXPECT(coarse.GetNumberOfTriangles() * 20 < fine.GetNumberOfTriangles());
  const RGB a = fine.Integrate(0.0), b = coarse.Integrate(0.0);
  for (int c = 0; c < 3; ++c)
  {
    PENUMBRA_EXPECT_REL(b[c], a[c], 1e-12);
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.01, 0.99);
  for (int k = 0; k < 200; ++k)
  {
    const double x = unit(rng), z = unit(rng);
    const RGB value = coarse.Evaluate(Vec3(x, 1.0, z)), exact = linear(x, z);
    for (int c = 0; c < 3; ++c)
    {
      PENUMBRA_EXPECT_NEAR(value[c], exact[c], 1e-12 * 4.0);
    }
  }
}

PENUMBRA_TEST(TestDroppedValuesWithinTolerance)
{
  const Field smooth = [](double x, double z) {
    return RGB(1.0 + 0.5 * std::sin(3.0 * x) * std::cos(2.0 * z), 2.0 + x * x, 0.3 + 0.1 * z * x);
  };
  const ShooterRadiance fine = Grid(40, smooth, false);
  for (const double tolerance : { 1e-3, 1e-2 })
  {
    const ShooterRadiance coarse = CoarsenShooterRadiance(fine, {}, tolerance);
    double worst = 0.0; // relative to the tolerance times the area mean
    for (std::size_t p = 0; p < fine.GetPoints().size(); ++p)
    {
      const RGB value = coarse.Evaluate(fine.GetPoints()[p]);
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst,
          std::abs(value[c] - fine.GetValues()[p][c]) / (tolerance * AreaMean(fine, c)));
      }
    }
    std::printf("tolerance %g: %d triangles -> %d, largest deviation at the fine points "
                "%.3f of the tolerance\n",
      tolerance, fine.GetNumberOfTriangles(), coarse.GetNumberOfTriangles(), worst);
    PENUMBRA_EXPECT(coarse.GetNumberOfTriangles() < fine.GetNumberOfTriangles() / 2);
    PENUMBRA_EXPECT(worst <= 1.0 + 1e-9);
  }
}

PENUMBRA_TEST(TestCreasesStay)
{
  // A kink along x = 0.5: every point of the crease stays, so the kink does.
  const Field kink = [](double x, double z) {
    const RGB value(1.0 + 4.0 * std::abs(x - 0.5), 1.0, 1.0 + z);
    return value;
  };
  std::vector<std::array<int, 2>> creases;
  const ShooterRadiance fine = Grid(20, kink, true, &creases);
  const ShooterRadiance coarse = CoarsenShooterRadiance(fine, creases, 1e-2);
  std::set<int> used;
  for (const auto& tri : coarse.GetTriangles())
  {
    used.insert(tri.begin(), tri.end());
  }
  int kept = 0;
  for (const auto& edge : creases)
  {
    kept += used.count(edge[0]) && used.count(edge[1]) ? 1 : 0;
  }
  std::printf("kink: %d triangles -> %d, %d of %zu crease edges' points kept\n",
    fine.GetNumberOfTriangles(), coarse.GetNumberOfTriangles(), kept, creases.size());
  PENUMBRA_EXPECT(kept == static_cast<int>(creases.size()));
  PENUMBRA_EXPECT(coarse.GetNumberOfTriangles() < fine.GetNumberOfTriangles());
  // Piecewise linear on either side of the crease: reproduced exactly.
  for (const double x : { 0.2, 0.45, 0.5, 0.55, 0.8 })
  {
    const RGB value = coarse.Evaluate(Vec3(x, 1.0, 0.37));
    PENUMBRA_EXPECT_NEAR(value.R, kink(x, 0.37).R, 1e-12);
  }
}

PENUMBRA_TEST(TestNothingToMerge)
{
  const ShooterRadiance constant(RGB(1.0, 2.0, 3.0));
  PENUMBRA_EXPECT(CoarsenShooterRadiance(constant, {}, 1e-2).IsConstant());
  const Field linear = [](double x, double) { return RGB(x, x, x); };
  const ShooterRadiance fine = Grid(6, linear, false);
  PENUMBRA_EXPECT(CoarsenShooterRadiance(fine, {}, 0.0).GetNumberOfTriangles() ==
    fine.GetNumberOfTriangles());
}
