// SPDX-License-Identifier: GPL-3.0-or-later
// The coarse level of the interreflections (penumbraIndirectLevel.h) against
// invariants: the restriction keeps each channel's integral and reproduces
// constants, the prolongation reproduces linear increments exactly, the
// lattice covers the polygon (areas add up, also for a non-convex one), the
// point count matches CountPoints, IndirectSpacing meets its budget, and no
// light is interpolated across an occluder (a wall standing on the surface,
// a plate hung just above it).
#include "penumbraIndirectLevel.h"
#include "penumbraRayCaster.h"
#include "penumbraTesting.h"

#include <cmath>
#include <random>
#include <vector>

using penumbra::Cross;
using penumbra::Dot;
using penumbra::IndirectLevel;
using penumbra::Length;
using penumbra::RGB;
using penumbra::Scene;
using penumbra::Surface;
using penumbra::SurfaceSamples;
using penumbra::Vec3;

namespace
{

/// An L-shaped polygon (non-convex) in a tilted plane, counter-clockwise.
Surface LShape()
{
  const double uv[6][2] = { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 3 }, { 0, 3 } };
  const Vec3 origin(0.3, -1.2, 2.0);
  const Vec3 u = penumbra::Normalized(Vec3(1.0, 0.2, -0.3));
  const Vec3 v = penumbra::Normalized(Cross(Vec3(0.1, 0.3, 1.0), u));
  Surface s;
  for (const auto& p : uv)
  {
    s.Vertices.push_back(origin + u * p[0] + v * p[1]);
  }
  s.Reflectance = RGB(0.5, 0.5, 0.5);
  return s;
}

/// Fine samples: a jittered grid of points clipped to the L (in its frame),
/// triangulated cell by cell; values random per point.
SurfaceSamples FineSamples(const Surface& s, int cells, std::mt19937& random)
{
  const Vec3 o = s.Vertices[0];
  const Vec3 u = penumbra::Normalized(s.Vertices[1] - s.Vertices[0]);
  const Vec3 n = penumbra::Normalized(Cross(s.Vertices[1] - s.Vertices[0], s.Vertices[2] - s.Vertices[1]));
  const Vec3 v = Cross(n, u);
  std::uniform_real_distribution<double> value(0.0, 2.0);
  SurfaceSamples f;
  // Points of a (cells*4) x (cells*3) lattice over [0,4] x [0,3]; cells
  // outside the L are skipped (the L is a union of whole cells).
  const int nu = 4 * cells, nv = 3 * cells;
  std::vector<int> id((nu + 1) * (nv + 1), -1);
  const auto inside = [&](double a, double b) { return a <= 1.0 + 1e-12 || b <= 1.0 + 1e-12; };
  for (int i = 0; i <= nu; ++i)
  {
    for (int j = 0; j <= nv; ++j)
    {
      const double a = 4.0 * i / nu, b = 3.0 * j / nv;
      if (inside(a, b))
      {
        id[i * (nv + 1) + j] = static_cast<int>(f.Points.size());
        f.Points.push_back(o + u * a + v * b);
        f.Total.emplace_back(value(random), value(random), value(random));
        f.Unshot.emplace_back(value(random), value(random), value(random));
      }
    }
  }
  for (int i = 0; i < nu; ++i)
  {
    for (int j = 0; j < nv; ++j)
    {
      const double a = 4.0 * (i + 0.5) / nu, b = 3.0 * (j + 0.5) / nv;
      if (!inside(a, b))
      {
        continue;
      }
      const int p00 = id[i * (nv + 1) + j], p10 = id[(i + 1) * (nv + 1) + j];
      const int p01 = id[i * (nv + 1) + j + 1], p11 = id[(i + 1) * (nv + 1) + j + 1];
      f.Triangles.push_back({ p00, p10, p11 });
      f.Triangles.push_back({ p00, p11, p01 });
    }
  }
  return f;
}

double Area(const SurfaceSamples& s, const std::array<int, 3>& t)
{
  return 0.5 * Length(Cross(s.Points[t[1]] - s.Points[t[0]], s.Points[t[2]] - s.Points[t[0]]));
}

/// Integral of the piecewise-linear interpolant of `values` over s's triangles.
RGB Integral(const SurfaceSamples& s, const std::vector<RGB>& values)
{
  RGB sum;
  for (const auto& t : s.Triangles)
  {
    sum += (values[t[0]] + values[t[1]] + values[t[2]]) * (Area(s, t) / 3.0);
  }
  return sum;
}

PENUMBRA_TEST(TestCoverAndCount)
{
  const Surface s = LShape();
  std::mt19937 random(1);
  const SurfaceSamples fine = FineSamples(s, 8, random);
  for (const double spacing : { 0.07, 0.3, 1.0, 10.0 })
  {
    const IndirectLevel level(s, spacing, fine);
    const SurfaceSamples coarse = level.Restrict(fine);
    double area = 0.0;
    for (const auto& t : coarse.Triangles)
    {
      area += Area(coarse, t);
    }
    PENUMBRA_EXPECT_REL(area, 6.0, 1e-12); // the L: 4 x 1 plus 1 x 2
    PENUMBRA_EXPECT(level.GetNumberOfPoints() == IndirectLevel::CountPoints(s, spacing));
    PENUMBRA_EXPECT(coarse.Points.size() == level.GetNumberOfPoints());
  }
}

PENUMBRA_TEST(TestRestriction)
{
  const Surface s = LShape();
  std::mt19937 random(2);
  const SurfaceSamples fine = FineSamples(s, 10, random);
  const RGB fineTotal = Integral(fine, fine.Total);
  const RGB fineUnshot = Integral(fine, fine.Unshot);
  for (const double spacing : { 0.05, 0.23, 0.8, 5.0 })
  {
    const IndirectLevel level(s, spacing, fine);
    const SurfaceSamples coarse = level.Restrict(fine);
    const RGB total = Integral(coarse, coarse.Total);
    const RGB unshot = Integral(coarse, coarse.Unshot);
    for (int c = 0; c < 3; ++c)
    {
      PENUMBRA_EXPECT_REL(total[c], fineTotal[c], 1e-12);
      PENUMBRA_EXPECT_REL(unshot[c], fineUnshot[c], 1e-12);
    }
    for (std::size_t k = 0; k < coarse.Points.size(); ++k)
    {
      PENUMBRA_EXPECT(coarse.Total[k].R >= 0.0 && coarse.Unshot[k].B >= 0.0);
    }
  }
  // A constant is reproduced at every coarse point.
  SurfaceSamples constant = fine;
  for (RGB& value : constant.Total)
  {
    value = RGB(0.25, 1.5, 3.0);
  }
  const IndirectLevel level(s, 0.3, constant);
  const SurfaceSamples coarse = level.Restrict(constant);
  double worst = 0.0;
  for (const RGB& value : coarse.Total)
  {
    worst = std::max({ worst, std::abs(value.R - 0.25), std::abs(value.G - 1.5), std::abs(value.B - 3.0) });
  }
  PENUMBRA_EXPECT_NEAR(worst, 0.0, 1e-12);
}

PENUMBRA_TEST(TestProlongation)
{
  const Surface s = LShape();
  std::mt19937 random(3);
  SurfaceSamples fine = FineSamples(s, 6, random);
  const std::vector<RGB> initial = fine.Total;
  const IndirectLevel level(s, 0.37, fine);
  const SurfaceSamples before = level.Restrict(fine);
  // A linear increment g(x) = a + b . x per channel is interpolated exactly.
  const Vec3 b[3] = { Vec3(0.1, -0.2, 0.3), Vec3(0.0, 0.5, 0.1), Vec3(-0.3, 0.05, 0.2) };
  const auto g = [&](const Vec3& x) {
    return RGB(2.0 + Dot(b[0], x), 2.0 + Dot(b[1], x), 2.0 + Dot(b[2], x));
  };
  SurfaceSamples after = before;
  for (std::size_t k = 0; k < after.Points.size(); ++k)
  {
    after.Total[k] += g(after.Points[k]);
  }
  level.Prolong(before, after, fine);
  double worst = 0.0;
  for (std::size_t k = 0; k < fine.Points.size(); ++k)
  {
    const RGB expected = initial[k] + g(fine.Points[k]);
    for (int c = 0; c < 3; ++c)
    {
      worst = std::max(worst, std::abs(fine.Total[k][c] - expected[c]));
    }
  }
  PENUMBRA_EXPECT_NEAR(worst, 0.0, 1e-12);
}

PENUMBRA_TEST(TestSpacing)
{
  Scene scene;
  scene.Surfaces.push_back(LShape());
  Surface square;
  square.Vertices = { Vec3(0, 0, 5), Vec3(2, 0, 5), Vec3(2, 2, 5), Vec3(0, 2, 5) };
  scene.Surfaces.push_back(square);
  const std::vector<std::size_t> fine = { 5000, 20 };
  PENUMBRA_EXPECT(penumbra::IndirectSpacing(scene, fine, 6000) == 0.0);
  for (const std::size_t budget : { 50u, 300u, 2000u })
  {
    const double h = penumbra::IndirectSpacing(scene, fine, budget);
    PENUMBRA_EXPECT(h > 0.0);
    std::size_t count = 0, finer = 0;
    for (std::size_t i = 0; i < 2; ++i)
    {
      count += std::min(fine[i], IndirectLevel::CountPoints(scene.Surfaces[i], h));
      finer += std::min(fine[i], IndirectLevel::CountPoints(scene.Surfaces[i], (1.0 - 1e-6) * h));
    }
    PENUMBRA_EXPECT(count <= budget);
    PENUMBRA_EXPECT(finer > budget); // the smallest spacing within the budget
  }
}

PENUMBRA_TEST(TestSeparateOccluded)
{
  // A 4 x 4 floor (y = 0, facing up), divided by a wall 1 high standing
  // on it at x = 3, and a 0.2 x 0.2 plate hung 5 mm above it, smaller than
  // the lattice spacing (1), so that no lattice point lies under it.
  Scene scene;
  Surface floor;
  floor.Vertices = { Vec3(0, 0, 0), Vec3(0, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, 0) };
  floor.Reflectance = RGB(0.5, 0.5, 0.5);
  Surface wall;
  wall.Vertices = { Vec3(3, 0, 0), Vec3(3, 1, 0), Vec3(3, 1, 4), Vec3(3, 0, 4) };
  wall.Reflectance = RGB(0.5, 0.5, 0.5);
  Surface plate;
  plate.Vertices = { Vec3(1.0, 0.005, 1.0), Vec3(1.0, 0.005, 1.2), Vec3(1.2, 0.005, 1.2),
    Vec3(1.2, 0.005, 1.0) };
  plate.Reflectance = RGB(0.5, 0.5, 0.5);
  scene.Surfaces = { floor, wall, plate };
  const penumbra::RayCaster caster(scene);

  SurfaceSamples fine;
  const int cells = 80; // 5 cm
  for (int i = 0; i <= cells; ++i)
  {
    for (int j = 0; j <= cells; ++j)
    {
      fine.Points.push_back(Vec3(4.0 * i / cells, 0.0, 4.0 * j / cells));
      fine.Total.emplace_back(0.0, 0.0, 0.0);
      fine.Unshot.emplace_back(0.0, 0.0, 0.0);
    }
  }
  for (int i = 0; i < cells; ++i)
  {
    for (int j = 0; j < cells; ++j)
    {
      const int p = i * (cells + 1) + j;
      fine.Triangles.push_back({ p, p + cells + 1, p + cells + 2 });
      fine.Triangles.push_back({ p, p + cells + 2, p + 1 });
    }
  }
  IndirectLevel level(floor, 1.0, fine);
  const std::size_t separate = level.SeparateOccluded(fine, 0, caster, penumbra::ParallelFor());
  PENUMBRA_EXPECT(separate == level.GetNumberOfSeparatePoints());
  const SurfaceSamples before = level.Restrict(fine);
  PENUMBRA_EXPECT(before.Points.size() == level.GetNumberOfPoints() + separate);
  PENUMBRA_EXPECT(before.Triangles.size() == level.Restrict(fine).Triangles.size());

  // Light arrives 1 on the near side of the wall, 5 beyond it, 0 under the
  // plate: every fine point must get exactly its own side's value.
  const auto underPlate = [](const Vec3& x) {
    return x.X > 1.0 && x.X < 1.2 && x.Z > 1.0 && x.Z < 1.2;
  };
  const auto arriving = [&](const Vec3& x) {
    return underPlate(x) ? 0.0 : (x.X < 3.0 ? 1.0 : 5.0);
  };
  SurfaceSamples after = before;
  for (std::size_t k = 0; k < after.Points.size(); ++k)
  {
    after.Total[k] += RGB(1.0, 1.0, 1.0) * arriving(after.Points[k]);
  }
  level.Prolong(before, after, fine);
  int checked = 0, under = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < fine.Points.size(); ++k)
  {
    const Vec3& x = fine.Points[k];
    const bool onPlateOutline = (std::abs(x.X - 1.0) < 1e-9 || std::abs(x.X - 1.2) < 1e-9 ||
                                  std::abs(x.Z - 1.0) < 1e-9 || std::abs(x.Z - 1.2) < 1e-9) &&
      x.X > 1.0 - 1e-9 && x.X < 1.2 + 1e-9 && x.Z > 1.0 - 1e-9 && x.Z < 1.2 + 1e-9;
    if (std::abs(x.X - 3.0) < 1e-9 || onPlateOutline)
    {
      continue; // on the wall's foot or under the plate's edge: either side
    }
    worst = std::max(worst, std::abs(fine.Total[k].G - arriving(x)));
    ++checked;
    under += underPlate(x) ? 1 : 0;
  }
  PENUMBRA_EXPECT(under == 9 && checked == 81 * 80 - 16);
  PENUMBRA_EXPECT_NEAR(worst, 0.0, 1e-12);
  // Only points near the occluders are evaluated on their own: those under
  // the plate and those sharing a lattice triangle (0.94 across) with a
  // corner beyond the wall or under the plate.
  PENUMBRA_EXPECT(separate >= 9 && separate < fine.Points.size() / 2);
  double farthest = 0.0;
  for (std::size_t k = level.GetNumberOfPoints(); k < before.Points.size(); ++k)
  {
    const Vec3& x = before.Points[k];
    const double toWall = std::abs(x.X - 3.0);
    const double toPlate = std::hypot(std::max({ 1.0 - x.X, x.X - 1.2, 0.0 }),
      std::max({ 1.0 - x.Z, x.Z - 1.2, 0.0 }));
    farthest = std::max(farthest, std::min(toWall, toPlate));
  }
  PENUMBRA_EXPECT(farthest < 0.95);

  // Without the separation, light crosses both (the premise of the test).
  SurfaceSamples plain = fine;
  for (RGB& value : plain.Total)
  {
    value = RGB(0.0, 0.0, 0.0);
  }
  const IndirectLevel blind(floor, 1.0, plain);
  const SurfaceSamples blindBefore = blind.Restrict(plain);
  SurfaceSamples blindAfter = blindBefore;
  for (std::size_t k = 0; k < blindAfter.Points.size(); ++k)
  {
    blindAfter.Total[k] += RGB(1.0, 1.0, 1.0) * arriving(blindAfter.Points[k]);
  }
  blind.Prolong(blindBefore, blindAfter, plain);
  double leak = 0.0;
  for (std::size_t k = 0; k < plain.Points.size(); ++k)
  {
    if (std::abs(plain.Points[k].X - 3.0) > 1e-9)
    {
      leak = std::max(leak, std::abs(plain.Total[k].G - arriving(plain.Points[k])));
    }
  }
  PENUMBRA_EXPECT(leak > 0.5);
}

} // namespace
