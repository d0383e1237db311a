// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSampleSet.h"

#include "penumbraBoundarySamples.h"
#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraSampleQuadrature.h"
#include "penumbraScene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace penumbra
{

namespace
{

bool IsFinite(const RGB& v)
{
  return std::isfinite(v.R) && std::isfinite(v.G) && std::isfinite(v.B);
}

} // namespace

RGB IntegrateLinear(
  const SurfaceSamples& s, const std::vector<double>& areas, const std::vector<RGB>& values)
{
  RGB sum;
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    const RGB mean = (values[tri[0]] + values[tri[1]] + values[tri[2]]) * (1.0 / 3.0);
    sum += mean * areas[t];
  }
  return sum;
}

SampleSet::SampleSet(const OccluderSet& occluders, std::size_t n)
  : Occluders(occluders)
{
  this->Surfaces.resize(n);
  this->Areas.resize(n);
  this->EvaluationPoints.resize(n);
  this->RayOrigins.resize(n);
  this->Weights.resize(n);
  this->UnshotPower.resize(n);
}

const PreparedPolygon& SampleSet::Polygon(int surfaceId) const
{
  return this->Occluders.GetPolygon(surfaceId);
}

void SampleSet::Validate(int surfaceId, const SurfaceSamples& samples) const
{
  const std::string where = "progressive shooter: surface " + std::to_string(surfaceId) + ": ";
  const std::size_t n = samples.Points.size();
  if (samples.Total.size() != n || samples.Unshot.size() != n)
  {
    throw InputError(where + std::to_string(n) + " points but " +
      std::to_string(samples.Total.size()) + " total and " + std::to_string(samples.Unshot.size()) +
      " unshot values");
  }
  if (samples.Triangles.empty() && n == 0)
  {
    return;
  }
  const PreparedPolygon& poly = this->Polygon(surfaceId);
  if (!poly.Valid)
  {
    throw InputError(where + "the scene polygon is degenerate and cannot take samples");
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    const Vec3& p = samples.Points[k];
    if (!IsFinite(p))
    {
      throw InputError(where + "point " + std::to_string(k) + " has non-finite coordinates");
    }
    if (!IsFinite(samples.Total[k]) || !IsFinite(samples.Unshot[k]))
    {
      throw InputError(where + "point " + std::to_string(k) + " has a non-finite radiance");
    }
    if (std::abs(Dot(poly.Normal, p) - poly.Offset) > 1e-6 * poly.Diameter)
    {
      throw InputError(where + "point " + std::to_string(k) + " lies off the surface's plane");
    }
  }
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    for (const int id : samples.Triangles[t])
    {
      if (id < 0 || static_cast<std::size_t>(id) >= n)
      {
        throw InputError(where + "triangle " + std::to_string(t) + " refers to point " +
          std::to_string(id) + ", out of range [0, " + std::to_string(n) + ")");
      }
    }
  }
}

void SampleSet::Set(
  int surfaceId, SurfaceSamples samples, double boundaryOffset, double rayOriginOffset)
{
  std::vector<double>& areas = this->Areas[surfaceId];
  areas.resize(samples.Triangles.size());
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    const Vec3& a = samples.Points[tri[0]];
    areas[t] = 0.5 * Length(Cross(samples.Points[tri[1]] - a, samples.Points[tri[2]] - a));
  }
  this->Surfaces[surfaceId] = std::move(samples);
  const PreparedPolygon* poly = this->Surfaces[surfaceId].Triangles.empty() ? nullptr : &this->Polygon(surfaceId);
  this->Weights[surfaceId] = poly
    ? ComputeQuadratureWeights(this->Surfaces[surfaceId], areas, poly->AxisU, poly->AxisV)
    : std::vector<double>(this->Surfaces[surfaceId].Points.size(), 0.0);
  this->UpdateEvaluationPoints(surfaceId, boundaryOffset, rayOriginOffset);
  this->UpdateUnshotPower(surfaceId);
}

void SampleSet::UpdateEvaluationPoints(
  int surfaceId, double boundaryOffset, double rayOriginOffset)
{
  const SurfaceSamples& samples = this->Surfaces[surfaceId];
  const bool any = !samples.Points.empty();
  const double diameter = any ? this->Polygon(surfaceId).Diameter : 0.0;
  ComputeEvaluationPoints(samples, this->Areas[surfaceId],
    any ? boundaryOffset * diameter : 0.0, any ? rayOriginOffset * diameter : 0.0,
    this->EvaluationPoints[surfaceId], this->RayOrigins[surfaceId]);
}

void SampleSet::UpdateUnshotPower(int surfaceId)
{
  const SurfaceSamples& s = this->Surfaces[surfaceId];
  this->UnshotPower[surfaceId] = this->Integral(surfaceId, s.Unshot) * Pi;
}

RGB SampleSet::Integral(int surfaceId, const std::vector<RGB>& values) const
{
  return Integrate(this->Weights[surfaceId], values);
}

void SampleSet::MatchUnshotToPower(int surfaceId)
{
  SurfaceSamples& s = this->Surfaces[surfaceId];
  const std::vector<double>& areas = this->Areas[surfaceId];
  double area = 0.0;
  std::vector<char> used(s.Points.size(), 0);
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    area += areas[t];
    for (const int k : s.Triangles[t])
    {
      used[k] = 1;
    }
  }
  if (!(area > 0.0))
  {
    return;
  }
  // A constant offset: linear in Unshot (so a run's result does not depend
  // on the order of its shots) and about 1e-3 of the mean on meshes fine
  // enough for the light.
  const RGB linear = IntegrateLinear(s, areas, s.Unshot);
  const RGB power = this->Integral(surfaceId, s.Unshot);
  RGB offset;
  for (int c = 0; c < 3; ++c)
  {
    offset[c] = (power[c] - linear[c]) / area;
  }
  for (std::size_t k = 0; k < s.Unshot.size(); ++k)
  {
    if (used[k])
    {
      s.Unshot[k] += offset;
    }
  }
  // UnshotPower keeps the quadrature's value, which the offset interpolant
  // now carries.
}

RGB SampleSet::TotalUnshotPower() const
{
  RGB sum;
  for (const RGB& p : this->UnshotPower)
  {
    sum += p;
  }
  return sum;
}

} // namespace penumbra
