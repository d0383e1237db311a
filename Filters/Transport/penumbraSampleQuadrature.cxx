// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSampleQuadrature.h"

#include "penumbraElementIntegral.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace penumbra
{

namespace
{

// Fits need this many neighbours before ring 2 is added (a quadratic has 5
// unknowns besides the value; a margin keeps the fit from interpolating).
constexpr std::size_t RingOnePoints = 8;
// Absolute sum of a triangle's weights, relative to its area, beyond which
// the triangle falls back to the linear interpolant's weights (whose sum is
// 1): the slope fits' weights grow as the stencil's spacing over the
// triangle's size.
constexpr double StableRowSum = 3.0;
// Inverse-distance weights of the fits are capped at this over the
// stencil's radius, so that one very close point cannot decide a slope.
constexpr double ClosestWeightDistance = 0.1;
// A pivot below this fraction of its column's original diagonal means the
// stencil cannot determine that unknown.
constexpr double PivotThreshold = 1e-9;

/**
 * Solve the weighted least-squares problem of the first `unknowns` columns
 * of `rows` (row r: columns rows[r][0..4]) by Cholesky of the normal
 * equations. Writes into `gradient` (2 per row) the weights of the first
 * two unknowns: unknown_j = sum_r gradient[2r + j] * rhs_r. Returns false
 * when the columns are (nearly) dependent.
 */
bool GradientWeights(const std::vector<std::array<double, 6>>& rows, int unknowns,
  std::vector<double>& gradient)
{
  double m[5][5] = {};
  for (const std::array<double, 6>& row : rows)
  {
    const double w2 = row[5] * row[5];
    for (int a = 0; a < unknowns; ++a)
    {
      for (int b = 0; b <= a; ++b)
      {
        m[a][b] += w2 * row[a] * row[b];
      }
    }
  }
  // In-place Cholesky, lower triangle.
  double l[5][5] = {};
  for (int j = 0; j < unknowns; ++j)
  {
    double d = m[j][j];
    for (int k = 0; k < j; ++k)
    {
      d -= l[j][k] * l[j][k];
    }
    if (!(d > PivotThreshold * m[j][j]) || !(m[j][j] > 0.0))
    {
      return false;
    }
    l[j][j] = std::sqrt(d);
    for (int i = j + 1; i < unknowns; ++i)
    {
      double s = m[i][j];
      for (int k = 0; k < j; ++k)
      {
        s -= l[i][k] * l[j][k];
      }
      l[i][j] = s / l[j][j];
    }
  }
  gradient.assign(2 * rows.size(), 0.0);
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    // x = M^-1 A^T W^2 e_r: forward then back substitution.
    double y[5];
    const double w2 = rows[r][5] * rows[r][5];
    for (int i = 0; i < unknowns; ++i)
    {
      double s = w2 * rows[r][i];
      for (int k = 0; k < i; ++k)
      {
        s -= l[i][k] * y[k];
      }
      y[i] = s / l[i][i];
    }
    for (int i = unknowns - 1; i >= 0; --i)
    {
      double s = y[i];
      for (int k = i + 1; k < unknowns; ++k)
      {
        s -= l[k][i] * y[k];
      }
      y[i] = s / l[i][i];
    }
    gradient[2 * r] = y[0];
    gradient[2 * r + 1] = y[1];
  }
  return true;
}

} // namespace

namespace
{

std::uint64_t EdgeKey(int a, int b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

/// The mesh around the points: incident triangles, triangles across each
/// edge, and the crease edges.
struct MeshAdjacency
{
  std::vector<std::vector<int>> Incident; // per point
  std::unordered_map<std::uint64_t, std::vector<int>> EdgeTriangles;
  std::unordered_set<std::uint64_t> Creases;
};

/**
 * The triangles of the sector of point i that holds triangle `seed` (the
 * triangles around i reached across edges at i that are not creases), grown
 * across non-crease edges until their corners other than i number at least
 * RingOnePoints (two layers at most). Returns those corners.
 */
std::vector<int> SectorStencil(const SurfaceSamples& samples, const MeshAdjacency& mesh, int i,
  int seed, std::vector<int>& sector)
{
  sector.assign(1, seed);
  // The sector: walk around i across its non-crease edges.
  for (std::size_t k = 0; k < sector.size(); ++k)
  {
    for (const int q : samples.Triangles[sector[k]])
    {
      const std::uint64_t key = EdgeKey(i, q);
      if (q == i || mesh.Creases.count(key))
      {
        continue;
      }
      for (const int t : mesh.EdgeTriangles.at(key))
      {
        if (std::find(sector.begin(), sector.end(), t) == sector.end())
        {
          sector.push_back(t);
        }
      }
    }
  }
  std::vector<int> region = sector;
  std::vector<int> points;
  const auto collect = [&]() {
    points.clear();
    for (const int t : region)
    {
      for (const int q : samples.Triangles[t])
      {
        if (q != i && std::find(points.begin(), points.end(), q) == points.end())
        {
          points.push_back(q);
        }
      }
    }
  };
  collect();
  std::size_t layerBegin = 0;
  for (int layer = 0; layer < 2 && points.size() < RingOnePoints; ++layer)
  {
    const std::size_t layerEnd = region.size();
    for (std::size_t k = layerBegin; k < layerEnd; ++k)
    {
      const std::array<int, 3>& tri = samples.Triangles[region[k]];
      for (int e = 0; e < 3; ++e)
      {
        const std::uint64_t key = EdgeKey(tri[e], tri[(e + 1) % 3]);
        if (mesh.Creases.count(key))
        {
          continue;
        }
        for (const int t : mesh.EdgeTriangles.at(key))
        {
          if (std::find(region.begin(), region.end(), t) == region.end())
          {
            region.push_back(t);
          }
        }
      }
    }
    layerBegin = layerEnd;
    collect();
  }
  return points;
}

} // namespace

std::vector<double> ComputeQuadratureWeights(
  const SurfaceSamples& samples, const std::vector<double>& areas, const Vec3& u, const Vec3& v)
{
  const std::size_t n = samples.Points.size();
  std::vector<double> weights(n, 0.0);
  if (samples.Triangles.empty())
  {
    return weights;
  }
  if (samples.LinearPower)
  {
    for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
    {
      for (const int k : samples.Triangles[t])
      {
        weights[k] += areas[t] / 3.0;
      }
    }
    return weights;
  }
  MeshAdjacency mesh;
  mesh.Incident.resize(n);
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    for (int e = 0; e < 3; ++e)
    {
      mesh.Incident[tri[e]].push_back(static_cast<int>(t));
      mesh.EdgeTriangles[EdgeKey(tri[e], tri[(e + 1) % 3])].push_back(static_cast<int>(t));
    }
  }
  for (const std::array<int, 2>& edge : samples.Creases)
  {
    mesh.Creases.insert(EdgeKey(edge[0], edge[1]));
  }
  std::vector<std::array<double, 2>> plane(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    plane[k] = { Dot(samples.Points[k], u), Dot(samples.Points[k], v) };
  }
  // Per sector: its stencil and gradient weights (in plane units); per
  // triangle corner: its sector (-1: no gradient).
  std::vector<std::vector<int>> stencils;
  std::vector<std::vector<double>> gradients;
  std::vector<int> cornerSector(3 * samples.Triangles.size(), -1);
  std::vector<char> done(3 * samples.Triangles.size(), 0);
  std::vector<std::array<double, 6>> rows;
  std::vector<int> sector;
  std::vector<std::pair<int, double>> row;
  for (std::size_t i = 0; i < n; ++i)
  {
    for (const int seed : mesh.Incident[i])
    {
      const std::array<int, 3>& seedTri = samples.Triangles[seed];
      const int seedCorner =
        static_cast<int>(std::find(seedTri.begin(), seedTri.end(), static_cast<int>(i)) -
          seedTri.begin());
      if (done[3 * seed + seedCorner])
      {
        continue;
      }
      std::vector<int> ring =
        SectorStencil(samples, mesh, static_cast<int>(i), seed, sector);
      const int id = static_cast<int>(stencils.size());
      for (const int t : sector)
      {
        const std::array<int, 3>& tri = samples.Triangles[t];
        for (int c = 0; c < 3; ++c)
        {
          if (tri[c] == static_cast<int>(i))
          {
            done[3 * t + c] = 1;
          }
        }
      }
      double h = 0.0;
      for (const int q : ring)
      {
        h = std::max(h, std::hypot(plane[q][0] - plane[i][0], plane[q][1] - plane[i][1]));
      }
      if (!(h > 0.0))
      {
        continue;
      }
      rows.clear();
      std::vector<int> used;
      for (const int q : ring)
      {
        const double du = (plane[q][0] - plane[i][0]) / h;
        const double dv = (plane[q][1] - plane[i][1]) / h;
        const double d = std::hypot(du, dv);
        if (d > 0.0)
        {
          rows.push_back({ du, dv, 0.5 * du * du, du * dv, 0.5 * dv * dv,
            1.0 / std::max(d, ClosestWeightDistance) });
          used.push_back(q);
        }
      }
      std::vector<double> g;
      if (!GradientWeights(rows, 5, g) && !GradientWeights(rows, 2, g))
      {
        continue;
      }
      for (double& x : g)
      {
        x /= h;
      }
      stencils.push_back(std::move(used));
      gradients.push_back(std::move(g));
      for (const int t : sector)
      {
        const std::array<int, 3>& tri = samples.Triangles[t];
        for (int c = 0; c < 3; ++c)
        {
          if (tri[c] == static_cast<int>(i))
          {
            cornerSector[3 * t + c] = id;
          }
        }
      }
    }
  }
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    const double corners[3][2] = { { plane[tri[0]][0], plane[tri[0]][1] },
      { plane[tri[1]][0], plane[tri[1]][1] }, { plane[tri[2]][0], plane[tri[2]][1] } };
    if (!(areas[t] > 0.0))
    {
      continue; // carries no power
    }
    double valueWeights[3];
    double gradientWeights[3][2];
    CloughTocherIntegralWeights(corners, valueWeights, gradientWeights);
    // The triangle's weights (corner values, then each stencil point's
    // share through the slopes), gathered first: a row whose absolute sum
    // exceeds StableRowSum times the area comes from a slope fit on points
    // far closer together than the triangle is wide, and would amplify
    // their noise; such a triangle takes the linear interpolant's weights.
    row.clear();
    for (int c = 0; c < 3; ++c)
    {
      const int i = tri[c];
      row.emplace_back(i, valueWeights[c]);
      const int id = cornerSector[3 * t + c];
      if (id < 0)
      {
        continue;
      }
      // gradient_i = sum_r G_r (f_r - f_i).
      const std::vector<int>& s = stencils[id];
      const std::vector<double>& g = gradients[id];
      for (std::size_t r = 0; r < s.size(); ++r)
      {
        const double w = gradientWeights[c][0] * g[2 * r] + gradientWeights[c][1] * g[2 * r + 1];
        row.emplace_back(s[r], w);
        row.emplace_back(i, -w);
      }
    }
    double absolute = 0.0;
    for (const auto& entry : row)
    {
      absolute += std::abs(entry.second);
    }
    if (absolute > StableRowSum * areas[t])
    {
      for (const int i : tri)
      {
        weights[i] += areas[t] / 3.0;
      }
      continue;
    }
    for (const auto& entry : row)
    {
      weights[entry.first] += entry.second;
    }
  }
  return weights;
}

RGB Integrate(const std::vector<double>& weights, const std::vector<RGB>& values)
{
  RGB sum;
  for (std::size_t k = 0; k < weights.size(); ++k)
  {
    sum += values[k] * weights[k];
  }
  return sum;
}

} // namespace penumbra
