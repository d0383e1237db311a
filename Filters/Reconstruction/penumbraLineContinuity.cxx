// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraLineContinuity.cxx
 * @brief Continuity across order-1 lines: each sector gradient is projected onto
 * the derivatives along the constrained edges bounding it.
 */
#include "penumbraReconstructionInternals.h"
#include "penumbraSampleMeshTopology.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

using detail::ConstrainedEdge;
using detail::Next;
using detail::Prev;

namespace
{

// Two constrained edges at a point count as one straight line when the sine
// of the angle between them is below this (about 5.7 degrees): solving for
// both directional derivatives separately would then be ill-conditioned.
constexpr double CollinearSine = 0.1;
// The three-point derivative along a line divides by the shorter of its two
// spacings: when that one is below this fraction of the longer (a point
// placed a rounding error from its neighbour, as where two sides of a
// discontinuity meet), the difference would be noise over a vanishing
// distance, and the fitted gradients are used instead.
constexpr double SpacingRatio = 1e-2;

} // namespace

//------------------------------------------------------------------------------
// Other end w of `edge` from its end v, the unit direction (tu, tv) from v to
// w; returns the edge's length.
double Reconstruction::Internals::EdgeDirection(
  int v, int edge, int& w, double& tu, double& tv) const
{
  w = this->EdgePoints[2 * edge] == v ? this->EdgePoints[2 * edge + 1] : this->EdgePoints[2 * edge];
  const double* pv = this->P(v);
  const double* pw = this->P(w);
  const double L = std::hypot(pw[0] - pv[0], pw[1] - pv[1]);
  tu = (pw[0] - pv[0]) / L;
  tv = (pw[1] - pv[1]) / L;
  return L;
}

//------------------------------------------------------------------------------
// Derivative at point v along constrained edge `edge` (toward its other end),
// from the values along the straight constrained line through v: a parabola
// through three consecutive points (centred when the line continues through
// v, else one-sided), else the mean over the two sides' fitted gradients.
double Reconstruction::Internals::LineDerivative(int v, int edge, int channel) const
{
  int w;
  double tu, tv;
  const double L = this->EdgeDirection(v, edge, w, tu, tv);
  const double* pv = this->P(v);
  const double* pw = this->P(w);
  const double fv = this->Value(v, channel);
  const double fw = this->Value(w, channel);

  // The constrained edge at `from` (other than `exclude`) whose direction is
  // closest to (du, dv), if within CollinearSine.
  auto straightContinuation = [this](int from, int exclude, double du, double dv, int& to) {
    int best = -1;
    double bestDot = 0.0;
    for (int i = this->PointEdgeStart[from]; i < this->PointEdgeStart[from + 1]; ++i)
    {
      const int e = this->PointEdges[i];
      if (e == exclude)
      {
        continue;
      }
      int o;
      double eu, ev;
      this->EdgeDirection(from, e, o, eu, ev);
      const double dot = eu * du + ev * dv;
      const double cross = std::abs(eu * dv - ev * du);
      if (dot > 0.0 && cross < CollinearSine && dot > bestDot)
      {
        bestDot = dot;
        best = e;
        to = o;
      }
    }
    return best;
  };

  int back = -1;
  if (straightContinuation(v, edge, -tu, -tv, back) >= 0)
  {
    const double* pb = this->P(back);
    const double a = std::hypot(pb[0] - pv[0], pb[1] - pv[1]);
    const double b = L;
    if (std::min(a, b) >= SpacingRatio * std::max(a, b))
    {
      const double fb = this->Value(back, channel);
      return (a * a * (fw - fv) + b * b * (fv - fb)) / (a * b * (a + b));
    }
  }
  int beyond = -1;
  if (straightContinuation(w, edge, tu, tv, beyond) >= 0 && beyond != v)
  {
    const double* pb = this->P(beyond);
    const double b = L;
    const double next = std::hypot(pb[0] - pw[0], pb[1] - pw[1]);
    if (std::min(b, next) >= SpacingRatio * std::max(b, next))
    {
      const double c = L + next;
      const double fb = this->Value(beyond, channel);
      return (c * c * (fw - fv) - b * b * (fb - fv)) / (b * c * (c - b));
    }
  }
  // Mean of the two sides' fitted gradients along the edge.
  double sum = 0.0;
  int count = 0;
  for (int side = 0; side < 2; ++side)
  {
    const int s3 = this->EdgeSides[2 * edge + side];
    if (s3 < 0)
    {
      continue;
    }
    const int t = s3 / 3;
    const int* tri = this->T(t);
    const int corner = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    const int sector = this->CornerSector[3 * t + corner];
    const double* fit =
      this->SectorFit.data() + (static_cast<std::size_t>(sector) * this->NC + channel) * 5;
    sum += fit[0] * tu + fit[1] * tv;
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::EnforceLineContinuity()
{
  const int ns = static_cast<int>(this->SectorPoint.size());
  const int nc = this->NC;
  std::vector<int> edges;
  std::vector<double> dirs;   // 2 per merged constraint
  std::vector<double> values; // nc per merged constraint
  for (int s = 0; s < ns; ++s)
  {
    const int v = this->SectorPoint[s];
    if (this->PointEdgeStart[v] == this->PointEdgeStart[v + 1])
    {
      continue;
    }
    // Constrained edges bounding this sector at v.
    edges.clear();
    for (int i = this->SectorCornerStart[s]; i < this->SectorCornerStart[s + 1]; ++i)
    {
      const int corner = this->SectorCorners[i];
      const int t = corner / 3;
      const int c = corner % 3;
      for (int k : { Next(c), Prev(c) })
      {
        const int e = this->TriangleEdge[3 * t + k];
        if (this->EdgeKinds[e] != ConstrainedEdge ||
          std::find(edges.begin(), edges.end(), e) != edges.end())
        {
          continue;
        }
        // An edge whose two sides share v's sector (the free end of a line)
        // needs no agreement: both sides use the same gradient.
        int sides[2];
        for (int j = 0; j < 2; ++j)
        {
          const int t2 = this->EdgeSides[2 * e + j] / 3;
          const int* tri2 = this->T(t2);
          sides[j] = this->CornerSector[3 * t2 + (tri2[0] == v ? 0 : (tri2[1] == v ? 1 : 2))];
        }
        if (sides[0] != sides[1])
        {
          edges.push_back(e);
        }
      }
    }
    if (edges.empty())
    {
      continue;
    }
    // Constraints g . t = D, nearly parallel ones merged into one.
    dirs.clear();
    values.clear();
    std::vector<int> merged;
    for (int e : edges)
    {
      int w;
      double tu, tv;
      this->EdgeDirection(v, e, w, tu, tv);
      int into = -1;
      for (std::size_t j = 0; j < merged.size(); ++j)
      {
        const double cross = std::abs(dirs[2 * j] * tv - dirs[2 * j + 1] * tu);
        if (cross < CollinearSine)
        {
          into = static_cast<int>(j);
          break;
        }
      }
      if (into < 0)
      {
        merged.push_back(1);
        dirs.push_back(tu);
        dirs.push_back(tv);
        for (int c = 0; c < nc; ++c)
        {
          values.push_back(this->LineDerivative(v, e, c));
        }
      }
      else
      {
        // g.t1 = D1 and g.t2 = D2 with t2 = +-t1 (nearly): one constraint
        // along the mean direction.
        const double sign = dirs[2 * into] * tu + dirs[2 * into + 1] * tv < 0.0 ? -1.0 : 1.0;
        const double mu = dirs[2 * into] + sign * tu;
        const double mv = dirs[2 * into + 1] + sign * tv;
        const double ml = std::hypot(mu, mv);
        for (int c = 0; c < nc; ++c)
        {
          const double d1 = values[into * nc + c];
          const double d2 = this->LineDerivative(v, e, c);
          values[into * nc + c] = (d1 + sign * d2) / ml;
        }
        dirs[2 * into] = mu / ml;
        dirs[2 * into + 1] = mv / ml;
        ++merged[into];
      }
    }
    const int m = static_cast<int>(merged.size());
    for (int c = 0; c < nc; ++c)
    {
      double* g = this->SectorGradient.data() + (static_cast<std::size_t>(s) * nc + c) * 2;
      if (m == 1)
      {
        // Least change: g += (D - g.t) t.
        const double r = values[c] - (g[0] * dirs[0] + g[1] * dirs[1]);
        g[0] += r * dirs[0];
        g[1] += r * dirs[1];
      }
      else
      {
        // Two or more independent directions determine g (least squares).
        double n00 = 0.0, n01 = 0.0, n11 = 0.0, r0 = 0.0, r1 = 0.0;
        for (int j = 0; j < m; ++j)
        {
          const double tu = dirs[2 * j];
          const double tv = dirs[2 * j + 1];
          n00 += tu * tu;
          n01 += tu * tv;
          n11 += tv * tv;
          r0 += tu * values[j * nc + c];
          r1 += tv * values[j * nc + c];
        }
        const double det = n00 * n11 - n01 * n01;
        g[0] = (n11 * r0 - n01 * r1) / det;
        g[1] = (n00 * r1 - n01 * r0) / det;
      }
    }
    ++this->Statistics.ConstrainedSectors;
  }
}

} // namespace penumbra
