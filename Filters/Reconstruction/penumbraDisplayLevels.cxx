// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDisplayLevels.cxx
 * @brief How finely the display cuts each input edge: the compact base
 * (level 2 only where the interpolant leaves the chord), or with
 * DisplayTolerance the level each triangle needs, raised until the linear
 * display is within the tolerance of the interpolant.
 */
#include "penumbraResampler.h"
#include "penumbraSampleMeshTopology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace penumbra
{

using detail::Next;
using detail::Prev;

namespace
{

/// The compact base halves an edge where the interpolant at its midpoint is
/// more than this fraction of the compact tolerance off the chord; the
/// merging then has the rest of the tolerance.
constexpr double CompactEdgeFraction = 0.5;

} // namespace

//------------------------------------------------------------------------------
// The compact display's base: level 2 (the dense display) only along the
// edges where the interpolant's midpoint is more than CompactEdgeFraction of
// the tolerance off the chord; the others stay whole, and their midpoints
// become test points of the merging, so that it still answers to the dense
// display there. Level 2 has no point inside a triangle, so a triangle whose
// edges all stay whole is within that fraction of its level-2 display
// everywhere.
void Reconstruction::Internals::Resampler::ChooseCompactEdges()
{
  const Internals& in = this->In;
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int ne = static_cast<int>(in.EdgeKinds.size());
  const int nc = this->NC;
  this->MidValues.assign(static_cast<std::size_t>(ne) * nc, 0.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = in.T(t);
    bool computed = false;
    for (int k = 0; k < 3; ++k)
    {
      const int e = in.TriangleEdge[3 * t + k];
      const int side = in.EdgeSides[2 * e] >= 0 ? in.EdgeSides[2 * e] : in.EdgeSides[2 * e + 1];
      if (side != 3 * t + k)
      {
        continue; // measured from its other side
      }
      if (!computed)
      {
        for (int c = 0; c < nc; ++c)
        {
          in.ComputeNet(t, c, this->Nets[c]);
        }
        computed = true;
      }
      double b[3];
      b[k] = 0.0;
      b[Next(k)] = 0.5;
      b[Prev(k)] = 0.5;
      in.EvaluateWithNets(t, this->Nets.data(), b, this->Value.data(), nullptr);
      double worst = 0.0;
      for (int c = 0; c < nc; ++c)
      {
        const double chord = 0.5 * (in.Value(tri[Next(k)], c) + in.Value(tri[Prev(k)], c));
        this->MidValues[static_cast<std::size_t>(e) * nc + c] = this->Value[c];
        worst = std::max(worst, std::abs(this->Value[c] - chord) / this->CompactTolerances[c]);
      }
      this->Segments[e] = worst > CompactEdgeFraction ? 2 : 1;
    }
  }
  this->Green = true;
  this->LeftOutDone.assign(static_cast<std::size_t>(ne), 0);
  this->LeftOutPoints.clear();
  this->LeftOutValues.clear();
  this->LeftOutTriangles.clear();
}

//------------------------------------------------------------------------------
// The level each triangle needs for DisplayTolerance, and each edge the larger
// of its triangles': an edge split more finely than one side needs only adds
// points to that side's strip, while a coarser one would leave the other
// side's strip beyond the tolerance.
void Reconstruction::Internals::Resampler::ChooseAdaptiveLevels()
{
  const Internals& in = this->In;
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int nc = this->NC;
  const int maximum = this->Options.MaximumSubdivisionLevel;
  // The receiver's area-weighted mean per channel: the display's error is
  // judged against what the surface shows, so a dim surface is cut as finely
  // as a bright one for the same relative error.
  std::vector<double> mean(nc, 0.0);
  double area = 0.0;
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = in.T(t);
    const double a = std::abs(in.Geometry[t].Area2);
    area += a;
    for (int c = 0; c < nc; ++c)
    {
      mean[c] += a *
        (std::abs(in.Value(tri[0], c)) + std::abs(in.Value(tri[1], c)) +
          std::abs(in.Value(tri[2], c))) /
        3.0;
    }
  }
  this->InverseTolerance.assign(nc, 0.0);
  bool any = false;
  for (int c = 0; c < nc; ++c)
  {
    const double tolerance = area > 0.0 ? this->Options.DisplayTolerance * mean[c] / area : 0.0;
    if (tolerance > 0.0 && std::isfinite(tolerance))
    {
      this->InverseTolerance[c] = 1.0 / tolerance;
      any = true;
    }
  }
  this->Needed.assign(nt, 1);
  if (!this->Cubic || !any)
  {
    this->InverseTolerance.clear(); // nothing to test
  }
  else
  {
    this->Nets.resize(nc);
    this->Value.resize(nc);
    for (int t = 0; t < nt; ++t)
    {
      for (int c = 0; c < nc; ++c)
      {
        in.ComputeNet(t, c, this->Nets[c]);
      }
      // The error of linear interpolation falls as 1 / n^2, so the next
      // level tried is the one that would just pass.
      int n = 1;
      for (double d = this->Deviation(t, n); d > 1.0 && n < maximum; d = this->Deviation(t, n))
      {
        const double guess = std::ceil(n * std::sqrt(d) * (1.0 - 1e-12));
        n = std::min(maximum, std::max(n + 1, static_cast<int>(std::min(guess, 1024.0))));
      }
      this->Needed[t] = n;
    }
  }
  // Linear mode: the display is the interpolant itself.
  this->CountEdgesFromLevels();
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::Resampler::CountEdgesFromLevels()
{
  const Internals& in = this->In;
  const int ne = static_cast<int>(in.EdgeKinds.size());
  for (int e = 0; e < ne; ++e)
  {
    int n = 1;
    for (int side = 0; side < 2; ++side)
    {
      const int corner = in.EdgeSides[2 * e + side];
      if (corner >= 0)
      {
        n = std::max(n, this->Needed[corner / 3]);
      }
    }
    this->Segments[e] = n;
  }
}

//------------------------------------------------------------------------------
// The largest |interpolant - display| over the regular level-n subdivision of
// triangle t (nets already computed), in units of the tolerance.
double Reconstruction::Internals::Resampler::Deviation(int t, int n)
{
  const Internals& in = this->In;
  const int nc = this->NC;
  const double step = 1.0 / n;
  // The interpolant at the lattice points (a, b): barycentrics ((n-a-b)/n, a/n, b/n).
  const int stride = n + 1;
  this->LatticeValues.resize(static_cast<std::size_t>(stride) * stride * nc);
  auto at = [&](int a, int b) {
    return this->LatticeValues.data() + (static_cast<std::size_t>(a) * stride + b) * nc;
  };
  auto bary = [&](int a, int b, double* out) {
    out[0] = (n - a - b) * step;
    out[1] = a * step;
    out[2] = b * step;
  };
  for (int a = 0; a <= n; ++a)
  {
    for (int b = 0; a + b <= n; ++b)
    {
      double corner[3];
      bary(a, b, corner);
      in.EvaluateWithNets(t, this->Nets.data(), corner, at(a, b), nullptr);
    }
  }
  double worst = 0.0;
  double corners[3][3];
  for (int a = 0; a < n; ++a)
  {
    for (int b = 0; a + b < n; ++b)
    {
      bary(a, b, corners[0]);
      bary(a + 1, b, corners[1]);
      bary(a, b + 1, corners[2]);
      worst = std::max(worst, this->PieceDeviation(t, corners, { at(a, b), at(a + 1, b), at(a, b + 1) }));
      if (a + b + 1 < n)
      {
        bary(a + 1, b + 1, corners[0]);
        worst = std::max(worst,
          this->PieceDeviation(t, corners, { at(a + 1, b + 1), at(a + 1, b), at(a, b + 1) }));
      }
    }
  }
  return worst;
}

//------------------------------------------------------------------------------
// The largest |interpolant - display| over one display triangle inside input
// triangle t (corner barycentrics b, display values p), in units of the
// tolerance: at the points of its own level-4 lattice other than its corners.
// Its edge midpoints and centroid alone miss the peaks of the element's three
// cubic pieces.
double Reconstruction::Internals::Resampler::PieceDeviation(
  int t, const double (&b)[3][3], const std::array<const double*, 3>& p)
{
  const int nc = this->NC;
  double* value = this->Value.data();
  const double* inverse = this->InverseTolerance.data();
  double worst = 0.0;
  for (int i = 0; i <= 4; ++i)
  {
    for (int j = 0; i + j <= 4; ++j)
    {
      const int k = 4 - i - j;
      if (i == 4 || j == 4 || k == 4)
      {
        continue;
      }
      const double w[3] = { 0.25 * i, 0.25 * j, 0.25 * k };
      double x[3];
      for (int d = 0; d < 3; ++d)
      {
        x[d] = w[0] * b[0][d] + w[1] * b[1][d] + w[2] * b[2][d];
      }
      this->In.EvaluateWithNets(t, this->Nets.data(), x, value, nullptr);
      for (int c = 0; c < nc; ++c)
      {
        const double shown = w[0] * p[0][c] + w[1] * p[1][c] + w[2] * p[2][c];
        worst = std::max(worst, std::abs(value[c] - shown) * inverse[c]);
      }
    }
  }
  return worst;
}

//------------------------------------------------------------------------------
// The output's triangles checked against the tolerance; the level of every
// input triangle holding one beyond it is raised (with the counts of its
// edges). The irregular layout of a triangle whose edges differ is coarser
// than the regular one its level was chosen with (near its corners the strips
// reach two lattice steps inward), so some need one more round. Returns
// whether a level was raised.
bool Reconstruction::Internals::Resampler::RaiseFailingLevels()
{
  const Internals& in = this->In;
  const ResampledMesh& out = this->Output;
  const int nc = this->NC;
  const int maximum = this->Options.MaximumSubdivisionLevel;
  const int no = out.GetNumberOfTriangles();
  bool raised = false;
  for (int o = 0; o < no;)
  {
    const int t = out.SourceTriangle[o];
    int end = o;
    while (end < no && out.SourceTriangle[end] == t)
    {
      ++end;
    }
    const int n = this->Needed[t];
    bool tested = true; // the regular layout its level was tested with
    for (int k = 0; k < 3; ++k)
    {
      tested = tested && this->Segments[in.TriangleEdge[3 * t + k]] == n;
    }
    if (n >= maximum || tested)
    {
      o = end;
      continue;
    }
    for (int c = 0; c < nc; ++c)
    {
      in.ComputeNet(t, c, this->Nets[c]);
    }
    double worst = 0.0;
    for (; o < end; ++o)
    {
      double b[3][3];
      std::array<const double*, 3> p;
      for (int i = 0; i < 3; ++i)
      {
        const int q = out.Triangles[3 * o + i];
        in.Barycentric(t, out.Points[2 * q], out.Points[2 * q + 1], b[i]);
        p[i] = out.Values.data() + static_cast<std::size_t>(q) * nc;
      }
      worst = std::max(worst, this->PieceDeviation(t, b, p));
    }
    if (worst > 1.0)
    {
      const double guess = std::ceil(n * std::sqrt(worst) * (1.0 - 1e-12));
      this->Needed[t] = std::min(maximum, std::max(n + 1, static_cast<int>(std::min(guess, 1024.0))));
      raised = true;
    }
  }
  return raised;
}

} // namespace penumbra
