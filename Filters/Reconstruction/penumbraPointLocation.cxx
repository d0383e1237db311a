// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraPointLocation.cxx
 * @brief Point location in the reconstruction: barycentric coordinates and a
 * uniform grid of triangles (about one per cell).
 */
#include "penumbraReconstructionInternals.h"
#include "penumbraPointLocation.h"
#include "penumbraSampleMeshTopology.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra
{

using detail::InsideTolerance;
using detail::Next;
using detail::Prev;

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
void Reconstruction::Internals::Barycentric(int t, double u, double v, double b[3]) const
{
  const int* tri = this->T(t);
  const double area2 = this->Geometry[t].Area2;
  for (int i = 0; i < 3; ++i)
  {
    const double* a = this->P(tri[Next(i)]);
    const double* c = this->P(tri[Prev(i)]);
    b[i] = ((c[0] - a[0]) * (v - a[1]) - (c[1] - a[1]) * (u - a[0])) / area2;
  }
}

//------------------------------------------------------------------------------
void detail::ClampBarycentric(const double in[3], double b[3])
{
  double sum = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    b[i] = in[i] > 0.0 ? in[i] : 0.0; // also maps NaN to 0
    sum += b[i];
  }
  if (!(sum > 0.0) || !std::isfinite(sum))
  {
    b[0] = b[1] = b[2] = 1.0 / 3.0;
    return;
  }
  for (int i = 0; i < 3; ++i)
  {
    b[i] /= sum;
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildGrid()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  this->GridStart.clear();
  this->GridTriangles.clear();
  this->GridDims[0] = this->GridDims[1] = 0;
  if (nt == 0)
  {
    return;
  }
  const double inf = std::numeric_limits<double>::infinity();
  double lo[2] = { inf, inf };
  double hi[2] = { -lo[0], -lo[1] };
  for (int t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double* p = this->P(this->T(t)[k]);
      for (int d = 0; d < 2; ++d)
      {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
    }
  }
  const double w = std::max(hi[0] - lo[0], 1e-300);
  const double h = std::max(hi[1] - lo[1], 1e-300);
  // About one triangle per cell, at most 2048 x 2048 cells.
  const double cell = std::sqrt(w * h / nt);
  for (int d = 0; d < 2; ++d)
  {
    const double extent = d == 0 ? w : h;
    const double n = cell > 0.0 ? std::ceil(extent / cell) : 1.0;
    this->GridDims[d] = static_cast<int>(std::min(2048.0, std::max(1.0, n)));
    this->GridOrigin[d] = lo[d];
    this->GridInverseCell[d] = this->GridDims[d] / extent;
  }
  const int nx = this->GridDims[0];
  const int ny = this->GridDims[1];
  auto cellRange = [&](int t, int r[4]) {
    double blo[2] = { inf, inf };
    double bhi[2] = { -blo[0], -blo[1] };
    for (int k = 0; k < 3; ++k)
    {
      const double* p = this->P(this->T(t)[k]);
      for (int d = 0; d < 2; ++d)
      {
        blo[d] = std::min(blo[d], p[d]);
        bhi[d] = std::max(bhi[d], p[d]);
      }
    }
    for (int d = 0; d < 2; ++d)
    {
      const int n = this->GridDims[d];
      auto cellOf = [&](double x) {
        const double f = std::floor((x - this->GridOrigin[d]) * this->GridInverseCell[d]);
        return std::min(n - 1, std::max(0, static_cast<int>(f)));
      };
      r[2 * d] = cellOf(blo[d]);
      r[2 * d + 1] = cellOf(bhi[d]);
    }
  };
  this->GridStart.assign(static_cast<std::size_t>(nx) * ny + 1, 0);
  int r[4];
  for (int t = 0; t < nt; ++t)
  {
    cellRange(t, r);
    for (int j = r[2]; j <= r[3]; ++j)
    {
      for (int i = r[0]; i <= r[1]; ++i)
      {
        ++this->GridStart[static_cast<std::size_t>(j) * nx + i + 1];
      }
    }
  }
  for (std::size_t i = 0; i + 1 < this->GridStart.size(); ++i)
  {
    this->GridStart[i + 1] += this->GridStart[i];
  }
  this->GridTriangles.assign(this->GridStart.back(), -1);
  std::vector<int> fill(this->GridStart.begin(), this->GridStart.end() - 1);
  for (int t = 0; t < nt; ++t)
  {
    cellRange(t, r);
    for (int j = r[2]; j <= r[3]; ++j)
    {
      for (int i = r[0]; i <= r[1]; ++i)
      {
        this->GridTriangles[fill[static_cast<std::size_t>(j) * nx + i]++] = t;
      }
    }
  }
}

//------------------------------------------------------------------------------
int Reconstruction::Internals::FindTriangle(double u, double v, double barycentric[3]) const
{
  const Internals& in = *this;
  if (in.GridDims[0] == 0 || !std::isfinite(u) || !std::isfinite(v))
  {
    return -1;
  }
  const double q[2] = { u, v };
  int cell[2];
  for (int d = 0; d < 2; ++d)
  {
    const double f = (q[d] - in.GridOrigin[d]) * in.GridInverseCell[d];
    const int n = in.GridDims[d];
    // Allow points just outside the box (tolerance); clamp to the grid.
    if (f < -1.0 || f > n + 1.0)
    {
      return -1;
    }
    cell[d] = std::min(n - 1, std::max(0, static_cast<int>(std::floor(f))));
  }
  const std::size_t c = static_cast<std::size_t>(cell[1]) * in.GridDims[0] + cell[0];
  int best = -1;
  double bestMin = -InsideTolerance;
  double b[3];
  for (int i = in.GridStart[c]; i < in.GridStart[c + 1]; ++i)
  {
    const int t = in.GridTriangles[i];
    in.Barycentric(t, u, v, b);
    const double m = std::min(b[0], std::min(b[1], b[2]));
    if (m >= bestMin)
    {
      bestMin = m;
      best = t;
      if (barycentric)
      {
        barycentric[0] = b[0];
        barycentric[1] = b[1];
        barycentric[2] = b[2];
      }
    }
  }
  return best;
}

} // namespace penumbra
