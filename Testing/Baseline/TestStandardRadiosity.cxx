// SPDX-License-Identifier: GPL-3.0-or-later
// Standard radiosity (the baseline) against independent references: the
// furnace (closed box, uniform emission and reflectance: L = L^e / (1 - rho)
// exactly), the energy identity and the closed box's loss, direct light of a
// square source on an open floor against Lambert's closed form at
// independent points as the mesh is refined (the convergence is printed and
// must be monotone), the adaptive subdivision at a shadow, thread
// independence, vertex-to-patch form factors in umbra and full light, and
// the settings' ranges.
#include "penumbraFormFactor.h"
#include "penumbraSceneLibrary.h"
#include "penumbraStandardRadiosity.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>
#include <vector>

using penumbra::Cross;
using penumbra::Dot;
using penumbra::FormFactorMode;
using penumbra::RGB;
using penumbra::Scene;
using penumbra::StandardRadiosity;
using penumbra::StandardRadiosityMesh;
using penumbra::StandardRadiositySettings;
using penumbra::StandardRadiositySummary;
using penumbra::Surface;
using penumbra::Vec3;

namespace
{

// A polygon whose front normal points along `front` (winding reversed if needed).
Surface Polygon(std::vector<Vec3> v, const Vec3& front, const RGB& rho, const RGB& le)
{
  if (Dot(Cross(v[1] - v[0], v[2] - v[0]), front) < 0.0)
  {
    std::reverse(v.begin(), v.end());
  }
  return Surface{ v, rho, le };
}

// The unit box [0,1]^3, every face facing inside, all with the same material.
Scene FurnaceBox(const RGB& rho, const RGB& le)
{
  Scene scene;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = 0; side < 2; ++side)
    {
      std::vector<Vec3> quad;
      const double c = side;
      const double corners[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
      for (const auto& uv : corners)
      {
        double p[3];
        p[axis] = c;
        p[(axis + 1) % 3] = uv[0];
        p[(axis + 2) % 3] = uv[1];
        quad.emplace_back(p[0], p[1], p[2]);
      }
      double front[3] = { 0, 0, 0 };
      front[axis] = side == 0 ? 1.0 : -1.0;
      scene.Surfaces.push_back(Polygon(quad, Vec3(front[0], front[1], front[2]), rho, le));
    }
  }
  return scene;
}

// A 2 x 2 m floor (y = 0, facing up, reflectance 0.5) under a 0.5 x 0.5 m
// black square light at height 1 facing down, emission 1, centred.
Scene SquareLightOverFloor()
{
  Scene scene;
  scene.Surfaces.push_back(Polygon({ { -1, 0, -1 }, { 1, 0, -1 }, { 1, 0, 1 }, { -1, 0, 1 } },
    Vec3(0, 1, 0), RGB(0.5, 0.5, 0.5), RGB()));
  scene.Surfaces.push_back(
    Polygon({ { -0.25, 1, -0.25 }, { 0.25, 1, -0.25 }, { 0.25, 1, 0.25 }, { -0.25, 1, 0.25 } },
      Vec3(0, -1, 0), RGB(), RGB(1, 1, 1)));
  return scene;
}

penumbra::ParallelFor TwoThreads()
{
  return [](std::size_t begin, std::size_t end,
           const std::function<void(std::size_t, std::size_t)>& body) {
    const std::size_t middle = begin + (end - begin) / 2;
    std::thread worker([&] { body(begin, middle); });
    body(middle, end);
    worker.join();
  };
}

// Linear interpolation of the display mesh at (x, z) on the floor (surface
// 0, the plane y = 0); NaN if no triangle contains the point.
double InterpolateOnFloor(const StandardRadiosityMesh& mesh, double x, double z)
{
  for (std::size_t t = 0; t < mesh.Triangles.size(); ++t)
  {
    if (mesh.TriangleSurface[t] != 0)
    {
      continue;
    }
    const Vec3& a = mesh.Points[mesh.Triangles[t][0]];
    const Vec3& b = mesh.Points[mesh.Triangles[t][1]];
    const Vec3& c = mesh.Points[mesh.Triangles[t][2]];
    const double det = (b.X - a.X) * (c.Z - a.Z) - (c.X - a.X) * (b.Z - a.Z);
    const double u = ((x - a.X) * (c.Z - a.Z) - (c.X - a.X) * (z - a.Z)) / det;
    const double v = ((b.X - a.X) * (z - a.Z) - (x - a.X) * (b.Z - a.Z)) / det;
    if (u >= -1e-12 && v >= -1e-12 && u + v <= 1 + 1e-12)
    {
      const double la = mesh.Radiance[mesh.Triangles[t][0]].R;
      const double lb = mesh.Radiance[mesh.Triangles[t][1]].R;
      const double lc = mesh.Radiance[mesh.Triangles[t][2]].R;
      return la + u * (lb - la) + v * (lc - la);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

PENUMBRA_TEST(TestFurnace)
{
  const RGB rho(0.3, 0.5, 0.7);
  const RGB le(1.0, 1.0, 1.0);
  StandardRadiositySettings settings;
  settings.PatchSize = 0.5;
  settings.ElementSize = 0.25;
  settings.UnshotFraction = 1e-7;
  // The converged field is uniform, so no element needs splitting; the
  // splits that transient non-uniformity of the shooting order triggers
  // leave a real error of the method (an element's power received before
  // its split was measured at the parent's corners): printed, not asserted.
  settings.MaximumSubdivisionDepth = 0;
  struct Case
  {
    FormFactorMode Mode;
    int Depth;
  };
  for (const Case c : { Case{ FormFactorMode::AnalyticVisibility, 0 },
         Case{ FormFactorMode::AnalyticVisibility, 3 }, Case{ FormFactorMode::Disc, 0 } })
  {
    const FormFactorMode mode = c.Mode;
    settings.FormFactor = mode;
    settings.MaximumSubdivisionDepth = c.Depth;
    StandardRadiosity solver(FurnaceBox(rho, le));
    solver.SetSettings(settings);
    const StandardRadiositySummary summary = solver.Run();
    const StandardRadiosityMesh mesh = solver.GetMesh();
    double worst = 0.0;
    for (const RGB& l : mesh.Radiance)
    {
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(l[c] * (1.0 - rho[c]) / le[c] - 1.0));
      }
    }
    const double escaped = summary.Energy.Escaped().Mean() / summary.Energy.Emitted.Mean();
    std::printf("furnace (%s form factors, subdivision depth %d): %d shots, %d vertices, "
                "largest relative error %.3g, escaped %.3g of the emitted power\n",
      mode == FormFactorMode::Disc ? "disc" : "analytic x visibility", c.Depth, summary.Shots,
      summary.Vertices, worst, escaped);
    if (mode == FormFactorMode::AnalyticVisibility && c.Depth == 0)
    {
      // In a convex closed box every patch is wholly visible from every
      // vertex, so the closed-form form factors of a vertex sum to exactly 1
      // and the only error left is the light not yet shot: at most
      // UnshotFraction of the emission, amplified by at most 1 / (1 - rho) =
      // 3.3 through later bounces, and spread unevenly (x 10 margin):
      // 3.3e-6 < 1e-5. What remains beyond rounding is a bug.
      PENUMBRA_EXPECT(worst < 1e-5);
      // The vertices' form factors sum to 1, so every shot's power lands on
      // the elements: nothing escapes a closed box beyond rounding.
      PENUMBRA_EXPECT(std::abs(escaped) < 1e-9);
    }
  }
}

PENUMBRA_TEST(TestEnergyBalance)
{
  StandardRadiositySettings settings;
  settings.UnshotFraction = 1e-2;
  settings.ElementSize = 0.1; // coarse: the identity does not depend on the mesh
  settings.ShooterSamples = 2;
  StandardRadiosity solver(penumbra::MakeBuiltinScene("cornell"));
  solver.SetSettings(settings);
  const StandardRadiositySummary summary = solver.Run();
  const penumbra::ShootingEnergy& e = summary.Energy;
  for (int c = 0; c < 3; ++c)
  {
    const double balance = e.Absorbed()[c] + e.Escaped()[c] + e.Unshot[c] + e.Residual()[c];
    PENUMBRA_EXPECT_REL(balance, e.Emitted[c], 1e-12);
  }
  // The Cornell box is open at the front: light escapes, but not most of it.
  const double escaped = e.Escaped().Mean() / e.Emitted.Mean();
  std::printf("Cornell box: %d shots, %d elements, %d vertices, %.2f s; absorbed %.4f, "
              "escaped %.4f, unshot %.4f of the emitted power\n",
    summary.Shots, summary.Elements, summary.Vertices, summary.Seconds,
    e.Absorbed().Mean() / e.Emitted.Mean(), escaped, e.Unshot.Mean() / e.Emitted.Mean());
  PENUMBRA_EXPECT(escaped > 0.0 && escaped < 0.5);
  PENUMBRA_EXPECT(summary.UnshotFraction <= 1e-2);
}

// Error of the displayed floor radiance against rho L^e F (Lambert's closed
// form) at 40 x 40 points that are not mesh vertices: RMS and maximum,
// relative to the mean.
struct DirectError
{
  double Rms = 0.0;
  double Max = 0.0;
  int Vertices = 0;
};

DirectError MeasureDirect(const StandardRadiositySettings& settings)
{
  const Scene scene = SquareLightOverFloor();
  StandardRadiosity solver(scene);
  solver.SetSettings(settings);
  const StandardRadiositySummary summary = solver.Run();
  const StandardRadiosityMesh mesh = solver.GetMesh();
  const std::vector<Vec3>& light = scene.Surfaces[1].Vertices;
  double sum2 = 0.0, sum = 0.0, worst = 0.0;
  int count = 0;
  for (int i = 0; i < 40; ++i)
  {
    for (int j = 0; j < 40; ++j)
    {
      // Irrational offsets: never on a vertex or an edge of any mesh tried.
      const double x = -1.0 + (i + 0.5 + 0.1 * std::sqrt(2.0)) / 40.0 * 2.0 * 0.99;
      const double z = -1.0 + (j + 0.5 + 0.1 * std::sqrt(3.0)) / 40.0 * 2.0 * 0.99;
      const double exact =
        0.5 * penumbra::PointPolygonFormFactorClipped(Vec3(x, 0, z), Vec3(0, 1, 0), light);
      const double shown = InterpolateOnFloor(mesh, x, z);
      PENUMBRA_EXPECT(std::isfinite(shown));
      sum2 += (shown - exact) * (shown - exact);
      sum += exact;
      worst = std::max(worst, std::abs(shown - exact));
      ++count;
    }
  }
  const double mean = sum / count;
  return { std::sqrt(sum2 / count) / mean, worst / mean, summary.Vertices };
}

PENUMBRA_TEST(TestDirectConvergence)
{
  // The form factor this test trusts: Howell's differential area to a
  // parallel unit square centred at distance 1.
  const std::vector<Vec3> unitSquare = { { -0.5, 1, -0.5 }, { 0.5, 1, -0.5 }, { 0.5, 1, 0.5 },
    { -0.5, 1, 0.5 } }; // facing down, toward the point
  PENUMBRA_EXPECT_NEAR(
    penumbra::PointPolygonFormFactorClipped(Vec3(0, 0, 0), Vec3(0, 1, 0), unitSquare), 0.239456,
    1e-6);

  StandardRadiositySettings settings;
  settings.SubdivisionThreshold = std::numeric_limits<double>::infinity(); // uniform meshes
  std::printf("direct light on the floor, uniform meshes (error relative to the mean):\n"
              "  element size   vertices   RMS        max\n");
  double previousRms = std::numeric_limits<double>::infinity();
  double previousMax = std::numeric_limits<double>::infinity();
  double firstRms = 0.0, lastRms = 0.0;
  for (double size : { 0.2, 0.1, 0.05, 0.025 })
  {
    settings.ElementSize = size;
    const DirectError error = MeasureDirect(settings);
    std::printf("  %-14g %-10d %-10.3g %-10.3g\n", size, error.Vertices, error.Rms, error.Max);
    PENUMBRA_EXPECT(error.Rms < previousRms);
    PENUMBRA_EXPECT(error.Max < previousMax);
    previousRms = error.Rms;
    previousMax = error.Max;
    firstRms = firstRms > 0.0 ? firstRms : error.Rms;
    lastRms = error.Rms;
  }
  // Linear interpolation of a smooth field errs like h^2: 8 times finer,
  // about 64 times smaller; at least 20 times is asked.
  PENUMBRA_EXPECT(lastRms < firstRms / 20.0);

  // Wallace et al.'s disc form factors: the vertex values themselves are
  // biased, and refining the shooter's samples is what reduces it.
  settings.ElementSize = 0.025;
  settings.FormFactor = FormFactorMode::Disc;
  std::printf("same, disc form factors at element size 0.025:\n  shooter samples   RMS        max\n");
  previousRms = std::numeric_limits<double>::infinity();
  for (int samples : { 1, 2, 4, 8 })
  {
    settings.ShooterSamples = samples;
    const DirectError error = MeasureDirect(settings);
    std::printf("  %-17d %-10.3g %-10.3g\n", samples, error.Rms, error.Max);
    PENUMBRA_EXPECT(error.Rms < previousRms);
    previousRms = error.Rms;
  }
}

PENUMBRA_TEST(TestAdaptiveSubdivision)
{
  // The paper's Fig. 3 in 3D: adaptive subdivision must refine around the
  // shadow, adding elements, and be deterministic across thread counts.
  StandardRadiositySettings settings;
  settings.UnshotFraction = 1e-2;
  const Scene scene = penumbra::MakeBuiltinScene("occluder");
  StandardRadiosity serial(scene);
  settings.MaximumSubdivisionDepth = 0;
  serial.SetSettings(settings);
  const StandardRadiositySummary uniform = serial.Run();
  settings.MaximumSubdivisionDepth = 3;
  serial.SetSettings(settings);
  const StandardRadiositySummary adaptive = serial.Run();
  std::printf("occluder scene: %d elements uniform, %d adaptive (%d splits), %.2f s\n",
    uniform.Elements, adaptive.Elements, adaptive.SubdividedElements, adaptive.Seconds);
  PENUMBRA_EXPECT(adaptive.SubdividedElements > 0);
  PENUMBRA_EXPECT(adaptive.Elements == uniform.Elements + 3 * adaptive.SubdividedElements);

  StandardRadiosity threaded(scene);
  threaded.SetSettings(settings);
  threaded.SetParallelFor(TwoThreads());
  threaded.Run();
  const StandardRadiosityMesh a = serial.GetMesh();
  const StandardRadiosityMesh b = threaded.GetMesh();
  PENUMBRA_EXPECT(a.Points.size() == b.Points.size());
  bool identical = a.Radiance.size() == b.Radiance.size();
  for (std::size_t k = 0; identical && k < a.Radiance.size(); ++k)
  {
    identical = a.Radiance[k].R == b.Radiance[k].R && a.Radiance[k].G == b.Radiance[k].G &&
      a.Radiance[k].B == b.Radiance[k].B;
  }
  PENUMBRA_EXPECT(identical);

  // Display mesh: every triangle counter-clockwise about its surface's normal.
  int inverted = 0;
  for (std::size_t t = 0; t < a.Triangles.size(); ++t)
  {
    const auto& tri = a.Triangles[t];
    const Vec3 normal = penumbra::ComputePolygonGeometry(
      scene.Surfaces[a.TriangleSurface[t]].Vertices).Normal;
    inverted += Dot(Cross(a.Points[tri[1]] - a.Points[tri[0]], a.Points[tri[2]] - a.Points[tri[0]]),
                  normal) <= 0.0;
  }
  PENUMBRA_EXPECT(inverted == 0);
}

PENUMBRA_TEST(TestFormFactors)
{
  // The occluder scene (paper Fig. 3): light (surface 1) 0.5 x 0.5 m at
  // y = 2, occluder 0.6 x 0.6 m at y = 1; umbra |x|, |z| < 0.35 m on the floor.
  const Scene scene = penumbra::MakeBuiltinScene("occluder");
  StandardRadiosity solver(scene);
  StandardRadiositySettings settings;
  settings.MaximumShots = 0; // mesh only
  solver.SetSettings(settings);
  solver.Run();
  const Vec3 up(0, 1, 0);
  auto toLight = [&](const Vec3& x) {
    double sum = 0.0;
    for (int p = 0; p < solver.GetNumberOfPatches(); ++p)
    {
      const std::array<Vec3, 3> corners = solver.GetPatch(p);
      bool onLight = true;
      for (const Vec3& c : corners)
      {
        onLight = onLight && std::abs(c.Y - 2.0) < 1e-12;
      }
      sum += onLight ? solver.FormFactor(x, up, 0, p) : 0.0;
    }
    return sum;
  };
  // In the umbra every ray is blocked; far outside the penumbra none is, and
  // the analytic mode then gives Lambert's closed form exactly.
  PENUMBRA_EXPECT(toLight(Vec3(0.1, 0, -0.2)) == 0.0);
  const Vec3 lit(1.5, 0, 1.2);
  PENUMBRA_EXPECT_REL(toLight(lit),
    penumbra::PointPolygonFormFactorClipped(lit, up, scene.Surfaces[1].Vertices), 1e-12);
  PENUMBRA_EXPECT_THROW(solver.FormFactor(lit, up, 0, -1), penumbra::InputError, "patch -1");
  PENUMBRA_EXPECT_THROW(
    solver.GetPatch(solver.GetNumberOfPatches()), penumbra::InputError, "out of range");
}

PENUMBRA_TEST(TestSettings)
{
  StandardRadiosity solver(SquareLightOverFloor());
  StandardRadiositySettings bad;
  bad.ElementSize = 0.0;
  PENUMBRA_EXPECT_THROW(solver.SetSettings(bad), penumbra::InputError, "ElementSize");
  bad = StandardRadiositySettings();
  bad.ShooterSamples = 0;
  PENUMBRA_EXPECT_THROW(solver.SetSettings(bad), penumbra::InputError, "ShooterSamples");
  bad = StandardRadiositySettings();
  bad.MaximumSubdivisionDepth = 13;
  PENUMBRA_EXPECT_THROW(solver.SetSettings(bad), penumbra::InputError, "MaximumSubdivisionDepth");
  bad = StandardRadiositySettings();
  bad.UnshotFraction = 2.0;
  PENUMBRA_EXPECT_THROW(solver.SetSettings(bad), penumbra::InputError, "UnshotFraction");
  Scene broken = SquareLightOverFloor();
  broken.Surfaces[0].Reflectance = RGB(1.5, 0, 0);
  PENUMBRA_EXPECT_THROW(StandardRadiosity{ broken }, penumbra::InputError, "cell 0");
}

} // namespace
