// SPDX-License-Identifier: GPL-3.0-or-later
// Throughput of the ray-cast evaluator: Embree occlusion rays per second on 1
// and 2 threads, and ray-cast evaluations (paper Eq. 6) per second at the
// default tolerance, on three scenes: the Cornell box (32 triangles), the
// Cornell box tessellated into 3.6 thousand triangles (same geometry),
// and, as a stress case, the Cornell box filled with a cloud of 1500 small
// tilted tiles (3032 triangles; 98 % of floor-to-light rays blocked). Rays go
// from floor points to light points, either incoherent (every ray from its own
// random origin) or 16 per origin (the evaluator's pattern). Last, the exact
// linear-source irradiance of one triangle (penumbraLinearSource.h), and the
// exact irradiance of a non-uniform shooter behind an occluder.
//
// Built with the project (PENUMBRA_BUILD_BENCHMARKS, on by default) as
// build/bin/penumbraRayCastBenchmark; the build flags are the project's (no -march=native,
// so that the numbers describe a portable build).
// Usage: penumbraRayCastBenchmark [rounds, default 3]
// Rates are the best of the rounds, per wall-clock second and per CPU second
// (summed over threads): on a shared machine the wall-clock 2-thread rows are
// only as good as the second core is free.
#include "penumbraLinearSource.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraSceneLibrary.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <random>
#include <thread>
#include <vector>

using namespace penumbra;

namespace
{

double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double ThreadCpu()
{
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Wall-clock seconds and CPU seconds (summed over the threads) of one timing.
struct Timing
{
  double Wall = 1e300;
  double Cpu = 1e300;
};

/**
 * Best wall-clock time (and, separately, best CPU time summed over threads)
 * of `rounds` runs of work(thread, threads) on `threads` threads. CPU time is
 * less sensitive to other processes on a shared machine; it does not see
 * hyper-thread siblings competing for the same core.
 */
Timing BestTime(int rounds, int threads, const std::function<void(int, int)>& work)
{
  Timing best;
  for (int r = 0; r < rounds; ++r)
  {
    std::vector<double> cpu(threads, 0.0);
    const auto timed = [&](int t) {
      const double c0 = ThreadCpu();
      work(t, threads);
      cpu[t] = ThreadCpu() - c0;
    };
    const double start = Now();
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t)
    {
      pool.emplace_back(timed, t);
    }
    timed(0);
    for (std::thread& t : pool)
    {
      t.join();
    }
    best.Wall = std::min(best.Wall, Now() - start);
    double sum = 0.0;
    for (const double c : cpu)
    {
      sum += c;
    }
    best.Cpu = std::min(best.Cpu, sum);
  }
  return best;
}

/// A uniformly distributed point of triangle (a, b, c).
Vec3 PointInTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double s, double t)
{
  if (s + t > 1.0)
  {
    s = 1.0 - s;
    t = 1.0 - t;
  }
  return a + (b - a) * s + (c - a) * t;
}

/// The Cornell box plus `tiles` small squares (20 to 40 mm) at random
/// positions and orientations inside it, reflectance 0.5.
Scene Cluttered(int tiles)
{
  Scene scene = MakeBuiltinScene("cornell");
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < tiles; ++k)
  {
    const Vec3 c(0.05 + 0.45 * u(rng), 0.05 + 0.45 * u(rng), 0.05 + 0.45 * u(rng));
    const Vec3 normal = Normalized(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    const Vec3 helper = std::abs(normal.X) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 a = Normalized(Cross(helper, normal));
    const Vec3 b = Cross(normal, a);
    const double h = 0.01 + 0.01 * u(rng);
    Surface s;
    s.Vertices = { c - a * h - b * h, c + a * h - b * h, c + a * h + b * h, c - a * h + b * h };
    s.Reflectance = RGB(0.5, 0.5, 0.5);
    scene.Surfaces.push_back(s);
  }
  return scene;
}

/**
 * The Cornell box with every surface but the floor (kept whole, id 0) and the
 * light (kept whole, id 2) cut into small triangles: a fan from the centroid,
 * each fan triangle split 4 ways `levels` times; the pieces are appended as
 * separate surfaces and the originals emptied of area (a degenerate polygon,
 * skipped by the ray caster).
 */
Scene Tessellated(int levels)
{
  const Scene cornell = MakeBuiltinScene("cornell");
  Scene scene = cornell;
  for (std::size_t s = 0; s < cornell.Surfaces.size(); ++s)
  {
    if (s == 0 || s == 2)
    {
      continue;
    }
    const std::vector<Vec3>& v = cornell.Surfaces[s].Vertices;
    Vec3 centre;
    for (const Vec3& p : v)
    {
      centre += p / static_cast<double>(v.size());
    }
    std::vector<std::array<Vec3, 3>> triangles;
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      triangles.push_back({ centre, v[i], v[(i + 1) % v.size()] });
    }
    for (int l = 0; l < levels; ++l)
    {
      std::vector<std::array<Vec3, 3>> next;
      for (const auto& t : triangles)
      {
        const Vec3 a = (t[0] + t[1]) * 0.5;
        const Vec3 b = (t[1] + t[2]) * 0.5;
        const Vec3 c = (t[2] + t[0]) * 0.5;
        next.push_back({ t[0], a, c });
        next.push_back({ a, t[1], b });
        next.push_back({ c, b, t[2] });
        next.push_back({ a, b, c });
      }
      triangles.swap(next);
    }
    for (const auto& t : triangles)
    {
      Surface piece = cornell.Surfaces[s];
      piece.Vertices = { t[0], t[1], t[2] };
      scene.Surfaces.push_back(piece);
    }
    scene.Surfaces[s].Vertices = { v[0], v[0], v[0] }; // zero area: skipped
  }
  return scene;
}

/**
 * Rays from points of the floor (surface 0) to points of the light (surface
 * 2): `perOrigin` consecutive rays share their origin.
 */
std::vector<OcclusionRay> FloorToLightRays(const RayCaster& caster, std::size_t count, int perOrigin)
{
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<OcclusionRay> rays(count);
  const auto sample = [&](int surface) {
    const int t = caster.GetFirstTriangle(surface) +
      static_cast<int>(u(rng) * caster.GetNumberOfSurfaceTriangles(surface));
    Vec3 p[3];
    caster.GetTriangle(t, p);
    return PointInTriangle(p[0], p[1], p[2], u(rng), u(rng));
  };
  for (std::size_t i = 0; i < count; ++i)
  {
    rays[i].Origin = i % perOrigin == 0 ? sample(0) : rays[i - 1].Origin;
    rays[i].Target = sample(2);
  }
  return rays;
}

void RayRows(const char* name, const Scene& scene, int rounds)
{
  const double start = Now();
  RayCaster caster(scene);
  const double build = Now() - start;
  const std::size_t count = 2000000;
  std::vector<unsigned char> occluded(count);
  std::printf("%s: %d triangles, Embree build %.1f ms\n", name, caster.GetNumberOfTriangles(),
    1e3 * build);
  std::printf("  %-11s %-20s %-9s %10s %10s   %s\n", "rays", "filter", "threads", "rays/s",
    "rays/CPU-s", "blocked");
  for (const int perOrigin : { 1, 16 })
  {
    const std::vector<OcclusionRay> rays = FloorToLightRays(caster, count, perOrigin);
    for (const bool ignore : { false, true })
    {
      for (const int threads : { 1, 2 })
      {
        std::vector<std::size_t> blockedPerThread(threads);
        const Timing seconds = BestTime(rounds, threads, [&](int t, int n) {
          const std::size_t first = count * t / n;
          const std::size_t last = count * (t + 1) / n;
          blockedPerThread[t] = caster.TraceOcclusion(rays.data() + first, last - first,
            occluded.data() + first, ignore ? 0 : -1, ignore ? 2 : -1);
        });
        std::size_t blocked = 0;
        for (const std::size_t b : blockedPerThread)
        {
          blocked += b;
        }
        std::printf("  %-11s %-20s %d thread%s %10.3g %10.3g   %5.1f%%\n",
          perOrigin == 1 ? "incoherent" : "16/origin", ignore ? "ignoring 2 surfaces" : "no filter",
          threads, threads > 1 ? "s" : " ", count / seconds.Wall, count / seconds.Cpu,
          100.0 * blocked / count);
      }
    }
  }
}

void EvaluationRows(const Scene& scene, int rounds)
{
  RayCastEvaluator evaluator(scene); // default tolerance 1e-3
  // Receiving points: a 40 x 40 grid over the floor (surface 0), shooter: the light.
  std::vector<Vec3> points;
  for (int j = 0; j < 40; ++j)
  {
    for (int i = 0; i < 40; ++i)
    {
      points.push_back(Vec3(0.552 * (i + 0.5) / 40.0, 0.0, 0.559 * (j + 0.5) / 40.0));
    }
  }
  std::vector<RayCastStatistics> stats(2);
  std::vector<double> sums(2);
  for (const int threads : { 1, 2 })
  {
    const Timing seconds = BestTime(rounds, threads, [&](int t, int n) {
      RayCastStatistics s;
      double sum = 0.0;
      for (std::size_t i = t; i < points.size(); i += n)
      {
        sum += evaluator.FormFactor(points[i], Vec3(0, 1, 0), 0, 2, &s);
      }
      if (n == 1)
      {
        stats[0] = s;
        sums[0] = sum;
      }
    });
    std::printf("  ray-cast evaluations (tolerance 1e-3), %d thread%s %10.3g /s %10.3g /CPU-s", threads,
      threads > 1 ? "s" : " ", points.size() / seconds.Wall, points.size() / seconds.Cpu);
    if (threads == 1)
    {
      std::printf("   (%.1f rays, %.1f pieces per evaluation; mean F %.6f)", double(stats[0].Rays) / points.size(),
        double(stats[0].Pieces) / points.size(), sums[0] / points.size());
    }
    std::printf("\n");
  }
}

void LinearSourceRow(int rounds)
{
  // A triangle of a shooter mesh seen from points of a parallel receiver.
  const Vec3 tri[3] = { { -0.5, 1, -0.4 }, { 0.6, 1, -0.5 }, { 0.2, 1, 0.6 } };
  const RGB values[3] = { { 1, 0.2, 3 }, { 0.1, 2, 3 }, { 2.5, 0.7, 0 } };
  std::vector<Vec3> points;
  for (int i = 0; i < 100000; ++i)
  {
    points.push_back(Vec3(-1.0 + 2.0 * (i % 317) / 317.0, 0.0, -1.0 + 2.0 * (i / 317) / 316.0));
  }
  double sum = 0.0;
  const Timing seconds = BestTime(rounds, 1, [&](int, int) {
    for (const Vec3& x : points)
    {
      sum += LinearTriangleIrradiance(x, Vec3(0, 1, 0), tri, values, Vec3(0, -1, 0)).G;
    }
  });
  std::printf("exact linear-source triangle irradiance (RGB), 1 thread: %.3g /s, %.3g /CPU-s (checksum %.6g)\n",
    points.size() / seconds.Wall, points.size() / seconds.Cpu, sum);
}

/**
 * Exact non-uniform shooter: the paper's Fig. 3 scene (floor, 0.5 m light at
 * 2 m, 0.6 m occluder at 1 m), the light carrying a piecewise-linear ramp on
 * 8 triangles; receiving points on a floor grid through light, penumbra and
 * umbra. Exact visibility (ExactEvaluator) then the linear-source closed form
 * per (visible piece, mesh triangle).
 */
void ExactNonUniformRow(int rounds)
{
  Scene scene = MakeBuiltinScene("occluder");
  int light = -1;
  for (std::size_t s = 0; s < scene.Surfaces.size(); ++s)
  {
    if (scene.Surfaces[s].Emission.Mean() > 0.0)
    {
      light = static_cast<int>(s);
    }
  }
  const PolygonGeometry g = ComputePolygonGeometry(scene.Surfaces[light].Vertices);
  const std::vector<Vec3>& v = scene.Surfaces[light].Vertices; // a quad
  std::vector<Vec3> points = { v[0], v[1], v[2], v[3], g.Centroid };
  std::vector<RGB> values = { { 0, 0, 0 }, { 1, 1, 1 }, { 2, 2, 2 }, { 1, 1, 1 }, { 3, 3, 3 } };
  std::vector<std::array<int, 3>> triangles = { { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 } };
  const ShooterRadiance radiance(points, triangles, values);
  ExactEvaluator exact(scene);
  std::vector<Vec3> xs;
  for (int j = 0; j < 50; ++j)
  {
    for (int i = 0; i < 50; ++i)
    {
      xs.push_back(Vec3(-1.2 + 2.4 * (i + 0.5) / 50, 0.0, -1.2 + 2.4 * (j + 0.5) / 50));
    }
  }
  double sum = 0.0;
  const Timing seconds = BestTime(rounds, 1, [&](int, int) {
    LinearSourceWorkspace workspace;
    for (const Vec3& x : xs)
    {
      sum += ExactShooterIrradiance(exact, x, Vec3(0, 1, 0), 0, light, radiance, workspace).G;
    }
  });
  std::printf("exact non-uniform shooter (4-triangle mesh, 1 occluder), 1 thread: %.3g /s, %.3g /CPU-s\n",
    xs.size() / seconds.Wall, xs.size() / seconds.Cpu);
}

} // namespace

int main(int argc, char** argv)
{
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::printf("hardware threads: %u\n", std::thread::hardware_concurrency());
  std::printf("load average at start: ");
  if (FILE* f = std::fopen("/proc/loadavg", "r"))
  {
    char line[128] = "";
    if (std::fgets(line, sizeof(line), f))
    {
      std::printf("%s", line);
    }
    std::fclose(f);
  }
  const Scene cornell = MakeBuiltinScene("cornell");
  const Scene tessellated = Tessellated(3);
  const Scene cluttered = Cluttered(1500);
  RayRows("cornell", cornell, rounds);
  EvaluationRows(cornell, rounds);
  RayRows("cornell tessellated", tessellated, rounds);
  EvaluationRows(tessellated, rounds);
  RayRows("cornell + 1500 tiles (stress)", cluttered, rounds);
  EvaluationRows(cluttered, rounds);
  LinearSourceRow(rounds);
  ExactNonUniformRow(rounds);
  return 0;
}
