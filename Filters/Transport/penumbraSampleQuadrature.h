// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSampleQuadrature.h
 * @brief The quadrature by which the progressive shooter integrates a
 * function given at the samples of a surface (private): one weight per
 * sample, exact for quadratics (Documentation/design/transport.md,
 * "Energy").
 */
#ifndef penumbraSampleQuadrature_h
#define penumbraSampleQuadrature_h

#include "penumbraSurfaceSamples.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

/**
 * Weights w such that sum_k w_k f(x_k) integrates f over the triangles of
 * `samples` (of areas `areas`, in the plane with in-plane axes `u`, `v`).
 * Each triangle contributes A (mean of its corner values + 1/8 sum_i g_i .
 * (c - x_i)), c its centroid and g_i the gradient at corner i of a weighted
 * least-squares quadratic through the corner's value and its ring-1
 * neighbours (ring 2 when ring 1 has too few points): exact for quadratics,
 * where the linear interpolant's integral misses the curvature term
 * (concave light loses about 0.1% per bounce on meshes fine enough for
 * direct light). A corner whose neighbours cannot determine a quadratic
 * falls back to a linear fit, and to the linear interpolant's weight (no
 * gradient) when they cannot determine a plane. Points used by no triangle
 * weigh 0. The weights sum to the area. With samples.LinearPower they are
 * the linear interpolant's (a third of each triangle's area per corner).
 */
std::vector<double> ComputeQuadratureWeights(
  const SurfaceSamples& samples, const std::vector<double>& areas, const Vec3& u, const Vec3& v);

/// sum_k weights[k] * values[k], per channel.
RGB Integrate(const std::vector<double>& weights, const std::vector<RGB>& values);

} // namespace penumbra

#endif
