// SPDX-License-Identifier: GPL-3.0-or-later
// The closed-form tail of the Jacobi sweeps (penumbraSweepTail.h) against
// the sum of a series of known modes: the unshot radiance after sweep k is
// u_k = sum_i c_i lambda_i^k v_i, so the light the sweeps would still add
// after sweep m is sum_i c_i lambda_i^(m+1) / (1 - lambda_i) v_i. With as
// many modes as differences seen the tail is exact (the Krylov space holds
// the solution), so with one mode it is the geometric tail; with more
// modes than differences it errs, by no more than it says it does when the
// series is dominated by its slowest mode.
#include "penumbraEnergyBookkeeping.h"
#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraSampleSet.h"
#include "penumbraSweepTail.h"
#include "penumbraTesting.h"

#include <cmath>
#include <cstdio>
#include <vector>

using penumbra::EnergyBookkeeping;
using penumbra::OccluderSet;
using penumbra::RGB;
using penumbra::SampleSet;
using penumbra::Scene;
using penumbra::ShotRecord;
using penumbra::Surface;
using penumbra::SurfaceSamples;
using penumbra::SweepTail;
using penumbra::Vec3;

namespace
{

/// Three unit squares (the tail reads only their samples), each a 3 x 3
/// grid of points, 8 triangles.
Scene Squares()
{
  Scene scene;
  for (int i = 0; i < 3; ++i)
  {
    Surface s;
    const double z = static_cast<double>(i);
    s.Vertices = { Vec3(0, 0, z), Vec3(1, 0, z), Vec3(1, 1, z), Vec3(0, 1, z) };
    s.Reflectance = RGB(0.5, 0.5, 0.5);
    scene.Surfaces.push_back(s);
  }
  return scene;
}

SurfaceSamples Grid(double z)
{
  SurfaceSamples s;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      s.Points.emplace_back(0.5 * i, 0.5 * j, z);
    }
  }
  for (int j = 0; j < 2; ++j)
  {
    for (int i = 0; i < 2; ++i)
    {
      const int a = 3 * j + i;
      s.Triangles.push_back({ a, a + 1, a + 4 });
      s.Triangles.push_back({ a, a + 4, a + 3 });
    }
  }
  s.Total.assign(s.Points.size(), RGB());
  s.Unshot.assign(s.Points.size(), RGB());
  return s;
}

/// A series of modes: per channel c, u_k(p) = sum_i C[i] Lambda[i][c]^k V_i(p).
struct Series
{
  std::vector<double> C;
  std::vector<RGB> Lambda;
  /// Mode i's value at point p (flattened over the surfaces): positive for
  /// the slowest, oscillating and smaller for the others.
  static double Mode(int i, int p)
  {
    return i == 0 ? 1.0 + 0.1 * std::sin(0.7 * p) : std::cos(1.3 * (i + 1) * p + i);
  }
  RGB At(int k, int p) const
  {
    RGB u;
    for (std::size_t i = 0; i < this->C.size(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        u[c] += this->C[i] * std::pow(this->Lambda[i][c], k) * Mode(static_cast<int>(i), p);
      }
    }
    return u;
  }
  /// sum_{k > m} u_k at point p.
  RGB Rest(int m, int p) const
  {
    RGB u;
    for (std::size_t i = 0; i < this->C.size(); ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        const double l = this->Lambda[i][c];
        u[c] += this->C[i] * std::pow(l, m + 1) / (1.0 - l) * Mode(static_cast<int>(i), p);
      }
    }
    return u;
  }
};

/// Set every sample's unshot radiance to u_k (and Total += u_k when `add`).
void Load(SampleSet& samples, const Series& series, int k, bool add)
{
  int p = 0;
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    SurfaceSamples& s = samples.Surfaces[i];
    for (std::size_t q = 0; q < s.Points.size(); ++q, ++p)
    {
      s.Unshot[q] = series.At(k, p);
      if (add)
      {
        s.Total[q] += s.Unshot[q];
      }
    }
    samples.UpdateUnshotPower(i);
  }
}

struct Outcome
{
  double Error = 0.0;     ///< pi * integral of |Total - exact| (mean channel), watts
  double Estimated = 0.0; ///< what the tail said it would leave
  double Rest = 0.0;      ///< pi * integral of the exact rest, the light the tail must add
  bool Ready = false;
  double UnshotAfter = 1.0;
};

/// Sweep `sweeps` times through the series, sum the tail, compare with the exact sum.
Outcome Run(const Series& series, int sweeps)
{
  const Scene scene = Squares();
  const OccluderSet occluders(scene);
  SampleSet samples(occluders, scene.Surfaces.size());
  for (int i = 0; i < 3; ++i)
  {
    samples.Set(i, Grid(static_cast<double>(i)), 0.0, 0.0);
  }
  Load(samples, series, 0, false);
  SweepTail tail;
  tail.Before(samples);
  for (int k = 1; k <= sweeps; ++k)
  {
    ShotRecord record;
    record.Power = samples.TotalUnshotPower();
    record.Absorbed = record.Power;
    Load(samples, series, k, true);
    tail.Observe(samples, record);
  }
  Outcome outcome;
  outcome.Ready = tail.IsReady();
  outcome.Estimated = tail.RemainingError();
  // Total before the tail: sum_{1..m} u_k; the exact solution adds Rest(m).
  std::vector<std::vector<RGB>> exact;
  int p = 0;
  for (const SurfaceSamples& s : samples.Surfaces)
  {
    exact.emplace_back();
    for (std::size_t q = 0; q < s.Points.size(); ++q, ++p)
    {
      exact.back().push_back(s.Total[q] + series.Rest(sweeps, p));
      outcome.Rest += penumbra::Pi * samples.LumpedWeights[exact.size() - 1][q] *
        series.Rest(sweeps, p).Mean();
    }
  }
  if (!outcome.Ready)
  {
    return outcome;
  }
  EnergyBookkeeping energy(RGB(1.0, 1.0, 1.0));
  tail.Apply(samples, energy);
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    const SurfaceSamples& s = samples.Surfaces[i];
    for (std::size_t q = 0; q < s.Points.size(); ++q)
    {
      for (int c = 0; c < 3; ++c)
      {
        outcome.Error += penumbra::Pi * samples.LumpedWeights[i][q] *
          std::abs(s.Total[q][c] - exact[i][q][c]) / 3.0;
      }
    }
  }
  outcome.UnshotAfter = samples.TotalUnshotPower().Mean();
  return outcome;
}

} // namespace

PENUMBRA_TEST(TestOneModeIsTheGeometricTail)
{
  Series series;
  series.C = { 2.0 };
  series.Lambda = { RGB(0.55, 0.5, 0.4) };
  // One sweep is not enough to trust a fit (see SweepTail::Observe); two are.
  PENUMBRA_EXPECT(!Run(series, 1).Ready);
  const Outcome one = Run(series, 2);
  PENUMBRA_EXPECT(one.Ready);
  PENUMBRA_EXPECT(one.Estimated <= 1e-12);
  PENUMBRA_EXPECT(one.Error <= 1e-12 * one.Rest);
  PENUMBRA_EXPECT(one.UnshotAfter == 0.0);
}

PENUMBRA_TEST(TestThreeModesSummedExactlyAfterThreeSweeps)
{
  Series series;
  series.C = { 2.0, 0.3, 0.2 };
  series.Lambda = { RGB(0.55, 0.5, 0.45), RGB(0.3, 0.25, 0.2), RGB(0.1, 0.12, 0.05) };
  const Outcome three = Run(series, 3);
  const double rest = three.Rest;
  PENUMBRA_EXPECT(three.Ready);
  PENUMBRA_EXPECT(three.Error <= 1e-9 * rest);
  PENUMBRA_EXPECT(three.Estimated <= 1e-9 * rest);
  // One sweep fewer (two differences for three modes) errs by much more.
  const Outcome two = Run(series, 2);
  PENUMBRA_EXPECT(two.Error > 1e3 * three.Error);
  std::printf("   three modes: tail error %.3g after 2 sweeps, %.3g after 3 (rest %.3g W)\n",
    two.Error, three.Error, rest);
}

PENUMBRA_TEST(TestMoreModesThanSweepsErrWithinTheEstimate)
{
  Series series;
  series.C = { 2.0, 0.3, 0.2, 0.15, 0.1 };
  series.Lambda = { RGB(0.55, 0.5, 0.45), RGB(0.4, 0.35, 0.3), RGB(0.25, 0.2, 0.2),
    RGB(0.12, 0.1, 0.1), RGB(0.05, 0.04, 0.03) };
  for (int sweeps = 2; sweeps <= 4; ++sweeps)
  {
    const Outcome outcome = Run(series, sweeps);
    PENUMBRA_EXPECT(outcome.Ready);
    PENUMBRA_EXPECT(outcome.Error <= outcome.Estimated);
    PENUMBRA_EXPECT(outcome.Error < 0.05 * outcome.Rest);
    std::printf("   five modes, %d sweeps: error %.3g, estimated %.3g\n", sweeps, outcome.Error,
      outcome.Estimated);
  }
}
