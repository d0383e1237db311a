// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraPointLocation.h
 * @brief Barycentric helpers of the reconstruction's point location.
 * Private to Penumbra::Reconstruction.
 *
 * The location grid and the barycentric coordinates of a triangle are
 * Reconstruction::Internals members (penumbraPointLocation.cxx).
 */
#ifndef penumbraPointLocation_h
#define penumbraPointLocation_h

namespace penumbra
{
namespace detail
{

/// Barycentric tolerance of point location.
constexpr double InsideTolerance = 1e-9;

/// Clamp barycentrics to the triangle and renormalise (NaN counts as 0; a
/// degenerate input gives the centroid).
void ClampBarycentric(const double in[3], double b[3]);

} // namespace detail
} // namespace penumbra

#endif
