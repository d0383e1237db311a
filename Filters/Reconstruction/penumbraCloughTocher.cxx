// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCloughTocher.cxx
 * @brief The Clough-Tocher element: incentre split of each triangle, control nets
 * from corner values and sector gradients, evaluation by de Casteljau.
 */
#include "penumbraElementIntegral.h"
#include "penumbraReconstructionInternals.h"
#include "penumbraPointLocation.h"
#include "penumbraSampleMeshTopology.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

using detail::ClampBarycentric;
using detail::Net;
using detail::Next;
using detail::Prev;
using detail::TriangleGeometry;

namespace
{

// Micro-triangle and its barycentrics (x, y, z) w.r.t. (corner k+1, corner
// k+2, split point) for macro barycentrics b (non-negative, summing to 1).
inline int MicroCoordinates(const TriangleGeometry& geo, const double b[3], double& x, double& y,
  double& z)
{
  int k = 0;
  double best = b[0] / geo.Sigma[0];
  for (int i = 1; i < 3; ++i)
  {
    const double r = b[i] / geo.Sigma[i];
    if (r < best)
    {
      best = r;
      k = i;
    }
  }
  z = best;
  x = std::max(0.0, b[Next(k)] - geo.Sigma[Next(k)] * z);
  y = std::max(0.0, b[Prev(k)] - geo.Sigma[Prev(k)] * z);
  return k;
}

// Value of the cubic on micro-triangle k at (x, y, z); optionally the
// derivatives with respect to x, y and z.
inline double EvaluateMicro(
  const Net& n, int k, double x, double y, double z, double* dx, double* dy, double* dz)
{
  const int P = Next(k);
  const int Q = Prev(k);
  const double b300 = n.F[P], b030 = n.F[Q], b003 = n.Z;
  const double b210 = n.E[P][Q], b120 = n.E[Q][P];
  const double b201 = n.A[P], b021 = n.A[Q];
  const double b111 = n.M[k];
  const double b102 = n.C[P], b012 = n.C[Q];
  if (dx)
  {
    const double xx = x * x, yy = y * y, zz = z * z;
    const double xy = 2.0 * x * y, xz = 2.0 * x * z, yz = 2.0 * y * z;
    *dx = 3.0 * (xx * b300 + xy * b210 + yy * b120 + xz * b201 + yz * b111 + zz * b102);
    *dy = 3.0 * (xx * b210 + xy * b120 + yy * b030 + xz * b111 + yz * b021 + zz * b012);
    *dz = 3.0 * (xx * b201 + xy * b111 + yy * b021 + xz * b102 + yz * b012 + zz * b003);
  }
  // de Casteljau: only non-negative weights, so a non-negative net gives a
  // non-negative value in floating point too.
  const double c200 = x * b300 + y * b210 + z * b201;
  const double c110 = x * b210 + y * b120 + z * b111;
  const double c020 = x * b120 + y * b030 + z * b021;
  const double c101 = x * b201 + y * b111 + z * b102;
  const double c011 = x * b111 + y * b021 + z * b012;
  const double c002 = x * b102 + y * b012 + z * b003;
  const double d100 = x * c200 + y * c110 + z * c101;
  const double d010 = x * c110 + y * c020 + z * c011;
  const double d001 = x * c101 + y * c011 + z * c002;
  return x * d100 + y * d010 + z * d001;
}

} // namespace

//------------------------------------------------------------------------------
void detail::ComputeTriangleGeometry(const double* const p[3], TriangleGeometry& g)
{
  g.Area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
  double len[3];
  for (int i = 0; i < 3; ++i)
  {
    // Edge opposite corner i, from corner i+1 to corner i+2.
    const double* a = p[Next(i)];
    const double* b = p[Prev(i)];
    const double eu = b[0] - a[0];
    const double ev = b[1] - a[1];
    len[i] = std::sqrt(eu * eu + ev * ev); // plane coordinates: no overflow
    g.GradB[i][0] = -ev / g.Area2;
    g.GradB[i][1] = eu / g.Area2;
  }
  const double perimeter = len[0] + len[1] + len[2];
  g.Diameter = std::max({ len[0], len[1], len[2] });
  g.Split[0] = 0.0;
  g.Split[1] = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    // Incentre: barycentrics proportional to the opposite edge lengths.
    g.Sigma[i] = len[i] / perimeter;
    g.Split[0] += g.Sigma[i] * p[i][0];
    g.Split[1] += g.Sigma[i] * p[i][1];
  }
  for (int k = 0; k < 3; ++k)
  {
    // The incircle touches edge k at distance (semi-perimeter - |edge
    // opposite corner k+1|) from corner k+1: always strictly inside.
    const double fromP = 0.5 * perimeter - len[Next(k)];
    g.Tau[k] = std::min(1.0, std::max(0.0, fromP / len[k]));
  }
}

//------------------------------------------------------------------------------
void detail::ComputeNet(const TriangleGeometry& geo, const double* const p[3], const double f[3],
  const double* const g[3], Net& net)
{
  // Gradient increments toward the neighbouring control points.
  double e[3][3];
  double a[3];
  for (int i = 0; i < 3; ++i)
  {
    net.F[i] = f[i];
    for (int j = 0; j < 3; ++j)
    {
      if (j != i)
      {
        e[i][j] = (g[i][0] * (p[j][0] - p[i][0]) + g[i][1] * (p[j][1] - p[i][1])) / 3.0;
        net.E[i][j] = net.F[i] + e[i][j];
      }
    }
    a[i] = (g[i][0] * (geo.Split[0] - p[i][0]) + g[i][1] * (geo.Split[1] - p[i][1])) / 3.0;
    net.A[i] = net.F[i] + a[i];
    net.E[i][i] = 0.0;
  }
  for (int k = 0; k < 3; ++k)
  {
    // Derivative along the normal of edge k linear along the edge; written
    // as a convex combination of the end values plus gradient terms, so that
    // zero gradients give a non-negative point exactly.
    const int P = Next(k);
    const int Q = Prev(k);
    const double tau = geo.Tau[k];
    net.M[k] = (1.0 - tau) * net.F[P] + tau * net.F[Q] +
      0.5 * (a[P] + a[Q] + (2.0 - 3.0 * tau) * e[P][Q] + (3.0 * tau - 1.0) * e[Q][P]);
  }
  // C1 across the three inner edges.
  for (int i = 0; i < 3; ++i)
  {
    net.C[i] = geo.Sigma[i] * net.A[i] + geo.Sigma[Next(i)] * net.M[Prev(i)] +
      geo.Sigma[Prev(i)] * net.M[Next(i)];
  }
  net.Z = geo.Sigma[0] * net.C[0] + geo.Sigma[1] * net.C[1] + geo.Sigma[2] * net.C[2];
}

//------------------------------------------------------------------------------
double detail::NetIntegral(const TriangleGeometry& geo, const Net& n)
{
  // Micro-triangle k (corners k+1, k+2 and the split point) has Sigma[k] of
  // the area; a cubic Bezier triangle integrates to its area times the mean
  // of its 10 control points.
  double sum = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const int P = Next(k);
    const int Q = Prev(k);
    const double points = n.F[P] + n.F[Q] + n.Z + n.E[P][Q] + n.E[Q][P] + n.A[P] + n.A[Q] +
      n.M[k] + n.C[P] + n.C[Q];
    sum += geo.Sigma[k] * points / 10.0;
  }
  return 0.5 * std::abs(geo.Area2) * sum;
}

//------------------------------------------------------------------------------
void CloughTocherIntegralWeights(
  const double corners[3][2], double valueWeights[3], double gradientWeights[3][2])
{
  const double* const p[3] = { corners[0], corners[1], corners[2] };
  TriangleGeometry geo;
  detail::ComputeTriangleGeometry(p, geo);
  // The integral is linear in the corner values and gradients: take it for
  // each unit input.
  const double zero[2] = { 0.0, 0.0 };
  for (int i = 0; i < 3; ++i)
  {
    double f[3] = { 0.0, 0.0, 0.0 };
    f[i] = 1.0;
    const double* const g[3] = { zero, zero, zero };
    Net net;
    detail::ComputeNet(geo, p, f, g, net);
    valueWeights[i] = detail::NetIntegral(geo, net);
    for (int d = 0; d < 2; ++d)
    {
      const double f0[3] = { 0.0, 0.0, 0.0 };
      double unit[2] = { 0.0, 0.0 };
      unit[d] = 1.0;
      const double* gi[3] = { zero, zero, zero };
      gi[i] = unit;
      detail::ComputeNet(geo, p, f0, gi, net);
      gradientWeights[i][d] = detail::NetIntegral(geo, net);
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeGeometry()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  this->Geometry.resize(nt);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    const double* const p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
    detail::ComputeTriangleGeometry(p, this->Geometry[t]);
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeNet(int t, int channel, Net& net) const
{
  const int* tri = this->T(t);
  const double* const p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
  double f[3];
  const double* g[3];
  for (int i = 0; i < 3; ++i)
  {
    f[i] = this->Value(tri[i], channel);
    g[i] = this->SectorGradient.data() +
      (static_cast<std::size_t>(this->CornerSector[3 * t + i]) * this->NC + channel) * 2;
  }
  detail::ComputeNet(this->Geometry[t], p, f, g, net);
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeZeroGradientNet(int t, int channel, Net& net) const
{
  const TriangleGeometry& geo = this->Geometry[t];
  const int* tri = this->T(t);
  for (int i = 0; i < 3; ++i)
  {
    net.F[i] = this->Value(tri[i], channel);
  }
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      net.E[i][j] = j != i ? net.F[i] : 0.0;
    }
    net.A[i] = net.F[i];
  }
  for (int k = 0; k < 3; ++k)
  {
    net.M[k] = (1.0 - geo.Tau[k]) * net.F[Next(k)] + geo.Tau[k] * net.F[Prev(k)];
  }
  for (int i = 0; i < 3; ++i)
  {
    net.C[i] = geo.Sigma[i] * net.A[i] + geo.Sigma[Next(i)] * net.M[Prev(i)] +
      geo.Sigma[Prev(i)] * net.M[Next(i)];
  }
  net.Z = geo.Sigma[0] * net.C[0] + geo.Sigma[1] * net.C[1] + geo.Sigma[2] * net.C[2];
}

//------------------------------------------------------------------------------
void detail::NetPoints(const Net& n, double out[19])
{
  out[0] = n.F[0];
  out[1] = n.F[1];
  out[2] = n.F[2];
  out[3] = n.E[0][1];
  out[4] = n.E[0][2];
  out[5] = n.E[1][0];
  out[6] = n.E[1][2];
  out[7] = n.E[2][0];
  out[8] = n.E[2][1];
  out[9] = n.A[0];
  out[10] = n.A[1];
  out[11] = n.A[2];
  out[12] = n.M[0];
  out[13] = n.M[1];
  out[14] = n.M[2];
  out[15] = n.C[0];
  out[16] = n.C[1];
  out[17] = n.C[2];
  out[18] = n.Z;
}

void Reconstruction::Internals::Evaluate(
  int t, const double bIn[3], double* value, double* gradient) const
{
  if (this->Options.Mode == ReconstructionMode::Linear)
  {
    this->EvaluateWithNets(t, nullptr, bIn, value, gradient);
    return;
  }
  Net nets[8] = {};
  std::vector<Net> many;
  Net* use = nets;
  if (this->NC > 8)
  {
    many.resize(this->NC);
    use = many.data();
  }
  for (int c = 0; c < this->NC; ++c)
  {
    this->ComputeNet(t, c, use[c]);
  }
  this->EvaluateWithNets(t, use, bIn, value, gradient);
}

//------------------------------------------------------------------------------
// Evaluate with nets already computed (one per channel; null in Linear mode).
void Reconstruction::Internals::EvaluateWithNets(
  int t, const Net* nets, const double bIn[3], double* value, double* gradient) const
{
  const Internals& in = *this;
  double b[3];
  ClampBarycentric(bIn, b);
  const int nc = in.NC;
  const int* tri = in.T(t);
  const TriangleGeometry& geo = in.Geometry[t];
  if (in.Options.Mode == ReconstructionMode::Linear || nets == nullptr)
  {
    for (int c = 0; c < nc; ++c)
    {
      const double f0 = in.Value(tri[0], c);
      const double f1 = in.Value(tri[1], c);
      const double f2 = in.Value(tri[2], c);
      value[c] = b[0] * f0 + b[1] * f1 + b[2] * f2;
      if (gradient)
      {
        gradient[2 * c] = f0 * geo.GradB[0][0] + f1 * geo.GradB[1][0] + f2 * geo.GradB[2][0];
        gradient[2 * c + 1] = f0 * geo.GradB[0][1] + f1 * geo.GradB[1][1] + f2 * geo.GradB[2][1];
      }
    }
    return;
  }
  double x, y, z;
  const int k = MicroCoordinates(geo, b, x, y, z);
  double gz[2] = { 0.0, 0.0 }, gx[2] = { 0.0, 0.0 }, gy[2] = { 0.0, 0.0 };
  if (gradient)
  {
    const int P = Next(k);
    const int Q = Prev(k);
    for (int d = 0; d < 2; ++d)
    {
      gz[d] = geo.GradB[k][d] / geo.Sigma[k];
      gx[d] = geo.GradB[P][d] - geo.Sigma[P] * gz[d];
      gy[d] = geo.GradB[Q][d] - geo.Sigma[Q] * gz[d];
    }
  }
  for (int c = 0; c < nc; ++c)
  {
    if (gradient)
    {
      double dx, dy, dz;
      value[c] = EvaluateMicro(nets[c], k, x, y, z, &dx, &dy, &dz);
      gradient[2 * c] = dx * gx[0] + dy * gy[0] + dz * gz[0];
      gradient[2 * c + 1] = dx * gx[1] + dy * gy[1] + dz * gz[1];
    }
    else
    {
      value[c] = EvaluateMicro(nets[c], k, x, y, z, nullptr, nullptr, nullptr);
    }
    if (!in.NetSlack.empty())
    {
      // The repair leaves nets up to a rounding slack below the samples'
      // minimum (or 0): clamp that, and only that.
      const double lowest = std::min(
        { 0.0, in.Value(tri[0], c), in.Value(tri[1], c), in.Value(tri[2], c) });
      if (value[c] < lowest &&
        value[c] >= lowest - in.NetSlack[static_cast<std::size_t>(t) * nc + c])
      {
        value[c] = lowest;
      }
    }
  }
}

} // namespace penumbra
