// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the adaptive sampler (paper section 4, adaptive supersampling
// inside the regions of the discontinuity mesh):
// - constraints survive refinement (every input segment still covered by
//   mesh edges of its order, no triangle crossing a segment, area kept, no
//   zero-area triangle), order-0 points keep one value per side;
// - analytic functions: a linear one needs no insertion, a smooth bump
//   converges as the tolerance shrinks;
// - direct light with the exact evaluator on the "seven" and "blind" floors:
//   error of the Clough-Tocher reconstruction at 20000 independent random
//   points against exact values, and against a uniform grid with linear
//   interpolation at the same sample count (the direct-light accuracy targets).
#include "penumbraAdaptiveSampler.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraExactEvaluator.h"
#include "penumbraReceiverTriangulation.h"
#include "penumbraReconstruction.h"
#include "penumbraScene.h"
#include "penumbraSceneLibrary.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

using namespace penumbra;

namespace
{

//------------------------------------------------------------------------------
// Helpers

// A hand-made receiver mesh: the unit square in z = 0 (front +z), cut by
// vertical lines x = xs[i] (the labels say their order: 0 duplicates the
// points), each strip split into `rows` rows of two triangles. Outline pieces
// are order -1.
ReceiverMesh StripMesh(const std::vector<double>& xs, const std::vector<int>& orders, int rows)
{
  ReceiverMesh m;
  m.ReceiverId = 0;
  std::vector<double> cols = { 0.0 };
  cols.insert(cols.end(), xs.begin(), xs.end());
  cols.push_back(1.0);
  const int nc = static_cast<int>(cols.size());
  // Geometric vertex of (column c, row r).
  auto vertex = [&](int c, int r) { return c * (rows + 1) + r; };
  // Point ids per strip side: pointOf[strip][side 0 left column / 1 right][row].
  std::map<std::pair<int, int>, int> shared; // (vertex, copy key) -> point
  auto point = [&](int c, int r, int strip) {
    // A point on an order-0 line belongs to the strip that uses it.
    const bool cut = c > 0 && c < nc - 1 && orders[c - 1] == 0;
    const int key = cut ? strip : -1;
    auto found = shared.find({ vertex(c, r), key });
    if (found != shared.end())
    {
      return found->second;
    }
    const int id = static_cast<int>(m.Points.size());
    m.Points.emplace_back(cols[c], static_cast<double>(r) / rows, 0.0);
    m.PointVertex.push_back(vertex(c, r));
    shared.emplace(std::make_pair(vertex(c, r), key), id);
    return id;
  };
  for (int s = 0; s + 1 < nc; ++s)
  {
    for (int r = 0; r < rows; ++r)
    {
      const int a = point(s, r, s), b = point(s + 1, r, s), c = point(s + 1, r + 1, s),
                d = point(s, r + 1, s);
      m.Triangles.push_back({ a, b, c });
      m.Triangles.push_back({ a, c, d });
    }
  }
  auto segment = [&](int pa, int pb, int order) {
    DiscontinuitySegment s;
    s.PointA = pa;
    s.PointB = pb;
    s.A = m.Points[pa];
    s.B = m.Points[pb];
    s.Order = order;
    s.ReceiverId = 0;
    s.SourceId = order >= 0 ? 7 : -1;
    m.Segments.push_back(s);
  };
  for (int s = 0; s + 1 < nc; ++s)
  {
    segment(point(s, 0, s), point(s + 1, 0, s), -1);                  // bottom
    segment(point(s + 1, rows, s), point(s, rows, s), -1);            // top
  }
  for (int r = 0; r < rows; ++r)
  {
    segment(point(0, r + 1, 0), point(0, r, 0), -1);                  // left side
    segment(point(nc - 1, r, nc - 2), point(nc - 1, r + 1, nc - 2), -1); // right side
    for (int c = 1; c + 1 < nc; ++c)
    {
      // The strip on the left of the line going up is strip c - 1.
      segment(point(c, r, c - 1), point(c, r + 1, c - 1), orders[c - 1]);
    }
  }
  return m;
}

double TriangleArea2D(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n)
{
  return 0.5 * Dot(Cross(b - a, c - a), n);
}

double MeshArea(const ReceiverMesh& m, const Vec3& n, double* minArea = nullptr)
{
  double area = 0.0, smallest = HUGE_VAL;
  for (const auto& t : m.Triangles)
  {
    const double a = TriangleArea2D(m.Points[t[0]], m.Points[t[1]], m.Points[t[2]], n);
    area += a;
    smallest = std::min(smallest, a);
  }
  if (minArea)
  {
    *minArea = smallest;
  }
  return area;
}

// Distance from p to segment ab, and its parameter along ab.
double SegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b, double* t = nullptr)
{
  const Vec3 d = b - a;
  const double s = std::clamp(Dot(p - a, d) / Dot(d, d), 0.0, 1.0);
  if (t)
  {
    *t = Dot(p - a, d) / Dot(d, d);
  }
  return Length(p - (a + s * d));
}

struct ConstraintCheck
{
  int Uncovered = 0;      // input segments not covered by output segments of their order
  int WrongOrder = 0;     // output pieces on an input segment with another order
  int Crossing = 0;       // output triangles whose interior a segment crosses
  double AreaError = 0.0; // relative
  double MinArea = 0.0;   // smallest output triangle area (relative to the mean)
};

// Every input segment covered by collinear output segments of its order;
// no output triangle crossed by an input segment; area kept.
ConstraintCheck CheckConstraints(const ReceiverMesh& in, const ReceiverMesh& out, const Vec3& n)
{
  ConstraintCheck check;
  double diameter = 0.0;
  for (const Vec3& p : in.Points)
  {
    diameter = std::max(diameter, Length(p - in.Points[0]));
  }
  const double eps = 1e-9 * diameter;
  for (const DiscontinuitySegment& s : in.Segments)
  {
    double covered = 0.0;
    for (const DiscontinuitySegment& o : out.Segments)
    {
      double ta, tb;
      if (SegmentDistance(o.A, s.A, s.B, &ta) > eps || SegmentDistance(o.B, s.A, s.B, &tb) > eps)
      {
        continue;
      }
      // Collinear and within s: its length counts if the order matches.
      const double lo = std::max(0.0, std::min(ta, tb)), hi = std::min(1.0, std::max(ta, tb));
      if (hi - lo <= 1e-12)
      {
        continue;
      }
      if (o.Order == s.Order)
      {
        covered += (hi - lo);
      }
      else
      {
        ++check.WrongOrder;
      }
    }
    // Lines with two kept sides are listed once per constrained edge.
    if (std::abs(covered - 1.0) > 1e-9)
    {
      ++check.Uncovered;
    }
  }
  // Crossing: an input segment meeting the open interior of a triangle.
  const Vec3 u = Normalized(in.Points[1] - in.Points[0]), v = Cross(n, u);
  auto to2 = [&](const Vec3& p) { return std::array<double, 2>{ Dot(p, u), Dot(p, v) }; };
  auto orient = [](const std::array<double, 2>& a, const std::array<double, 2>& b,
                  const std::array<double, 2>& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  for (const auto& t : out.Triangles)
  {
    const std::array<double, 2> p[3] = { to2(out.Points[t[0]]), to2(out.Points[t[1]]),
      to2(out.Points[t[2]]) };
    const double area2 = orient(p[0], p[1], p[2]);
    const double tol = 1e-9 * area2;
    for (const DiscontinuitySegment& s : in.Segments)
    {
      const auto a = to2(s.A), b = to2(s.B);
      // Bounding boxes first.
      if (std::max(a[0], b[0]) < std::min({ p[0][0], p[1][0], p[2][0] }) ||
        std::min(a[0], b[0]) > std::max({ p[0][0], p[1][0], p[2][0] }) ||
        std::max(a[1], b[1]) < std::min({ p[0][1], p[1][1], p[2][1] }) ||
        std::min(a[1], b[1]) > std::max({ p[0][1], p[1][1], p[2][1] }))
      {
        continue;
      }
      // Separating axis: the segment's line with all three vertices on one
      // side (or on it), or a triangle edge with both end points outside.
      const double la = orient(a, b, p[0]), lb = orient(a, b, p[1]), lc = orient(a, b, p[2]);
      const double lineTol = 1e-9 * std::hypot(b[0] - a[0], b[1] - a[1]) *
        std::sqrt(std::abs(area2));
      if ((la >= -lineTol && lb >= -lineTol && lc >= -lineTol) ||
        (la <= lineTol && lb <= lineTol && lc <= lineTol))
      {
        continue;
      }
      bool separated = false;
      for (int k = 0; k < 3 && !separated; ++k)
      {
        const auto& e0 = p[k];
        const auto& e1 = p[(k + 1) % 3];
        separated = orient(e0, e1, a) <= tol && orient(e0, e1, b) <= tol;
      }
      check.Crossing += !separated;
    }
  }
  const double inArea = MeshArea(in, n);
  double minArea = 0.0;
  const double outArea = MeshArea(out, n, &minArea);
  check.AreaError = std::abs(outArea - inArea) / inArea;
  check.MinArea = minArea / (outArea / out.Triangles.size());
  return check;
}

// Radiance functions of a point (applied to each channel with a tint).
using ScalarField = std::function<double(const Vec3&)>;
RadianceBatchFunction Batch(const ScalarField& f, long long* calls = nullptr)
{
  return [f, calls](const Vec3* points, int count, RGB* values) {
    for (int i = 0; i < count; ++i)
    {
      const double s = f(points[i]);
      values[i] = RGB(s, 0.5 * s, 0.25 * s);
    }
    if (calls)
    {
      *calls += count;
    }
  };
}

struct ErrorStats
{
  double Rms = 0.0, P99 = 0.0, Max = 0.0; // relative to the reference (mean)
};

// Errors of the reconstruction of `result` at random points (u, v) given by
// `sample` against `exact`, relative to `reference` (first channel).
ErrorStats MeasureErrors(const AdaptiveSamplingResult& result, ReconstructionMode mode,
  const std::vector<Vec3>& points, const std::vector<double>& exact, double reference)
{
  Reconstruction r;
  ReconstructionOptions options;
  options.Mode = mode;
  r.Build(result.Samples, options);
  std::vector<double> errors;
  errors.reserve(points.size());
  double sum2 = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Vec3 d = points[i] - result.Origin;
    const double u = Dot(d, result.AxisU), v = Dot(d, result.AxisV);
    const int t = r.FindTriangle(u, v);
    double value[3] = { 0.0, 0.0, 0.0 };
    if (t >= 0)
    {
      r.EvaluateAt(t, u, v, value);
    }
    const double e = std::abs(value[0] - exact[i]) / reference;
    errors.push_back(e);
    sum2 += e * e;
  }
  std::sort(errors.begin(), errors.end());
  ErrorStats s;
  s.Rms = std::sqrt(sum2 / errors.size());
  s.P99 = errors[static_cast<std::size_t>(0.99 * (errors.size() - 1))];
  s.Max = errors.back();
  return s;
}

//------------------------------------------------------------------------------
// A linear function is reproduced by the initial mesh: no insertion, probes
// zero.
PENUMBRA_TEST(TestLinear)
{
  const ReceiverMesh mesh = StripMesh({ 0.3, 0.7 }, { 1, 2 }, 3);
  long long calls = 0;
  const auto f = Batch([](const Vec3& p) { return 1.0 + 2.0 * p.X - 0.5 * p.Y; }, &calls);
  const AdaptiveSamplingResult r = SampleReceiver(mesh, f);
  PENUMBRA_EXPECT(r.Statistics.Passes == 0);
  PENUMBRA_EXPECT(r.Statistics.Samples == r.Statistics.InitialSamples);
  PENUMBRA_EXPECT(static_cast<int>(r.Mesh.Points.size()) == static_cast<int>(mesh.Points.size()));
  PENUMBRA_EXPECT(r.Statistics.Converged);
  PENUMBRA_EXPECT(calls == r.Statistics.Evaluations);
  double worst = 0.0;
  for (double x : r.Probes.Residuals)
  {
    worst = std::max(worst, std::abs(x));
  }
  // Outline points are evaluated SideOffset inside: residuals of that order.
  PENUMBRA_EXPECT(worst < 1e-8);
  PENUMBRA_EXPECT(r.Probes.Triangles.size() == 3 * r.Mesh.Triangles.size());
  // Linear criterion too.
  AdaptiveSamplingSettings linear;
  linear.Interpolant.Mode = ReconstructionMode::Linear;
  PENUMBRA_EXPECT(SampleReceiver(mesh, f, linear).Statistics.Passes == 0);
  std::printf("linear: %d samples, %lld evaluations, max probe residual %.3g\n",
    r.Statistics.Samples, r.Statistics.Evaluations, worst);
}

//------------------------------------------------------------------------------
// MaximumEdgeLength: a linear function needs no sample, yet every edge of the
// result is at most the limit (and the values stay exact: nothing else moves).
PENUMBRA_TEST(TestMaximumEdgeLength)
{
  const ReceiverMesh mesh = StripMesh({ 0.3, 0.7 }, { 1, 2 }, 3);
  const auto f = Batch([](const Vec3& p) { return 1.0 + 2.0 * p.X - 0.5 * p.Y; }, nullptr);
  AdaptiveSamplingSettings settings;
  settings.MaximumEdgeLength = 0.07;
  const AdaptiveSamplingResult r = SampleReceiver(mesh, f, settings);
  double longest = 0.0, worst = 0.0;
  for (const auto& tri : r.Mesh.Triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      longest = std::max(longest, Length(r.Mesh.Points[tri[k]] - r.Mesh.Points[tri[(k + 1) % 3]]));
    }
  }
  for (double x : r.Probes.Residuals)
  {
    worst = std::max(worst, std::abs(x));
  }
  std::printf("maximum edge length 0.07: %d samples (%d initially), longest edge %.4f, max probe "
              "residual %.3g\n",
    r.Statistics.Samples, r.Statistics.InitialSamples, longest, worst);
  PENUMBRA_EXPECT(r.Statistics.Converged);
  PENUMBRA_EXPECT(longest <= 0.07 * (1.0 + 1e-12));
  PENUMBRA_EXPECT(r.Statistics.Samples > 4 * r.Statistics.InitialSamples);
  PENUMBRA_EXPECT(worst < 1e-8);
  settings.MaximumEdgeLength = -1.0;
  PENUMBRA_EXPECT_THROW(SampleReceiver(mesh, f, settings), InputError, "MaximumEdgeLength");
}

//------------------------------------------------------------------------------
// Order-0 line: a step function across it is exact on both sides (each copy
// of a point on the line evaluated inside its side), and refinement of a
// smooth function around it keeps per-side values.
PENUMBRA_TEST(TestStep)
{
  const ReceiverMesh mesh = StripMesh({ 0.4, 0.7 }, { 0, 1 }, 4);
  auto step = [](const Vec3& p) { return p.X < 0.4 ? 1.0 : 3.0; };
  const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(step));
  PENUMBRA_EXPECT(r.Statistics.Passes == 0); // piecewise constant: nothing to insert
  int wrong = 0;
  for (std::size_t t = 0; t < r.Mesh.Triangles.size(); ++t)
  {
    const auto& tri = r.Mesh.Triangles[t];
    const Vec3 c = (r.Mesh.Points[tri[0]] + r.Mesh.Points[tri[1]] + r.Mesh.Points[tri[2]]) / 3.0;
    for (int k = 0; k < 3; ++k)
    {
      wrong += r.Values[tri[k]].R != step(c);
    }
  }
  PENUMBRA_EXPECT(wrong == 0);

  // Step plus a bump centred on the line: refinement splits the order-0
  // edges, and every copy still carries its own side's value (compared with
  // the function evaluated just inside the side of its triangle).
  auto bumpStep = [&](const Vec3& p) {
    const double dx = p.X - 0.4, dy = p.Y - 0.5;
    return step(p) + 2.0 * std::exp(-(dx * dx + dy * dy) / 0.01);
  };
  AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = 1e-3;
  const AdaptiveSamplingResult s = SampleReceiver(mesh, Batch(bumpStep), settings);
  PENUMBRA_EXPECT(s.Statistics.ConstrainedSplits > 0);
  int copiesOnLine = 0, wrongSide = 0;
  for (std::size_t t = 0; t < s.Mesh.Triangles.size(); ++t)
  {
    const auto& tri = s.Mesh.Triangles[t];
    const Vec3 c = (s.Mesh.Points[tri[0]] + s.Mesh.Points[tri[1]] + s.Mesh.Points[tri[2]]) / 3.0;
    for (int k = 0; k < 3; ++k)
    {
      const Vec3& p = s.Mesh.Points[tri[k]];
      if (std::abs(p.X - 0.4) > 1e-12)
      {
        continue;
      }
      ++copiesOnLine;
      // The value must be this side's limit (up to the side offset).
      const Vec3 inside = p + 1e-9 * Normalized(c - p);
      wrongSide += std::abs(s.Values[tri[k]].R - bumpStep(inside)) > 1e-5;
    }
  }
  const ConstraintCheck check = CheckConstraints(mesh, s.Mesh, Vec3(0, 0, 1));
  PENUMBRA_EXPECT(copiesOnLine > 0);
  PENUMBRA_EXPECT(wrongSide == 0);
  PENUMBRA_EXPECT(check.Uncovered == 0);
  PENUMBRA_EXPECT(check.WrongOrder == 0);
  PENUMBRA_EXPECT(check.Crossing == 0);
  PENUMBRA_EXPECT(check.AreaError < 1e-9);
  PENUMBRA_EXPECT(check.MinArea > 0.0);
  std::printf("step + bump: %d -> %d samples, %d constrained splits, %d corner values on the "
              "order-0 line, %d wrong side\n",
    s.Statistics.InitialSamples, s.Statistics.Samples, s.Statistics.ConstrainedSplits,
    copiesOnLine, wrongSide);
}

//------------------------------------------------------------------------------
// A smooth bump converges as the tolerance shrinks; constraints survive.
PENUMBRA_TEST(TestBumpConvergence)
{
  const ReceiverMesh mesh = StripMesh({ 0.3, 0.75 }, { 1, 2 }, 2);
  auto bump = [](const Vec3& p) {
    const double dx = p.X - 0.55, dy = p.Y - 0.45;
    return 0.2 + std::exp(-(dx * dx + dy * dy) / 0.02);
  };
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Vec3> points(20000);
  std::vector<double> exact(points.size());
  double mean = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    points[i] = Vec3(uniform(rng), uniform(rng), 0.0);
    exact[i] = bump(points[i]);
    mean += exact[i] / points.size();
  }
  double previousRms = HUGE_VAL, firstRms = 0.0, lastRms = 0.0;
  int monotonic = 0, levels = 0;
  for (double tolerance : { 1e-2, 3e-3, 1e-3, 3e-4, 1e-4 })
  {
    AdaptiveSamplingSettings settings;
    settings.SamplingTolerance = tolerance;
    const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(bump), settings);
    const ErrorStats e =
      MeasureErrors(r, ReconstructionMode::CloughTocher, points, exact, mean);
    const ConstraintCheck check = CheckConstraints(mesh, r.Mesh, Vec3(0, 0, 1));
    PENUMBRA_EXPECT(r.Statistics.Converged);
    PENUMBRA_EXPECT(check.Uncovered == 0 && check.WrongOrder == 0 && check.Crossing == 0);
    PENUMBRA_EXPECT(check.AreaError < 1e-9 && check.MinArea > 0.0);
    // The error stays within a few tolerances: the edge midpoints bound it
    // on the edges, not inside the triangles (measured: 1.4 to 3.2 times).
    PENUMBRA_EXPECT(e.Max < 5.0 * tolerance);
    std::printf("bump tol %.0e: %5d samples, %6lld evaluations, %2d passes, error RMS %.2e p99 "
                "%.2e max %.2e (of the mean)\n",
      tolerance, r.Statistics.Samples, r.Statistics.Evaluations, r.Statistics.Passes, e.Rms, e.P99,
      e.Max);
    monotonic += e.Rms < previousRms;
    previousRms = e.Rms;
    firstRms = levels == 0 ? e.Rms : firstRms;
    lastRms = e.Rms;
    ++levels;
  }
  PENUMBRA_EXPECT(monotonic == levels);
  PENUMBRA_EXPECT(lastRms < firstRms / 30.0);
}

//------------------------------------------------------------------------------
// Late passes rebuild the interpolant only around the points just inserted
// and keep the other triangles' residuals: every final probe must equal the
// residual against an interpolant built on the whole final mesh.
PENUMBRA_TEST(TestLocalizedPassesMatchWholeRebuild)
{
  const ReceiverMesh mesh = StripMesh({ 0.3, 0.75 }, { 1, 2 }, 2);
  auto field = [](const Vec3& p) {
    const double dx = p.X - 0.55, dy = p.Y - 0.45;
    return 0.5 + std::exp(-(dx * dx + dy * dy) / 0.01) + 0.3 * std::sin(9.0 * p.X * p.Y);
  };
  AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = 1e-4;
  const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(field), settings);
  PENUMBRA_EXPECT(r.Statistics.LocalizedPasses > 0);
  Reconstruction whole;
  ReconstructionOptions options = settings.Interpolant;
  whole.Build(r.Samples, options);
  static const double bary[3][3] = { { 0.5, 0.5, 0.0 }, { 0.0, 0.5, 0.5 }, { 0.5, 0.0, 0.5 } };
  std::vector<int> seen(r.Mesh.Triangles.size(), 0);
  double worst = 0.0, largest = 0.0;
  for (std::size_t q = 0; q < r.Probes.Triangles.size(); ++q)
  {
    const int t = r.Probes.Triangles[q];
    const int k = seen[t]++; // probes of a triangle come in edge order
    const auto& tri = r.Mesh.Triangles[t];
    const Vec3 mid = 0.5 * (r.Mesh.Points[tri[k]] + r.Mesh.Points[tri[(k + 1) % 3]]);
    if (std::min({ mid.X, mid.Y, 1.0 - mid.X, 1.0 - mid.Y }) < 1e-6)
    {
      continue; // outline midpoints are evaluated SideOffset inside
    }
    double value[3];
    whole.Evaluate(t, bary[k], value);
    const double residual = field(mid) - value[0];
    worst = std::max(worst, std::abs(residual - r.Probes.Residuals[3 * q]));
    largest = std::max(largest, std::abs(residual));
  }
  std::printf("localized passes: %d of %d, %d samples, largest probe residual %.3e, largest "
              "difference from a whole rebuild %.3e\n",
    r.Statistics.LocalizedPasses, r.Statistics.Passes, r.Statistics.Samples, largest, worst);
  PENUMBRA_EXPECT(worst <= 1e-12 + 1e-9 * largest);
}

//------------------------------------------------------------------------------
// Budget, passes and determinism (independent of the order in which the
// evaluation function computes its batch).
PENUMBRA_TEST(TestBudgetAndDeterminism)
{
  const ReceiverMesh mesh = StripMesh({ 0.3, 0.75 }, { 0, 1 }, 2);
  auto bump = [](const Vec3& p) {
    const double dx = p.X - 0.55, dy = p.Y - 0.45;
    return 0.2 + std::exp(-(dx * dx + dy * dy) / 0.01);
  };
  AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = 1e-4;
  settings.MaximumSamplesPerSurface = 200;
  const AdaptiveSamplingResult capped = SampleReceiver(mesh, Batch(bump), settings);
  PENUMBRA_EXPECT(capped.Statistics.BudgetReached);
  PENUMBRA_EXPECT(!capped.Statistics.Converged);
  PENUMBRA_EXPECT(capped.Statistics.Samples <= 200);
  PENUMBRA_EXPECT(capped.Statistics.Samples > 150);
  PENUMBRA_EXPECT(capped.Probes.Triangles.size() == 3 * capped.Mesh.Triangles.size());
  PENUMBRA_EXPECT(capped.Statistics.MaximumResidual > 1.0); // the failures are reported
  settings.MaximumSamplesPerSurface = 200000;
  settings.MaximumPasses = 2;
  const AdaptiveSamplingResult twoPasses = SampleReceiver(mesh, Batch(bump), settings);
  PENUMBRA_EXPECT(twoPasses.Statistics.Passes == 2);
  PENUMBRA_EXPECT(!twoPasses.Statistics.BudgetReached);

  // Same result whatever the evaluation order inside a batch.
  settings = AdaptiveSamplingSettings();
  settings.SamplingTolerance = 1e-3;
  settings.ProbeCentroids = true;
  const AdaptiveSamplingResult a = SampleReceiver(mesh, Batch(bump), settings);
  const RadianceBatchFunction reversed = [&](const Vec3* points, int count, RGB* values) {
    for (int i = count - 1; i >= 0; --i)
    {
      Batch(bump)(points + i, 1, values + i);
    }
  };
  const AdaptiveSamplingResult b = SampleReceiver(mesh, reversed, settings);
  bool same = a.Mesh.Triangles == b.Mesh.Triangles && a.Mesh.Points.size() == b.Mesh.Points.size() &&
    a.Samples.Points == b.Samples.Points && a.Samples.Values == b.Samples.Values &&
    a.Probes.Residuals == b.Probes.Residuals;
  PENUMBRA_EXPECT(same);
  PENUMBRA_EXPECT(a.Probes.Triangles.size() == 4 * a.Mesh.Triangles.size());
  // Each insertion adds one sample, two when it splits a two-sided order-0
  // edge (at most the constrained splits).
  const int added = a.Statistics.Samples - a.Statistics.InitialSamples;
  const int insertions = a.Statistics.FaceInsertions + a.Statistics.EdgeInsertions;
  PENUMBRA_EXPECT(added >= insertions && added <= insertions + a.Statistics.ConstrainedSplits);
  std::printf("budget 200: %d samples (budget reached), max residual %.1f tol; deterministic: "
              "%s\n",
    capped.Statistics.Samples, capped.Statistics.MaximumResidual, same ? "yes" : "no");
}

//------------------------------------------------------------------------------
// Direct light with the exact evaluator (the light as the only shooter).
struct DirectLight
{
  ExactEvaluator Evaluator;
  std::vector<int> Candidates;
  int Receiver, Light;
  Vec3 Normal;
  RGB Tint;

  DirectLight(const Scene& scene, int receiver, int light)
    : Evaluator(scene)
    , Receiver(receiver)
    , Light(light)
    , Normal(ComputePolygonGeometry(scene.Surfaces[receiver].Vertices).Normal)
    , Tint(scene.Surfaces[receiver].Reflectance.R * scene.Surfaces[light].Emission.R,
        scene.Surfaces[receiver].Reflectance.G * scene.Surfaces[light].Emission.G,
        scene.Surfaces[receiver].Reflectance.B * scene.Surfaces[light].Emission.B)
  {
    this->Evaluator.ShaftCandidates(light, receiver, this->Candidates);
  }

  void operator()(const Vec3* points, int count, RGB* values) const
  {
    VisibilityWorkspace workspace;
    for (int i = 0; i < count; ++i)
    {
      const double f = this->Evaluator.FormFactor(
        points[i], this->Normal, this->Receiver, this->Light, this->Candidates, workspace);
      values[i] = RGB(this->Tint.R * f, this->Tint.G * f, this->Tint.B * f);
    }
  }
};

// Constraints survive on real discontinuity meshes (Cornell floor with its
// block footprints, and the paper scenes), values per side on order-0 lines.
PENUMBRA_TEST(TestMesherMeshes)
{
  struct Case
  {
    const char* Name;
    int Light;
  };
  for (const Case& cs : { Case{ "cornell", 2 }, Case{ "seven", 1 }, Case{ "blind", 1 } })
  {
    const Scene scene = MakeBuiltinScene(cs.Name);
    DiscontinuityMesher mesher(scene);
    DiscontinuityMeshSettings meshSettings;
    meshSettings.Shooters = { cs.Light };
    const ReceiverMesh mesh = mesher.MeshReceiver(0, meshSettings);
    const DirectLight direct(scene, 0, cs.Light);
    AdaptiveSamplingSettings settings;
    settings.SamplingTolerance = 0.01;
    const AdaptiveSamplingResult r = SampleReceiver(
      mesh, [&](const Vec3* p, int n, RGB* v) { direct(p, n, v); }, settings);
    const Vec3 normal(0, 1, 0);
    const ConstraintCheck check = CheckConstraints(mesh, r.Mesh, normal);
    PENUMBRA_EXPECT(check.Uncovered == 0);
    PENUMBRA_EXPECT(check.WrongOrder == 0);
    PENUMBRA_EXPECT(check.Crossing == 0);
    PENUMBRA_EXPECT(check.AreaError < 1e-9);
    PENUMBRA_EXPECT(check.MinArea > 0.0);
    PENUMBRA_EXPECT(r.Statistics.Irregularities == 0);
    PENUMBRA_EXPECT(r.Statistics.RejectedInsertions == 0);
    PENUMBRA_EXPECT(r.Statistics.Samples > r.Statistics.InitialSamples);
    // Every triangle counter-clockwise seen from the front, and the sample
    // mesh is the same mesh.
    int clockwise = 0;
    for (const auto& t : r.Mesh.Triangles)
    {
      clockwise += !(TriangleArea2D(r.Mesh.Points[t[0]], r.Mesh.Points[t[1]], r.Mesh.Points[t[2]],
                       normal) > 0.0);
    }
    PENUMBRA_EXPECT(clockwise == 0);
    PENUMBRA_EXPECT(r.Samples.GetNumberOfTriangles() == static_cast<int>(r.Mesh.Triangles.size()));
    PENUMBRA_EXPECT(r.Samples.GetNumberOfPoints() == static_cast<int>(r.Values.size()));
    // Every value is the exact limit at its point from inside its triangles
    // (within the side offset's effect): the limit taken toward the centroid
    // of each triangle using the point. Where these limits disagree the
    // function has no limit at the point within that side (the corners of
    // the Cornell blocks: shadow lines fan out from a contact corner, the
    // value depends on the direction of approach); such singular points are
    // counted, not checked.
    const double mean = r.ReferenceRadiance.R;
    std::vector<double> lo(r.Values.size(), HUGE_VAL), hi(r.Values.size(), -HUGE_VAL);
    for (const auto& t : r.Mesh.Triangles)
    {
      const Vec3 c = (r.Mesh.Points[t[0]] + r.Mesh.Points[t[1]] + r.Mesh.Points[t[2]]) / 3.0;
      for (int k = 0; k < 3; ++k)
      {
        const Vec3& p = r.Mesh.Points[t[k]];
        RGB exact;
        const Vec3 inside = p + 1e-9 * Normalized(c - p);
        direct(&inside, 1, &exact);
        lo[t[k]] = std::min(lo[t[k]], exact.R);
        hi[t[k]] = std::max(hi[t[k]], exact.R);
      }
    }
    int wrong = 0, singular = 0;
    for (std::size_t p = 0; p < r.Values.size(); ++p)
    {
      if (hi[p] - lo[p] > 1e-4 * mean)
      {
        ++singular;
        continue;
      }
      wrong += std::abs(r.Values[p].R - 0.5 * (lo[p] + hi[p])) > 1e-4 * mean;
    }
    PENUMBRA_EXPECT(wrong == 0);
    // Only the Cornell block corners are singular (6 of the 8 are in the
    // light's view; the value there is one of its directional limits).
    PENUMBRA_EXPECT(singular <= (std::string(cs.Name) == "cornell" ? 8 : 0));
    int order0 = 0;
    for (const DiscontinuitySegment& s : r.Mesh.Segments)
    {
      order0 += s.Order == 0;
    }
    std::printf("%-7s floor: %zu -> %zu points, %zu -> %zu segments (%d order 0), %d constrained "
                "splits, %d passes, %lld evaluations, area error %.1e, %d wrong values, %d "
                "singular points\n",
      cs.Name, mesh.Points.size(), r.Mesh.Points.size(), mesh.Segments.size(),
      r.Mesh.Segments.size(), order0, r.Statistics.ConstrainedSplits, r.Statistics.Passes,
      r.Statistics.Evaluations, check.AreaError, wrong, singular);

    // Uniform baseline: about the requested count, same area, boundary kept.
    const AdaptiveSamplingResult u = SampleReceiverUniform(
      mesh, 3000, [&](const Vec3* p, int n, RGB* v) { direct(p, n, v); });
    PENUMBRA_EXPECT(std::abs(u.Statistics.Samples - 3000) <= 60);
    PENUMBRA_EXPECT(std::abs(MeshArea(u.Mesh, normal) - MeshArea(mesh, normal)) <
      1e-9 * MeshArea(mesh, normal));
  }
}

// The accuracy targets on direct light: error of the Clough-Tocher
// reconstruction of the adaptive samples at 20000 random floor points
// against the exact values, relative to the floor's mean radiance; a
// uniform grid with linear interpolation at the same sample count; and the
// calibration of the error estimate (with the sampler's probes) at the same
// points. The accuracy targets are the seven-occluder and blind floors'; the
// calibration is also asserted on the Cornell floor (lit by its light, the
// blocks' footprints cut out).
PENUMBRA_TEST(TestDirectAccuracy)
{
  const struct
  {
    const char* Name;
    int Light;
    bool AccuracyTargets;
  } cases[] = { { "seven", 1, true }, { "blind", 1, true }, { "cornell", 2, false } };
  for (const auto& c : cases)
  {
    const Scene scene = MakeBuiltinScene(c.Name);
    DiscontinuityMesher mesher(scene);
    DiscontinuityMeshSettings meshSettings;
    meshSettings.Shooters = { c.Light };
    const ReceiverMesh mesh = mesher.MeshReceiver(0, meshSettings);
    const DirectLight direct(scene, 0, c.Light);
    const RadianceBatchFunction f = [&](const Vec3* p, int n, RGB* v) { direct(p, n, v); };
    const auto start = std::chrono::steady_clock::now();
    const AdaptiveSamplingResult adaptive = SampleReceiver(mesh, f);
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const AdaptiveSamplingResult uniform =
      SampleReceiverUniform(mesh, adaptive.Statistics.Samples, f);
    Reconstruction cubicReconstruction;
    cubicReconstruction.Build(adaptive.Samples);

    // Independent points (not the samples), uniform over the floor's meshed
    // part.
    const auto& fv = scene.Surfaces[0].Vertices;
    double lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
    for (const Vec3& p : fv)
    {
      lo[0] = std::min(lo[0], p.X);
      hi[0] = std::max(hi[0], p.X);
      lo[1] = std::min(lo[1], p.Z);
      hi[1] = std::max(hi[1], p.Z);
    }
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> uniform01(0.0, 1.0);
    std::vector<Vec3> points;
    std::vector<int> triangles;
    std::vector<double> barycentrics;
    while (points.size() < 20000)
    {
      const Vec3 p(lo[0] + uniform01(rng) * (hi[0] - lo[0]), fv[0].Y,
        lo[1] + uniform01(rng) * (hi[1] - lo[1]));
      const Vec3 d = p - adaptive.Origin;
      double b[3];
      const int t =
        cubicReconstruction.FindTriangle(Dot(d, adaptive.AxisU), Dot(d, adaptive.AxisV), b);
      if (t >= 0)
      {
        points.push_back(p);
        triangles.push_back(t);
        barycentrics.insert(barycentrics.end(), b, b + 3);
      }
    }
    std::vector<RGB> exactRgb(points.size());
    direct(points.data(), static_cast<int>(points.size()), exactRgb.data());
    std::vector<double> exact(points.size());
    double mean = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      exact[i] = exactRgb[i].R;
      mean += exact[i] / points.size();
    }
    const ErrorStats cubic =
      MeasureErrors(adaptive, ReconstructionMode::CloughTocher, points, exact, mean);
    const ErrorStats linear =
      MeasureErrors(adaptive, ReconstructionMode::Linear, points, exact, mean);
    const ErrorStats grid = MeasureErrors(uniform, ReconstructionMode::Linear, points, exact, mean);

    // Error estimate against the actual error, first channel.
    const int n = static_cast<int>(points.size());
    std::vector<double> estimates(3 * points.size());
    cubicReconstruction.EstimateErrors(n, triangles.data(), barycentrics.data(),
      &adaptive.Probes, ErrorEstimateOptions(), estimates.data());
    int covered = 0;
    double sumEstimate = 0.0, sumError = 0.0;
    for (int i = 0; i < n; ++i)
    {
      double value[3];
      cubicReconstruction.Evaluate(triangles[i], &barycentrics[3 * i], value);
      const double error = std::abs(value[0] - exact[i]);
      covered += estimates[3 * i] >= error ? 1 : 0;
      sumEstimate += estimates[3 * i];
      sumError += error;
    }
    const double coverage = static_cast<double>(covered) / n;
    const double ratio = sumEstimate / sumError;

    std::printf("%s floor, direct light, tolerance %.3g: %d samples, %lld evaluations, %d "
                "passes, %.2f s\n"
                "  adaptive + Clough-Tocher: RMS %.4f%%  p99 %.3f%%  max %.3f%% of the mean\n"
                "  adaptive + linear:        RMS %.4f%%  p99 %.3f%%  max %.3f%%\n"
                "  uniform (%d) + linear:  RMS %.4f%%  p99 %.3f%%  max %.3f%%  (RMS %.0f times "
                "the adaptive one)\n"
                "  error estimate >= actual error at %.1f%% of the points; mean estimate / "
                "mean error %.2f\n",
      c.Name, AdaptiveSamplingSettings().SamplingTolerance, adaptive.Statistics.Samples,
      adaptive.Statistics.Evaluations, adaptive.Statistics.Passes, seconds, 100 * cubic.Rms,
      100 * cubic.P99, 100 * cubic.Max, 100 * linear.Rms, 100 * linear.P99, 100 * linear.Max,
      uniform.Statistics.Samples, 100 * grid.Rms, 100 * grid.P99, 100 * grid.Max,
      grid.Rms / cubic.Rms, 100 * coverage, ratio);
    // The direct-light accuracy targets.
    if (c.AccuracyTargets)
    {
      PENUMBRA_EXPECT(cubic.Rms <= 1e-3);
      PENUMBRA_EXPECT(cubic.P99 <= 1e-2);
      PENUMBRA_EXPECT(cubic.Max <= 3e-2);
      PENUMBRA_EXPECT(grid.Rms >= 10.0 * cubic.Rms);
      PENUMBRA_EXPECT(std::abs(uniform.Statistics.Samples - adaptive.Statistics.Samples) <=
        adaptive.Statistics.Samples / 50);
    }
    PENUMBRA_EXPECT(coverage >= 0.9);
    PENUMBRA_EXPECT(ratio <= 10.0);
  }
}

//------------------------------------------------------------------------------
// The uniform grid samples the outline too, at about the grid's spacing: the
// outline given by its corners alone once left long thin triangles along each
// edge (6% error along a floor's edge in test_adversarial.py), and a strip
// narrower than the grid (aspect 1e6) got its four corners and nothing else.
PENUMBRA_TEST(TestUniformSamplesTheOutline)
{
  for (const double height : { 1.0, 1e-6 })
  {
    ReceiverMesh mesh = StripMesh({}, {}, 1);
    for (Vec3& p : mesh.Points)
    {
      p.Y *= height;
    }
    for (DiscontinuitySegment& segment : mesh.Segments)
    {
      segment.A = mesh.Points[segment.PointA];
      segment.B = mesh.Points[segment.PointB];
    }
    const AdaptiveSamplingResult r = SampleReceiverUniform(
      mesh, 256, Batch([](const Vec3& p) { return 2.0 + std::sin(3.0 * p.X); }));
    double longest = 0.0;
    for (const DiscontinuitySegment& segment : r.Mesh.Segments)
    {
      if (segment.Order < 0)
      {
        longest = std::max(longest, Length(segment.B - segment.A));
      }
    }
    // The square: grid spacing 1/16 (256 samples); the strip: its perimeter
    // (about 2) over half the samples.
    const double spacing = height == 1.0 ? 1.0 / 16.0 : 2.0 * 2.0 / 256.0;
    std::printf("uniform sampling of a 1 x %g rectangle: %d samples, longest outline edge %.4f\n",
      height, r.Statistics.Samples, longest);
    PENUMBRA_EXPECT(longest <= 1.01 * spacing);
    PENUMBRA_EXPECT(r.Statistics.Samples >= (height == 1.0 ? 200 : 120));
    PENUMBRA_EXPECT(std::abs(MeshArea(r.Mesh, Vec3(0, 0, 1)) - height) < 1e-9 * height);
  }
}

//------------------------------------------------------------------------------
// A strip 1e-6 wide and 1 long (aspect 1e6) is refined along its length: all
// its triangles are narrower than MinimumFeatureSize times its diameter, and
// the strip was once left with its initial points (1.3% RMS error in
// test_adversarial.py's sliver case).
PENUMBRA_TEST(TestThinStripIsRefined)
{
  ReceiverMesh mesh = StripMesh({ 0.5 }, { 1 }, 1);
  for (Vec3& p : mesh.Points)
  {
    p.Y *= 1e-6;
  }
  for (DiscontinuitySegment& segment : mesh.Segments)
  {
    segment.A = mesh.Points[segment.PointA];
    segment.B = mesh.Points[segment.PointB];
  }
  const AdaptiveSamplingResult r =
    SampleReceiver(mesh, Batch([](const Vec3& p) { return 2.0 + std::sin(3.0 * p.X); }));
  double worst = 0.0;
  for (double x : r.Probes.Residuals)
  {
    worst = std::max(worst, std::abs(x));
  }
  std::printf("thin strip: %d -> %d samples, largest probe residual %.3g (tolerance %.3g)\n",
    r.Statistics.InitialSamples, r.Statistics.Samples, worst, r.Tolerance.R);
  PENUMBRA_EXPECT(r.Statistics.Samples > 4 * r.Statistics.InitialSamples);
  PENUMBRA_EXPECT(r.Statistics.Converged);
  PENUMBRA_EXPECT(worst <= r.Tolerance.R);
}

//------------------------------------------------------------------------------
// The unit square around a small square [c, c + a]^2 of order-1 lines (the
// shadow lines a small occluder casts).
ReceiverMesh SmallFeatureMesh(double c, double a)
{
  ReceiverMesh m;
  m.ReceiverId = 0;
  const Vec3 outer[4] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } };
  const Vec3 inner[4] = { { c, c, 0 }, { c + a, c, 0 }, { c + a, c + a, 0 }, { c, c + a, 0 } };
  for (int k = 0; k < 4; ++k)
  {
    m.Points.push_back(outer[k]);
    m.PointVertex.push_back(k);
  }
  for (int k = 0; k < 4; ++k)
  {
    m.Points.push_back(inner[k]);
    m.PointVertex.push_back(4 + k);
  }
  for (int k = 0; k < 4; ++k)
  {
    const int n = (k + 1) % 4;
    m.Triangles.push_back({ k, n, 4 + n });
    m.Triangles.push_back({ k, 4 + n, 4 + k });
  }
  m.Triangles.push_back({ 4, 5, 6 });
  m.Triangles.push_back({ 4, 6, 7 });
  for (int k = 0; k < 4; ++k)
  {
    for (int ring = 0; ring < 2; ++ring)
    {
      DiscontinuitySegment s;
      s.PointA = 4 * ring + k;
      s.PointB = 4 * ring + (k + 1) % 4;
      s.A = m.Points[s.PointA];
      s.B = m.Points[s.PointB];
      s.Order = ring == 0 ? -1 : 1;
      s.SourceId = ring == 0 ? -1 : 7;
      s.ReceiverId = 0;
      m.Segments.push_back(s);
    }
  }
  return m;
}

//------------------------------------------------------------------------------
// A feature 1e-4 the receiver's size, below the default MinimumFeatureSize
// of the receiver (1e-4 of its diameter, 1.4e-4): its discontinuity lines
// mark it, and it is refined to the tolerance like a large one. A bump of
// that size centred in it is checked at random points around it.
PENUMBRA_TEST(TestSmallFeatureIsResolved)
{
  const double c = 0.3, a = 1e-4;
  const ReceiverMesh mesh = SmallFeatureMesh(c, a);
  const Vec3 centre(c + 0.5 * a, c + 0.5 * a, 0.0);
  auto bump = [&](const Vec3& p) {
    const double dx = (p.X - centre.X) / a, dy = (p.Y - centre.Y) / a;
    return 0.2 + std::exp(-4.0 * (dx * dx + dy * dy));
  };
  const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(bump));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> around(-a, 2.0 * a);
  std::vector<Vec3> points(4000);
  std::vector<double> exact(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    points[i] = Vec3(c + around(rng), c + around(rng), 0.0);
    exact[i] = bump(points[i]);
  }
  // Relative to the tolerance's reference (the receiver's mean radiance).
  const double reference = r.ReferenceRadiance.R;
  const ErrorStats e =
    MeasureErrors(r, ReconstructionMode::CloughTocher, points, exact, reference);
  const double tolerance = AdaptiveSamplingSettings().SamplingTolerance;
  std::printf("feature 1e-4 of the receiver: %d -> %d samples, %d passes, converged %d; "
              "around it error max %.2e, RMS %.2e of the mean (tolerance %.0e)\n",
    r.Statistics.InitialSamples, r.Statistics.Samples, r.Statistics.Passes,
    static_cast<int>(r.Statistics.Converged), e.Max, e.Rms, tolerance);
  PENUMBRA_EXPECT(r.Statistics.Converged);
  PENUMBRA_EXPECT(e.Max < 5.0 * tolerance);
}

//------------------------------------------------------------------------------
// The same small feature far from the origin (coordinates 1e4): refinement
// stops 1e7 ulps above the coordinates' rounding, so the output, written in
// 3D and projected again (as vtkPenumbraRadianceReconstructor does), keeps every
// triangle counter-clockwise. Refined down to the feature's floor (1e-7
// here), slivers came back flat or flipped (a 1,000-polygon room's
// evaluator output was refused by the reconstructor).
PENUMBRA_TEST(TestRefinementStaysAboveRounding)
{
  const double offset = 1e4, c = 0.3, a = 1e-4;
  ReceiverMesh mesh = SmallFeatureMesh(c, a);
  for (Vec3& p : mesh.Points)
  {
    p = p + Vec3(offset, offset, 0.0);
  }
  for (DiscontinuitySegment& segment : mesh.Segments)
  {
    segment.A = mesh.Points[segment.PointA];
    segment.B = mesh.Points[segment.PointB];
  }
  const Vec3 centre(offset + c + 0.5 * a, offset + c + 0.5 * a, 0.0);
  auto bump = [&](const Vec3& p) {
    const double dx = (p.X - centre.X) / a, dy = (p.Y - centre.Y) / a;
    return 0.2 + std::exp(-4.0 * (dx * dx + dy * dy));
  };
  const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(bump));
  const double ulp = std::numeric_limits<double>::epsilon() * (offset + 1.0);
  double narrowest = HUGE_VAL;
  int flipped = 0;
  const Vec3 origin = r.Mesh.Points[r.Mesh.Triangles[0][0]];
  for (const auto& t : r.Mesh.Triangles)
  {
    // Projected from 3D onto x, y about another origin, as a reader would.
    const Vec3 p0 = r.Mesh.Points[t[0]] - origin, p1 = r.Mesh.Points[t[1]] - origin,
               p2 = r.Mesh.Points[t[2]] - origin;
    const double area2 = (p1.X - p0.X) * (p2.Y - p0.Y) - (p1.Y - p0.Y) * (p2.X - p0.X);
    const double longest = std::max({ Length(p1 - p0), Length(p2 - p1), Length(p0 - p2) });
    flipped += area2 <= 0.0;
    narrowest = std::min(narrowest, area2 / longest);
  }
  std::printf("feature 1e-4 at coordinates 1e4: %d -> %d samples; narrowest triangle %.3g "
              "(%.3g ulps of the coordinates), %d flat or flipped\n",
    r.Statistics.InitialSamples, r.Statistics.Samples, narrowest, narrowest / ulp, flipped);
  PENUMBRA_EXPECT(flipped == 0);
  PENUMBRA_EXPECT(narrowest > 1e5 * ulp);
}

//------------------------------------------------------------------------------
// MinimumFeatureSize 0 with a singular point (the value depends on the
// direction from it, as at a contact corner): refinement never converges and
// must stop above rounding. It once split triangles until they were
// degenerate, and the interpolant refused them.
PENUMBRA_TEST(TestZeroMinimumFeatureSizeStops)
{
  const ReceiverMesh mesh = StripMesh({ 0.5 }, { 1 }, 2);
  auto fan = [](const Vec3& p) {
    return 1.0 + 0.5 * std::sin(3.0 * std::atan2(p.Y - 0.5, p.X - 0.5));
  };
  AdaptiveSamplingSettings settings;
  settings.MinimumFeatureSize = 0.0;
  settings.MaximumPasses = 10000;
  const AdaptiveSamplingResult r = SampleReceiver(mesh, Batch(fan), settings);
  double narrowest = HUGE_VAL;
  const auto& m = r.Samples;
  for (int t = 0; t < m.GetNumberOfTriangles(); ++t)
  {
    const double* p[3];
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      p[k] = &m.Points[2 * m.Triangles[3 * t + k]];
    }
    for (int k = 0; k < 3; ++k)
    {
      longest = std::max(longest, std::hypot(p[(k + 1) % 3][0] - p[k][0], p[(k + 1) % 3][1] - p[k][1]));
    }
    const double area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
      (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    narrowest = std::min(narrowest, area2 / longest);
  }
  bool built = true;
  try
  {
    Reconstruction interpolant;
    interpolant.Build(r.Samples, ReconstructionOptions());
  }
  catch (const InputError&)
  {
    built = false;
  }
  std::printf("singular point, MinimumFeatureSize 0: %d samples, %d passes, narrowest "
              "triangle %.2e, interpolant built %d\n",
    r.Statistics.Samples, r.Statistics.Passes, narrowest, static_cast<int>(built));
  PENUMBRA_EXPECT(built);
  PENUMBRA_EXPECT(narrowest > 1e-10);
  PENUMBRA_EXPECT(!r.Statistics.BudgetReached);
  PENUMBRA_EXPECT(r.Statistics.Passes < settings.MaximumPasses);
}

//------------------------------------------------------------------------------
// A seed that rounds just outside the outline (the centroid of a sliver along
// it) must not keep the region between the outline and the triangulation's
// far bounding square: its corners have no vertex id, and a point copied from
// one indexed every per-vertex array out of bounds.
PENUMBRA_TEST(TestSeedOutsideTheOutline)
{
  const std::vector<P2> square = { { 0.0, 0.0 }, { 1.0, 0.0 }, { 1.0, 1.0 }, { 0.0, 1.0 } };
  std::vector<detail::RefinableSegment> outline;
  for (int k = 0; k < 4; ++k)
  {
    detail::RefinableSegment segment;
    segment.A = k;
    segment.B = (k + 1) % 4;
    segment.Order = -1;
    outline.push_back(segment);
  }
  detail::RefinableTriangulation triangulation(
    square, outline, { { 0.5, 0.5 }, { 0.5, -1e-9 }, { 1.0 + 1e-9, 0.5 } });
  detail::RefinableSnapshot snapshot;
  triangulation.Extract(snapshot);
  const int vertices = static_cast<int>(snapshot.Vertices.size());
  bool valid = true;
  for (const int vertex : snapshot.PointVertex)
  {
    valid = valid && vertex >= 0 && vertex < vertices;
  }
  PENUMBRA_EXPECT(valid);
  if (!valid)
  {
    return;
  }
  double area = 0.0;
  for (const auto& t : snapshot.Triangles)
  {
    const P2& a = snapshot.Vertices[snapshot.PointVertex[t[0]]];
    const P2& b = snapshot.Vertices[snapshot.PointVertex[t[1]]];
    const P2& c = snapshot.Vertices[snapshot.PointVertex[t[2]]];
    area += 0.5 * Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]);
  }
  PENUMBRA_EXPECT_NEAR(area, 1.0, 1e-12);
  PENUMBRA_EXPECT(triangulation.GetIrregularities() >= 1);
}

//------------------------------------------------------------------------------
// Settings and input errors.
PENUMBRA_TEST(TestBadInput)
{
  const ReceiverMesh mesh = StripMesh({ 0.5 }, { 1 }, 1);
  const auto f = Batch([](const Vec3&) { return 1.0; });
  AdaptiveSamplingSettings bad;
  bad.SamplingTolerance = -1.0;
  PENUMBRA_EXPECT_THROW(SampleReceiver(mesh, f, bad), InputError, "SamplingTolerance");
  bad = AdaptiveSamplingSettings();
  bad.SideOffset = 0.0;
  PENUMBRA_EXPECT_THROW(SampleReceiver(mesh, f, bad), InputError, "SideOffset");
  bad = AdaptiveSamplingSettings();
  bad.MaximumSamplesPerSurface = 0;
  PENUMBRA_EXPECT_THROW(SampleReceiver(mesh, f, bad), InputError, "MaximumSamplesPerSurface");
  PENUMBRA_EXPECT_THROW(SampleReceiver(ReceiverMesh(), f), InputError, "no triangle");
  PENUMBRA_EXPECT_THROW(SampleReceiver(mesh, RadianceBatchFunction()), InputError, "function");
  ReceiverMesh broken = mesh;
  broken.Triangles[0][1] = 999;
  PENUMBRA_EXPECT_THROW(SampleReceiver(broken, f), InputError, "triangle 0");
  PENUMBRA_EXPECT_THROW(SampleReceiverUniform(mesh, 2, f), InputError, "numberOfSamples");
}

} // namespace
