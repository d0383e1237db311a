// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraOvershoot.cxx
 * @brief Overshoot of the Clough-Tocher interpolant over triangles much
 * larger than the data its corner gradients come from: gradients scaled per
 * point so that no edge's control point leaves the values around the point
 * by more than a few times their spread.
 */
#include "penumbraReconstructionInternals.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

// The change of the interpolant along an edge at its end point, g . e, is at
// most this many times the spread of the values around the point (or the
// change of the value along the edge, if larger).
constexpr double OvershootFactor = 3.0;

} // namespace

//------------------------------------------------------------------------------
// A point can carry a steep gradient that is right at the scale of its
// smallest triangles (a contact shadow sampled at a fraction of a
// millimetre) and also be a corner of a triangle a thousand times larger,
// where the unrefined light is smooth. The cubic along that triangle's edges
// starts with the steep slope and overshoots by the slope times the edge's
// length: single display points ten times the surface's light on a
// furnished office's walls and desks. A smooth function sampled by a mesh
// whose triangles around a point differ in size by less than about
// 2 * OvershootFactor is untouched: |g . e| is then within that factor of
// the values' spread around the point. All sectors of a point are scaled by
// the same factor, which keeps the agreement along order-1 lines.
void Reconstruction::Internals::LimitOvershoot()
{
  const int np = this->Mesh.GetNumberOfPoints();
  const int nc = this->NC;
  std::vector<double> low(static_cast<std::size_t>(np) * nc, 1e300);
  std::vector<double> high(static_cast<std::size_t>(np) * nc, -1e300);
  const int nt = this->Mesh.GetNumberOfTriangles();
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int c = 0; c < nc; ++c)
    {
      const double lo = std::min({ this->Value(tri[0], c), this->Value(tri[1], c),
        this->Value(tri[2], c) });
      const double hi = std::max({ this->Value(tri[0], c), this->Value(tri[1], c),
        this->Value(tri[2], c) });
      for (int k = 0; k < 3; ++k)
      {
        const std::size_t i = static_cast<std::size_t>(tri[k]) * nc + c;
        low[i] = std::min(low[i], lo);
        high[i] = std::max(high[i], hi);
      }
    }
  }
  std::vector<double> factor(static_cast<std::size_t>(np) * nc, 1.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int k = 0; k < 3; ++k)
    {
      const int p = tri[k];
      const double* pp = this->P(p);
      const std::size_t s = this->CornerSector[3 * t + k];
      for (int c = 0; c < nc; ++c)
      {
        const std::size_t i = static_cast<std::size_t>(p) * nc + c;
        const double* g = this->SectorGradient.data() + (s * nc + c) * 2;
        const double spread = high[i] - low[i];
        for (int j = 1; j < 3; ++j)
        {
          const int q = tri[(k + j) % 3];
          const double change = std::abs(g[0] * (this->P(q)[0] - pp[0]) + g[1] * (this->P(q)[1] - pp[1]));
          const double allowed =
            OvershootFactor * std::max(spread, std::abs(this->Value(q, c) - this->Value(p, c)));
          if (change > allowed)
          {
            factor[i] = std::min(factor[i], allowed / change);
          }
        }
      }
    }
  }
  const int ns = static_cast<int>(this->SectorPoint.size());
  for (int s = 0; s < ns; ++s)
  {
    const int p = this->SectorPoint[s];
    for (int c = 0; c < nc; ++c)
    {
      const double f = factor[static_cast<std::size_t>(p) * nc + c];
      if (f < 1.0)
      {
        double* g = this->SectorGradient.data() + (static_cast<std::size_t>(s) * nc + c) * 2;
        g[0] *= f;
        g[1] *= f;
        ++this->Statistics.OvershootGradients;
      }
    }
  }
}

} // namespace penumbra
