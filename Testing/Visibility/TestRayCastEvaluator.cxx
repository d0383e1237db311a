// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the ray-cast evaluator (paper Eq. 6, penumbraRayCastEvaluator.h):
// convergence to the closed-form corner formula for an unoccluded square
// source as the tolerance shrinks; convergence in a penumbra toward the light
// rectangle minus the occluder's projection (corner formula with signs) and
// toward the exact evaluator; a non-uniform shooter against the exact
// linear-source result; identical results on 1 and 2 threads; no
// self-occlusion of receiver and shooter; watertight occluders; bad settings.
#include "penumbraExactEvaluator.h"
#include "penumbraFormFactor.h"
#include "penumbraLinearSource.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraShooterRadiance.h"
#include "penumbraTesting.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

using namespace penumbra;

namespace
{

constexpr double Pi = 3.141592653589793238462643383279502884;

/**
 * Form factor from a differential area to a parallel rectangle of sides a, b
 * at distance c, the area element facing one corner (Howell's catalogue,
 * configuration B-3). Odd in a and in b, so that signed sides give the
 * inclusion-exclusion of corner rectangles.
 */
double CornerFormFactor(double a, double b, double c)
{
  const double x = a / c;
  const double y = b / c;
  const double sx = std::sqrt(1 + x * x);
  const double sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * Pi);
}

/// Form factor from (px, 0, pz) facing +y to the rectangle [x0,x1] x [z0,z1] at height c.
double RectangleFormFactor(double px, double pz, double x0, double x1, double z0, double z1, double c)
{
  if (x1 <= x0 || z1 <= z0)
  {
    return 0.0;
  }
  return CornerFormFactor(x1 - px, z1 - pz, c) - CornerFormFactor(x0 - px, z1 - pz, c) -
    CornerFormFactor(x1 - px, z0 - pz, c) + CornerFormFactor(x0 - px, z0 - pz, c);
}

/// A horizontal square [x0,x1] x [z0,z1] at height y, facing up or down.
Surface Square(double x0, double x1, double z0, double z1, double y, bool up, RGB emission = RGB(),
  RGB reflectance = RGB(0.5, 0.5, 0.5))
{
  Surface s;
  if (up)
  {
    s.Vertices = { { x0, y, z0 }, { x0, y, z1 }, { x1, y, z1 }, { x1, y, z0 } };
  }
  else
  {
    s.Vertices = { { x0, y, z0 }, { x1, y, z0 }, { x1, y, z1 }, { x0, y, z1 } };
  }
  s.Emission = emission;
  s.Reflectance = reflectance;
  return s;
}

PENUMBRA_TEST(TestUnoccludedConvergence)
{
  std::printf("unoccluded unit square at height 1, floor point (0.2, 0, 0.1)\n");
  Scene scene;
  scene.Surfaces.push_back(Square(-2, 2, -2, 2, 0, true));                      // 0: floor
  scene.Surfaces.push_back(Square(-0.5, 0.5, -0.5, 0.5, 1, false, RGB(1, 1, 1))); // 1: light
  RayCastEvaluator evaluator(scene);
  const Vec3 x(0.2, 0, 0.1);
  const Vec3 n(0, 1, 0);
  const double exact = RectangleFormFactor(0.2, 0.1, -0.5, 0.5, -0.5, 0.5, 1.0);
  // The library's Lambert formula agrees with the corner formula.
  PENUMBRA_EXPECT_REL(PointPolygonFormFactorClipped(x, n, scene.Surfaces[1].Vertices), exact, 1e-13);
  // Centred: Howell's value 0.239456 (design.md).
  PENUMBRA_EXPECT_NEAR(RectangleFormFactor(0, 0, -0.5, 0.5, -0.5, 0.5, 1.0), 0.239456, 1e-6);
  evaluator.SetMaxDepth(12);
  double previous = 1.0;
  double first = 0.0;
  double last = 0.0;
  for (const double tolerance : { 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6 })
  {
    evaluator.SetTolerance(tolerance);
    RayCastStatistics stats;
    const double f = evaluator.FormFactor(x, n, 0, 1, &stats);
    const double error = std::abs(f - exact) / exact;
    std::printf("  tolerance %.0e: F = %.10f (exact %.10f), relative error %.2e, %lld rays, %lld pieces\n",
      tolerance, f, exact, error, stats.Rays, stats.Pieces);
    PENUMBRA_EXPECT(error <= previous * 1.5 + 1e-12); // falls (allowing small wiggles)
    if (tolerance == 1e-1)
    {
      first = error;
    }
    previous = std::max(error, 1e-300);
    last = error;
  }
  PENUMBRA_EXPECT(last < 1e-4);
  PENUMBRA_EXPECT(last < first);
  // The disc term keeps even one piece per triangle sensible: MaxDepth 0.
  evaluator.SetMaxDepth(0);
  evaluator.SetMinDepth(0);
  const double coarse = evaluator.FormFactor(x, n, 0, 1);
  std::printf("  MaxDepth 0 (2 samples): F = %.6f, relative error %.2e\n", coarse,
    std::abs(coarse - exact) / exact);
  PENUMBRA_EXPECT(std::abs(coarse - exact) / exact < 0.1);
}

/// Scene of the paper's Fig. 3: floor, square light at y = 2, square occluder at y = 1.
Scene OccluderScene()
{
  Scene scene;
  scene.Surfaces.push_back(Square(-2, 2, -2, 2, 0, true));                             // 0: floor
  scene.Surfaces.push_back(Square(-0.25, 0.25, -0.25, 0.25, 2, false, RGB(50, 50, 50))); // 1: light
  scene.Surfaces.push_back(Square(-0.3, 0.3, -0.3, 0.3, 1, true));                    // 2: occluder
  return scene;
}

/**
 * Visible form factor from floor point (px, 0, pz) of the OccluderScene light:
 * the occluder [-0.3, 0.3]^2 at height 1 projects from x onto the light's
 * plane (height 2) as the rectangle 2 o - p; subtract its overlap with the
 * light (corner formula with signs).
 */
double OccludedReference(double px, double pz)
{
  const double light = RectangleFormFactor(px, pz, -0.25, 0.25, -0.25, 0.25, 2.0);
  const double sx0 = std::max(-0.25, 2 * -0.3 - px);
  const double sx1 = std::min(0.25, 2 * 0.3 - px);
  const double sz0 = std::max(-0.25, 2 * -0.3 - pz);
  const double sz1 = std::min(0.25, 2 * 0.3 - pz);
  return light - RectangleFormFactor(px, pz, sx0, sx1, sz0, sz1, 2.0);
}

PENUMBRA_TEST(TestOccludedConvergence)
{
  std::printf("penumbra of the Fig. 3 scene, floor point (0.5, 0, 0.1)\n");
  const Scene scene = OccluderScene();
  RayCastEvaluator evaluator(scene);
  evaluator.SetMaxDepth(16);
  const Vec3 x(0.5, 0, 0.1);
  const Vec3 n(0, 1, 0);
  const double reference = OccludedReference(0.5, 0.1);
  const double light = RectangleFormFactor(0.5, 0.1, -0.25, 0.25, -0.25, 0.25, 2.0);
  std::printf("  visible fraction of the light's form factor: %.4f\n", reference / light);
  PENUMBRA_EXPECT(reference > 0.1 * light && reference < 0.9 * light); // really a penumbra
  // The exact evaluator (exact visibility + Lambert) agrees with the corner formula.
  ExactEvaluator exact(scene);
  VisibilityWorkspace workspace;
  const double exactF = exact.FormFactor(x, n, 0, 1, workspace);
  std::printf("  corner-formula reference %.12f, exact evaluator %.12f\n", reference, exactF);
  PENUMBRA_EXPECT_REL(exactF, reference, 1e-12);
  double first = 0.0;
  double last = 0.0;
  // Pieces crossed by the shadow edge carry an O(size) centroid-sampling
  // error: the error falls like the square root of the tolerance here.
  for (const double tolerance : { 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7 })
  {
    evaluator.SetTolerance(tolerance);
    RayCastStatistics stats;
    const double f = evaluator.FormFactor(x, n, 0, 1, &stats);
    const double error = std::abs(f - reference) / reference;
    std::printf("  tolerance %.0e: F = %.8f, relative error %.2e, %lld rays, deepest level %d\n",
      tolerance, f, error, stats.Rays, stats.DeepestLevel);
    if (tolerance == 1e-1)
    {
      first = error;
    }
    last = error;
  }
  PENUMBRA_EXPECT(last < first);
  PENUMBRA_EXPECT(last < 1e-3);
  // Contributed radiance: rho Le F.
  evaluator.SetTolerance(1e-7);
  const RGB radiance = evaluator.ContributedRadiance(x, n, 0, 1);
  PENUMBRA_EXPECT_REL(radiance.G, 0.5 * 50 * reference, 1e-3);
  // Umbra and full light.
  evaluator.SetTolerance(1e-3);
  PENUMBRA_EXPECT_NEAR(evaluator.FormFactor(Vec3(0, 0, 0), n, 0, 1), 0.0, 0.0);
  const double lit = evaluator.FormFactor(Vec3(1.5, 0, 0.2), n, 0, 1);
  PENUMBRA_EXPECT_REL(lit, RectangleFormFactor(1.5, 0.2, -0.25, 0.25, -0.25, 0.25, 2.0), 1e-3);
}

/// A ramp over the light of the Fig. 3 scene: (0, 0.2, 1) at x = -0.25 to (1, 0.2, 0) at 0.25.
ShooterRadiance RampOnLight()
{
  std::vector<Vec3> points;
  std::vector<RGB> values;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      const double u = -0.25 + 0.25 * i;
      const double v = -0.25 + 0.25 * j;
      points.push_back(Vec3(u, 2, v));
      const double t = (u + 0.25) / 0.5;
      values.push_back(RGB(t, 0.2 + (i == 1 && j == 1 ? 0.6 : 0.0), 1 - t));
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
  return ShooterRadiance(points, triangles, values);
}

PENUMBRA_TEST(TestNonUniformShooter)
{
  std::printf("non-uniform shooter (piecewise-linear ramp on the light)\n");
  const Scene scene = OccluderScene();
  const ShooterRadiance ramp = RampOnLight();
  RayCastEvaluator evaluator(scene);
  evaluator.SetMaxDepth(16);
  ExactEvaluator exact(scene);
  LinearSourceWorkspace workspace;
  const Vec3 n(0, 1, 0);
  // Unoccluded point: against the closed form over the whole light.
  {
    const Vec3 x(1.3, 0, -0.4);
    const RGB reference =
      UnoccludedShooterIrradiance(x, n, ramp, scene.Surfaces[1].Vertices, workspace);
    const RGB viaExact = ExactShooterIrradiance(exact, x, n, 0, 1, ramp, workspace);
    evaluator.SetTolerance(1e-6);
    const RGB rayCast = evaluator.Irradiance(x, n, 0, 1, ramp);
    std::printf("  lit point: closed form (%.9f, %.9f, %.9f), ray cast (%.9f, %.9f, %.9f)\n",
      reference.R, reference.G, reference.B, rayCast.R, rayCast.G, rayCast.B);
    for (int c = 0; c < 3; ++c)
    {
      PENUMBRA_EXPECT_REL(viaExact[c], reference[c], 1e-12);
      PENUMBRA_EXPECT_REL(rayCast[c], reference[c], 1e-4);
    }
    // The ramp is not the constant: the bright (red) side is the near one.
    PENUMBRA_EXPECT(reference.R > reference.B);
  }
  // Penumbra point: visible part of the light is x in [0.1, 0.25] (see
  // OccludedReference); integrate the ramp over it with a hand-made region.
  {
    const Vec3 x(0.5, 0, 0.1);
    VisibleRegion region;
    region.Offsets = { 0, 4 };
    region.Points = { { 0.1, 2, -0.25 }, { 0.25, 2, -0.25 }, { 0.25, 2, 0.25 }, { 0.1, 2, 0.25 } };
    const RGB reference = VisibleShooterIrradiance(x, n, ramp, region, Vec3(0, -1, 0), workspace);
    const RGB viaExact = ExactShooterIrradiance(exact, x, n, 0, 1, ramp, workspace);
    std::printf("  penumbra point: hand-made region (%.9f, %.9f, %.9f), exact evaluator (%.9f, %.9f, %.9f)\n",
      reference.R, reference.G, reference.B, viaExact.R, viaExact.G, viaExact.B);
    for (int c = 0; c < 3; ++c)
    {
      PENUMBRA_EXPECT_REL(viaExact[c], reference[c], 1e-10);
    }
    double first = 0.0;
    double last = 0.0;
    for (const double tolerance : { 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7 })
    {
      evaluator.SetTolerance(tolerance);
      const RGB rayCast = evaluator.Irradiance(x, n, 0, 1, ramp);
      double error = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        error = std::max(error, std::abs(rayCast[c] - reference[c]) / reference.Mean());
      }
      std::printf("  tolerance %.0e: ray cast (%.9f, %.9f, %.9f), max error / mean %.2e\n",
        tolerance, rayCast.R, rayCast.G, rayCast.B, error);
      first = tolerance == 1e-2 ? error : first;
      last = error;
    }
    PENUMBRA_EXPECT(last < first);
    PENUMBRA_EXPECT(last < 1e-3);
  }
}

PENUMBRA_TEST(TestHalfLitAgreement)
{
  std::printf("half-lit shooter (Fig. 7/8): exact and ray cast agree\n");
  Scene scene;
  scene.Surfaces.push_back(Square(-3, 3, -3, 3, 0, true));            // 0: receiver
  scene.Surfaces.push_back(Square(-1, 1, -1, 1, 1, false, RGB(1, 1, 1))); // 1: shooter
  // Dark for u < -0.05, bright for u > 0.05, a ramp in between.
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
  RayCastEvaluator evaluator(scene);
  evaluator.SetTolerance(1e-5);
  evaluator.SetMaxDepth(12);
  ExactEvaluator exact(scene);
  LinearSourceWorkspace workspace;
  for (const double s : { -1.0, -0.5, 0.0, 0.5, 1.0 })
  {
    const Vec3 x(s, 0, 0);
    const double e = ExactShooterIrradiance(exact, x, Vec3(0, 1, 0), 0, 1, halfLit, workspace).R;
    const double r = evaluator.Irradiance(x, Vec3(0, 1, 0), 0, 1, halfLit).R;
    std::printf("  x = %5.2f: exact %.8f, ray cast %.8f\n", s, e, r);
    PENUMBRA_EXPECT_REL(r, e, 1e-3);
  }
  PENUMBRA_EXPECT(evaluator.Irradiance(Vec3(0.5, 0, 0), Vec3(0, 1, 0), 0, 1, halfLit).R >
    evaluator.Irradiance(Vec3(-0.5, 0, 0), Vec3(0, 1, 0), 0, 1, halfLit).R);
}

PENUMBRA_TEST(TestDeterminism)
{
  std::printf("determinism: 1 thread vs 2 threads\n");
  const Scene scene = OccluderScene();
  RayCastEvaluator evaluator(scene);
  const ShooterRadiance ramp = RampOnLight();
  const int count = 400;
  std::vector<Vec3> xs;
  for (int i = 0; i < count; ++i)
  {
    // A fixed spiral over the floor, through light, penumbra and umbra.
    const double r = 1.5 * (i + 0.5) / count;
    const double a = 2.399963229728653 * i;
    xs.push_back(Vec3(r * std::cos(a), 0, r * std::sin(a)));
  }
  const auto evaluate = [&](int i) { return evaluator.Irradiance(xs[i], Vec3(0, 1, 0), 0, 1, ramp); };
  std::vector<RGB> serial(count);
  for (int i = 0; i < count; ++i)
  {
    serial[i] = evaluate(i);
  }
  std::vector<RGB> parallel(count);
  // Two threads, interleaved, in reverse order: another order and another split.
  std::thread t0([&] {
    for (int i = count - 1; i >= 0; i -= 2)
    {
      parallel[i] = evaluate(i);
    }
  });
  std::thread t1([&] {
    for (int i = count - 2; i >= 0; i -= 2)
    {
      parallel[i] = evaluate(i);
    }
  });
  t0.join();
  t1.join();
  int differences = 0;
  for (int i = 0; i < count; ++i)
  {
    differences += std::memcmp(&serial[i], &parallel[i], sizeof(RGB)) != 0;
  }
  std::printf("  %d points, %d bitwise differences\n", count, differences);
  PENUMBRA_EXPECT(differences == 0);
}

PENUMBRA_TEST(TestNoSelfOcclusion)
{
  std::printf("receiver and shooter do not occlude themselves\n");
  // An L-shaped pair: floor (receiver) and a wall (shooter) meeting at x = 0.
  Scene scene;
  scene.Surfaces.push_back(Square(0, 1, 0, 1, 0, true)); // 0: floor
  Surface wall;
  wall.Vertices = { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 1, 1 }, { 0, 0, 1 } }; // facing +x
  wall.Emission = RGB(1, 1, 1);
  scene.Surfaces.push_back(wall);
  RayCastEvaluator evaluator(scene);
  evaluator.SetTolerance(1e-5);
  evaluator.SetMaxDepth(12);
  PENUMBRA_EXPECT(ComputePolygonGeometry(wall.Vertices).Normal.X > 0.99);
  for (const double d : { 1e-3, 1e-2, 0.3 })
  {
    const Vec3 x(d, 0, 0.5);
    const double exact = PointPolygonFormFactorClipped(x, Vec3(0, 1, 0), wall.Vertices);
    const double rayCast = evaluator.FormFactor(x, Vec3(0, 1, 0), 0, 1);
    std::printf("  %.0e from the wall: exact %.8f, ray cast %.8f\n", d, exact, rayCast);
    PENUMBRA_EXPECT_REL(rayCast, exact, 2e-3);
  }
}

PENUMBRA_TEST(TestWatertight)
{
  std::printf("rays through the diagonal of a quad occluder are blocked\n");
  Scene scene;
  scene.Surfaces.push_back(Square(-1, 1, -1, 1, 1, true)); // split along a diagonal
  RayCaster caster(scene);
  PENUMBRA_EXPECT(caster.GetNumberOfTriangles() == 2);
  PENUMBRA_EXPECT(caster.GetNumberOfSurfaceTriangles(0) == 2);
  std::vector<OcclusionRay> rays;
  for (int i = 0; i < 1001; ++i)
  {
    // Points on both diagonals of the square at y = 1.
    const double t = -0.999 + 1.998 * i / 1000.0;
    rays.push_back({ Vec3(0.1 * t, 0, 0.2), Vec3(t, 1, t) + (Vec3(t, 1, t) - Vec3(0.1 * t, 0, 0.2)) });
    rays.push_back({ Vec3(0.3, 0, -0.1 * t), Vec3(t, 1, -t) * 2.0 - Vec3(0.3, 0, -0.1 * t) });
  }
  std::vector<unsigned char> occluded(rays.size());
  const std::size_t blocked = caster.TraceOcclusion(rays.data(), rays.size(), occluded.data());
  std::printf("  %zu of %zu blocked\n", blocked, rays.size());
  PENUMBRA_EXPECT(blocked == rays.size());
  // Ignoring the occluder lets them all through.
  PENUMBRA_EXPECT(caster.TraceOcclusion(rays.data(), rays.size(), occluded.data(), 0) == 0);
  PENUMBRA_EXPECT(!caster.IsOccluded(Vec3(0, 0, 0), Vec3(0, 0.99, 0)));
  PENUMBRA_EXPECT(caster.IsOccluded(Vec3(0, 0, 0), Vec3(0, 1.01, 0)));
}

PENUMBRA_TEST(TestSettings)
{
  const Scene scene = OccluderScene();
  RayCastEvaluator evaluator(scene);
  PENUMBRA_EXPECT(evaluator.GetTolerance() == 1e-3);
  PENUMBRA_EXPECT(evaluator.GetMinDepth() == 1);
  PENUMBRA_EXPECT(evaluator.GetMaxDepth() == 8);
  PENUMBRA_EXPECT(evaluator.GetRelativeRayOffset() == 1e-5);
  PENUMBRA_EXPECT_THROW(evaluator.SetTolerance(0.0), InputError, "Tolerance");
  PENUMBRA_EXPECT_THROW(evaluator.SetTolerance(1.5), InputError, "(0, 1]");
  PENUMBRA_EXPECT_THROW(evaluator.SetAbsoluteTolerance(-1.0), InputError, "AbsoluteTolerance");
  PENUMBRA_EXPECT_THROW(evaluator.SetMaxDepth(17), InputError, "MaxDepth");
  PENUMBRA_EXPECT_THROW(evaluator.SetMinDepth(-1), InputError, "MinDepth");
  PENUMBRA_EXPECT_THROW(evaluator.SetRelativeRayOffset(0.5), InputError, "RelativeOffset");
  PENUMBRA_EXPECT_THROW(evaluator.FormFactor(Vec3(), Vec3(0, 1, 0), 0, 7), InputError, "shooter id 7");
  evaluator.SetMaxDepth(2);
  evaluator.SetMinDepth(3);
  PENUMBRA_EXPECT_THROW(evaluator.FormFactor(Vec3(), Vec3(0, 1, 0), 0, 1), InputError, "exceeds MaxDepth");
  // Behind the shooter: nothing.
  evaluator.SetMinDepth(1);
  PENUMBRA_EXPECT(evaluator.FormFactor(Vec3(0, 3, 0), Vec3(0, -1, 0), -1, 1) == 0.0);
}

} // namespace
