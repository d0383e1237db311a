// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraEscapeRays.h"

#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraRayCaster.h"
#include "penumbraSampleSet.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

constexpr double OriginInset = 0.01;

} // namespace

int EscapeRays::RaysPerSurface(int surfaces)
{
  const long long budget = 1LL << 24;
  const long long each = surfaces > 0 ? budget / surfaces : budget;
  return static_cast<int>(std::max(256LL, std::min(16384LL, each)));
}

void EscapeRays::Ensure(const SampleSet& samples, const std::vector<int>& surfaces,
  const RayCaster& caster, const ParallelFor& loop)
{
  const int count = samples.GetNumberOfSurfaces();
  if (static_cast<int>(this->Surfaces.size()) != count)
  {
    this->Surfaces.assign(count, SurfaceRays());
  }
  std::vector<int> todo;
  for (const int j : surfaces)
  {
    if (!this->Surfaces[j].Traced && !samples.Surfaces[j].Triangles.empty())
    {
      todo.push_back(j);
    }
  }
  const int rays = RaysPerSurface(count);
  RunParallel(loop, todo.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<Vec3> origins(rays), directions(rays);
    std::vector<int> hits(rays);
    std::vector<Origin> where(rays);
    for (std::size_t item = begin; item < end; ++item)
    {
      const int j = todo[item];
      const SurfaceSamples& s = samples.Surfaces[j];
      const std::vector<double>& areas = samples.Areas[j];
      const PreparedPolygon& poly = samples.Polygon(j);
      std::vector<double> cumulative(areas.size());
      double total = 0.0;
      for (std::size_t t = 0; t < areas.size(); ++t)
      {
        total += areas[t];
        cumulative[t] = total;
      }
      SurfaceRays& out = this->Surfaces[j];
      out.Traced = true;
      out.Rays = rays;
      out.Escaping.clear();
      out.Backs.clear();
      if (!(total > 0.0))
      {
        continue;
      }
      for (int r = 0; r < rays; ++r)
      {
        const unsigned index = static_cast<unsigned>(r) + 1u;
        // Triangle by area, then a uniform point in it from the rest of the
        // first coordinate and the second.
        const double u = RadicalInverse(index, 2) * total;
        std::size_t t = static_cast<std::size_t>(
          std::lower_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
        t = std::min(t, areas.size() - 1);
        while (t + 1 < areas.size() && !(areas[t] > 0.0))
        {
          ++t;
        }
        const double start = cumulative[t] - areas[t];
        const double su = areas[t] > 0.0 ? std::min(1.0, std::max(0.0, (u - start) / areas[t])) : 0.5;
        const double root = std::sqrt(su);
        const double v = RadicalInverse(index, 3);
        // Kept 1% off the triangle's edges toward its centroid: a ray from
        // a surface's outline could slip between it and a neighbour.
        const double a = OriginInset / 3.0 + (1.0 - OriginInset) * root * (1.0 - v);
        const double b = OriginInset / 3.0 + (1.0 - OriginInset) * root * v;
        where[r] = { static_cast<int>(t), static_cast<float>(a), static_cast<float>(b) };
        const std::array<int, 3>& tri = s.Triangles[t];
        origins[r] =
          s.Points[tri[0]] * (1.0 - a - b) + s.Points[tri[1]] * a + s.Points[tri[2]] * b;
        // Cosine-distributed direction about the normal.
        const double radius = std::sqrt(RadicalInverse(index, 5));
        const double phi = 2.0 * Pi * RadicalInverse(index, 7);
        const double z = std::sqrt(std::max(0.0, 1.0 - radius * radius));
        directions[r] = poly.AxisU * (radius * std::cos(phi)) +
          poly.AxisV * (radius * std::sin(phi)) + poly.Normal * z;
      }
      caster.FindNearest(origins.data(), directions.data(), rays, hits.data(), j);
      for (int r = 0; r < rays; ++r)
      {
        const int hit = hits[r];
        if (hit < 0 || samples.EvaluationPoints[hit].empty())
        {
          out.Escaping.push_back(where[r]);
        }
        else if (Dot(samples.Polygon(hit).Normal, directions[r]) >= 0.0)
        {
          out.Backs.push_back(where[r]);
        }
      }
    }
  });
}

bool EscapeRays::IsClosed(int surface) const
{
  return this->Surfaces.at(surface).Escaping.empty();
}

int EscapeRays::GetEscapingRays(int surface) const
{
  return static_cast<int>(this->Surfaces.at(surface).Escaping.size());
}

double EscapeRays::UniformEscapedFraction(int surface) const
{
  const SurfaceRays& rays = this->Surfaces.at(surface);
  return rays.Rays > 0 ? static_cast<double>(rays.Escaping.size()) / rays.Rays : 0.0;
}

double EscapeRays::UniformBackFraction(int surface) const
{
  const SurfaceRays& rays = this->Surfaces.at(surface);
  return rays.Rays > 0 ? static_cast<double>(rays.Backs.size()) / rays.Rays : 0.0;
}

RGB EscapeRays::BackFraction(const SampleSet& samples, int surface) const
{
  return this->Fraction(samples, surface, this->Surfaces.at(surface).Backs);
}

RGB EscapeRays::EscapedFraction(const SampleSet& samples, int surface) const
{
  return this->Fraction(samples, surface, this->Surfaces.at(surface).Escaping);
}

RGB EscapeRays::Fraction(
  const SampleSet& samples, int surface, const std::vector<Origin>& origins) const
{
  const SurfaceRays& rays = this->Surfaces.at(surface);
  RGB fraction;
  if (origins.empty() || rays.Rays == 0)
  {
    return fraction;
  }
  const SurfaceSamples& s = samples.Surfaces[surface];
  RGB sum;
  for (const Origin& h : origins)
  {
    const std::array<int, 3>& tri = s.Triangles[h.Triangle];
    sum += s.Unshot[tri[0]] * (1.0 - h.A - h.B) + s.Unshot[tri[1]] * h.A + s.Unshot[tri[2]] * h.B;
  }
  // The origins are spread by area (up to the 1% inset), so the mean of the
  // unshot radiance over them is its linear integral over the area.
  double area = 0.0;
  for (const double a : samples.Areas[surface])
  {
    area += a;
  }
  const RGB linear = IntegrateLinear(s, samples.Areas[surface], s.Unshot);
  for (int c = 0; c < 3; ++c)
  {
    fraction[c] = linear[c] > 0.0
      ? std::min(1.0, std::max(0.0, sum[c] * area / (rays.Rays * linear[c])))
      : 0.0;
  }
  return fraction;
}

} // namespace penumbra
