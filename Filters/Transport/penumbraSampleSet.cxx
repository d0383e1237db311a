// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSampleSet.h"

#include "penumbraBoundarySamples.h"
#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraSampleQuadrature.h"
#include "penumbraScene.h"

#include <algorithm>
#include <array>
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
  this->LumpedWeights.resize(n);
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
  // A weight below 0 (a few samples on creases) could give a negative
  // power to a positive function: it is handed to the other corners of its
  // triangles, by their linear weights, which keeps the sum (constants
  // integrate exactly) and moves the mass by less than a triangle.
  const SurfaceSamples& set = this->Surfaces[surfaceId];
  std::vector<double> lumped(set.Points.size(), 0.0);
  for (std::size_t t = 0; t < set.Triangles.size(); ++t)
  {
    for (const int k : set.Triangles[t])
    {
      lumped[k] += areas[t] / 3.0;
    }
  }
  std::vector<double>& weights = this->Weights[surfaceId];
  for (int pass = 0; pass < 4; ++pass)
  {
    std::vector<double> moved(weights.size(), 0.0);
    bool any = false;
    for (std::size_t t = 0; t < set.Triangles.size(); ++t)
    {
      const std::array<int, 3>& tri = set.Triangles[t];
      for (int c = 0; c < 3; ++c)
      {
        const int k = tri[c];
        if (!(weights[k] < 0.0) || !(lumped[k] > 0.0))
        {
          continue;
        }
        // This triangle's share of k's negative weight, to its other corners.
        const double share = weights[k] * (areas[t] / 3.0) / lumped[k];
        const int a = tri[(c + 1) % 3], b = tri[(c + 2) % 3];
        const double wa = lumped[a], wb = lumped[b];
        if (wa + wb > 0.0)
        {
          moved[a] += share * wa / (wa + wb);
          moved[b] += share * wb / (wa + wb);
          moved[k] -= share;
          any = true;
        }
      }
    }
    for (std::size_t k = 0; k < weights.size(); ++k)
    {
      weights[k] += moved[k];
    }
    if (!any)
    {
      break;
    }
  }
  for (std::size_t k = 0; k < weights.size(); ++k)
  {
    weights[k] = lumped[k] > 0.0 ? std::max(0.0, weights[k]) : 0.0;
  }
  this->LumpedWeights[surfaceId] = std::move(lumped);
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

RGB SampleSet::ReflectedPower(int surfaceId, const RGB& emission) const
{
  const SurfaceSamples& s = this->Surfaces[surfaceId];
  std::vector<RGB> reflected(s.Total.size());
  for (std::size_t k = 0; k < reflected.size(); ++k)
  {
    reflected[k] = s.Total[k] + emission * -1.0;
  }
  return this->Integral(surfaceId, reflected) * Pi;
}

void SampleSet::MatchUnshotToPower(int surfaceId)
{
  SurfaceSamples& s = this->Surfaces[surfaceId];
  const std::vector<double>& lumped = this->LumpedWeights[surfaceId];
  const RGB linear = IntegrateLinear(s, this->Areas[surfaceId], s.Unshot);
  const RGB power = this->Integral(surfaceId, s.Unshot);
  for (int c = 0; c < 3; ++c)
  {
    // A constant over the samples where the radiance is not zero: smooth
    // (no sample-to-sample ripple) and no light where there was none (the
    // umbra of a secondary shooter stays dark).
    double support = 0.0;
    for (std::size_t k = 0; k < s.Unshot.size(); ++k)
    {
      support += s.Unshot[k][c] > 0.0 ? lumped[k] : 0.0;
    }
    if (!(support > 0.0))
    {
      continue;
    }
    const double offset = (power[c] - linear[c]) / support;
    for (RGB& value : s.Unshot)
    {
      if (value[c] > 0.0)
      {
        value[c] = std::max(0.0, value[c] + offset);
      }
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
