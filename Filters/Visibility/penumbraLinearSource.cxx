// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraLinearSource.h"

#include "penumbraFormFactor.h"
#include "penumbraMath.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

constexpr int ClausenTerms = 26;

/// zeta(2k): closed forms for k <= 4, a direct sum (tail below 1e-17) beyond.
double Zeta2k(int k)
{
  switch (k)
  {
    case 1:
      return Pi * Pi / 6.0;
    case 2:
      return std::pow(Pi, 4) / 90.0;
    case 3:
      return std::pow(Pi, 6) / 945.0;
    case 4:
      return std::pow(Pi, 8) / 9450.0;
    default:
      break;
  }
  double sum = 0.0;
  for (int i = 60; i >= 1; --i) // smallest terms first
  {
    sum += std::pow(static_cast<double>(i), -2.0 * k);
  }
  return sum;
}

/**
 * Coefficients c_k = |B_2k| / (2k (2k+1)!) = zeta(2k) / (k (2k+1) (2 pi)^2k)
 * of Cl2(t) = t - t ln t + sum_k c_k t^(2k+1), |t| < 2 pi. At t = pi the
 * terms fall like 4^-k / k^2: 26 terms reach 1e-18.
 */
struct ClausenTable
{
  double C[ClausenTerms + 1];
  ClausenTable()
  {
    C[0] = 0.0;
    for (int k = 1; k <= ClausenTerms; ++k)
    {
      C[k] = Zeta2k(k) / (k * (2.0 * k + 1.0) * std::pow(2.0 * Pi, 2.0 * k));
    }
  }
};

/// Gauss-Legendre nodes and weights on [0, 1] (N points), by Newton on P_N.
template <int N>
struct GaussLegendre
{
  double X[N];
  double W[N];
  GaussLegendre()
  {
    for (int i = 0; i < N; ++i)
    {
      double z = std::cos(Pi * (i + 0.75) / (N + 0.5));
      double dp = 1.0;
      for (int it = 0; it < 100; ++it)
      {
        double p0 = 1.0;
        double p1 = z;
        for (int k = 2; k <= N; ++k)
        {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = N * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16)
        {
          break;
        }
      }
      this->X[i] = 0.5 * (1.0 - z);
      this->W[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

/**
 * Ratio radius / distance below which a polygon counts as small and far and
 * its moments are computed by the degree-14 rule below. The kernel is then
 * analytic in a complex neighbourhood of radius about distance / sqrt(2)
 * around the polygon; measured against adaptive quadrature and Lambert's
 * formula, the rule errs by 1e-13 relative at most up to 0.15 (a clipped
 * quadrilateral at 0.2 by 3e-13), as the closed form does, at a fraction
 * of its cost (no Clausen functions).
 */
constexpr double FarRatio = 0.15;
/**
 * Below this ratio the degree-7 rule (4 x 4) is as accurate, at a quarter
 * of the cost: measured 1e-14 relative at 0.011, 2e-13 at 0.02 (1e-12 at
 * 0.028). Small triangles of a shooter's mesh seen from across a room are
 * most of an exact secondary shot's pairs.
 */
constexpr double VeryFarRatio = 0.02;

/**
 * Moments of a small, far polygon by an N x N Gauss-Legendre rule on each
 * fan triangle (Duffy map, exact for degree 2N - 2), in coordinates relative
 * to `centre` so that no digit is lost to the distance. Fan triangles carry
 * their signed area (about m): a concave polygon is integrated exactly, and
 * the result does not depend on the polygon's orientation.
 */
template <int N>
IrradianceMoments FarMoments(const Vec3& x, const Vec3& n, const Vec3* v, int count,
  const Vec3& m, const Vec3& centre)
{
  static const GaussLegendre<N> rule;
  const Vec3 offset = centre - x; // y - x = offset + local
  double k0 = 0.0;
  Vec3 k1;
  const Vec3 a = v[0] - centre;
  for (int i = 1; i + 1 < count; ++i)
  {
    const Vec3 b = v[i] - centre;
    const Vec3 c = v[i + 1] - centre;
    const double area2 = Dot(Cross(b - a, c - a), m); // signed, twice the area
    for (int p = 0; p < N; ++p)
    {
      const double s = rule.X[p];
      for (int q = 0; q < N; ++q)
      {
        const double t = rule.X[q] * (1.0 - s);
        const double weight = rule.W[p] * rule.W[q] * (1.0 - s) * area2;
        const Vec3 local = a + (b - a) * s + (c - a) * t;
        const Vec3 r = offset + local;
        const double r2 = SquaredLength(r);
        const double kernel = weight * Dot(n, r) * -Dot(m, r) / (r2 * r2);
        k0 += kernel;
        k1 += local * kernel;
      }
    }
  }
  IrradianceMoments result;
  result.Centroid = k0 != 0.0 ? centre + k1 / k0 : centre;
  result.FormFactor = std::max(0.0, std::abs(k0) / Pi);
  return result;
}

/// Im Li2(r e^{i t}) for 0 <= r < 1 given ln r (Lewin's reduction to Cl2).
double ImDilog(double r, double logR, double t)
{
  if (!(r > 0.0))
  {
    return 0.0;
  }
  const double omega = std::atan2(r * std::sin(t), 1.0 - r * std::cos(t));
  return omega * logR + 0.5 * (Clausen2(2.0 * t) + Clausen2(2.0 * omega) - Clausen2(2.0 * (t + omega)));
}

/// Phi(beta, T) = sum_n (-1)^(n+1) (beta^n - 1) sin(n T) / n^2, via Cl2 and Im Li2.
double Phi(double beta, double logBeta, double angle)
{
  const double t = angle + Pi;
  return Clausen2(t) - ImDilog(beta, logBeta, t);
}

/**
 * int over the edge parameter t in [tA, tB] of ln((c^2 + t^2) / h^2) |d| / (d^2 + t^2) dt
 * = int_{psiA}^{psiB} ln(1 + (d/h)^2 sec^2 psi) dpsi, psi = atan(t / |d|), |d| > 0.
 */
double EdgeLogIntegral(double h, double absD, double c, double tA, double tB)
{
  const double psiA = std::atan2(tA, absD);
  const double psiB = std::atan2(tB, absD);
  const double ratio = h / (c + absD);
  const double logBeta = 2.0 * std::log(ratio);
  const double beta = ratio * ratio;
  return -(psiB - psiA) * logBeta + Phi(beta, logBeta, 2.0 * psiB) -
    Phi(beta, logBeta, 2.0 * psiA);
}

/**
 * Moments of an oriented polygon (counter-clockwise about m up to the sign
 * `orientation`) lying in front of x's tangent plane. See the header for the
 * derivation; R_i = v_i - x throughout.
 */
IrradianceMoments OrientedMoments(
  const Vec3& x, const Vec3& n, const Vec3* v, int count, const Vec3& m, double orientation)
{
  IrradianceMoments result;
  const Vec3 w = -m; // from x towards the plane
  double h = 0.0;
  Vec3 centre;
  for (int i = 0; i < count; ++i)
  {
    h += Dot(w, v[i] - x);
    centre += v[i];
  }
  h /= count;
  centre = centre / count;
  result.Centroid = centre;
  if (!(h > 0.0))
  {
    return result; // x on or behind the emitting side
  }
  double radius2 = 0.0;
  for (int i = 0; i < count; ++i)
  {
    radius2 = std::max(radius2, SquaredLength(v[i] - centre));
  }
  const double distance2 = SquaredLength(centre - x);
  if (radius2 <= VeryFarRatio * VeryFarRatio * distance2)
  {
    return FarMoments<4>(x, n, v, count, m, centre);
  }
  if (radius2 <= FarRatio * FarRatio * distance2)
  {
    return FarMoments<8>(x, n, v, count, m, centre);
  }
  // Lambert's formula for F, so that a constant radiance gives exactly
  // pi L PointPolygonFormFactor.
  const double formFactor = orientation * PointPolygonFormFactorSigned(x, n, v, count);
  if (!(formFactor > 0.0))
  {
    return result;
  }
  const double nw = Dot(n, w);
  const Vec3 a = n - w * nw; // in-plane part of n
  Vec3 j1;
  Vec3 j2;
  double logArea = 0.0; // int dA / (h^2 + |q|^2)
  Vec3 rA = v[count - 1] - x;
  for (int i = 0; i < count; ++i)
  {
    const Vec3 rB = v[i] - x;
    Vec3 e = rB - rA;
    e -= w * Dot(e, w);
    const double length = Length(e);
    if (length > 0.0)
    {
      const Vec3 tau = e / length;
      const Vec3 nu = Cross(tau, m); // outward for a counter-clockwise polygon
      const double d = 0.5 * (Dot(nu, rA) + Dot(nu, rB));
      const double tA = Dot(tau, rA);
      const double tB = Dot(tau, rB);
      const double c2 = h * h + d * d;
      const double c = std::sqrt(c2);
      // K0 = int dt / (c^2 + t^2) as one atan2 (no cancellation), K1 = int t dt / (c^2 + t^2).
      const double k0 = std::atan2(c * (tB - tA), c2 + tA * tB) / c;
      const double k1 = 0.5 * std::log1p((tB - tA) * (tB + tA) / (c2 + tA * tA));
      const double an = Dot(a, nu);
      const double at = Dot(a, tau);
      j1 += nu * (-0.5 * k0);
      j2 += nu * (-0.5 * (d * an * k0 + 0.5 * k1 * at)) + tau * (-0.25 * k1 * an);
      if (d != 0.0)
      {
        const double integral = EdgeLogIntegral(h, std::abs(d), c, tA, tB);
        logArea += (d > 0.0 ? 0.5 : -0.5) * integral;
      }
    }
    rA = rB;
  }
  // First moment about the foot p0 = x + h w (in-plane), then the centroid.
  const Vec3 firstInPlane = j1 * (h * h * nw) + j2 * h + a * (0.5 * h * logArea);
  result.FormFactor = formFactor;
  const Vec3 centroid = x + w * h + firstInPlane * (orientation / (Pi * formFactor));
  // With x at a vertex within rounding of the plane (a box's corner on the
  // floor), the edge integrals meet 0 / 0; F is then tiny, and the vertex
  // mean stands in for the centroid.
  const bool finite =
    std::isfinite(centroid.X) && std::isfinite(centroid.Y) && std::isfinite(centroid.Z);
  result.Centroid = finite ? centroid : centre;
  return result;
}

/// Sign of the polygon's orientation about m (0 when degenerate).
double Orientation(const Vec3* v, int count, const Vec3& m)
{
  Vec3 newell;
  for (int i = 0; i < count; ++i)
  {
    newell += Cross(v[i], v[(i + 1) % count]);
  }
  const double s = Dot(newell, m);
  return s > 0.0 ? 1.0 : (s < 0.0 ? -1.0 : 0.0);
}

/// Make sure `buffer` can hold `size` points.
void Reserve(std::vector<Vec3>& buffer, std::size_t size)
{
  if (buffer.size() < size)
  {
    buffer.resize(size);
  }
}

/**
 * Clip the polygon (count points) to the inside of the triangle `points`
 * (oriented counter-clockwise about m by `orientation`). Returns the
 * number of points of the result, left in workspace.Clip0 or Clip1 (*out).
 */
int ClipToTriangle(const Vec3* polygon, int count, const Vec3 points[3], const Vec3& m,
  LinearSourceWorkspace& workspace, const Vec3** out)
{
  const Vec3* source = polygon;
  std::vector<Vec3>* buffers[2] = { &workspace.Clip0, &workspace.Clip1 };
  const double orientation = Orientation(points, 3, m);
  for (int k = 0; k < 3 && count > 0; ++k)
  {
    const Vec3& p = points[k];
    const Vec3& q = points[(k + 1) % 3];
    const Vec3 inward = Cross(m, q - p) * orientation;
    std::vector<Vec3>& target = *buffers[k % 2];
    Reserve(target, 2 * static_cast<std::size_t>(count) + 2);
    count = ClipPolygonToHalfSpace(source, count, inward, Dot(inward, p), target.data());
    source = target.data();
  }
  *out = source;
  return count;
}

/// Sum over the candidate mesh triangles of the linear-source irradiance of triangle and polygon.
RGB MeshIrradiance(const Vec3& x, const Vec3& n, const ShooterRadiance& radiance,
  const Vec3* polygon, int count, const Vec3& m, LinearSourceWorkspace& workspace)
{
  RGB sum;
  radiance.FindTriangles(polygon, count, workspace.Triangles);
  for (const int t : workspace.Triangles)
  {
    const RadianceTriangle tri = radiance.GetTriangle(t);
    const Vec3* clipped = nullptr;
    const int m2 = ClipToTriangle(polygon, count, tri.Points, m, workspace, &clipped);
    if (m2 >= 3)
    {
      sum += LinearPolygonIrradiance(x, n, clipped, m2, m, radiance.GetTriangleFunction(t));
    }
  }
  return sum;
}

} // namespace

double Clausen2(double theta)
{
  static const ClausenTable table;
  if (!std::isfinite(theta))
  {
    return theta != theta ? theta : 0.0 * theta; // NaN in, NaN out
  }
  // Reduce to [-pi, pi]. remainder is exact; so is one subtraction of 2 pi
  // for |theta| <= 3 pi (Sterbenz), the common case, at a fraction of the cost.
  const double magnitude = std::abs(theta);
  double t = magnitude <= Pi ? theta
    : (magnitude <= 3.0 * Pi ? theta - std::copysign(2.0 * Pi, theta)
                             : std::remainder(theta, 2.0 * Pi));
  const double sign = t < 0.0 ? -1.0 : 1.0;
  t = std::abs(t);
  if (t == 0.0)
  {
    return 0.0;
  }
  // Term k is below zeta(2k) (t / 2 pi)^(2k) / (2 k^2): no more terms than
  // reach 1e-17 relative for this t (a hot path of every closed form).
  const int terms = t <= 0.25 * Pi ? 10 : (t <= 0.5 * Pi ? 14 : ClausenTerms);
  const double t2 = t * t;
  double series = 0.0;
  for (int k = terms; k >= 1; --k)
  {
    series = (series + table.C[k]) * t2;
  }
  return sign * t * (1.0 - std::log(t) + series);
}

IrradianceMoments ComputeIrradianceMoments(
  const Vec3& x, const Vec3& n, const Vec3* vertices, int count, const Vec3& frontNormal)
{
  if (count < 3)
  {
    return IrradianceMoments();
  }
  const Vec3 m = Normalized(frontNormal);
  const double offset = Dot(n, x);
  bool allFront = true;
  for (int i = 0; i < count && allFront; ++i)
  {
    allFront = Dot(n, vertices[i]) >= offset;
  }
  const Vec3* polygon = vertices;
  Vec3 stackBuffer[128];
  std::vector<Vec3> heapBuffer;
  if (!allFront)
  {
    Vec3* out = stackBuffer;
    if (count > 64)
    {
      heapBuffer.resize(2 * static_cast<std::size_t>(count));
      out = heapBuffer.data();
    }
    count = ClipPolygonToHalfSpace(vertices, count, n, offset, out);
    polygon = out;
    if (count < 3)
    {
      return IrradianceMoments();
    }
  }
  const double orientation = Orientation(polygon, count, m);
  if (orientation == 0.0)
  {
    return IrradianceMoments();
  }
  return OrientedMoments(x, n, polygon, count, m, orientation);
}

RGB LinearPolygonIrradiance(const Vec3& x, const Vec3& n, const Vec3* vertices, int count,
  const Vec3& frontNormal, const LinearRadiance& radiance)
{
  const IrradianceMoments moments = ComputeIrradianceMoments(x, n, vertices, count, frontNormal);
  if (!(moments.FormFactor > 0.0))
  {
    return RGB();
  }
  // E = int L k dA = pi F L(centroid) for a linear L.
  return radiance.Evaluate(moments.Centroid) * (Pi * moments.FormFactor);
}

RGB LinearTriangleIrradiance(const Vec3& x, const Vec3& n, const Vec3 points[3],
  const RGB values[3], const Vec3& frontNormal)
{
  return LinearPolygonIrradiance(
    x, n, points, 3, frontNormal, LinearRadiance::FromTriangle(points, values));
}

RGB VisibleShooterIrradiance(const Vec3& x, const Vec3& n, const ShooterRadiance& radiance,
  const VisibleRegion& region, const Vec3& shooterNormal, LinearSourceWorkspace& workspace)
{
  const int pieces = region.GetNumberOfPieces();
  RGB sum;
  if (radiance.IsConstant())
  {
    double formFactor = 0.0;
    for (int k = 0; k < pieces; ++k)
    {
      const int first = region.Offsets[k];
      formFactor += PointPolygonFormFactorClipped(
        x, n, region.Points.data() + first, region.Offsets[k + 1] - first);
    }
    return radiance.GetConstantValue() * (Pi * formFactor);
  }
  const Vec3 m = Normalized(shooterNormal);
  for (int k = 0; k < pieces; ++k)
  {
    const int first = region.Offsets[k];
    sum += MeshIrradiance(
      x, n, radiance, region.Points.data() + first, region.Offsets[k + 1] - first, m, workspace);
  }
  return sum;
}

RGB UnoccludedShooterIrradiance(const Vec3& x, const Vec3& n, const ShooterRadiance& radiance,
  const std::vector<Vec3>& shooter, LinearSourceWorkspace& workspace)
{
  if (shooter.size() < 3)
  {
    return RGB();
  }
  if (radiance.IsConstant())
  {
    return radiance.GetConstantValue() * (Pi * PointPolygonFormFactorClipped(x, n, shooter));
  }
  Vec3 newell;
  for (std::size_t i = 0; i < shooter.size(); ++i)
  {
    newell += Cross(shooter[i], shooter[(i + 1) % shooter.size()]);
  }
  // A concave shooter clipped by a triangle may keep zero-width bridges; the
  // contour integrals traverse them twice in opposite directions, so they cancel.
  return MeshIrradiance(x, n, radiance, shooter.data(), static_cast<int>(shooter.size()),
    Normalized(newell), workspace);
}

RGB ExactShooterIrradiance(const ExactEvaluator& evaluator, const Vec3& x, const Vec3& n,
  int receiverId, int shooterId, const ShooterRadiance& radiance, LinearSourceWorkspace& workspace)
{
  if (radiance.IsConstant())
  {
    const double f = evaluator.FormFactor(x, n, receiverId, shooterId, workspace.Visibility);
    return radiance.GetConstantValue() * (Pi * f);
  }
  evaluator.FormFactor(x, n, receiverId, shooterId, workspace.Visibility, &workspace.Region);
  const Vec3& normal = evaluator.GetOccluders().GetPolygon(shooterId).Normal;
  return VisibleShooterIrradiance(x, n, radiance, workspace.Region, normal, workspace);
}

} // namespace penumbra
