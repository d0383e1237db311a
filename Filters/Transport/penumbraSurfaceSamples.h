// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSurfaceSamples.h
 * @brief The sample mesh of one surface and its two radiance functions, the
 * unit of data the progressive shooter and the coarse indirect level work
 * on (Documentation/design/transport.md, "Representation").
 */
#ifndef penumbraSurfaceSamples_h
#define penumbraSurfaceSamples_h

#include "penumbraVector.h"

#include <array>
#include <vector>

namespace penumbra
{

/**
 * The sample mesh of one surface and its radiance functions. Points lie in
 * the surface's plane (within 1e-6 of its diameter); triangles index Points
 * (orientation free); Total and Unshot hold one RGB value per point, in
 * W sr^-1 m^-2. The triangles should cover the surface once.
 */
struct SurfaceSamples
{
  std::vector<Vec3> Points;
  std::vector<std::array<int, 3>> Triangles;
  std::vector<RGB> Total;  ///< total radiance at each point
  std::vector<RGB> Unshot; ///< unshot radiance at each point
  /// Mesh edges (pairs of point ids) on lines where the radiance may have
  /// a kink or a jump (discontinuities of order 0 and 1): the quadrature
  /// of the powers fits no slope across them. Optional; without them a fit
  /// near such a line smears its kink. []
  std::vector<std::array<int, 2>> Creases;
  /// Receive one irradiance for the whole surface, evaluated at one point
  /// (the centroid of the triangles, or of the largest if that lies
  /// outside) and added at every point: for surfaces smaller than the
  /// resolution wanted (the coarse level's small polygons), at a fraction
  /// of the cost. It still shoots its linear unshot radiance. [false]
  bool Uniform = false;
  /// Integrate powers with the linear interpolant instead of the quadrature
  /// exact for quadratics: for a coarse level, whose restriction and
  /// prolongation conserve the linear interpolant's integral. [false]
  bool LinearPower = false;
};

} // namespace penumbra

#endif
