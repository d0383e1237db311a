// SPDX-License-Identifier: GPL-3.0-or-later
// Exact visibility and the exact form factor of a partly occluded shooter,
// against closed forms (aligned rectangles) and against an independent
// brute-force Monte Carlo integration written here (uniform samples on the
// shooter, a segment test against every polygon of the scene).
#include "penumbraExactEvaluator.h"
#include "penumbraFormFactor.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <string>
#include <vector>

// Count heap allocations, to check that queries allocate nothing once a
// workspace has grown.
static long long AllocationCount = 0;
void* operator new(std::size_t size)
{
  ++AllocationCount;
  if (void* p = std::malloc(size ? size : 1))
  {
    return p;
  }
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept
{
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept
{
  std::free(p);
}

using penumbra::Cross;
using penumbra::Dot;
using penumbra::Length;
using penumbra::Scene;
using penumbra::Surface;
using penumbra::Vec3;

namespace
{

const double Pi = 3.14159265358979323846;

// ---------------------------------------------------------------- scenes

// A polygon oriented so that its front normal has a positive component along
// `front` (the winding is reversed if needed).
Surface Polygon(std::vector<Vec3> v, const Vec3& front)
{
  Vec3 area;
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    area += Cross(v[i], v[(i + 1) % v.size()]);
  }
  if (Dot(area, front) < 0.0)
  {
    std::reverse(v.begin(), v.end());
  }
  Surface s;
  s.Vertices = v;
  s.Reflectance = penumbra::RGB(0.5, 0.5, 0.5);
  return s;
}

// Axis-aligned rectangle at height z, x in [x0,x1], y in [y0,y1].
Surface HorizontalRect(double x0, double x1, double y0, double y1, double z, double facing)
{
  return Polygon(
    { { x0, y0, z }, { x1, y0, z }, { x1, y1, z }, { x0, y1, z } }, Vec3(0, 0, facing));
}

// The unit light [-0.5, 0.5]^2 at height h facing down, and a floor.
Scene LightAndFloor(double h)
{
  Scene scene;
  Surface light = HorizontalRect(-0.5, 0.5, -0.5, 0.5, h, -1.0);
  light.Emission = penumbra::RGB(10, 8, 6);
  light.Reflectance = penumbra::RGB(0, 0, 0);
  scene.Surfaces.push_back(light);                                  // 0: shooter
  scene.Surfaces.push_back(HorizontalRect(-3, 3, -3, 3, 0.0, 1.0)); // 1: receiver
  return scene;
}

// The light [-0.5, 0.5]^2 at height h over an 80 m square floor, and 2000
// random quads (5 cm to 55 cm half-sides, random tilts) with centres over
// the floor at heights zCentre +- zSpread.
Scene ScatteredQuads(double h, unsigned seed, double zCentre, double zSpread)
{
  Scene scene = LightAndFloor(h);
  scene.Surfaces[1] = HorizontalRect(-40, 40, -40, 40, 0.0, 1.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i)
  {
    const Vec3 c(40.0 * u(rng), 40.0 * u(rng), zCentre + zSpread * u(rng));
    const Vec3 a = penumbra::Normalized(Vec3(u(rng), u(rng), u(rng)));
    const Vec3 b = penumbra::Normalized(Cross(a, Vec3(u(rng), u(rng), u(rng))));
    const double size = 0.05 + 0.5 * (1.0 + u(rng));
    scene.Surfaces.push_back(Polygon({ c - a * size - b * size, c + a * size - b * size,
                                       c + a * size + b * size, c - a * size + b * size },
      Cross(a, b)));
  }
  return scene;
}

// Whether a 21 x 21 grid over the quad v has a point in the pyramid from x
// (on the floor) to the light [-0.5, 0.5]^2 at height h.
bool QuadMeetsPyramid(const std::vector<Vec3>& v, const Vec3& x, double h)
{
  for (int i = 0; i <= 20; ++i)
  {
    for (int j = 0; j <= 20; ++j)
    {
      const double s = i / 20.0, t = j / 20.0;
      const Vec3 p = (v[0] * (1 - s) + v[1] * s) * (1 - t) + (v[3] * (1 - s) + v[2] * s) * t;
      const double f = p.Z / h;
      if (f > 0.0 && f <= 1.0)
      {
        const Vec3 q = x + (p - x) / f;
        if (std::abs(q.X) <= 0.5 + 1e-9 && std::abs(q.Y) <= 0.5 + 1e-9)
        {
          return true;
        }
      }
    }
  }
  return false;
}

void AddBox(Scene& scene, const Vec3& lo, const Vec3& hi)
{
  const double x0 = lo.X, y0 = lo.Y, z0 = lo.Z, x1 = hi.X, y1 = hi.Y, z1 = hi.Z;
  scene.Surfaces.push_back(
    Polygon({ { x0, y0, z1 }, { x1, y0, z1 }, { x1, y1, z1 }, { x0, y1, z1 } }, Vec3(0, 0, 1)));
  scene.Surfaces.push_back(
    Polygon({ { x0, y0, z0 }, { x1, y0, z0 }, { x1, y1, z0 }, { x0, y1, z0 } }, Vec3(0, 0, -1)));
  scene.Surfaces.push_back(
    Polygon({ { x0, y0, z0 }, { x0, y1, z0 }, { x0, y1, z1 }, { x0, y0, z1 } }, Vec3(-1, 0, 0)));
  scene.Surfaces.push_back(
    Polygon({ { x1, y0, z0 }, { x1, y1, z0 }, { x1, y1, z1 }, { x1, y0, z1 } }, Vec3(1, 0, 0)));
  scene.Surfaces.push_back(
    Polygon({ { x0, y0, z0 }, { x1, y0, z0 }, { x1, y0, z1 }, { x0, y0, z1 } }, Vec3(0, -1, 0)));
  scene.Surfaces.push_back(
    Polygon({ { x0, y1, z0 }, { x1, y1, z0 }, { x1, y1, z1 }, { x0, y1, z1 } }, Vec3(0, 1, 0)));
}

// ---------------------------------------------------------------- references

double CornerParallel(double a, double b, double c)
{
  const double X = a / c, Y = b / c;
  const double sx = std::sqrt(1.0 + X * X), sy = std::sqrt(1.0 + Y * Y);
  return (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2.0 * Pi);
}

// Parallel axis-aligned rectangle relative to the foot of the normal at distance c.
double ParallelRectangle(double x0, double x1, double y0, double y1, double c)
{
  if (x1 <= x0 || y1 <= y0)
  {
    return 0.0;
  }
  return CornerParallel(x1, y1, c) - CornerParallel(x0, y1, c) - CornerParallel(x1, y0, c) +
    CornerParallel(x0, y0, c);
}

struct Estimate
{
  double Mean;
  double StdErr;
};

// Newell normal, independent of the code under test.
Vec3 NewellNormal(const std::vector<Vec3>& v)
{
  Vec3 a;
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    a += Cross(v[i], v[(i + 1) % v.size()]);
  }
  return a / Length(a);
}

// Crossing-number point-in-polygon test after dropping the dominant axis.
bool InsidePolygon(const std::vector<Vec3>& v, const Vec3& normal, const Vec3& p)
{
  const double ax = std::abs(normal.X), ay = std::abs(normal.Y), az = std::abs(normal.Z);
  const int drop = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
  const int i0 = drop == 0 ? 1 : 0, i1 = drop == 2 ? 1 : 2;
  bool inside = false;
  const std::size_t n = v.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    const double yi = v[i][i1], yj = v[j][i1];
    if ((yi > p[i1]) != (yj > p[i1]))
    {
      const double xc = v[j][i0] + (p[i1] - yj) * (v[i][i0] - v[j][i0]) / (yi - yj);
      if (p[i0] < xc)
      {
        inside = !inside;
      }
    }
  }
  return inside;
}

// Brute force: F = int_shooter v(x,y) cos_x cos_y / (pi r^2) dA, uniform
// samples in the shooter's bounding rectangle (rejection handles concave
// shooters), every other polygon tested against the open segment x-y.
Estimate MonteCarlo(const Scene& scene, int shooter, int receiver, const Vec3& x, const Vec3& n,
  int samples, unsigned seed)
{
  const std::vector<Vec3>& sv = scene.Surfaces[shooter].Vertices;
  const Vec3 ns = NewellNormal(sv);
  const Vec3 u = (sv[1] - sv[0]) / Length(sv[1] - sv[0]);
  const Vec3 w = Cross(ns, u);
  double u0 = 1e300, u1 = -1e300, w0 = 1e300, w1 = -1e300;
  for (const Vec3& p : sv)
  {
    u0 = std::min(u0, Dot(p - sv[0], u));
    u1 = std::max(u1, Dot(p - sv[0], u));
    w0 = std::min(w0, Dot(p - sv[0], w));
    w1 = std::max(w1, Dot(p - sv[0], w));
  }
  const double boxArea = (u1 - u0) * (w1 - w0);
  std::vector<Vec3> normals(scene.Surfaces.size());
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    normals[i] = NewellNormal(scene.Surfaces[i].Vertices);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < samples; ++k)
  {
    const Vec3 y =
      sv[0] + u * (u0 + (u1 - u0) * uniform(rng)) + w * (w0 + (w1 - w0) * uniform(rng));
    double f = 0.0;
    if (InsidePolygon(sv, ns, y))
    {
      const Vec3 d = y - x;
      const double r2 = Dot(d, d), r = std::sqrt(r2);
      const double cx = Dot(n, d) / r, cy = -Dot(ns, d) / r;
      if (cx > 0.0 && cy > 0.0)
      {
        bool blocked = false;
        for (std::size_t i = 0; i < scene.Surfaces.size() && !blocked; ++i)
        {
          if (static_cast<int>(i) == shooter || static_cast<int>(i) == receiver)
          {
            continue;
          }
          const std::vector<Vec3>& ov = scene.Surfaces[i].Vertices;
          const double den = Dot(normals[i], d);
          if (den == 0.0)
          {
            continue;
          }
          const double t = Dot(normals[i], ov[0] - x) / den;
          if (t > 1e-12 && t < 1.0 - 1e-12)
          {
            blocked = InsidePolygon(ov, normals[i], x + d * t);
          }
        }
        if (!blocked)
        {
          f = boxArea * cx * cy / (Pi * r2);
        }
      }
    }
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / samples;
  const double var = std::max(0.0, (sum2 / samples - mean * mean)) * samples / (samples - 1.0);
  return { mean, std::sqrt(var / samples) };
}

// ---------------------------------------------------------------- checks

// Exact (three ways: BVH pyramid, shaft candidates, all polygons) against Monte Carlo.
void CompareMonteCarlo(const char* name, const Scene& scene, int shooter, int receiver,
  const Vec3& x, const Vec3& n, int samples = 1000000)
{
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  const double exact = evaluator.FormFactor(x, n, receiver, shooter, ws);
  std::vector<int> shaft;
  evaluator.ShaftCandidates(shooter, receiver, shaft);
  const double viaShaft = evaluator.FormFactor(x, n, receiver, shooter, shaft, ws);
  std::vector<int> all;
  for (int i = 0; i < static_cast<int>(scene.Surfaces.size()); ++i)
  {
    all.push_back(i);
  }
  const double viaAll =
    penumbra::VisibleFormFactor(evaluator.GetOccluders(), x, n, shooter, receiver, all, ws);
  PENUMBRA_EXPECT_NEAR(viaShaft, exact, 1e-14);
  PENUMBRA_EXPECT_NEAR(viaAll, exact, 1e-14);
  const double open =
    penumbra::PointPolygonFormFactorClipped(x, n, scene.Surfaces[shooter].Vertices);
  PENUMBRA_EXPECT(exact >= 0.0 && exact <= open + 1e-15);

  // Seed from the case's name, so that cases do not change each other's samples.
  unsigned seed = 2166136261u;
  for (const char* c = name; *c; ++c)
  {
    seed = (seed ^ static_cast<unsigned char>(*c)) * 16777619u;
  }
  const Estimate mc = MonteCarlo(scene, shooter, receiver, x, n, samples, seed);
  const double z = mc.StdErr > 0 ? (exact - mc.Mean) / mc.StdErr : 0.0;
  std::printf("%-34s exact %.9f  MC %.9f +- %.1e  (z = %+5.2f, unoccluded %.6f)\n", name, exact,
    mc.Mean, mc.StdErr, z, open);
  penumbra::testing::Report(std::abs(exact - mc.Mean) <= 3.0 * mc.StdErr + 1e-13, __FILE__,
    __LINE__, std::string(name) + ": exact and Monte Carlo differ by more than 3 standard errors");
}

// One parallel occluder under a parallel light: the visible part is the light
// minus the occluder's projection, both aligned rectangles, so F is a signed
// sum of closed-form corner rectangles.
PENUMBRA_TEST(TestOneOccluderClosedForm)
{
  const double h = 2.0, zo = 1.0;
  const double ox0 = -0.3, ox1 = 0.4, oy0 = -0.2, oy1 = 0.25;
  Scene scene = LightAndFloor(h);
  scene.Surfaces.push_back(HorizontalRect(ox0, ox1, oy0, oy1, zo, -1.0));
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  penumbra::VisibleRegion region;
  const double points[][2] = { { 0.2, -0.1 }, { 0.0, 0.0 }, { 0.7, 0.3 }, { 1.2, 0.0 },
    { -0.9, 1.1 }, { 2.5, 2.5 }, { 0.05, 0.6 } };
  for (const auto& p : points)
  {
    const Vec3 x(p[0], p[1], 0.0);
    // Projection of the occluder from x onto z = h: y = x + (q - x) h / zo.
    const double s = h / zo;
    const double px0 = p[0] + (ox0 - p[0]) * s, px1 = p[0] + (ox1 - p[0]) * s;
    const double py0 = p[1] + (oy0 - p[1]) * s, py1 = p[1] + (oy1 - p[1]) * s;
    const double ix0 = std::max(px0, -0.5), ix1 = std::min(px1, 0.5);
    const double iy0 = std::max(py0, -0.5), iy1 = std::min(py1, 0.5);
    const double full = ParallelRectangle(-0.5 - p[0], 0.5 - p[0], -0.5 - p[1], 0.5 - p[1], h);
    const double hidden = ParallelRectangle(ix0 - p[0], ix1 - p[0], iy0 - p[1], iy1 - p[1], h);
    const double reference = full - hidden;
    const double f = evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, ws, &region);
    PENUMBRA_EXPECT_REL(f, reference, 1e-12);
    const double hiddenArea = std::max(0.0, ix1 - ix0) * std::max(0.0, iy1 - iy0);
    PENUMBRA_EXPECT_NEAR(region.GetArea(), 1.0 - hiddenArea, 1e-13);
    std::printf(
      "one occluder, x = (%5.2f, %5.2f): F = %.15f closed form %.15f\n", p[0], p[1], f, reference);
    // Contributed radiance rho * Le * F.
    const penumbra::RGB l = evaluator.ContributedRadiance(x, Vec3(0, 0, 1), 1, 0, ws);
    PENUMBRA_EXPECT_REL(l.R, 0.5 * 10.0 * reference, 1e-12);
    PENUMBRA_EXPECT_REL(l.B, 0.5 * 6.0 * reference, 1e-12);
  }
  // A pure visibility query (n = 0): F = 0, the region is the same.
  {
    const Vec3 x(0.2, -0.1, 0.0);
    PENUMBRA_EXPECT(evaluator.FormFactor(x, Vec3(0, 0, 0), 1, 0, ws, &region) == 0.0);
    const double px0 = 2 * ox0 - x.X, px1 = 2 * ox1 - x.X, py0 = 2 * oy0 - x.Y, py1 = 2 * oy1 - x.Y;
    const double hidden =
      (std::min(px1, 0.5) - std::max(px0, -0.5)) * (std::min(py1, 0.5) - std::max(py0, -0.5));
    PENUMBRA_EXPECT_NEAR(region.GetArea(), 1.0 - hidden, 1e-13);
    // From a corner of the occluder itself (lying on it): the occluder does
    // not hide anything from its own vertex, the light is fully visible.
    PENUMBRA_EXPECT(
      evaluator.FormFactor(Vec3(ox0, oy0, zo), Vec3(0, 0, 0), -1, 0, ws, &region) == 0.0);
    PENUMBRA_EXPECT_NEAR(region.GetArea(), 1.0, 1e-13);
  }
  // A larger occluder hides the light completely from under its centre.
  Scene full = LightAndFloor(h);
  full.Surfaces.push_back(HorizontalRect(-0.6, 0.6, -0.6, 0.6, zo, 1.0));
  penumbra::ExactEvaluator umbra(full);
  PENUMBRA_EXPECT(umbra.FormFactor(Vec3(0.02, -0.03, 0), Vec3(0, 0, 1), 1, 0, ws, &region) == 0.0);
  PENUMBRA_EXPECT(region.GetNumberOfPieces() == 0);
  // Also when the same occluder is cut into two touching halves.
  Scene halves = LightAndFloor(h);
  halves.Surfaces.push_back(HorizontalRect(-0.6, 0.0, -0.6, 0.6, zo, 1.0));
  halves.Surfaces.push_back(HorizontalRect(0.0, 0.6, -0.6, 0.6, zo, -1.0));
  penumbra::ExactEvaluator split(halves);
  PENUMBRA_EXPECT(split.FormFactor(Vec3(0.02, -0.03, 0), Vec3(0, 0, 1), 1, 0, ws) == 0.0);
}

PENUMBRA_TEST(TestOverlappingOccluders)
{
  Scene scene = LightAndFloor(2.0);
  scene.Surfaces.push_back(HorizontalRect(-0.4, 0.1, -0.3, 0.2, 1.2, -1.0));
  scene.Surfaces.push_back(HorizontalRect(-0.1, 0.35, -0.1, 0.4, 0.8, 1.0));
  scene.Surfaces.push_back(
    Polygon({ { -0.2, -0.4, 1.5 }, { 0.3, -0.4, 1.0 }, { 0.3, 0.0, 1.0 }, { -0.2, 0.0, 1.5 } },
      Vec3(1, 0, 1)));
  scene.Surfaces.push_back(
    Polygon({ { 0.0, 0.1, 1.6 }, { 0.4, 0.3, 1.4 }, { 0.1, 0.5, 1.7 } }, Vec3(0, 0, -1)));
  // Two occluders crossing each other.
  scene.Surfaces.push_back(Polygon(
    { { -0.45, 0.2, 1.3 }, { 0.05, 0.2, 1.3 }, { 0.05, 0.45, 1.55 }, { -0.45, 0.45, 1.55 } },
    Vec3(0, 0, 1)));
  scene.Surfaces.push_back(
    Polygon({ { -0.3, 0.1, 1.55 }, { -0.3, 0.5, 1.55 }, { -0.3, 0.5, 1.2 }, { -0.3, 0.1, 1.2 } },
      Vec3(1, 0, 0)));
  CompareMonteCarlo(
    "overlapping occluders, centre", scene, 0, 1, Vec3(0.0, 0.0, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "overlapping occluders, penumbra", scene, 0, 1, Vec3(0.45, -0.3, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "overlapping occluders, side", scene, 0, 1, Vec3(-0.8, 0.6, 0.0), Vec3(0, 0, 1));
}

PENUMBRA_TEST(TestBoxOnFloor)
{
  Scene scene = LightAndFloor(1.5);
  AddBox(scene, Vec3(0.1, -0.2, 0.0), Vec3(0.5, 0.2, 0.6)); // bottom face lies on the floor
  CompareMonteCarlo("box on floor, next to it", scene, 0, 1, Vec3(0.55, 0.0, 0.0), Vec3(0, 0, 1));
  // 1e-9 from the lit face x = 0.5, whose plane the whole light is behind:
  // only the strip x > 0.5 - 1.5e-9 of the light is seen over the box's top
  // edge (z = 0.6), too thin for Monte Carlo to see; closed form instead.
  {
    const double e = 1e-9;
    penumbra::ExactEvaluator evaluator(scene);
    penumbra::VisibilityWorkspace ws;
    const double f = evaluator.FormFactor(Vec3(0.5 + e, 0.05, 0.0), Vec3(0, 0, 1), 1, 0, ws);
    // Light point (lx, ly, 1.5) is seen iff the ray crosses the face's plane
    // x = 0.5 outside the face: at parameter t = e / (0.5 + e - lx) it is at
    // z = 1.5 t, y = 0.05 + t (ly - 0.05). Blocked for t < tb(ly), so the
    // visible strip along the edge lx = 0.5 has width e (1/tb - 1); the
    // kernel cos cos / (pi r^2) is constant across it to O(e).
    auto tb = [](double ly) {
      double t = 0.4; // top edge z = 0.6
      if (ly > 0.2)
      {
        t = std::min(t, 0.15 / (ly - 0.05)); // passes beside y = 0.2
      }
      if (ly < -0.2)
      {
        t = std::min(t, 0.25 / (0.05 - ly)); // passes beside y = -0.2
      }
      return t;
    };
    double reference = 0.0;
    const double breaks[] = { -0.5, 0.2, 0.425, 0.5 };
    for (int piece = 0; piece < 3; ++piece)
    {
      const int steps = 2000; // Simpson's rule on smooth pieces
      const double a = breaks[piece], h = (breaks[piece + 1] - a) / steps;
      for (int i = 0; i <= steps; ++i)
      {
        const double ly = a + i * h;
        const double r2 = (ly - 0.05) * (ly - 0.05) + 2.25 + e * e;
        const double g = e * (1.0 / tb(ly) - 1.0) * 2.25 / (Pi * r2 * r2);
        reference += g * h / 3.0 * (i == 0 || i == steps ? 1.0 : (i % 2 ? 4.0 : 2.0));
      }
    }
    PENUMBRA_EXPECT_REL(f, reference, 1e-6);
    std::printf("box on floor, 1e-9 from its face: F = %.9e, reference %.9e\n", f, reference);
  }
  CompareMonteCarlo(
    "box on floor, shadow side", scene, 0, 1, Vec3(0.1 - 1e-7, 0.1, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "box on floor, near a corner", scene, 0, 1, Vec3(0.52, 0.21, 0.0), Vec3(0, 0, 1));
  // Exactly on the contact line (the box's side plane through x): the side
  // face is seen edge-on and casts nothing; the rest of the box still does.
  CompareMonteCarlo(
    "box on floor, on the contact line", scene, 0, 1, Vec3(0.5, 0.1, 0.0), Vec3(0, 0, 1));
}

PENUMBRA_TEST(TestStraddlingShooterPlane)
{
  Scene scene = LightAndFloor(2.0);
  // Vertical plate piercing the light.
  scene.Surfaces.push_back(
    Polygon({ { 0.1, -0.3, 1.5 }, { 0.1, 0.3, 1.5 }, { 0.1, 0.3, 2.5 }, { 0.1, -0.3, 2.5 } },
      Vec3(1, 0, 0)));
  // Tilted plate crossing the light's plane.
  scene.Surfaces.push_back(
    Polygon({ { -0.4, -0.2, 1.7 }, { 0.0, -0.2, 2.3 }, { 0.0, 0.3, 2.3 }, { -0.4, 0.3, 1.7 } },
      Vec3(0, 0, -1)));
  CompareMonteCarlo(
    "straddling the shooter's plane", scene, 0, 1, Vec3(0.3, 0.1, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo("straddling, other side", scene, 0, 1, Vec3(-0.6, -0.2, 0.0), Vec3(0, 0, 1));
}

PENUMBRA_TEST(TestTouchingAndTangent)
{
  Scene scene = LightAndFloor(2.0);
  // A wall whose top edge lies in the light (touches the shooter).
  scene.Surfaces.push_back(
    Polygon({ { -0.2, 0.1, 1.2 }, { 0.3, 0.1, 1.2 }, { 0.3, 0.1, 2.0 }, { -0.2, 0.1, 2.0 } },
      Vec3(0, 1, 0)));
  // A wall crossing the floor near x (straddles x's tangent plane).
  scene.Surfaces.push_back(
    Polygon({ { -0.7, -0.5, -0.2 }, { -0.7, 0.5, -0.2 }, { -0.7, 0.5, 0.8 }, { -0.7, -0.5, 0.8 } },
      Vec3(1, 0, 0)));
  CompareMonteCarlo("touching the shooter", scene, 0, 1, Vec3(0.1, 0.4, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "touching the shooter, other side", scene, 0, 1, Vec3(0.0, -0.3, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "crossing the tangent plane", scene, 0, 1, Vec3(-0.75, 0.1, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo(
    "crossing the tangent plane (lit)", scene, 0, 1, Vec3(-0.65, 0.1, 0.0), Vec3(0, 0, 1));
}

PENUMBRA_TEST(TestTiltedReceiver)
{
  // The receiver's tangent plane cuts the light: clipping plus occluders.
  Scene scene = LightAndFloor(2.0);
  const Vec3 n = penumbra::Normalized(Vec3(1.0, 0.0, 0.2));
  const Vec3 x(0.0, 0.1, 0.5);
  const Vec3 t1(0, 1, 0), t2 = Cross(n, t1);
  scene.Surfaces[1] = Polygon({ x - t1 - t2, x + t1 - t2, x + t1 + t2, x - t1 + t2 }, n);
  scene.Surfaces.push_back(HorizontalRect(-0.1, 0.3, -0.2, 0.2, 1.3, 1.0));
  CompareMonteCarlo("tilted receiver, clipped light", scene, 0, 1, x, n);
}

PENUMBRA_TEST(TestConcave)
{
  Scene scene;
  // L-shaped light at z = 2 facing down (a concave shooter).
  Surface light = Polygon({ { -0.5, -0.5, 2 }, { 0.5, -0.5, 2 }, { 0.5, 0.0, 2 }, { 0.0, 0.0, 2 },
                            { 0.0, 0.5, 2 }, { -0.5, 0.5, 2 } },
    Vec3(0, 0, -1));
  scene.Surfaces.push_back(light);
  scene.Surfaces.push_back(HorizontalRect(-3, 3, -3, 3, 0.0, 1.0));
  // A U-shaped (concave) occluder, tilted.
  scene.Surfaces.push_back(
    Polygon({ { -0.4, -0.3, 1.0 }, { 0.4, -0.3, 1.2 }, { 0.4, 0.3, 1.2 }, { 0.2, 0.3, 1.15 },
              { 0.2, -0.1, 1.15 }, { -0.2, -0.1, 1.05 }, { -0.2, 0.3, 1.05 }, { -0.4, 0.3, 1.0 } },
      Vec3(0, 0, 1)));
  CompareMonteCarlo(
    "concave shooter and occluder", scene, 0, 1, Vec3(0.05, 0.1, 0.0), Vec3(0, 0, 1));
  CompareMonteCarlo("concave, off-centre", scene, 0, 1, Vec3(-0.4, 0.5, 0.0), Vec3(0, 0, 1));
  // Unoccluded concave shooter: the exact value is Lambert's formula on the L.
  Scene open;
  open.Surfaces = { scene.Surfaces[0], scene.Surfaces[1] };
  penumbra::ExactEvaluator evaluator(open);
  penumbra::VisibilityWorkspace ws;
  const Vec3 x(0.3, 0.2, 0.0);
  PENUMBRA_EXPECT_REL(evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, ws),
    ParallelRectangle(-0.5 - 0.3, 0.5 - 0.3, -0.5 - 0.2, 0.0 - 0.2, 2.0) +
      ParallelRectangle(-0.5 - 0.3, 0.0 - 0.3, 0.0 - 0.2, 0.5 - 0.2, 2.0),
    1e-12);
}

PENUMBRA_TEST(TestEdgeOn)
{
  Scene scene = LightAndFloor(2.0);
  // A vertical plate in the plane x = 0, through the floor.
  scene.Surfaces.push_back(
    Polygon({ { 0.0, -1.0, -0.5 }, { 0.0, 1.0, -0.5 }, { 0.0, 1.0, 1.5 }, { 0.0, -1.0, 1.5 } },
      Vec3(1, 0, 0)));
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  const Vec3 n(0, 0, 1);
  // In the plate's plane: seen edge-on, it hides nothing.
  const Vec3 x(0.0, 0.2, 0.0);
  const double open = ParallelRectangle(-0.5, 0.5, -0.7, 0.3, 2.0);
  PENUMBRA_EXPECT_REL(evaluator.FormFactor(x, n, 1, 0, ws), open, 1e-12);
  // Just beside it: it hides the other half of the light (but for the
  // sliver seen over its top edge).
  CompareMonteCarlo("edge-on plate, x at +1e-10", scene, 0, 1, Vec3(1e-10, 0.2, 0.0), n);
  CompareMonteCarlo("edge-on plate, x at -1e-6", scene, 0, 1, Vec3(-1e-6, 0.2, 0.0), n);
  // Towards the plane from one side the value converges to the half light,
  // down to rounding level (OccluderSet::GetPlaneTolerance(), ~1e-14 here).
  const double half = ParallelRectangle(0.0, 0.5, -0.7, 0.3, 2.0);
  for (double e = 1e-3; e > 5e-14; e *= 0.1)
  {
    const double f = evaluator.FormFactor(Vec3(e, 0.2, 0.0), n, 1, 0, ws);
    PENUMBRA_EXPECT(f >= half - 1e-15 && f <= half + 0.3 * e);
  }
}

PENUMBRA_TEST(TestShooterPlane)
{
  Scene scene = LightAndFloor(2.0);
  scene.Surfaces.push_back(HorizontalRect(-0.2, 0.2, -0.2, 0.2, 1.0, 1.0));
  // A wall through the light's edge line x = 0.5 as receiver.
  scene.Surfaces.push_back(
    Polygon({ { 0.5, -1, 0 }, { 0.5, 1, 0 }, { 0.5, 1, 2.5 }, { 0.5, -1, 2.5 } }, Vec3(-1, 0, 0)));
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  penumbra::VisibleRegion region;
  // On the shooter's plane, inside and outside it, and on an edge's line.
  const Vec3 onPlane[] = { { 0.2, 0.1, 2.0 }, { 0.9, 0.0, 2.0 }, { 0.5, 0.0, 2.0 },
    { 0.5, 0.7, 2.0 } };
  for (const Vec3& x : onPlane)
  {
    PENUMBRA_EXPECT(evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, ws, &region) == 0.0);
    PENUMBRA_EXPECT(evaluator.FormFactor(x, Vec3(-1, 0, 0), 3, 0, ws) == 0.0);
  }
  // Behind the light (it emits downwards only).
  PENUMBRA_EXPECT(evaluator.FormFactor(Vec3(0, 0, 2.5), Vec3(0, 0, -1), 1, 0, ws) == 0.0);
  // Approaching the light's edge from below, on the wall through its edge
  // line: the light fills a quarter of the directions in the limit, so F
  // grows to 1/2 (and is 0 on the plane itself). Finite all the way.
  // The light is moved to z = 0 so that 0 - e is representable down to 1e-300.
  Scene low;
  low.Surfaces.push_back(HorizontalRect(-0.5, 0.5, -0.5, 0.5, 0.0, -1.0));
  low.Surfaces.push_back(Polygon(
    { { 0.5, -1, -2 }, { 0.5, 1, -2 }, { 0.5, 1, 0.5 }, { 0.5, -1, 0.5 } }, Vec3(-1, 0, 0)));
  low.Surfaces.push_back(HorizontalRect(-0.2, 0.2, -0.2, 0.2, -1.0, 1.0));
  penumbra::ExactEvaluator lowEvaluator(low);
  double previous = 0.0;
  for (double e = 1e-2; e > 1e-300; e *= 1e-7)
  {
    const double f = lowEvaluator.FormFactor(Vec3(0.5, 0.0, -e), Vec3(-1, 0, 0), 1, 0, ws);
    PENUMBRA_EXPECT(std::isfinite(f) && f >= previous && f <= 0.5 + 1e-15);
    previous = f;
  }
  PENUMBRA_EXPECT_NEAR(previous, 0.5, 1e-14);
  PENUMBRA_EXPECT(lowEvaluator.FormFactor(Vec3(0.5, 0.0, 0.0), Vec3(-1, 0, 0), 1, 0, ws) == 0.0);
  // On the wall through the edge line, below the light: the light is seen at
  // grazing angles, half of it behind the tangent plane. Compare with MC.
  CompareMonteCarlo(
    "receiver through an edge line", scene, 0, 3, Vec3(0.5, 0.1, 1.4), Vec3(-1, 0, 0));
}

// The Cornell box (millimetres), the light 0.1 mm below the ceiling.
Scene CornellBox()
{
  Scene scene;
  Surface light =
    Polygon({ { 343, 548.7, 227 }, { 343, 548.7, 332 }, { 213, 548.7, 332 }, { 213, 548.7, 227 } },
      Vec3(0, -1, 0));
  light.Emission = penumbra::RGB(17, 12, 4);
  scene.Surfaces.push_back(light); // 0
  scene.Surfaces.push_back(
    Polygon({ { 552.8, 0, 0 }, { 0, 0, 0 }, { 0, 0, 559.2 }, { 549.6, 0, 559.2 } },
      Vec3(0, 1, 0))); // 1 floor
  scene.Surfaces.push_back(
    Polygon({ { 556, 548.8, 0 }, { 556, 548.8, 559.2 }, { 0, 548.8, 559.2 }, { 0, 548.8, 0 } },
      Vec3(0, -1, 0))); // 2 ceiling
  scene.Surfaces.push_back(
    Polygon({ { 549.6, 0, 559.2 }, { 0, 0, 559.2 }, { 0, 548.8, 559.2 }, { 556, 548.8, 559.2 } },
      Vec3(0, 0, -1))); // 3 back
  scene.Surfaces.push_back(
    Polygon({ { 0, 0, 559.2 }, { 0, 0, 0 }, { 0, 548.8, 0 }, { 0, 548.8, 559.2 } },
      Vec3(1, 0, 0))); // 4 right
  scene.Surfaces.push_back(
    Polygon({ { 552.8, 0, 0 }, { 549.6, 0, 559.2 }, { 556, 548.8, 559.2 }, { 556, 548.8, 0 } },
      Vec3(-1, 0, 0))); // 5 left
  auto block = [&scene](const std::vector<Vec3>& top) {
    Vec3 centre;
    for (const Vec3& v : top)
    {
      centre += Vec3(v.X, 0.5 * v.Y, v.Z) * 0.25;
    }
    scene.Surfaces.push_back(Polygon(top, Vec3(0, 1, 0)));
    for (std::size_t i = 0; i < 4; ++i)
    {
      const Vec3 a = top[i], b = top[(i + 1) % 4];
      const Vec3 mid = (a + b) * 0.5 - Vec3(0, 0.5 * a.Y, 0);
      scene.Surfaces.push_back(
        Polygon({ a, b, Vec3(b.X, 0, b.Z), Vec3(a.X, 0, a.Z) }, mid - centre));
    }
  };
  block({ { 130, 165, 65 }, { 82, 165, 225 }, { 240, 165, 272 }, { 290, 165, 114 } });   // 6-10
  block({ { 423, 330, 247 }, { 265, 330, 296 }, { 314, 330, 456 }, { 472, 330, 406 } }); // 11-15
  return scene;
}

PENUMBRA_TEST(TestCornellBox)
{
  const Scene scene = CornellBox();
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  // Out of both blocks' shadows (rays to the light pass by the tall block's
  // corner (423, 247) and over the short block): only the light matters, so
  // the closed form applies (the ceiling behind it and the walls are culled).
  const Vec3 x(400, 0, 150);
  const double reference = ParallelRectangle(213 - 400, 343 - 400, 227 - 150, 332 - 150, 548.7);
  PENUMBRA_EXPECT_REL(evaluator.FormFactor(x, Vec3(0, 1, 0), 1, 0, ws), reference, 1e-12);
  // Under the short block (inside its footprint): nothing.
  PENUMBRA_EXPECT(evaluator.FormFactor(Vec3(200, 0, 150), Vec3(0, 1, 0), 1, 0, ws) == 0.0);
  CompareMonteCarlo(
    "Cornell floor by the tall block", scene, 0, 1, Vec3(278, 0, 279.5), Vec3(0, 1, 0));
  CompareMonteCarlo("Cornell short block's penumbra", scene, 0, 1, Vec3(180, 0, 20), Vec3(0, 1, 0));
  CompareMonteCarlo(
    "Cornell short block's penumbra 2", scene, 0, 1, Vec3(20, 0, 140), Vec3(0, 1, 0));
  CompareMonteCarlo("Cornell tall block's penumbra", scene, 0, 1, Vec3(260, 0, 300), Vec3(0, 1, 0));
  CompareMonteCarlo(
    "Cornell tall block's penumbra 2", scene, 0, 1, Vec3(300, 0, 460), Vec3(0, 1, 0));
  CompareMonteCarlo("Cornell short block's top", scene, 0, 6, Vec3(200, 165, 200), Vec3(0, 1, 0));
  CompareMonteCarlo("Cornell right wall", scene, 0, 4, Vec3(0, 200, 350), Vec3(1, 0, 0));
  CompareMonteCarlo("Cornell tall block's side", scene, 0, 12, Vec3(289.5, 100, 376),
    penumbra::Normalized(Cross(Vec3(314 - 265, 0, 456 - 296), Vec3(0, 1, 0))));
}

PENUMBRA_TEST(TestSymmetryAndBounds)
{
  // A scene symmetric under y -> -y.
  Scene scene = LightAndFloor(2.0);
  scene.Surfaces.push_back(HorizontalRect(-0.3, 0.2, -0.25, 0.25, 1.0, 1.0));
  scene.Surfaces.push_back(
    Polygon({ { 0.1, -0.4, 1.5 }, { 0.4, -0.4, 1.2 }, { 0.4, 0.4, 1.2 }, { 0.1, 0.4, 1.5 } },
      Vec3(0, 0, 1)));
  scene.Surfaces.push_back(
    Polygon({ { -0.4, -0.1, 1.4 }, { -0.2, 0.0, 1.4 }, { -0.4, 0.1, 1.4 } }, Vec3(0, 0, 1)));
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coord(-1.5, 1.5);
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i)
  {
    const double px = coord(rng), py = coord(rng);
    const double a = evaluator.FormFactor(Vec3(px, py, 0), Vec3(0, 0, 1), 1, 0, ws);
    const double b = evaluator.FormFactor(Vec3(px, -py, 0), Vec3(0, 0, 1), 1, 0, ws);
    worst = std::max(worst, std::abs(a - b));
  }
  PENUMBRA_EXPECT(worst <= 1e-14);
  std::printf("symmetry y -> -y: largest difference %.2e over 2000 points\n", worst);

  // Random occluders, random points: 0 <= F <= unoccluded F, finite; the
  // three culling paths agree; the light's visible area never grows.
  int failures = 0;
  double worstPath = 0.0;
  for (int trial = 0; trial < 40; ++trial)
  {
    Scene random = LightAndFloor(2.0);
    std::uniform_real_distribution<double> u(-0.8, 0.8), hgt(0.05, 2.3), size(0.05, 0.5);
    const int count = 1 + trial % 12;
    for (int k = 0; k < count; ++k)
    {
      const Vec3 c(u(rng), u(rng), hgt(rng));
      const Vec3 a = penumbra::Normalized(Vec3(u(rng), u(rng), u(rng)));
      const Vec3 b = penumbra::Normalized(Cross(a, Vec3(u(rng), u(rng), u(rng))));
      const Vec3 e = Cross(a, b);
      const double s1 = size(rng), s2 = size(rng);
      random.Surfaces.push_back(Polygon(
        { c - b * s1 - e * s2, c + b * s1 - e * s2, c + b * s1 + e * s2, c - b * s1 + e * s2 }, a));
    }
    penumbra::ExactEvaluator ev(random);
    std::vector<int> shaft, all;
    ev.ShaftCandidates(0, 1, shaft);
    for (int i = 0; i < static_cast<int>(random.Surfaces.size()); ++i)
    {
      all.push_back(i);
    }
    penumbra::VisibleRegion region;
    for (int i = 0; i < 200; ++i)
    {
      const Vec3 x(coord(rng), coord(rng), 0.0);
      const Vec3 n(0, 0, 1);
      const double f = ev.FormFactor(x, n, 1, 0, ws, &region);
      const double open =
        penumbra::PointPolygonFormFactorClipped(x, n, random.Surfaces[0].Vertices);
      const double fs = ev.FormFactor(x, n, 1, 0, shaft, ws);
      const double fa = penumbra::VisibleFormFactor(ev.GetOccluders(), x, n, 0, 1, all, ws);
      worstPath = std::max({ worstPath, std::abs(f - fs), std::abs(f - fa) });
      if (!(std::isfinite(f) && f >= 0.0 && f <= open + 1e-15 && region.GetArea() <= 1.0 + 1e-13))
      {
        ++failures;
      }
    }
  }
  // Tilted shooters and receivers in general position: the shaft (convex
  // hull of both) and the per-point pyramid never drop a blocker.
  for (int trial = 0; trial < 60; ++trial)
  {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto randomQuad = [&](const Vec3& c, double size) {
      const Vec3 a = penumbra::Normalized(Vec3(u(rng), u(rng), u(rng)));
      const Vec3 b = penumbra::Normalized(Cross(a, Vec3(u(rng), u(rng), u(rng))));
      const Vec3 e = Cross(a, b);
      return Polygon({ c - b * size - e * size, c + b * size - e * size, c + b * size + e * size,
                       c - b * size + e * size },
        a);
    };
    Scene random;
    random.Surfaces.push_back(randomQuad(Vec3(0, 0, 2), 0.6));
    random.Surfaces.push_back(randomQuad(Vec3(0, 0, 0), 1.0));
    for (int k = 0; k < 15; ++k)
    {
      random.Surfaces.push_back(
        randomQuad(Vec3(1.2 * u(rng), 1.2 * u(rng), 1.0 + 1.2 * u(rng)), 0.25));
    }
    penumbra::ExactEvaluator ev(random);
    std::vector<int> shaft, all;
    const bool active = ev.ShaftCandidates(0, 1, shaft);
    for (int i = 0; i < static_cast<int>(random.Surfaces.size()); ++i)
    {
      all.push_back(i);
    }
    const std::vector<Vec3>& r = random.Surfaces[1].Vertices;
    const Vec3 n = penumbra::Normalized(Cross(r[1] - r[0], r[2] - r[0]));
    for (int i = 0; i < 100; ++i)
    {
      const double s = 0.5 * (u(rng) + 1.0), t = 0.5 * (u(rng) + 1.0);
      const Vec3 x = r[0] + (r[1] - r[0]) * s + (r[3] - r[0]) * t;
      const double fa = penumbra::VisibleFormFactor(ev.GetOccluders(), x, n, 0, 1, all, ws);
      const double fs = active ? ev.FormFactor(x, n, 1, 0, shaft, ws) : 0.0;
      const double fb = ev.FormFactor(x, n, 1, 0, ws);
      worstPath = std::max({ worstPath, std::abs(fa - fs), std::abs(fa - fb) });
      if (!(std::isfinite(fa) && fa >= 0.0 && fa <= 1.0))
      {
        ++failures;
      }
    }
  }
  PENUMBRA_EXPECT(failures == 0);
  PENUMBRA_EXPECT(worstPath <= 1e-15);
  std::printf("random scenes: %d bound violations, culling paths differ by at most %.2e\n",
    failures, worstPath);
}

// ---------------------------------------------------------------- projection reference

// Lambert's formula written out again here, in world coordinates.
double LambertReference(const Vec3& x, const Vec3& n, const std::vector<Vec3>& poly)
{
  double sum = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k)
  {
    const Vec3 a = poly[k] - x, b = poly[(k + 1) % poly.size()] - x;
    const Vec3 c = Cross(b, a);
    const double s = Length(c);
    if (s > 0.0)
    {
      sum += std::atan2(s, Dot(a, b)) * Dot(n, c) / s;
    }
  }
  return sum / (2.0 * Pi);
}

// Convex polygon in the plane z = h (counter-clockwise seen from +z) clipped by
// another one: Sutherland-Hodgman with the clipper's edges.
std::vector<Vec3> ClipConvexXY(std::vector<Vec3> subject, const std::vector<Vec3>& clipper)
{
  for (std::size_t e = 0; e < clipper.size() && !subject.empty(); ++e)
  {
    const Vec3 p = clipper[e], q = clipper[(e + 1) % clipper.size()];
    auto side = [&](
                  const Vec3& v) { return (q.X - p.X) * (v.Y - p.Y) - (q.Y - p.Y) * (v.X - p.X); };
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < subject.size(); ++i)
    {
      const Vec3 a = subject[i], b = subject[(i + 1) % subject.size()];
      const double sa = side(a), sb = side(b);
      if (sa >= 0)
      {
        out.push_back(a);
      }
      if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0))
      {
        out.push_back(a + (b - a) * (sa / (sa - sb)));
      }
    }
    subject = out.size() >= 3 ? out : std::vector<Vec3>();
  }
  return subject;
}

// Occluders strictly between x (on the floor) and the light: the visible
// form factor by inclusion-exclusion over the central projections of the
// occluders, F = F(L) - sum F(L n Pi) + sum F(L n Pi n Pj) - ..., each term an
// exact Lambert integral of a convex polygon. Independent of the code under
// test (projection instead of half-planes, no piece subtraction).
PENUMBRA_TEST(TestInclusionExclusion)
{
  std::mt19937_64 rng(99);
  // Heights from just above the floor to just below the light: occluders
  // with a vertex within 5% of x's level take the general (half-plane) path
  // of the code under test, the others its projection path.
  std::uniform_real_distribution<double> u(-1.0, 1.0), hgt(0.03, 1.97), size(0.08, 0.3);
  double worst = 0.0;
  int cases = 0;
  for (int trial = 0; trial < 300; ++trial)
  {
    const double h = 2.0;
    Scene scene = LightAndFloor(h);
    const int count = 1 + trial % 3;
    for (int k = 0; k < count; ++k)
    {
      Vec3 c(0.4 * u(rng), 0.4 * u(rng), hgt(rng));
      const Vec3 a = penumbra::Normalized(Vec3(0.5 * u(rng), 0.5 * u(rng), 1.0));
      const Vec3 b = penumbra::Normalized(Cross(a, Vec3(u(rng), u(rng), u(rng))));
      const Vec3 e = Cross(a, b);
      const double s1 = size(rng), s2 = size(rng);
      std::vector<Vec3> quad = { c - b * s1 - e * s2, c + b * s1 - e * s2, c + b * s1 + e * s2,
        c - b * s1 + e * s2 };
      if (trial % 2)
      {
        quad.pop_back(); // a triangle
      }
      // Strictly between the floor and the light, or try again.
      bool inside = true;
      for (const Vec3& v : quad)
      {
        inside &= v.Z > 0.01 && v.Z < h - 1e-3;
      }
      if (!inside)
      {
        --k;
        continue;
      }
      scene.Surfaces.push_back(Polygon(quad, u(rng) > 0 ? a : -a));
    }
    penumbra::ExactEvaluator evaluator(scene);
    penumbra::VisibilityWorkspace ws;
    for (int i = 0; i < 10; ++i)
    {
      const Vec3 x(0.6 * u(rng), 0.6 * u(rng), 0.0), n(0, 0, 1);
      // The light, counter-clockwise seen from +z, and the projections.
      const std::vector<Vec3> light = { { -0.5, -0.5, h }, { 0.5, -0.5, h }, { 0.5, 0.5, h },
        { -0.5, 0.5, h } };
      std::vector<std::vector<Vec3>> shadows;
      for (int k = 2; k < static_cast<int>(scene.Surfaces.size()); ++k)
      {
        std::vector<Vec3> p;
        for (const Vec3& v : scene.Surfaces[k].Vertices)
        {
          p.push_back(x + (v - x) * (h / v.Z));
        }
        double area = 0.0;
        for (std::size_t j = 0; j < p.size(); ++j)
        {
          area += p[j].X * p[(j + 1) % p.size()].Y - p[j].Y * p[(j + 1) % p.size()].X;
        }
        if (area < 0.0)
        {
          std::reverse(p.begin(), p.end());
        }
        shadows.push_back(p);
      }
      // F of a region given counter-clockwise from +z: Lambert with the
      // front facing down means reversed order.
      auto formFactor = [&](std::vector<Vec3> poly) {
        if (poly.size() < 3)
        {
          return 0.0;
        }
        std::reverse(poly.begin(), poly.end());
        return LambertReference(x, n, poly);
      };
      double reference = formFactor(light);
      const int m = static_cast<int>(shadows.size());
      for (int mask = 1; mask < (1 << m); ++mask)
      {
        std::vector<Vec3> region = light;
        int bits = 0;
        for (int k = 0; k < m; ++k)
        {
          if (mask & (1 << k))
          {
            region = ClipConvexXY(region, shadows[k]);
            ++bits;
          }
        }
        reference += (bits % 2 ? -1.0 : 1.0) * formFactor(region);
      }
      const double f = evaluator.FormFactor(x, n, 1, 0, ws);
      worst = std::max(worst, std::abs(f - reference));
      ++cases;
    }
  }
  PENUMBRA_EXPECT(worst <= 1e-14);
  std::printf("inclusion-exclusion over projected shadows: %d cases, largest difference %.2e\n",
    cases, worst);
}

double LambertReference(const Vec3& x, const Vec3& n, const std::vector<Vec3>& poly);

// Area of a planar polygon (Newell), computed here.
double PolygonArea(const std::vector<Vec3>& v)
{
  Vec3 a;
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    a += Cross(v[i], v[(i + 1) % v.size()]);
  }
  return 0.5 * Length(a);
}

PENUMBRA_TEST(TestDecomposition)
{
  // Concave outlines (counter-clockwise seen from +z, then tilted in 3D).
  const std::vector<std::vector<double>> outlines = {
    { 0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2 },                                     // L
    { 0, 0, 3, 0, 3, 2, 2, 2, 2, 1, 1, 1, 1, 2, 0, 2 },                         // U
    { 0, 0, 5, 0, 5, 3, 4, 3, 4, 1, 3, 1, 3, 3, 2, 3, 2, 1, 1, 1, 1, 3, 0, 3 }, // comb
    { 0, -1, 0.3, -0.3, 1, 0, 0.3, 0.3, 0, 1, -0.3, 0.3, -1, 0, -0.3, -0.3 },   // star
    { 0, 0, 1, 0, 2, 0, 2, 1, 0, 1 },                                           // collinear vertex
  };
  const Vec3 a = penumbra::Normalized(Vec3(1, 0.2, 0.3));
  const Vec3 b = penumbra::Normalized(Cross(Vec3(0.1, 0.2, 1), a));
  const Vec3 c = Cross(a, b);
  Scene scene;
  for (const auto& o : outlines)
  {
    Surface s;
    for (std::size_t i = 0; i < o.size(); i += 2)
    {
      s.Vertices.push_back(Vec3(5, -3, 7) + a * o[i] + b * o[i + 1]);
    }
    scene.Surfaces.push_back(s);
  }
  // A degenerate (collinear) polygon and one with a non-finite vertex are
  // kept (ids stay the scene's) but ignored.
  Surface flat;
  flat.Vertices = { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 } };
  scene.Surfaces.push_back(flat);
  Surface broken;
  broken.Vertices = { { 0, 0, 1 }, { 1e300 * 1e300, 0, 1 }, { 0, 1, 1 } };
  scene.Surfaces.push_back(broken);
  penumbra::OccluderSet set(scene);
  PENUMBRA_EXPECT(set.GetNumberOfPolygons() == 7);
  PENUMBRA_EXPECT(!set.GetPolygon(5).Valid && !set.GetPolygon(6).Valid);
  PENUMBRA_EXPECT(std::isfinite(set.GetTolerance()) && set.GetTolerance() > 0.0);
  const int expectedPieces[] = { 2, 3, 5, 4, 1 };
  for (int p = 0; p < 5; ++p)
  {
    const penumbra::PreparedPolygon& poly = set.GetPolygon(p);
    PENUMBRA_EXPECT(poly.Valid);
    PENUMBRA_EXPECT(Dot(poly.Normal, c) > 0.999999999);
    double area = 0.0;
    bool convex = true, planar = true, consistent = true;
    for (int k = poly.FirstPiece; k < poly.FirstPiece + poly.NumberOfPieces; ++k)
    {
      const penumbra::ConvexPiece& piece = set.GetPieces()[k];
      std::vector<Vec3> v(set.GetPieceVertices().begin() + piece.First,
        set.GetPieceVertices().begin() + piece.First + piece.Count);
      area += PolygonArea(v);
      for (int i = 0; i < piece.Count; ++i)
      {
        const Vec3 e0 = v[(i + 1) % piece.Count] - v[i];
        const Vec3 e1 = v[(i + 2) % piece.Count] - v[(i + 1) % piece.Count];
        convex &= Dot(Cross(e0, e1), c) > 1e-12; // strictly convex: collinear vertices removed
        planar &= std::abs(Dot(v[i] - scene.Surfaces[p].Vertices[0], c)) < 1e-12;
        const double* q = set.GetPiecePoints2D().data() + 2 * (piece.First + i);
        consistent &= Length(poly.Centroid + poly.AxisU * q[0] + poly.AxisV * q[1] - v[i]) < 1e-12;
      }
    }
    PENUMBRA_EXPECT_REL(area, PolygonArea(scene.Surfaces[p].Vertices), 1e-13);
    PENUMBRA_EXPECT(convex && planar && consistent);
    PENUMBRA_EXPECT(poly.NumberOfPieces <= expectedPieces[p]);
  }
  // Queries with a degenerate shooter or non-finite input return 0.
  penumbra::VisibilityWorkspace ws;
  std::vector<int> all = { 0, 1, 2, 3, 4, 5, 6 };
  PENUMBRA_EXPECT(
    penumbra::VisibleFormFactor(set, Vec3(0, 0, 5), Vec3(0, 0, -1), 5, -1, all, ws) == 0.0);
  const double nan = std::nan("");
  PENUMBRA_EXPECT(
    penumbra::VisibleFormFactor(set, Vec3(nan, 0, 0), Vec3(0, 0, 1), 0, -1, all, ws) == 0.0);
  // The concave L as a shooter, unoccluded (the other outlines are coplanar
  // with it): Lambert's formula over the whole outline; from behind, 0.
  const Vec3 front = Vec3(5, -3, 7) + c * 2.0 + a * 0.5 + b * 0.5;
  PENUMBRA_EXPECT_REL(penumbra::VisibleFormFactor(set, front, -c, 0, -1, all, ws),
    LambertReference(front, -c, scene.Surfaces[0].Vertices), 1e-13);
  const Vec3 back = Vec3(5, -3, 7) - c * 2.0 + a * 0.5 + b * 0.5;
  PENUMBRA_EXPECT(penumbra::VisibleFormFactor(set, back, c, 0, -1, all, ws) == 0.0);
}

PENUMBRA_TEST(TestNoAllocation)
{
  Scene scene = LightAndFloor(2.0);
  AddBox(scene, Vec3(0.1, -0.2, 0.0), Vec3(0.5, 0.2, 0.6));
  scene.Surfaces.push_back(
    Polygon({ { -0.4, -0.2, 1.7 }, { 0.0, -0.2, 2.3 }, { 0.0, 0.3, 2.3 }, { -0.4, 0.3, 1.7 } },
      Vec3(0, 0, -1)));
  scene.Surfaces.push_back(
    Polygon({ { -0.4, -0.3, 1.0 }, { 0.4, -0.3, 1.2 }, { 0.4, 0.3, 1.2 }, { 0.2, 0.3, 1.15 },
              { 0.2, -0.1, 1.15 }, { -0.2, -0.1, 1.05 }, { -0.2, 0.3, 1.05 }, { -0.4, 0.3, 1.0 } },
      Vec3(0, 0, 1)));
  penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace ws;
  std::vector<int> shaft;
  evaluator.ShaftCandidates(0, 1, shaft);
  std::vector<Vec3> points;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  for (int i = 0; i < 500; ++i)
  {
    points.emplace_back(coord(rng), coord(rng), 0.0);
  }
  double first = 0.0, second = 0.0;
  for (const Vec3& x : points) // warm-up: the workspace grows
  {
    first += evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, ws);
    first += evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, shaft, ws);
  }
  const long long before = AllocationCount;
  for (const Vec3& x : points)
  {
    second += evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, ws);
    second += evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, shaft, ws);
  }
  const long long allocations = AllocationCount - before; // before any reporting
  PENUMBRA_EXPECT(allocations == 0);
  PENUMBRA_EXPECT(first == second);
  std::printf("heap allocations in 1000 warm queries: %lld\n", allocations);
}

PENUMBRA_TEST(TestCulling)
{
  // Query A keeps the blockers and drops what is outside the shaft.
  Scene scene = LightAndFloor(2.0);
  scene.Surfaces.push_back(HorizontalRect(-0.2, 0.2, -0.2, 0.2, 1.0, 1.0));  // 2: inside
  scene.Surfaces.push_back(HorizontalRect(-0.2, 0.2, -0.2, 0.2, 3.0, 1.0));  // 3: above the light
  scene.Surfaces.push_back(HorizontalRect(-0.2, 0.2, -0.2, 0.2, -1.0, 1.0)); // 4: below the floor
  scene.Surfaces.push_back(HorizontalRect(5.0, 6.0, 5.0, 6.0, 1.0, 1.0));    // 5: far away
  scene.Surfaces.push_back(HorizontalRect(3.1, 3.5, -0.2, 0.2, 1.9, 1.0));   // 6: outside the hull
  scene.Surfaces.push_back(HorizontalRect(2.5, 2.9, -0.2, 0.2, 0.1, 1.0));   // 7: inside the hull
  scene.Surfaces.push_back(
    HorizontalRect(-0.5, 0.5, -0.5, 0.5, 2.0, 1.0)); // 8: coplanar with the light
  penumbra::OccluderSet set(scene);
  std::vector<int> shaft;
  PENUMBRA_EXPECT(set.ShaftCandidates(0, 1, shaft));
  PENUMBRA_EXPECT((shaft == std::vector<int>{ 2, 7 }));
  // A pair facing away exchanges nothing.
  Scene away = LightAndFloor(2.0);
  away.Surfaces[1] = HorizontalRect(-3, 3, -3, 3, 0.0, -1.0);
  penumbra::OccluderSet awaySet(away);
  PENUMBRA_EXPECT(!awaySet.ShaftCandidates(0, 1, shaft));
  // Query B: from under the light, only the central occluder is in the pyramid.
  penumbra::CullingVolume frustum;
  PENUMBRA_EXPECT(set.BuildFrustum(Vec3(0, 0, 0), Vec3(0, 0, 1), 0, frustum));
  std::vector<int> candidates;
  set.VolumeCandidates(frustum, 0, 1, candidates);
  PENUMBRA_EXPECT((candidates == std::vector<int>{ 2 }));
  PENUMBRA_EXPECT(!set.BuildFrustum(Vec3(0, 0, 3), Vec3(0, 0, 1), 0, frustum));
}

// The capsule BuildFrustum puts around its pyramid only removes polygons
// that miss the pyramid: among randomly placed and tilted quads, for thin
// pyramids (points far from the light) and wide ones (points under it), the
// candidates with the capsule are those without it (box and planes alone,
// which keep some polygons that miss a thin pyramid) less polygons none of
// whose points, on a 21 x 21 grid over each, lies in the pyramid.
PENUMBRA_TEST(TestCapsuleKeepsCandidates)
{
  const double h = 3.0;
  const Scene scene = ScatteredQuads(h, 11, 1.5, 1.45);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const penumbra::OccluderSet set(scene);
  penumbra::CullingVolume frustum;
  std::vector<int> with, without;
  long long kept = 0, removed = 0;
  int queries = 0;
  for (int k = 0; k < 500; ++k)
  {
    const double reach = k % 2 ? 40.0 : 1.0;
    const Vec3 x(reach * u(rng), reach * u(rng), 0.0);
    if (!set.BuildFrustum(x, Vec3(0, 0, 1), 0, frustum))
    {
      continue;
    }
    ++queries;
    PENUMBRA_EXPECT(frustum.CapsuleRadius > 0.0);
    set.VolumeCandidates(frustum, 0, 1, with);
    frustum.CapsuleRadius = -1.0;
    set.VolumeCandidates(frustum, 0, 1, without);
    std::sort(with.begin(), with.end());
    std::sort(without.begin(), without.end());
    PENUMBRA_EXPECT(std::includes(without.begin(), without.end(), with.begin(), with.end()));
    kept += static_cast<long long>(with.size());
    for (const int id : without)
    {
      if (std::binary_search(with.begin(), with.end(), id))
      {
        continue;
      }
      ++removed;
      PENUMBRA_EXPECT(!QuadMeetsPyramid(scene.Surfaces[id].Vertices, x, h));
    }
  }
  PENUMBRA_EXPECT(queries > 400);
  PENUMBRA_EXPECT(kept > 0 && removed > 0);
  std::printf("capsule: %d pyramids, %lld candidates kept, %lld that miss the pyramid removed\n",
    queries, kept, removed);
}

// The tile query (OccluderSet::TileCandidates) lists every polygon that the
// pyramid of a point of the tile meets: filtered by that pyramid it gives
// the traversal's candidates and at most a few that miss the pyramid, for random tiles (1 cm to 4 m) around
// points under and far from the light, among randomly placed and tilted
// quads, some of them crossing the light's plane; and the evaluator, whose
// traversals use such tiles, gives the form factors of explicit traversals.
PENUMBRA_TEST(TestTileCandidatesMatchTheTraversal)
{
  const double h = 3.0;
  const Scene scene = ScatteredQuads(h, 5, 1.6, 1.6);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const penumbra::OccluderSet set(scene);
  penumbra::CullingVolume frustum, shaft;
  std::vector<int> traversal, tile, filtered;
  long long listed = 0, kept = 0, extra = 0;
  int queries = 0;
  for (int k = 0; k < 400; ++k)
  {
    const double reach = k % 2 ? 40.0 : 1.0;
    const Vec3 x(reach * u(rng), reach * u(rng), 0.0);
    if (!set.BuildFrustum(x, Vec3(0, 0, 1), 0, frustum))
    {
      continue;
    }
    ++queries;
    const double side = std::pow(10.0, -2.0 + 2.6 * 0.5 * (1.0 + u(rng)));
    const Vec3 corner(x.X - side * 0.5 * (1.0 + u(rng)), x.Y - side * 0.5 * (1.0 + u(rng)), 0.0);
    const Vec3 square[4] = { corner, corner + Vec3(side, 0, 0), corner + Vec3(side, side, 0),
      corner + Vec3(0, side, 0) };
    PENUMBRA_EXPECT(set.TileCandidates(square, 0, 1, tile, shaft));
    set.VolumeCandidates(frustum, 0, 1, traversal);
    filtered.clear();
    set.FilterCandidates(frustum, tile.data(), static_cast<int>(tile.size()), 0, 1, filtered);
    std::sort(traversal.begin(), traversal.end());
    // Every polygon the traversal finds; the few more miss the pyramid.
    PENUMBRA_EXPECT(
      std::includes(filtered.begin(), filtered.end(), traversal.begin(), traversal.end()));
    for (const int id : filtered)
    {
      if (!std::binary_search(traversal.begin(), traversal.end(), id))
      {
        ++extra;
        PENUMBRA_EXPECT(!QuadMeetsPyramid(scene.Surfaces[id].Vertices, x, h));
      }
    }
    listed += static_cast<long long>(tile.size());
    kept += static_cast<long long>(traversal.size());
  }
  PENUMBRA_EXPECT(queries > 300 && kept > 0);
  std::printf("tiles: %d pyramids, %lld polygons listed by their tiles, %lld kept by the "
              "traversal, %lld more that miss the pyramid\n",
    queries, listed, kept, extra);

  const penumbra::ExactEvaluator evaluator(scene);
  penumbra::VisibilityWorkspace cached, fresh;
  std::vector<int> all(scene.Surfaces.size() - 2);
  for (std::size_t i = 0; i < all.size(); ++i)
  {
    all[i] = static_cast<int>(i) + 2;
  }
  for (int k = 0; k < 200; ++k)
  {
    const Vec3 x(4.0 * u(rng), 4.0 * u(rng), 0.0);
    const double withTiles = evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, cached);
    // A candidate list longer than the evaluator's limit is traversed.
    const double traversed = evaluator.FormFactor(x, Vec3(0, 0, 1), 1, 0, all, fresh);
    PENUMBRA_EXPECT(withTiles == traversed);
  }
}

} // namespace
