// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSampleSet.h
 * @brief The progressive shooter's samples of every surface (private): the
 * meshes and radiance values it was given, and what the shots derive from
 * them (triangle areas, evaluation points, ray origins, unshot powers).
 */
#ifndef penumbraSampleSet_h
#define penumbraSampleSet_h

#include "penumbraSurfaceSamples.h"
#include "penumbraVector.h"

#include <cstddef>
#include <vector>

namespace penumbra
{

class OccluderSet;
struct PreparedPolygon;

/// Integral of the linear interpolant of `values` over the triangles of
/// `s` (of areas `areas`), per channel.
RGB IntegrateLinear(
  const SurfaceSamples& s, const std::vector<double>& areas, const std::vector<RGB>& values);

/// The samples of all surfaces of a scene, indexed by surface id.
struct SampleSet
{
  /// No samples yet for `surfaces` surfaces, whose polygons are `occluders`'
  /// (kept by reference: it must outlive the set).
  SampleSet(const OccluderSet& occluders, std::size_t surfaces);

  const OccluderSet& Occluders; ///< the scene's polygons: planes, diameters, areas
  std::vector<SurfaceSamples> Surfaces;
  std::vector<std::vector<double>> Areas; ///< per surface: the area of each triangle
  /// Per surface: where each sample is evaluated (penumbraBoundarySamples.h);
  /// one point for a Uniform surface with triangles.
  std::vector<std::vector<Vec3>> EvaluationPoints;
  std::vector<std::vector<Vec3>> RayOrigins; ///< fast method: where visibility rays start
  /// Per surface: the quadrature weight of each sample (penumbraSampleQuadrature.h,
  /// never negative).
  std::vector<std::vector<double>> Weights;
  /// Per surface: the linear interpolant's weight of each sample (a third of
  /// the area of its triangles).
  std::vector<std::vector<double>> LumpedWeights;
  std::vector<RGB> UnshotPower; ///< per surface: pi * integral of Unshot

  int GetNumberOfSurfaces() const { return static_cast<int>(this->Surfaces.size()); }
  const PreparedPolygon& Polygon(int surfaceId) const;

  /// Throws InputError naming the surface and the first offending point or
  /// triangle of `samples` (see ProgressiveShooter::SetSurfaceSamples).
  void Validate(int surfaceId, const SurfaceSamples& samples) const;

  /// Take `samples` for surface `surfaceId` (validated) and derive the rest;
  /// offsets as in ProgressiveShooterSettings.
  void Set(int surfaceId, SurfaceSamples samples, double boundaryOffset, double rayOriginOffset);

  /// Recompute the evaluation points and ray origins of surface `surfaceId`.
  void UpdateEvaluationPoints(int surfaceId, double boundaryOffset, double rayOriginOffset);

  /// Recompute UnshotPower[surfaceId] from its unshot radiance.
  void UpdateUnshotPower(int surfaceId);

  /// Integral over surface `surfaceId` of a function given at its samples
  /// (Weights), per channel.
  RGB Integral(int surfaceId, const std::vector<RGB>& values) const;

  /// pi * integral of (Total - `emission`) over surface `surfaceId`: the
  /// light it reflects now, per channel.
  RGB ReflectedPower(int surfaceId, const RGB& emission) const;

  /**
   * Offset the unshot radiance of surface `surfaceId`, per channel, by a
   * constant where it is positive, so that its linear interpolant, which the
   * shots emit, carries the unshot power (the quadrature's integral, which
   * sees the curvature the interpolant misses; values that would go below 0
   * stay at 0). Linear in Unshot as long as its zeros stay where they are,
   * so the order of the shots hardly matters. UnshotPower is kept: call it
   * once per shot, just before the unshot radiance is shot.
   */
  void MatchUnshotToPower(int surfaceId);

  /// Sum of UnshotPower, in surface order.
  RGB TotalUnshotPower() const;
};

} // namespace penumbra

#endif
