// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraScene.h
 * @brief The scene model of the Penumbra core: planar polygonal surfaces that
 * emit and reflect diffusely on their front side and occlude from both sides.
 *
 * A Scene is what every stage of the pipeline reads. It mirrors the data
 * contract of the VTK filters (one polygon cell = one surface, cell arrays
 * `Reflectance` and `Emission`) without any VTK type.
 */
#ifndef penumbraScene_h
#define penumbraScene_h

#include "penumbraCommonModule.h" // for export macro
#include "penumbraVector.h"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra
{

/**
 * Thrown for input that does not follow the data contract. The message names
 * the offending cell, array, line or setting and says what is wrong with it.
 */
class PENUMBRACOMMON_EXPORT InputError : public std::runtime_error
{
public:
  explicit InputError(const std::string& message)
    : std::runtime_error(message)
  {
  }
};

/// One planar polygon of the scene, with its material.
struct Surface
{
  /// Vertices, counter-clockwise seen from the front (right-hand-rule normal).
  std::vector<Vec3> Vertices;
  /// Diffuse (hemispherical) reflectance per channel, each in [0, 1).
  RGB Reflectance;
  /// Emitted radiance L^e per channel, W sr^-1 m^-2, each >= 0.
  RGB Emission;
};

/**
 * The reflectance the solver's sampled values carry on a black channel.
 * A sampled value is L^e + rho_t E / pi, with rho_t the surface's reflectance
 * where it is positive and this on black channels, so that the light reaching a
 * black surface is still sampled, meshed and reconstructed (Irradiance =
 * pi (value - L^e) / rho_t) while it reflects nothing: the power a shot leaves
 * to be shot again uses the true reflectance. Small enough that a black
 * surface's value differs from L^e by less than 1e-6 of its irradiance over pi.
 */
constexpr double BlackTrackingReflectance = 1e-6;

/// The reflectance of a surface's sampled values (see BlackTrackingReflectance).
inline RGB TrackedReflectance(const RGB& reflectance)
{
  return RGB(reflectance.R > 0.0 ? reflectance.R : BlackTrackingReflectance,
    reflectance.G > 0.0 ? reflectance.G : BlackTrackingReflectance,
    reflectance.B > 0.0 ? reflectance.B : BlackTrackingReflectance);
}

/// The share of a sampled value's reflected part (value - L^e) that is
/// reflected radiance: 1 per channel, 0 on black channels.
inline RGB ReflectedShare(const RGB& reflectance)
{
  return RGB(reflectance.R > 0.0 ? 1.0 : 0.0, reflectance.G > 0.0 ? 1.0 : 0.0,
    reflectance.B > 0.0 ? 1.0 : 0.0);
}

/// Derived geometry of a planar polygon.
struct PolygonGeometry
{
  Vec3 Normal;           ///< unit front normal
  double Offset = 0.0;   ///< plane: Dot(Normal, x) == Offset
  double Area = 0.0;     ///< area in squared scene units
  Vec3 Centroid;         ///< area centroid
  double Diameter = 0.0; ///< largest vertex-to-vertex distance
};

/// Geometry of a polygon from its vertices (Newell normal). Area is 0 for a
/// degenerate polygon, in which case Normal is the zero vector.
PENUMBRACOMMON_EXPORT PolygonGeometry ComputePolygonGeometry(const std::vector<Vec3>& vertices);

/**
 * Ear-clipping triangulation of a simple planar polygon `v` (either
 * orientation) with unit normal `normal`, in its own plane; appends index
 * triples into `v` to `out`. Collinear or numerically ambiguous remainders
 * are cut at their flattest vertex, so it always ends with at most
 * v.size() - 2 triangles (zero-area ones are left out).
 */
PENUMBRACOMMON_EXPORT void TriangulatePolygon(
  const std::vector<Vec3>& v, const Vec3& normal, std::vector<std::array<int, 3>>& out);

/// A collection of surfaces; surface i corresponds to input cell i.
struct Scene
{
  std::vector<Surface> Surfaces;

  /// Largest extent of the bounding box (0 for an empty scene).
  PENUMBRACOMMON_EXPORT double Size() const;
  /// Total emitted power pi * sum(L^e * A) per channel, in watts.
  PENUMBRACOMMON_EXPORT RGB EmittedPower() const;
  /// The same surfaces, vertices and materials, to the bit.
  PENUMBRACOMMON_EXPORT bool IsIdentical(const Scene& other) const;
};

/// Tolerances used by ValidateScene, relative to the polygon's diameter.
struct ValidationTolerances
{
  /// Largest allowed distance of a vertex from the polygon's plane.
  double Planarity = 1e-6;
  /// Smallest allowed edge length and polygon width.
  double Degeneracy = 1e-9;
};

/**
 * Check a scene against the data contract. Throws InputError naming the first
 * offending cell ("cell 12: ...") for: fewer than three vertices, non-finite
 * coordinates or material values, repeated or nearly coincident consecutive
 * vertices, zero area or a sliver narrower than the degeneracy tolerance,
 * non-planar vertices, self-intersecting outlines, reflectance outside [0, 1),
 * or negative emission. When `cellNumbers` is given (e.g. RepairScene's
 * source cells), messages name cell cellNumbers[i] for surface i, so that
 * they point into the file the user has.
 */
PENUMBRACOMMON_EXPORT void ValidateScene(const Scene& scene,
  const ValidationTolerances& tolerances = ValidationTolerances(),
  const std::vector<std::size_t>* cellNumbers = nullptr);

} // namespace penumbra

#endif
