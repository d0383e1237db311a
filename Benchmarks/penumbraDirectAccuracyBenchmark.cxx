// SPDX-License-Identifier: GPL-3.0-or-later
// Accuracy of adaptive sampling + reconstruction on direct light, against the
// direct-light accuracy targets: for the "seven" and "blind" floors and the Cornell floor, the
// floor's discontinuity mesh is sampled adaptively with the exact evaluator
// (the light as the only shooter), reconstructed, and compared with exact
// values at 20000 independent random points of the floor. Errors are
// |reconstructed - exact| relative to the floor's mean exact radiance (first
// channel; the light is grey or a constant tint, so the channels agree).
//
// Rows:
//   adaptive+cubic   refined against Clough-Tocher, reconstructed with it
//   adaptive+linear  the same samples reconstructed linearly
//   adapt(lin)+lin   refined against linear interpolation, reconstructed linearly
//   adapt(lin)+cubic the same samples reconstructed with Clough-Tocher
//   uniform+linear   a square grid with the same sample count, boundary-only
//                    constraints, linear (the classic radiosity result)
//   uniform+cubic    the same grid, Clough-Tocher
//
// Built with the project (PENUMBRA_BUILD_BENCHMARKS, on by default) as
// build/bin/penumbraDirectAccuracyBenchmark; the build flags are the project's (no -march=native,
// so that the numbers describe a portable build).
// Usage: penumbraDirectAccuracyBenchmark [relative tolerance, default 0.002]
//   [threads, default 1] [interior events 0/1, default 1]
#include "penumbraAdaptiveSampler.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraExactEvaluator.h"
#include "penumbraReconstruction.h"
#include "penumbraSceneLibrary.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace penumbra;

namespace
{

struct Errors
{
  double Rms = 0.0, P99 = 0.0, Max = 0.0;
};

// Exact direct radiance from `light` on `receiver` at many points, split over
// `threads` threads (one workspace each; each point independent, so the
// result does not depend on the thread count).
class DirectLight
{
public:
  DirectLight(const Scene& scene, int receiver, int light, int threads)
    : Evaluator(scene)
    , Receiver(receiver)
    , Light(light)
    , Threads(std::max(1, threads))
    , Normal(ComputePolygonGeometry(scene.Surfaces[receiver].Vertices).Normal)
    , Tint(scene.Surfaces[receiver].Reflectance.R * scene.Surfaces[light].Emission.R,
        scene.Surfaces[receiver].Reflectance.G * scene.Surfaces[light].Emission.G,
        scene.Surfaces[receiver].Reflectance.B * scene.Surfaces[light].Emission.B)
  {
    this->Evaluator.ShaftCandidates(light, receiver, this->Candidates);
  }

  void operator()(const Vec3* points, int count, RGB* values) const
  {
    auto work = [&](int begin, int end) {
      VisibilityWorkspace workspace;
      for (int i = begin; i < end; ++i)
      {
        const double f = this->Evaluator.FormFactor(points[i], this->Normal, this->Receiver,
          this->Light, this->Candidates, workspace);
        values[i] = RGB(this->Tint.R * f, this->Tint.G * f, this->Tint.B * f);
      }
    };
    const int threads = count < 256 ? 1 : this->Threads;
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k)
    {
      pool.emplace_back(work, static_cast<int>(static_cast<long long>(count) * k / threads),
        static_cast<int>(static_cast<long long>(count) * (k + 1) / threads));
    }
    work(0, count / threads);
    for (std::thread& t : pool)
    {
      t.join();
    }
  }

  RadianceBatchFunction Function() const
  {
    return [this](const Vec3* p, int n, RGB* v) { (*this)(p, n, v); };
  }

private:
  ExactEvaluator Evaluator;
  std::vector<int> Candidates;
  int Receiver, Light, Threads;
  Vec3 Normal;
  RGB Tint;
};

Errors Measure(const AdaptiveSamplingResult& result, ReconstructionMode mode,
  const std::vector<Vec3>& points, const std::vector<RGB>& exact, double mean)
{
  Reconstruction r;
  ReconstructionOptions options;
  options.Mode = mode;
  r.Build(result.Samples, options);
  std::vector<double> errors;
  double sum2 = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Vec3 d = points[i] - result.Origin;
    const double u = Dot(d, result.AxisU), v = Dot(d, result.AxisV);
    double value[3] = { 0.0, 0.0, 0.0 };
    const int t = r.FindTriangle(u, v);
    if (t >= 0)
    {
      r.EvaluateAt(t, u, v, value);
    }
    const double e = std::abs(value[0] - exact[i].R) / mean;
    errors.push_back(e);
    sum2 += e * e;
  }
  std::sort(errors.begin(), errors.end());
  Errors e;
  e.Rms = std::sqrt(sum2 / errors.size());
  e.P99 = errors[static_cast<std::size_t>(0.99 * (errors.size() - 1))];
  e.Max = errors.back();
  return e;
}

// Calibration of the error estimate built from the sampler's probes (the
// pointwise estimate of ErrorEstimateOptions, default safety factors) against
// the actual error. Coverage = fraction of points where the estimate is at
// least the actual error; ratio = mean estimate / mean actual error.
void Calibration(const AdaptiveSamplingResult& result, const std::vector<Vec3>& points,
  const std::vector<RGB>& exact, double& coverage, double& ratio)
{
  Reconstruction r;
  r.Build(result.Samples);
  std::vector<int> triangles;
  std::vector<double> barycentrics, actual;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Vec3 d = points[i] - result.Origin;
    const double u = Dot(d, result.AxisU), v = Dot(d, result.AxisV);
    double b[3], value[3];
    const int t = r.FindTriangle(u, v, b);
    if (t >= 0)
    {
      r.Evaluate(t, b, value);
      triangles.push_back(t);
      barycentrics.insert(barycentrics.end(), b, b + 3);
      actual.push_back(std::abs(value[0] - exact[i].R));
    }
  }
  const int n = static_cast<int>(triangles.size());
  std::vector<double> estimates(3 * actual.size());
  r.EstimateErrors(n, triangles.data(), barycentrics.data(), &result.Probes,
    ErrorEstimateOptions(), estimates.data());
  int covered = 0;
  double sumEstimate = 0.0, sumError = 0.0;
  for (int i = 0; i < n; ++i)
  {
    covered += estimates[3 * i] >= actual[i];
    sumEstimate += estimates[3 * i];
    sumError += actual[i];
  }
  coverage = static_cast<double>(covered) / std::max(n, 1);
  ratio = sumEstimate / std::max(sumError, 1e-300);
}

void Row(const char* name, const AdaptiveSamplingResult& r, double seconds, const Errors& e)
{
  std::printf("  %-16s %7d %9lld %8.2f   %8.4f%% %8.3f%% %8.3f%%\n", name, r.Statistics.Samples,
    r.Statistics.Evaluations, seconds, 100 * e.Rms, 100 * e.P99, 100 * e.Max);
}

void RunCase(const char* sceneName, int light, double tolerance, int threads, bool interior)
{
  const Scene scene = MakeBuiltinScene(sceneName);
  const int floor = 0;
  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshSettings meshSettings;
  meshSettings.Shooters = { light };
  meshSettings.InteriorEvents = interior;
  const auto meshStart = std::chrono::steady_clock::now();
  const ReceiverMesh mesh = mesher.MeshReceiver(floor, meshSettings);
  const double meshSeconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - meshStart).count();
  const DirectLight direct(scene, floor, light, threads);
  const RadianceBatchFunction f = direct.Function();

  AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = tolerance;
  auto timed = [](auto&& run, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    auto r = run();
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  double tCubic = 0.0, tLinear = 0.0, tUniform = 0.0;
  const AdaptiveSamplingResult cubic = timed([&] { return SampleReceiver(mesh, f, settings); }, tCubic);
  AdaptiveSamplingSettings linearSettings = settings;
  linearSettings.Interpolant.Mode = ReconstructionMode::Linear;
  const AdaptiveSamplingResult linear =
    timed([&] { return SampleReceiver(mesh, f, linearSettings); }, tLinear);
  const AdaptiveSamplingResult uniform = timed(
    [&] { return SampleReceiverUniform(mesh, cubic.Statistics.Samples, f, settings); }, tUniform);

  // 20000 random points of the floor's kept region (outside block footprints).
  Reconstruction locator;
  locator.Build(cubic.Samples);
  const auto& fv = scene.Surfaces[floor].Vertices;
  Vec3 lo = fv[0], hi = fv[0];
  for (const Vec3& p : fv)
  {
    lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
    hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
  }
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> uniform01(0.0, 1.0);
  std::vector<Vec3> points;
  while (points.size() < 20000)
  {
    const Vec3 p(lo.X + uniform01(rng) * (hi.X - lo.X), lo.Y, lo.Z + uniform01(rng) * (hi.Z - lo.Z));
    const Vec3 d = p - cubic.Origin;
    if (locator.FindTriangle(Dot(d, cubic.AxisU), Dot(d, cubic.AxisV)) >= 0)
    {
      points.push_back(p);
    }
  }
  std::vector<RGB> exact(points.size());
  direct(points.data(), static_cast<int>(points.size()), exact.data());
  double mean = 0.0;
  for (const RGB& e : exact)
  {
    mean += e.R / exact.size();
  }

  std::printf("%s floor (light %d, %zu mesh points, %zu segments, mesh %.2f s, mean radiance "
              "%.4g, tolerance %.2g, %s interior events)\n",
    sceneName, light, mesh.Points.size(), mesh.Segments.size(), meshSeconds, mean, tolerance,
    interior ? "with" : "without");
  std::printf("  %-16s %7s %9s %8s   %9s %9s %9s\n", "method", "samples", "evals", "time s",
    "RMS", "p99", "max");
  const Errors eCubic = Measure(cubic, ReconstructionMode::CloughTocher, points, exact, mean);
  Row("adaptive+cubic", cubic, tCubic, eCubic);
  Row("adaptive+linear", cubic, tCubic,
    Measure(cubic, ReconstructionMode::Linear, points, exact, mean));
  Row("adapt(lin)+lin", linear, tLinear,
    Measure(linear, ReconstructionMode::Linear, points, exact, mean));
  Row("adapt(lin)+cubic", linear, tLinear,
    Measure(linear, ReconstructionMode::CloughTocher, points, exact, mean));
  const Errors eUniform = Measure(uniform, ReconstructionMode::Linear, points, exact, mean);
  Row("uniform+linear", uniform, tUniform, eUniform);
  Row("uniform+cubic", uniform, tUniform,
    Measure(uniform, ReconstructionMode::CloughTocher, points, exact, mean));
  double coverage = 0.0, ratio = 0.0;
  Calibration(cubic, points, exact, coverage, ratio);
  std::printf("  adaptive+cubic: %d passes, converged %s, %d failing triangles left (narrower "
              "than the minimum feature size), %d rejected insertions, max final residual %.2f "
              "tol; uniform/adaptive RMS ratio %.1f; error estimate >= actual at %.1f%% of "
              "points, mean estimate / mean error %.2f\n",
    cubic.Statistics.Passes, cubic.Statistics.Converged ? "yes" : "no",
    cubic.Statistics.UnrefinedFailures, cubic.Statistics.RejectedInsertions,
    cubic.Statistics.MaximumResidual, eUniform.Rms / eCubic.Rms, 100.0 * coverage, ratio);
}

} // namespace

int main(int argc, char** argv)
{
  const double tolerance = argc > 1 ? std::atof(argv[1]) : 0.002;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const bool interior = argc > 3 ? std::atoi(argv[3]) != 0 : true;
  RunCase("seven", 1, tolerance, threads, interior);
  RunCase("blind", 1, tolerance, threads, interior);
  RunCase("cornell", 2, tolerance, threads, interior);
  return 0;
}
