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

} // namespace

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
  std::vector<double> base(static_cast<std::size_t>(this->SectorGradient.size()));
  base = this->SectorGradient;
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
  this->ComputeNetSlack(base);
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
