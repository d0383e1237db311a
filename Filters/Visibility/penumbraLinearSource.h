// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraLinearSource.h
 * @brief Exact irradiance from planar polygons whose radiance varies linearly
 * over them, and from non-uniform (piecewise-linear) shooters through their
 * visible region.
 *
 * The problem is the one Chen and Arvo solved in closed form ("A closed-form
 * solution for the irradiance due to linearly-varying luminaires", EGRW 2000);
 * the formula used here is derived independently, by Green's theorem in the
 * source plane, and also needs exactly one non-elementary function, Clausen's
 * integral.
 *
 * Derivation. Put x at the origin; let the source plane have front normal m,
 * let w = -m, h = w.(y - x) > 0 the distance from x to the plane and p0 the
 * foot of the perpendicular; write points of the plane as y = p0 + q. The
 * irradiance kernel is k(y) = cos(theta_x) cos(theta_y) / r^2
 * = (n.y) h / (h^2 + |q|^2)^2, with n.y = (n.w) h + a.q (a: in-plane part of
 * n). For a linear radiance L(y) = L(p0) + g.q,
 *
 *   E = L(p0) pi F + g.K1,  K1 = integral of q k(y) dA  (first moment),
 *
 * where F is Lambert's form factor. K1 splits into h^2 (n.w) J1 + h J2 with
 * J1 = int q / (h^2+|q|^2)^2 and J2 = int q (a.q) / (h^2+|q|^2)^2. Both are
 * divergences plus one remainder: with f = -1/(2 (h^2+|q|^2)) and S a
 * symmetric 2x2 matrix, div(S q f) = tr(S) f + q^T S q / (h^2+|q|^2)^2 and
 * div(g / (h^2+|q|^2)) = -2 g.q / (h^2+|q|^2)^2. So every term is a sum of
 * edge integrals of rational functions of the edge parameter t (an arctangent
 * K0 = int dt / (c^2 + t^2) and a logarithm K1 = int t dt / (c^2 + t^2), with
 * c^2 = h^2 + d^2, d the edge line's distance from p0), plus
 *
 *   I = int_P dA / (h^2 + |q|^2)  (the integral of 1/r^2 over the polygon),
 *
 * which, summed edge by edge in polar coordinates about p0 (signed angles), is
 * (1/2) sign(d) int ln(1 + k sec^2 psi) dpsi with k = d^2/h^2 and psi the
 * angle from the edge's perpendicular. Writing cos^2 psi + k as
 * |1 + beta e^{2 i psi}|^2 / (4 beta), beta = h^2 / (c + |d|)^2 < 1,
 *
 *   int_0^Psi ln(1 + k sec^2 psi) dpsi = -Psi ln(beta) + Phi(beta, 2 Psi),
 *   Phi(beta, T) = Cl2(T + pi) - Im Li2(beta e^{i (T + pi)}),
 *
 * and Im Li2(r e^{i t}) = omega ln r + (Cl2(2t) + Cl2(2 omega)
 * - Cl2(2t + 2 omega)) / 2, omega = atan2(r sin t, 1 - r cos t) (Lewin,
 * "Polylogarithms and associated functions", 1981, eq. 5.23): only Cl2 is
 * needed. Clausen2 evaluates it from its series about 0 in Bernoulli numbers
 * (written with zeta(2k)), to about 1e-16 absolute.
 *
 * The result is written E = pi F L(C), with C = x + (first moment) / (pi F)
 * the kernel-weighted centroid, which lies in the polygon's convex hull, so
 * that L is never extrapolated.
 *
 * Accuracy. Each edge term is computed to a few ulps of its own magnitude.
 * The sum loses digits by cancellation when the polygon is small and far (the
 * edge terms are O(1) while the sum is of the order of the solid angle, and
 * the moment about p0 nearly cancels (C - p0) pi F): about 1e-16 times
 * (distance / size)^2 relative; Lambert's formula for F has the same loss
 * (3e-10 at 10^4 sizes). So when the polygon's radius is below 0.15 of its
 * distance from x, F and C are computed instead by a degree-14
 * Gauss-Legendre rule (8 x 8, Duffy map, per fan triangle; below 0.02, the
 * degree-7 rule 4 x 4) in coordinates centred on the polygon: the kernel is
 * analytic within about distance / sqrt(2) of the polygon, and against
 * adaptive quadrature these rules err by 1e-13 relative at most,
 * at a fraction of the closed form's cost. Otherwise F is Lambert's formula (PointPolygonFormFactorSigned),
 * so that a constant radiance gives pi L F exactly. Remaining loss: when x is
 * close to the source plane but outside the polygon's footprint, the edge
 * terms (Lambert's included) are O(1) while F is O(h / size): the relative
 * error grows as h shrinks (6e-11 measured at h = 1e-3 of the size; the
 * absolute error stays at rounding level). Elsewhere the tests (against
 * adaptive quadrature) measure 1e-15 to 5e-14.
 */
#ifndef penumbraLinearSource_h
#define penumbraLinearSource_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraExactEvaluator.h"
#include "penumbraShooterRadiance.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

/**
 * Clausen's integral Cl2(theta) = -int_0^theta ln|2 sin(t/2)| dt
 * = sum_k sin(k theta) / k^2, for any finite theta (odd, 2 pi periodic).
 * Absolute error about 1e-16 (maximum value 1.0149416 at pi/3).
 */
PENUMBRAVISIBILITY_EXPORT double Clausen2(double theta);

/**
 * Zeroth and first moments of the irradiance kernel
 * k(y) = cos(theta_x) cos(theta_y) / r^2 over a polygon, as the form factor
 * F = (1/pi) int k dA and the kernel-weighted centroid
 * C = int y k dA / int k dA (a point of the polygon's plane, inside its convex
 * hull). For a radiance L linear over the polygon the irradiance at x is
 * exactly E = pi F L(C): one geometric computation serves every channel and
 * every linear function. F is Lambert's PointPolygonFormFactor unless the
 * polygon is small and far (see the file comment).
 */
struct IrradianceMoments
{
  /// Lambert's point-to-polygon form factor, in [0, 1].
  double FormFactor = 0.0;
  /// Kernel-weighted centroid (the vertex mean when FormFactor is 0).
  Vec3 Centroid;
};

/**
 * Exact moments of the polygon `vertices` (planar, simple, convex or not; in
 * either orientation) whose emitting side faces along the unit vector
 * `frontNormal`, seen from the differential area at x with unit normal n.
 * The polygon is clipped to x's front half-space Dot(n, y - x) >= 0 first.
 * Zero when x is not strictly in front of the polygon's plane. No heap
 * allocation for polygons of up to 64 vertices.
 */
PENUMBRAVISIBILITY_EXPORT IrradianceMoments ComputeIrradianceMoments(
  const Vec3& x, const Vec3& n, const Vec3* vertices, int count, const Vec3& frontNormal);

/**
 * Exact irradiance (W m^-2 per channel) at x (unit normal n) from the polygon
 * `vertices` (as in ComputeIrradianceMoments) emitting the linear radiance
 * `radiance` from its side `frontNormal`. With a constant radiance L it is
 * pi L PointPolygonFormFactorClipped(...) up to rounding.
 */
PENUMBRAVISIBILITY_EXPORT RGB LinearPolygonIrradiance(const Vec3& x, const Vec3& n,
  const Vec3* vertices, int count, const Vec3& frontNormal, const LinearRadiance& radiance);

/**
 * Exact irradiance at x (unit normal n) from a triangle whose radiance is
 * `values` at `points` and linear in between, emitting from its side
 * `frontNormal`.
 */
PENUMBRAVISIBILITY_EXPORT RGB LinearTriangleIrradiance(const Vec3& x, const Vec3& n,
  const Vec3 points[3], const RGB values[3], const Vec3& frontNormal);

/// Scratch memory of the shooter-level functions below: one per thread.
struct LinearSourceWorkspace
{
  std::vector<Vec3> Clip0;     ///< clipping buffers
  std::vector<Vec3> Clip1;
  std::vector<int> Triangles;  ///< candidate mesh triangles
  VisibleRegion Region;        ///< visible region of the current query
  VisibilityWorkspace Visibility; ///< scratch of the exact visibility code
};

/**
 * Exact irradiance at x (unit normal n) from a shooter emitting `radiance`
 * from its side `shooterNormal`, through the visible region `region`
 * (convex pieces in the shooter's plane, as computed by the exact visibility
 * code; pieces are clipped to x's front half-space again here). A constant
 * radiance L gives pi L times the sum of the pieces' form factors; a mesh
 * gives the sum, over mesh triangles and pieces, of the linear-source
 * irradiance of (triangle intersected with piece) with the triangle's linear
 * function. Thread-safe with one workspace per thread.
 */
PENUMBRAVISIBILITY_EXPORT RGB VisibleShooterIrradiance(const Vec3& x, const Vec3& n,
  const ShooterRadiance& radiance, const VisibleRegion& region, const Vec3& shooterNormal,
  LinearSourceWorkspace& workspace);

/**
 * Exact irradiance at x (unit normal n) from an unoccluded shooter polygon
 * `shooter` (simple, counter-clockwise seen from its emitting side) emitting
 * `radiance`. For a mesh the shooter is clipped to each triangle, so a mesh
 * larger than the shooter is cut to it.
 */
PENUMBRAVISIBILITY_EXPORT RGB UnoccludedShooterIrradiance(const Vec3& x, const Vec3& n,
  const ShooterRadiance& radiance, const std::vector<Vec3>& shooter,
  LinearSourceWorkspace& workspace);

/**
 * Exact irradiance at x (on receiver `receiverId`, or -1; unit normal n) from
 * shooter `shooterId` of the evaluator's scene emitting `radiance` (NOT the
 * scene's Emission), with exact visibility: the evaluator's visible region,
 * then VisibleShooterIrradiance. The contributed radiance is
 * rho_receiver / pi times this. Thread-safe with one workspace per thread.
 */
PENUMBRAVISIBILITY_EXPORT RGB ExactShooterIrradiance(const ExactEvaluator& evaluator, const Vec3& x,
  const Vec3& n, int receiverId, int shooterId, const ShooterRadiance& radiance,
  LinearSourceWorkspace& workspace);

} // namespace penumbra

#endif
