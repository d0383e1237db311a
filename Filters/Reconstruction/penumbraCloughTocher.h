// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCloughTocher.h
 * @brief The Clough-Tocher element of the reconstruction: per-triangle
 * geometry (incentre split) and the cubic Bezier control net of one
 * triangle and channel. Private to Penumbra::Reconstruction.
 *
 * The nets are computed and evaluated by Reconstruction::Internals
 * (penumbraCloughTocher.cxx).
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraCloughTocher_h
#define penumbraCloughTocher_h

namespace penumbra
{
namespace detail
{

/// Per-triangle geometry of the Clough-Tocher element.
struct TriangleGeometry
{
  double Sigma[3];    ///< incentre barycentrics
  double Tau[3];      ///< edge k (corner k+1 -> k+2): foot of the incentre, parameter from k+1
  double Split[2];    ///< incentre position
  double GradB[3][2]; ///< gradients of the barycentric coordinates
  double Area2;       ///< twice the signed area
  double Diameter;    ///< longest edge
};

/// Control net of one triangle for one channel: 19 distinct control points.
struct Net
{
  double F[3];    ///< corner values
  double E[3][3]; ///< E[i][j]: edge point next to corner i on edge i-j
  double A[3];    ///< inner point next to corner i toward the split point
  double M[3];    ///< middle point of micro-triangle k (edge opposite corner k)
  double C[3];    ///< point next to the split point toward corner i
  double Z;       ///< split point
};

/// The 19 control points of a net, in a fixed order.
void NetPoints(const Net& n, double out[19]);

/// The element's geometry for the triangle of 2D corners p.
void ComputeTriangleGeometry(const double* const p[3], TriangleGeometry& geo);

/// The net of the triangle of corners p for corner values f and corner
/// gradients g (d/du, d/dv each).
void ComputeNet(const TriangleGeometry& geo, const double* const p[3], const double f[3],
  const double* const g[3], Net& net);

/// Integral of the element over its triangle.
double NetIntegral(const TriangleGeometry& geo, const Net& net);

} // namespace detail
} // namespace penumbra

#endif
