// SPDX-License-Identifier: GPL-3.0-or-later
// Throughput of the exact radiance evaluator on one core: point-to-polygon
// form factors without occlusion, and exact visibility with 1, 7 and 30
// occluders in the pyramid from the receiving points to the light.
//
// Built with the project (PENUMBRA_BUILD_BENCHMARKS, on by default) as
// build/bin/penumbraEvaluatorBenchmark; the build flags are the project's (no -march=native,
// so that the numbers describe a portable build).
// Usage: penumbraEvaluatorBenchmark [seconds per row, default 1]
// Rates are per second of this thread's CPU time (best of several rounds), so
// that other processes sharing the machine distort them as little as possible.
#include "penumbraExactEvaluator.h"
#include "penumbraFormFactor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

using namespace penumbra;

namespace
{

Surface Quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  Surface s;
  s.Vertices = { a, b, c, d };
  s.Reflectance = RGB(0.5, 0.5, 0.5);
  return s;
}

// The unit light at height 2 facing down over a floor, plus `count` small
// tilted squares placed so that each meets the pyramid from every receiving
// point of the benchmark (|x|, |y| <= 0.2 on the floor) to the light.
Scene MakeScene(int count, unsigned seed)
{
  Scene scene;
  scene.Surfaces.push_back(
    Quad({ -0.5, -0.5, 2 }, { -0.5, 0.5, 2 }, { 0.5, 0.5, 2 }, { 0.5, -0.5, 2 }));
  scene.Surfaces[0].Emission = RGB(10, 10, 10);
  scene.Surfaces.push_back(Quad({ -3, -3, 0 }, { 3, -3, 0 }, { 3, 3, 0 }, { -3, 3, 0 }));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), height(0.6, 1.8);
  for (int k = 0; k < count; ++k)
  {
    const double z = height(rng);
    // Centre inside the cross-section at height z of the pyramid from every
    // receiving point to the light, |x|, |y| <= 0.35 z - 0.2, or within
    // reach of it: half-sides of 0.06 to 0.16 overlap it in every case.
    const double reach = std::max(0.0, 0.35 * z - 0.2) + 0.05;
    const Vec3 c(reach * u(rng), reach * u(rng), z);
    const double side = 0.06 + 0.05 * (u(rng) + 1.0);
    const Vec3 a = Normalized(Vec3(0.3 * u(rng), 0.3 * u(rng), 1.0));
    const Vec3 b = Normalized(Cross(a, Vec3(u(rng), u(rng), 0.1)));
    const Vec3 e = Cross(a, b);
    scene.Surfaces.push_back(Quad(c - b * side - e * side, c + b * side - e * side,
      c + b * side + e * side, c - b * side + e * side));
  }
  return scene;
}

struct Row
{
  const char* Name;
  double Rate;
  double Mean;
};

double ThreadSeconds()
{
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Evaluations per CPU second of `eval` over the points: the best of rounds
// of one pass each, for about `seconds` in total.
template<typename F>
Row Measure(const char* name, const std::vector<Vec3>& points, double seconds, F eval)
{
  double sum = 0.0, best = 0.0, total = 0.0;
  long long passes = 0;
  do
  {
    ++passes;
    const double start = ThreadSeconds();
    for (const Vec3& x : points)
    {
      sum += eval(x);
    }
    const double elapsed = ThreadSeconds() - start;
    best = std::max(best, static_cast<double>(points.size()) / elapsed);
    total += elapsed;
  } while (total < seconds);
  return { name, best, sum / (static_cast<double>(passes) * static_cast<double>(points.size())) };
}

} // namespace

int main(int argc, char** argv)
{
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<Vec3> points(4096);
  for (Vec3& p : points)
  {
    p = Vec3(u(rng), u(rng), 0.0);
  }
  const Vec3 n(0, 0, 1);
  std::vector<Row> rows;

  const Scene open = MakeScene(0, 2);
  const std::vector<Vec3>& light = open.Surfaces[0].Vertices;
  rows.push_back(Measure("point-quad, Lambert only", points, seconds,
    [&](const Vec3& x) { return PointPolygonFormFactor(x, n, light.data(), 4); }));
  rows.push_back(Measure("point-quad, clipped Lambert", points, seconds,
    [&](const Vec3& x) { return PointPolygonFormFactorClipped(x, n, light.data(), 4); }));
  {
    ExactEvaluator evaluator(open);
    VisibilityWorkspace ws;
    std::vector<int> shaft;
    evaluator.ShaftCandidates(0, 1, shaft);
    rows.push_back(Measure("unoccluded, evaluator (BVH)", points, seconds,
      [&](const Vec3& x) { return evaluator.FormFactor(x, n, 1, 0, ws); }));
    rows.push_back(Measure("unoccluded, evaluator (shaft)", points, seconds,
      [&](const Vec3& x) { return evaluator.FormFactor(x, n, 1, 0, shaft, ws); }));
  }
  static const char* names[][2] = { { "1 occluder, BVH", "1 occluder, shaft list" },
    { "7 occluders, BVH", "7 occluders, shaft list" },
    { "30 occluders, BVH", "30 occluders, shaft list" } };
  const int counts[] = { 1, 7, 30 };
  std::vector<double> piecesPerQuery;
  for (int i = 0; i < 3; ++i)
  {
    const Scene scene = MakeScene(counts[i], 3 + i);
    ExactEvaluator evaluator(scene);
    VisibilityWorkspace ws;
    std::vector<int> shaft;
    evaluator.ShaftCandidates(0, 1, shaft);
    // Check that every occluder is in every point's pyramid.
    CullingVolume frustum;
    std::vector<int> inPyramid;
    int minimum = 1 << 30;
    for (const Vec3& x : points)
    {
      evaluator.GetOccluders().BuildFrustum(x, n, 0, frustum);
      evaluator.GetOccluders().VolumeCandidates(frustum, 0, 1, inPyramid);
      minimum = std::min(minimum, static_cast<int>(inPyramid.size()));
    }
    VisibleRegion region;
    double pieces = 0.0;
    for (const Vec3& x : points)
    {
      evaluator.FormFactor(x, n, 1, 0, ws, &region);
      pieces += region.GetNumberOfPieces();
    }
    std::printf("%2d occluders: at least %d in every pyramid, %.1f visible pieces on average\n",
      counts[i], minimum, pieces / points.size());
    rows.push_back(Measure(names[i][0], points, seconds,
      [&](const Vec3& x) { return evaluator.FormFactor(x, n, 1, 0, ws); }));
    rows.push_back(Measure(names[i][1], points, seconds,
      [&](const Vec3& x) { return evaluator.FormFactor(x, n, 1, 0, shaft, ws); }));
  }

  std::printf("\n%-32s %16s %12s\n", "case (one core)", "evaluations/s", "mean F");
  std::printf("%-32s %16s %12s\n", "", "(per CPU second)", "");
  for (const Row& r : rows)
  {
    std::printf("%-32s %16.0f %12.6f\n", r.Name, r.Rate, r.Mean);
  }
  return 0;
}
