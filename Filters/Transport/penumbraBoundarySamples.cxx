// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraBoundarySamples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

namespace penumbra
{

namespace
{

/// Angle of triangle `tri` at its corner k.
double AngleAt(const SurfaceSamples& s, const std::array<int, 3>& tri, int k)
{
  const Vec3 u = s.Points[tri[(k + 1) % 3]] - s.Points[tri[k]];
  const Vec3 v = s.Points[tri[(k + 2) % 3]] - s.Points[tri[k]];
  return std::atan2(Length(Cross(u, v)), Dot(u, v));
}

Vec3 Centroid(const SurfaceSamples& s, const std::array<int, 3>& tri)
{
  return (s.Points[tri[0]] + s.Points[tri[1]] + s.Points[tri[2]]) / 3.0;
}

/// The one point of a Uniform surface: the centroid of the triangles'
/// area, or if that lies in none of them (a concave surface) the centroid
/// of the largest.
Vec3 UniformPoint(const SurfaceSamples& samples, const std::vector<double>& areas)
{
  Vec3 centroid;
  double total = 0.0;
  std::size_t largest = 0;
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    centroid += (samples.Points[tri[0]] + samples.Points[tri[1]] + samples.Points[tri[2]]) *
      (areas[t] / 3.0);
    total += areas[t];
    largest = areas[t] > areas[largest] ? t : largest;
  }
  const Vec3 fallback = Centroid(samples, samples.Triangles[largest]);
  centroid = total > 0.0 ? centroid / total : fallback;
  bool inside = false;
  for (std::size_t t = 0; t < samples.Triangles.size() && !inside; ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    const Vec3 a = samples.Points[tri[0]], b = samples.Points[tri[1]], c = samples.Points[tri[2]];
    const Vec3 normal = Cross(b - a, c - a);
    inside = Dot(Cross(b - a, centroid - a), normal) >= 0.0 &&
      Dot(Cross(c - b, centroid - b), normal) >= 0.0 &&
      Dot(Cross(a - c, centroid - c), normal) >= 0.0;
  }
  return inside ? centroid : fallback;
}

/// Per point: 1 if an incident edge is used by one triangle only.
std::vector<char> BoundaryPoints(const SurfaceSamples& samples)
{
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * samples.Triangles.size());
  for (const std::array<int, 3>& tri : samples.Triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = tri[k];
      const int b = tri[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<char> boundary(samples.Points.size(), 0);
  for (std::size_t e = 0; e < edges.size();)
  {
    std::size_t f = e + 1;
    while (f < edges.size() && edges[f] == edges[e])
    {
      ++f;
    }
    if (f - e == 1)
    {
      boundary[edges[e].first] = 1;
      boundary[edges[e].second] = 1;
    }
    e = f;
  }
  return boundary;
}

/// Incident triangles of every point (CSR), degenerate ones left out: point
/// k's are Triangle[Start[k], Start[k + 1]), with the corner k is of each.
struct Incidence
{
  std::vector<int> Start;
  std::vector<int> Triangle;
  std::vector<int> Corner;
};

Incidence IncidentTriangles(const SurfaceSamples& samples, const std::vector<double>& areas)
{
  const std::size_t n = samples.Points.size();
  Incidence result;
  std::vector<int>& start = result.Start;
  start.assign(n + 1, 0);
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    for (int k = 0; k < 3 && areas[t] > 0.0; ++k)
    {
      ++start[samples.Triangles[t][k] + 1];
    }
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    start[k + 1] += start[k];
  }
  result.Triangle.resize(static_cast<std::size_t>(start[n]));
  result.Corner.resize(result.Triangle.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    for (int k = 0; k < 3 && areas[t] > 0.0; ++k)
    {
      const int slot = fill[samples.Triangles[t][k]]++;
      result.Triangle[slot] = static_cast<int>(t);
      result.Corner[slot] = k;
    }
  }
  return result;
}

/**
 * Target of boundary point k: the centroid of its incident triangle with
 * the largest angle there; on a tie (within 1e-9) the mean of the tied
 * centroids, so that the rule does not depend on the triangles' order
 * (mirror-symmetric meshes give mirror-symmetric points), unless that mean
 * lies outside every incident corner (a reflex fan): then the first.
 */
Vec3 InwardTarget(const SurfaceSamples& samples, const Incidence& incidence, std::size_t k)
{
  const Vec3& p = samples.Points[k];
  const int begin = incidence.Start[k], end = incidence.Start[k + 1];
  double largest = -1.0;
  for (int slot = begin; slot < end; ++slot)
  {
    largest = std::max(largest,
      AngleAt(samples, samples.Triangles[incidence.Triangle[slot]], incidence.Corner[slot]));
  }
  Vec3 sum;
  Vec3 first;
  int ties = 0;
  for (int slot = begin; slot < end; ++slot)
  {
    const std::array<int, 3>& tri = samples.Triangles[incidence.Triangle[slot]];
    if (AngleAt(samples, tri, incidence.Corner[slot]) >= largest * (1.0 - 1e-9))
    {
      const Vec3 centroid = Centroid(samples, tri);
      first = ties == 0 ? centroid : first;
      sum += centroid;
      ++ties;
    }
  }
  const Vec3 target = sum / static_cast<double>(ties);
  if (ties == 1)
  {
    return target;
  }
  for (int slot = begin; slot < end; ++slot)
  {
    // Inside the corner at p: d = alpha u + beta v with alpha, beta >= 0.
    const std::array<int, 3>& tri = samples.Triangles[incidence.Triangle[slot]];
    const Vec3 u = samples.Points[tri[(incidence.Corner[slot] + 1) % 3]] - p;
    const Vec3 v = samples.Points[tri[(incidence.Corner[slot] + 2) % 3]] - p;
    const Vec3 d = target - p;
    const Vec3 normal = Cross(u, v);
    if (Dot(Cross(d, v), normal) >= 0.0 && Dot(Cross(u, d), normal) >= 0.0)
    {
      return target;
    }
  }
  return first;
}

} // namespace

void ComputeEvaluationPoints(const SurfaceSamples& samples, const std::vector<double>& areas,
  double offset, double rayOffset, std::vector<Vec3>& eval, std::vector<Vec3>& origins)
{
  if (samples.Uniform && !samples.Triangles.empty())
  {
    eval.assign(1, UniformPoint(samples, areas));
    origins = eval;
    return;
  }
  eval = samples.Points;
  origins = samples.Points;
  if (!(offset > 0.0 || rayOffset > 0.0))
  {
    return;
  }
  const std::vector<char> boundary = BoundaryPoints(samples);
  const Incidence incidence = IncidentTriangles(samples, areas);
  for (std::size_t k = 0; k < samples.Points.size(); ++k)
  {
    if (!boundary[k] || incidence.Start[k] == incidence.Start[k + 1])
    {
      continue;
    }
    const Vec3& p = samples.Points[k];
    const Vec3 d = InwardTarget(samples, incidence, k) - p;
    const double length = Length(d);
    if (length > 0.0)
    {
      eval[k] = p + d * std::min(0.5, offset / length);
      origins[k] = p + d * std::min(0.5, rayOffset / length);
    }
  }
}

} // namespace penumbra
