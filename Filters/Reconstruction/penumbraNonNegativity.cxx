// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraNonNegativity.cxx
 * @brief Non-negativity of the Clough-Tocher interpolant: gradients scaled toward
 * zero per point and channel until every control net is non-negative up to
 * a rounding slack.
 */
#include "penumbraReconstructionInternals.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

using detail::NetPoints;

namespace
{

// Below this many repairs of one triangle, gradients are scaled by the exact
// factor; beyond, they are set to zero (guarantees termination).
constexpr int MaximumScalingsPerTriangle = 8;
// The scale factor is shrunk by this relative amount so that the repaired
// net stays non-negative after rounding.
constexpr double ScaleMargin = 1e-9;
// Net values this far below the samples' minimum, relative to the values
// and gradients entering the net, are rounding, not negativity to repair.
constexpr double NetRoundingSlack = 1e-12;

// One constraint on a gradient g: Direction . g >= Bound.
struct HalfPlane
{
  double Direction[2];
  double Bound;
};

bool Satisfies(const HalfPlane& h, const double g[2])
{
  const double dot = h.Direction[0] * g[0] + h.Direction[1] * g[1];
  const double scale = std::hypot(h.Direction[0], h.Direction[1]) * std::hypot(g[0], g[1]);
  return dot >= h.Bound - 1e-12 * (scale + std::abs(h.Bound));
}

bool SatisfiesAll(const std::vector<HalfPlane>& planes, const double g[2])
{
  for (const HalfPlane& h : planes)
  {
    if (!Satisfies(h, g))
    {
      return false;
    }
  }
  return true;
}

// Replaces g, which violates some of `planes`, by the nearest point of their
// intersection (which holds zero: every bound is <= 0): its projection onto
// one boundary line, or a corner where two lines meet, or zero.
void NearestFeasible(const std::vector<HalfPlane>& planes, double g[2])
{
  double best[2] = { 0.0, 0.0 };
  double bestDistance = g[0] * g[0] + g[1] * g[1];
  auto consider = [&](const double q[2]) {
    const double d = (q[0] - g[0]) * (q[0] - g[0]) + (q[1] - g[1]) * (q[1] - g[1]);
    if (d < bestDistance && SatisfiesAll(planes, q))
    {
      bestDistance = d;
      best[0] = q[0];
      best[1] = q[1];
    }
  };
  const std::size_t n = planes.size();
  for (std::size_t k = 0; k < n; ++k)
  {
    const HalfPlane& h = planes[k];
    const double length2 = h.Direction[0] * h.Direction[0] + h.Direction[1] * h.Direction[1];
    if (length2 > 0.0)
    {
      const double shift = (h.Bound - (h.Direction[0] * g[0] + h.Direction[1] * g[1])) / length2;
      const double q[2] = { g[0] + shift * h.Direction[0], g[1] + shift * h.Direction[1] };
      consider(q);
    }
    for (std::size_t l = k + 1; l < n; ++l)
    {
      const HalfPlane& o = planes[l];
      const double det = h.Direction[0] * o.Direction[1] - h.Direction[1] * o.Direction[0];
      if (std::abs(det) > 1e-12 * length2)
      {
        const double q[2] = { (h.Bound * o.Direction[1] - o.Bound * h.Direction[1]) / det,
          (h.Direction[0] * o.Bound - o.Direction[0] * h.Bound) / det };
        consider(q);
      }
    }
  }
  g[0] = best[0];
  g[1] = best[1];
}

} // namespace

//------------------------------------------------------------------------------
// Before any scaling: at a point with one sector, the gradient is moved to
// the nearest one that keeps the control points next to the point (E and A,
// the latter implied by the two E of its corner) above their triangles'
// lowest sample. Where the light falls to zero along an edge (a surface's
// border in the plane of a source, an umbra's boundary) the fitted gradient
// carries a small along-edge part of either sign; scaling the three corners'
// gradients for it would flatten the slope into the edge, and with it the
// reconstruction of the whole ramp. The projection removes only that part.
// Points with several sectors keep the common scaling, which keeps
// continuity across order-1 lines.
void Reconstruction::Internals::ProjectCornerGradients()
{
  const int np = this->Mesh.GetNumberOfPoints();
  const int ns = static_cast<int>(this->SectorPoint.size());
  const int nc = this->NC;
  std::vector<int> sectorsOfPoint(np, 0);
  for (int s = 0; s < ns; ++s)
  {
    ++sectorsOfPoint[this->SectorPoint[s]];
  }
  std::vector<HalfPlane> planes;
  for (int s = 0; s < ns; ++s)
  {
    const int point = this->SectorPoint[s];
    if (sectorsOfPoint[point] != 1)
    {
      continue;
    }
    const double* p = this->P(point);
    for (int c = 0; c < nc; ++c)
    {
      double* g = this->SectorGradient.data() + (static_cast<std::size_t>(s) * nc + c) * 2;
      const double f = this->Value(point, c);
      planes.clear();
      for (int k = this->SectorCornerStart[s]; k < this->SectorCornerStart[s + 1]; ++k)
      {
        const int t = this->SectorCorners[k] / 3;
        const int* tri = this->T(t);
        const double lowest =
          std::min(0.0, std::min(this->Value(tri[0], c), std::min(this->Value(tri[1], c),
                                                              this->Value(tri[2], c))));
        for (int j = 0; j < 3; ++j)
        {
          if (tri[j] != point)
          {
            // E = f + g . (p_j - p) / 3 >= lowest.
            const double* q = this->P(tri[j]);
            planes.push_back({ { q[0] - p[0], q[1] - p[1] }, 3.0 * (lowest - f) });
          }
        }
      }
      if (!SatisfiesAll(planes, g))
      {
        NearestFeasible(planes, g);
        ++this->Statistics.ProjectedGradients;
      }
    }
  }
}

//------------------------------------------------------------------------------
// Rounding slack per triangle and channel: a net this far below the
// samples' minimum is rounding, not negativity to repair (evaluation clamps
// it). Relative to the channel's largest value and to the values and
// gradients entering the net (gradient times the triangle's size), the
// largest gradient of each point over all its sectors (`base`): the
// tangential projections across order-1 edges mix the sectors' gradients (in
// an unlit sector next to a lit one a net of zeros can come out at -8e-18;
// repairing it would zero the lit sector's gradient too).
void Reconstruction::Internals::ComputeNetSlack(const std::vector<double>& base)
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int np = this->Mesh.GetNumberOfPoints();
  const int nc = this->NC;
  std::vector<double> largestValue(nc, 0.0);
  for (int p = 0; p < np; ++p)
  {
    for (int c = 0; c < nc; ++c)
    {
      largestValue[c] = std::max(largestValue[c], std::abs(this->Value(p, c)));
    }
  }
  std::vector<double> largestGradient(static_cast<std::size_t>(np) * nc, 0.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::size_t s = this->CornerSector[3 * t + corner];
      for (int c = 0; c < nc; ++c)
      {
        double& g = largestGradient[static_cast<std::size_t>(tri[corner]) * nc + c];
        g = std::max(g, std::hypot(base[(s * nc + c) * 2], base[(s * nc + c) * 2 + 1]));
      }
    }
  }
  this->NetSlack.assign(static_cast<std::size_t>(nt) * nc, 0.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int c = 0; c < nc; ++c)
    {
      double magnitude = largestValue[c];
      for (int i = 0; i < 3; ++i)
      {
        magnitude = std::max(magnitude,
          std::abs(this->Value(tri[i], c)) +
            this->Geometry[t].Diameter *
              largestGradient[static_cast<std::size_t>(tri[i]) * nc + c]);
      }
      this->NetSlack[static_cast<std::size_t>(t) * nc + c] = NetRoundingSlack * magnitude;
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::EnforceNonNegativity()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int np = this->Mesh.GetNumberOfPoints();
  const int nc = this->NC;
  std::vector<double> alpha(static_cast<std::size_t>(np) * nc, 1.0);
  // The slack is that of the fitted gradients, so that a projection cannot
  // shrink it.
  this->ComputeNetSlack(this->SectorGradient);
  this->ProjectCornerGradients();
  const std::vector<double> base = this->SectorGradient;
  std::vector<int> scalings(nt, 0);
  std::vector<char> queued(nt, 1);
  std::vector<int> queue(nt);
  for (int t = 0; t < nt; ++t)
  {
    queue[t] = t;
  }
  std::size_t head = 0;
  // Apply a point's factors to all its sectors.
  auto applyPoint = [&](int point, int channel) {
    const double f = alpha[static_cast<std::size_t>(point) * nc + channel];
    for (int i = this->PointTriangleStart[point]; i < this->PointTriangleStart[point + 1]; ++i)
    {
      const int t = this->PointTriangles[i];
      const int* tri = this->T(t);
      const int corner = tri[0] == point ? 0 : (tri[1] == point ? 1 : 2);
      const std::size_t s = this->CornerSector[3 * t + corner];
      for (int d = 0; d < 2; ++d)
      {
        this->SectorGradient[(s * nc + channel) * 2 + d] = f * base[(s * nc + channel) * 2 + d];
      }
      if (!queued[t])
      {
        queued[t] = 1;
        queue.push_back(t);
      }
    }
  };
  Net net, zero;
  double cur[19], low[19];
  int passes = nt > 0 ? 1 : 0;
  std::size_t passEnd = queue.size();
  while (head < queue.size())
  {
    if (head == passEnd)
    {
      ++passes;
      passEnd = queue.size();
    }
    const int t = queue[head++];
    queued[t] = 0;
    const int* tri = this->T(t);
    for (int c = 0; c < nc; ++c)
    {
      const double f0 = this->Value(tri[0], c);
      const double f1 = this->Value(tri[1], c);
      const double f2 = this->Value(tri[2], c);
      const double lowest = std::min(0.0, std::min(f0, std::min(f1, f2)));
      const double slack = this->NetSlack[static_cast<std::size_t>(t) * nc + c];
      this->ComputeNet(t, c, net);
      NetPoints(net, cur);
      double minimum = cur[0];
      for (int j = 1; j < 19; ++j)
      {
        minimum = std::min(minimum, cur[j]);
      }
      if (minimum >= lowest - slack)
      {
        continue;
      }
      double lambda = 0.0;
      if (scalings[t] < MaximumScalingsPerTriangle)
      {
        // The net is affine in a common factor of the three points'
        // gradients: the largest factor keeping it above `lowest`.
        this->ComputeZeroGradientNet(t, c, zero);
        NetPoints(zero, low);
        lambda = 1.0;
        for (int j = 0; j < 19; ++j)
        {
          if (cur[j] < lowest)
          {
            const double room = std::max(0.0, low[j] - lowest);
            lambda = std::min(lambda, room / (low[j] - cur[j]));
          }
        }
        lambda = std::max(0.0, lambda * (1.0 - ScaleMargin));
      }
      ++scalings[t];
      for (int i = 0; i < 3; ++i)
      {
        double& a = alpha[static_cast<std::size_t>(tri[i]) * nc + c];
        if (a > 0.0)
        {
          a *= lambda;
          applyPoint(tri[i], c);
        }
      }
    }
  }
  this->Statistics.RepairPasses = passes;
  for (double a : alpha)
  {
    if (a < 1.0)
    {
      ++this->Statistics.ScaledGradients;
      if (a == 0.0)
      {
        ++this->Statistics.ZeroedGradients;
      }
    }
  }
}

} // namespace penumbra
