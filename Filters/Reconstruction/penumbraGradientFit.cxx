// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraGradientFit.cxx
 * @brief Per-sector weighted least-squares Taylor fits of the reconstruction:
 * the quadratic gradient fit and the cubic error model (one factorisation).
 */
#include "penumbraReconstructionInternals.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

// A fit column keeping less than this fraction of its norm after
// orthogonalisation against the previous ones is taken as undetermined by
// the stencil (offsets are scaled to O(1)).
constexpr double FitRankThreshold = 1e-6;
// The cubic error model needs at least this many neighbours (9 unknowns).
constexpr int CubicModelPoints = 12;
// A neighbour closer to the fitted point than this fraction of the stencil's
// radius carries no derivative information: it is a duplicate, or the twin
// of a point across a discontinuity whose two sides the mesher placed a
// rounding error apart, and its value difference over that distance would
// dictate the gradient (the rows are weighted by the inverse distance).
constexpr double CoincidentFraction = 1e-4;
// A fitted gradient is at most this many times the steepest secant from the
// fitted point to a point of its stencil (see SecantBounds). Twice was too
// tight next to a contact, where the light rises like r log r from the
// contact line (a box's foot on a floor moved 1e6 from the origin: 9% off).
constexpr double SecantFactor = 10.0;

} // namespace

//------------------------------------------------------------------------------
// Points around sector s on its side of every constraint: the sector's
// triangles, then ring by ring the triangles of the sectors of the points
// reached (never across a constrained edge or a cut), until at least
// `minPoints` points or `maxRings` rings. The sector's own point is excluded,
// and so are points within CoincidentFraction of the stencil's radius of it.
void Reconstruction::Internals::GatherNeighbours(
  int s, int minPoints, int maxRings, FitWorkspace& w) const
{
  const int stamp = ++w.Stamp;
  w.Points.clear();
  w.Triangles.clear();
  w.PointStamp[this->SectorPoint[s]] = stamp;
  auto addSector = [&](int sector) {
    for (int i = this->SectorCornerStart[sector]; i < this->SectorCornerStart[sector + 1]; ++i)
    {
      const int t = this->SectorCorners[i] / 3;
      if (w.TriangleStamp[t] == stamp)
      {
        continue;
      }
      w.TriangleStamp[t] = stamp;
      w.Triangles.push_back(t);
      const int* tri = this->T(t);
      for (int k = 0; k < 3; ++k)
      {
        if (w.PointStamp[tri[k]] != stamp)
        {
          w.PointStamp[tri[k]] = stamp;
          w.Points.push_back(tri[k]);
        }
      }
    }
  };
  addSector(s);
  std::size_t ringBegin = 0;
  for (int ring = 1; ring < maxRings && static_cast<int>(w.Points.size()) < minPoints; ++ring)
  {
    const std::size_t ringEnd = w.Triangles.size();
    for (std::size_t i = ringBegin; i < ringEnd; ++i)
    {
      const int t = w.Triangles[i];
      for (int k = 0; k < 3; ++k)
      {
        addSector(this->CornerSector[3 * t + k]);
      }
    }
    if (w.Triangles.size() == ringEnd)
    {
      break; // nothing more on this side
    }
    ringBegin = ringEnd;
  }
  const double* pv = this->P(this->SectorPoint[s]);
  auto distance2 = [&](int q) {
    const double du = this->P(q)[0] - pv[0];
    const double dv = this->P(q)[1] - pv[1];
    return du * du + dv * dv;
  };
  double h2 = 0.0;
  for (const int q : w.Points)
  {
    h2 = std::max(h2, distance2(q));
  }
  const double nearest2 = CoincidentFraction * CoincidentFraction * h2;
  w.Points.erase(std::remove_if(w.Points.begin(), w.Points.end(),
                   [&](int q) { return !(distance2(q) > nearest2); }),
    w.Points.end());
}

//------------------------------------------------------------------------------
// Weighted least-squares Taylor polynomial at point v through its value,
// fitted to w.Points. The columns are, in order, du, dv (degree 1), du^2/2,
// du dv, dv^2/2 (degree 2), du^3/6, du^2 dv/2, du dv^2/2, dv^3/6 (degree 3),
// offsets scaled by the largest distance for conditioning, rows weighted by
// the inverse distance. Modified Gram-Schmidt on [A | B] (backward stable
// for least squares) factors the first `maxColumns` columns once; since the
// columns are processed in order, the fits of degree 1, 2 and 3 are nested
// back-substitutions of the same factor. A column that keeps less than
// FitRankThreshold of its norm after orthogonalisation ends the usable
// prefix (the stencil cannot determine it).
void Reconstruction::Internals::FactorFit(int v, int maxColumns, FitWorkspace& w) const
{
  const int nc = this->NC;
  const int width = 9 + nc;
  const double* pv = this->P(v);
  double h2 = 0.0;
  for (int q : w.Points)
  {
    const double du = this->P(q)[0] - pv[0];
    const double dv = this->P(q)[1] - pv[1];
    h2 = std::max(h2, du * du + dv * dv);
  }
  const double h = std::sqrt(h2);
  w.Scale = h;
  w.Rows = 0;
  w.Usable = 0;
  if (!(h > 0.0))
  {
    return;
  }
  const int n = static_cast<int>(w.Points.size());
  w.Columns.resize(static_cast<std::size_t>(width) * n);
  w.R.assign(static_cast<std::size_t>(9) * width, 0.0);
  int rows = 0;
  for (int q : w.Points)
  {
    const double du = (this->P(q)[0] - pv[0]) / h;
    const double dv = (this->P(q)[1] - pv[1]) / h;
    // GatherNeighbours left out the points too close to v to inform a fit.
    const double wgt = 1.0 / std::sqrt(du * du + dv * dv);
    const double row[9] = { du, dv, 0.5 * du * du, du * dv, 0.5 * dv * dv, du * du * du / 6.0,
      0.5 * du * du * dv, 0.5 * du * dv * dv, dv * dv * dv / 6.0 };
    for (int j = 0; j < 9; ++j)
    {
      w.Columns[static_cast<std::size_t>(j) * n + rows] = wgt * row[j];
    }
    for (int c = 0; c < nc; ++c)
    {
      w.Columns[static_cast<std::size_t>(9 + c) * n + rows] =
        wgt * (this->Value(q, c) - this->Value(v, c));
    }
    ++rows;
  }
  w.Rows = rows;
  // Columns live at stride n (the allocated row count); only `rows` are used.
  const int m = std::min(maxColumns, rows);
  for (int k = 0; k < m; ++k)
  {
    double* a = w.Columns.data() + static_cast<std::size_t>(k) * n;
    double norm2 = 0.0;
    for (int i = 0; i < rows; ++i)
    {
      norm2 += a[i] * a[i];
    }
    // Norm before orthogonalisation: recompute from the projections.
    double projected2 = 0.0;
    for (int j = 0; j < k; ++j)
    {
      projected2 += w.R[j * width + k] * w.R[j * width + k];
    }
    const double rkk = std::sqrt(norm2);
    if (!(rkk > FitRankThreshold * std::sqrt(norm2 + projected2)))
    {
      break;
    }
    w.R[k * width + k] = rkk;
    for (int i = 0; i < rows; ++i)
    {
      a[i] /= rkk;
    }
    for (int j = k + 1; j < width; ++j)
    {
      if (j >= maxColumns && j < 9)
      {
        continue;
      }
      double* b = w.Columns.data() + static_cast<std::size_t>(j) * n;
      double r = 0.0;
      for (int i = 0; i < rows; ++i)
      {
        r += a[i] * b[i];
      }
      w.R[k * width + j] = r;
      for (int i = 0; i < rows; ++i)
      {
        b[i] -= r * a[i];
      }
    }
    w.Usable = k + 1;
  }
}

// Coefficients of the fit on the first `columns` (<= w.Usable) columns,
// unscaled, `stride` doubles per channel (the rest zero).
void Reconstruction::Internals::SolveFit(
  int columns, FitWorkspace& w, double* out, int stride) const
{
  const int nc = this->NC;
  const int width = 9 + nc;
  const double h = w.Scale;
  const double scale[9] = { h, h, h * h, h * h, h * h, h * h * h, h * h * h, h * h * h, h * h * h };
  std::fill(out, out + static_cast<std::size_t>(stride) * nc, 0.0);
  for (int c = 0; c < nc; ++c)
  {
    double x[9];
    for (int k = columns - 1; k >= 0; --k)
    {
      double r = w.R[k * width + 9 + c];
      for (int j = k + 1; j < columns; ++j)
      {
        r -= w.R[k * width + j] * x[j];
      }
      x[k] = r / w.R[k * width + k];
    }
    for (int k = 0; k < columns; ++k)
    {
      out[static_cast<std::size_t>(c) * stride + k] = x[k] / scale[k];
    }
  }
}

// Gradient when every neighbour lies on one line through v: the derivative
// along that line (minimum-norm least squares), zero across it.
void Reconstruction::Internals::SolveCollinear(
  int v, FitWorkspace& w, double* out, int stride) const
{
  const int nc = this->NC;
  std::fill(out, out + static_cast<std::size_t>(stride) * nc, 0.0);
  const double* pv = this->P(v);
  // Weighted least squares of f(q) - f(v) = D * (d . t) along the mean direction t.
  double tu = 0.0, tv = 0.0;
  for (int q : w.Points)
  {
    double du = this->P(q)[0] - pv[0];
    double dv = this->P(q)[1] - pv[1];
    if (du * tu + dv * tv < 0.0)
    {
      du = -du;
      dv = -dv;
    }
    tu += du;
    tv += dv;
  }
  const double tl = std::sqrt(tu * tu + tv * tv);
  if (!(tl > 0.0))
  {
    return;
  }
  tu /= tl;
  tv /= tl;
  for (int c = 0; c < nc; ++c)
  {
    double num = 0.0, den = 0.0;
    for (int q : w.Points)
    {
      const double s = (this->P(q)[0] - pv[0]) * tu + (this->P(q)[1] - pv[1]) * tv;
      const double d2 = (this->P(q)[0] - pv[0]) * (this->P(q)[0] - pv[0]) +
        (this->P(q)[1] - pv[1]) * (this->P(q)[1] - pv[1]);
      // Rows weighted by 1/distance, as in the other fits.
      num += s * (this->Value(q, c) - this->Value(v, c)) / d2;
      den += s * s / d2;
    }
    if (den > 0.0)
    {
      out[static_cast<std::size_t>(c) * stride] = num / den * tu;
      out[static_cast<std::size_t>(c) * stride + 1] = num / den * tv;
    }
  }
}

//------------------------------------------------------------------------------
// Per channel, SecantFactor times the steepest secant |f(q) - f(v)| / |q - v|
// from v to a point q of the stencil. A smooth function's gradient is within
// a small factor of its steepest secant over points around it, but a least-
// squares fit whose stencil is nearly degenerate (points along one line,
// the two sides of a discontinuity interleaved on it a few micrometres
// apart, a single point off it) can return gradients a million times
// steeper, which the interpolant then spreads over every triangle at v.
void Reconstruction::Internals::SecantBounds(
  int v, const FitWorkspace& w, std::vector<double>& bounds) const
{
  const double* pv = this->P(v);
  std::fill(bounds.begin(), bounds.end(), 0.0);
  for (int q : w.Points)
  {
    // sqrt, not hypot: plane coordinates neither overflow nor underflow
    // when squared, and this is the fit's hottest loop.
    const double du = this->P(q)[0] - pv[0];
    const double dv = this->P(q)[1] - pv[1];
    const double d = std::sqrt(du * du + dv * dv);
    for (int c = 0; c < this->NC; ++c)
    {
      bounds[c] = std::max(bounds[c], std::abs(this->Value(q, c) - this->Value(v, c)) / d);
    }
  }
  for (double& b : bounds)
  {
    b *= SecantFactor;
  }
}

// Scale each channel's gradient (the first two of its `stride` coefficients
// in `fit`) down to its bound.
void Reconstruction::Internals::LimitGradient(
  const std::vector<double>& bounds, double* fit, int stride)
{
  for (int c = 0; c < this->NC; ++c)
  {
    double* g = fit + static_cast<std::size_t>(c) * stride;
    const double norm = std::hypot(g[0], g[1]);
    if (norm > bounds[c])
    {
      const double scale = norm > 0.0 ? bounds[c] / norm : 0.0;
      g[0] *= scale;
      g[1] *= scale;
      ++this->Statistics.LimitedGradients;
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::FitGradients()
{
  const int ns = static_cast<int>(this->SectorPoint.size());
  const int nc = this->NC;
  this->SectorFit.assign(static_cast<std::size_t>(ns) * 5 * nc, 0.0);
  this->SectorModel.assign(static_cast<std::size_t>(ns) * 9 * nc, 0.0);
  FitWorkspace w;
  std::vector<double> bounds(nc);
  w.PointStamp.assign(this->Mesh.GetNumberOfPoints(), 0);
  w.TriangleStamp.assign(this->Mesh.GetNumberOfTriangles(), 0);
  for (int s = 0; s < ns; ++s)
  {
    const int v = this->SectorPoint[s];
    // Gradient: quadratic fit on ring 1, ring 2 when ring 1 is small; the
    // same factor gives the cubic error model when the stencil is large enough.
    this->GatherNeighbours(s, this->Options.MinimumFitPoints, 2, w);
    const bool wantModel = this->Options.ErrorModel || this->Options.CubicGradients;
    const bool cubicHere = wantModel && static_cast<int>(w.Points.size()) >= CubicModelPoints;
    this->FactorFit(v, cubicHere ? 9 : 5, w);
    double* fit = this->SectorFit.data() + static_cast<std::size_t>(s) * 5 * nc;
    if (w.Usable >= 5)
    {
      this->SolveFit(5, w, fit, 5);
      ++this->Statistics.QuadraticFits;
    }
    else if (w.Usable >= 2)
    {
      this->SolveFit(2, w, fit, 5);
      ++this->Statistics.LinearFits;
    }
    else if (w.Rows >= 1)
    {
      this->SolveCollinear(v, w, fit, 5);
      ++this->Statistics.LinearFits;
    }
    else
    {
      ++this->Statistics.ZeroGradients;
    }
    this->SecantBounds(v, w, bounds);
    this->LimitGradient(bounds, fit, 5);
    // Error model: a cubic fit (on rings 2-3 when ring 2 is too small), or
    // the quadratic when the stencil cannot determine a cubic.
    double* model = this->SectorModel.data() + static_cast<std::size_t>(s) * 9 * nc;
    if (!cubicHere && !wantModel)
    {
      w.Usable = 0;
    }
    else if (!cubicHere)
    {
      this->GatherNeighbours(s, CubicModelPoints, 3, w);
      if (static_cast<int>(w.Points.size()) >= CubicModelPoints)
      {
        this->FactorFit(v, 9, w);
      }
      else
      {
        w.Usable = 0;
      }
    }
    if (w.Usable == 9)
    {
      this->SolveFit(9, w, model, 9);
      this->LimitGradient(bounds, model, 9);
      ++this->Statistics.CubicModels;
    }
    else
    {
      for (int c = 0; c < nc; ++c)
      {
        std::copy(fit + 5 * c, fit + 5 * c + 5, model + 9 * c);
      }
    }
  }

  // The interpolant's gradients (the cubic model's, when asked, starts with
  // the gradient; it is the quadratic fit where no cubic was possible).
  this->SectorGradient.assign(static_cast<std::size_t>(ns) * 2 * nc, 0.0);
  const bool cubic = this->Options.CubicGradients;
  for (std::size_t i = 0; i < static_cast<std::size_t>(ns) * nc; ++i)
  {
    const double* g = cubic ? this->SectorModel.data() + 9 * i : this->SectorFit.data() + 5 * i;
    this->SectorGradient[2 * i] = g[0];
    this->SectorGradient[2 * i + 1] = g[1];
  }
}

} // namespace penumbra
