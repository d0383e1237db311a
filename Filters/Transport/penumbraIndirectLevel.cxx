// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraIndirectLevel.h"

#include "penumbraPlaneFrame.h"
#include "penumbraRayCaster.h"
#include <algorithm>
#include <cmath>
#include <map>

namespace penumbra
{

namespace
{

/// Largest lattice resolution of one ear: bounds the memory whatever the spacing.
constexpr int MaximumResolution = 1024;

/// Largest midpoint-rule resolution of one fine triangle in the restriction.
constexpr int MaximumQuadrature = 64;

/// The frame of the plane with unit normal n, as TriangulatePolygon uses it.

/// Lattice resolution of a polygon whose longest ear edge is `longest`.
int ResolutionFor(double longest, double spacing)
{
  const double n = std::ceil(longest / spacing);
  return static_cast<int>(std::max(1.0, std::min(n, static_cast<double>(MaximumResolution))));
}

/// Points of `ears` ear triangles cut in n x n with shared diagonals made once.
std::size_t LatticeCount(std::size_t ears, int n)
{
  if (ears == 0)
  {
    return 0;
  }
  const std::size_t m = static_cast<std::size_t>(n);
  return ears * (m + 1) * (m + 2) / 2 - (ears - 1) * (m + 1);
}

/// Index of lattice point (i, j), j <= n - i, in a row-major triangular array.
int LatticeIndex(int n, int i, int j)
{
  return i * (n + 1) - i * (i - 1) / 2 + j;
}

/// The ears of a surface and their longest edge.
double EarTriangles(const Surface& surface, Vec3& normal, std::vector<std::array<int, 3>>& ears)
{
  normal = ComputePolygonGeometry(surface.Vertices).Normal;
  ears.clear();
  TriangulatePolygon(surface.Vertices, normal, ears);
  double longest = 0.0;
  for (const std::array<int, 3>& ear : ears)
  {
    for (int k = 0; k < 3; ++k)
    {
      longest = std::max(
        longest, Length(surface.Vertices[ear[(k + 1) % 3]] - surface.Vertices[ear[k]]));
    }
  }
  return longest;
}

} // namespace

IndirectLevel::IndirectLevel(const Surface& surface, double spacing, const SurfaceSamples& fine)
  : Spacing(spacing)
{
  if (!(spacing > 0.0))
  {
    throw InputError("the spacing of the indirect level must be positive, got " +
      std::to_string(spacing));
  }
  Vec3 normal;
  const double longest = EarTriangles(surface, normal, this->Ears);
  this->Normal = normal;
  InPlaneAxes(normal, this->AxisU, this->AxisV);
  const std::vector<Vec3>& v = surface.Vertices;
  for (const Vec3& p : v)
  {
    this->Corners.push_back({ Dot(p, this->AxisU), Dot(p, this->AxisV) });
  }
  const int n = ResolutionFor(longest, spacing);
  this->Resolution = n;

  // Lattice points; a point on an ear's edge or corner gets the same id
  // (and bit-identical position) from both ears sharing it.
  std::map<std::array<int, 3>, int> shared;
  const auto pointAt = [&](const std::array<int, 3>& c, int i, int j) {
    std::array<int, 3> key;
    Vec3 position;
    bool boundary = true;
    const auto onEdge = [&](int a, int b, int p) {
      if (a > b)
      {
        std::swap(a, b);
        p = n - p;
      }
      key = { a, b, p };
      position = v[a] + (v[b] - v[a]) * (static_cast<double>(p) / n);
    };
    if (i == 0 && j == 0)
    {
      key = { c[0], -1, 0 };
      position = v[c[0]];
    }
    else if (i == n || j == n)
    {
      const int corner = i == n ? c[1] : c[2];
      key = { corner, -1, 0 };
      position = v[corner];
    }
    else if (j == 0)
    {
      onEdge(c[0], c[1], i);
    }
    else if (i == 0)
    {
      onEdge(c[0], c[2], j);
    }
    else if (i + j == n)
    {
      onEdge(c[1], c[2], j);
    }
    else
    {
      boundary = false;
      position = v[c[0]] + (v[c[1]] - v[c[0]]) * (static_cast<double>(i) / n) +
        (v[c[2]] - v[c[0]]) * (static_cast<double>(j) / n);
    }
    if (boundary)
    {
      const auto inserted = shared.emplace(key, static_cast<int>(this->Points.size()));
      if (!inserted.second)
      {
        return inserted.first->second;
      }
    }
    this->Points.push_back(position);
    return static_cast<int>(this->Points.size()) - 1;
  };
  for (const std::array<int, 3>& ear : this->Ears)
  {
    std::vector<int> ids(static_cast<std::size_t>((n + 1) * (n + 2) / 2));
    for (int i = 0; i <= n; ++i)
    {
      for (int j = 0; i + j <= n; ++j)
      {
        ids[LatticeIndex(n, i, j)] = pointAt(ear, i, j);
      }
    }
    for (int i = 0; i < n; ++i)
    {
      for (int j = 0; i + j < n; ++j)
      {
        this->Triangles.push_back(
          { ids[LatticeIndex(n, i, j)], ids[LatticeIndex(n, i + 1, j)], ids[LatticeIndex(n, i, j + 1)] });
        if (i + j < n - 1)
        {
          this->Triangles.push_back({ ids[LatticeIndex(n, i + 1, j)],
            ids[LatticeIndex(n, i + 1, j + 1)], ids[LatticeIndex(n, i, j + 1)] });
        }
      }
    }
    this->LatticeIds.push_back(std::move(ids));
  }
  this->Mass.assign(this->Points.size(), 0.0);
  this->QuadratureSize = spacing;
  for (const std::array<int, 3>& t : this->Triangles)
  {
    const Vec3 e[3] = { this->Points[t[1]] - this->Points[t[0]],
      this->Points[t[2]] - this->Points[t[1]], this->Points[t[0]] - this->Points[t[2]] };
    const double area = 0.5 * Length(Cross(e[0], -e[2]));
    for (int k = 0; k < 3; ++k)
    {
      this->Mass[t[k]] += area / 3.0;
    }
    // Restriction quadrature: at most half the smallest height of a lattice
    // triangle, so that every lattice point's support gets quadrature points.
    const double longest = std::max({ Length(e[0]), Length(e[1]), Length(e[2]) });
    if (area > 0.0)
    {
      this->QuadratureSize = std::min(this->QuadratureSize, area / longest);
    }
  }
  this->FineLocations.reserve(fine.Points.size());
  for (const Vec3& p : fine.Points)
  {
    this->FineLocations.push_back(this->Locate(p));
  }
}

std::size_t IndirectLevel::CountPoints(const Surface& surface, double spacing)
{
  Vec3 normal;
  std::vector<std::array<int, 3>> ears;
  const double longest = EarTriangles(surface, normal, ears);
  return LatticeCount(ears.size(), ResolutionFor(longest, spacing));
}

IndirectLevel::Location IndirectLevel::Locate(const Vec3& p) const
{
  Location where;
  where.Corners = { 0, 0, 0 };
  where.Weights = { 1.0, 0.0, 0.0 };
  if (this->Ears.empty())
  {
    return where;
  }
  const double u = Dot(p, this->AxisU);
  const double w = Dot(p, this->AxisV);
  // The ear containing p, or the one it is least outside of (rounding).
  int best = 0;
  double bestScore = -HUGE_VAL;
  double l1 = 0.0, l2 = 0.0;
  for (std::size_t e = 0; e < this->Ears.size() && bestScore < 0.0; ++e)
  {
    const std::array<double, 2>& a = this->Corners[this->Ears[e][0]];
    const std::array<double, 2>& b = this->Corners[this->Ears[e][1]];
    const std::array<double, 2>& c = this->Corners[this->Ears[e][2]];
    const double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (det == 0.0)
    {
      continue;
    }
    const double m1 = ((u - a[0]) * (c[1] - a[1]) - (w - a[1]) * (c[0] - a[0])) / det;
    const double m2 = ((b[0] - a[0]) * (w - a[1]) - (b[1] - a[1]) * (u - a[0])) / det;
    const double score = std::min({ 1.0 - m1 - m2, m1, m2 });
    if (score > bestScore)
    {
      bestScore = score;
      best = static_cast<int>(e);
      l1 = m1;
      l2 = m2;
    }
  }
  // Clamp into the ear, then into its lattice cell.
  l1 = std::max(0.0, l1);
  l2 = std::max(0.0, l2);
  if (l1 + l2 > 1.0)
  {
    const double sum = l1 + l2;
    l1 /= sum;
    l2 /= sum;
  }
  const int n = this->Resolution;
  const double s = l1 * n;
  const double t = l2 * n;
  const int i = std::max(0, std::min(static_cast<int>(std::floor(s)), n - 1));
  const int j = std::max(0, std::min(static_cast<int>(std::floor(t)), n - 1 - i));
  const double fs = s - i;
  const double ft = t - j;
  const std::vector<int>& ids = this->LatticeIds[best];
  if (fs + ft <= 1.0 || i + j == n - 1)
  {
    where.Corners = { ids[LatticeIndex(n, i, j)], ids[LatticeIndex(n, i + 1, j)],
      ids[LatticeIndex(n, i, j + 1)] };
    where.Weights = { 1.0 - fs - ft, fs, ft };
  }
  else
  {
    where.Corners = { ids[LatticeIndex(n, i + 1, j)], ids[LatticeIndex(n, i + 1, j + 1)],
      ids[LatticeIndex(n, i, j + 1)] };
    where.Weights = { 1.0 - ft, fs + ft - 1.0, 1.0 - fs };
  }
  // Rounding may leave a weight slightly negative: clamp and renormalise.
  double sum = 0.0;
  for (double& weight : where.Weights)
  {
    weight = std::max(0.0, weight);
    sum += weight;
  }
  for (double& weight : where.Weights)
  {
    weight = sum > 0.0 ? weight / sum : 1.0 / 3.0;
  }
  return where;
}

std::size_t IndirectLevel::SeparateOccluded(
  const SurfaceSamples& fine, int surfaceId, const RayCaster& caster, const ParallelFor& loop)
{
  if (fine.Points.size() != this->FineLocations.size())
  {
    throw InputError("IndirectLevel::SeparateOccluded: the samples are not those of this level");
  }
  // Test points are pulled a little toward the centre of the fine point's
  // lattice triangle, off the outline, where rays along a neighbouring
  // surface would graze it.
  constexpr double Inward = 1e-3;
  const double height = 0.5 * this->Spacing;
  const Vec3 up = this->Normal * height;
  const std::size_t count = this->FineLocations.size();
  std::vector<unsigned char> keep(count * 3, 1), alone(count, 0);
  RunParallel(loop, count, [&](std::size_t begin, std::size_t end) {
    std::vector<OcclusionRay> rays;
    std::vector<unsigned char> hit;
    for (std::size_t k = begin; k < end; ++k)
    {
      const Location& where = this->FineLocations[k];
      const Vec3 centre = (this->Points[where.Corners[0]] + this->Points[where.Corners[1]] +
                            this->Points[where.Corners[2]]) *
        (1.0 / 3.0);
      const Vec3 p = fine.Points[k] + (centre - fine.Points[k]) * Inward;
      // Rays: 0 the point's own cover; per corner c: its cover, then the
      // segment between the two lifted points.
      rays.assign(7, OcclusionRay());
      rays[0] = { p, p + up };
      for (int c = 0; c < 3; ++c)
      {
        const Vec3 corner =
          this->Points[where.Corners[c]] + (centre - this->Points[where.Corners[c]]) * Inward;
        rays[1 + 2 * c] = { corner, corner + up };
        rays[2 + 2 * c] = { p + up, corner + up };
      }
      hit.assign(rays.size(), 0);
      caster.TraceOcclusion(rays.data(), rays.size(), hit.data(), surfaceId);
      double sum = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        const bool usable = where.Weights[c] > 0.0 && hit[1 + 2 * c] == hit[0] && !hit[2 + 2 * c];
        keep[3 * k + c] = usable ? 1 : 0;
        sum += usable ? where.Weights[c] : 0.0;
      }
      // A point that lost a corner lies near an occluder, whose shadow of
      // the interreflected light (a contact, a pocket) the lattice cannot
      // follow: it is evaluated on its own too.
      double all = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        all += where.Weights[c] > 0.0 ? where.Weights[c] : 0.0;
      }
      alone[k] = sum < all ? 1 : 0;
    }
  });
  // Points on their own cost as much as lattice points: on a cluttered
  // surface (a bookcase's back behind its books), where they would be more
  // than the lattice's points and a quarter of the fine ones, they would
  // defeat the level, and they keep plain interpolation.
  std::size_t lone = 0;
  for (const unsigned char a : alone)
  {
    lone += a;
  }
  const bool separate = lone <= std::max(this->Points.size(), count / 4);
  this->Separate.clear();
  this->SeparatePoints.clear();
  this->SeparateIndex.assign(count, -1);
  for (std::size_t k = 0; k < count; ++k)
  {
    Location& where = this->FineLocations[k];
    if (alone[k] && separate)
    {
      this->SeparateIndex[k] = static_cast<int>(this->Separate.size());
      this->Separate.push_back(static_cast<int>(k));
      continue;
    }
    // Otherwise (a cluttered surface) from the corners it keeps, or all.
    double sum = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      sum += keep[3 * k + c] ? where.Weights[c] : 0.0;
    }
    if (sum > 0.0)
    {
      for (int c = 0; c < 3; ++c)
      {
        where.Weights[c] = keep[3 * k + c] ? where.Weights[c] / sum : 0.0;
      }
    }
  }
  // A point on its own lies in no triangle, so the shooter evaluates it
  // where it is; on a contact line (the foot of a box standing on the
  // surface) that is on the neighbouring surface's edge, where its closed
  // forms and rays are singular. Like a boundary sample, it is evaluated a
  // little inside: toward the centroid of its largest fine triangle, by
  // 1e-4 of the surface's diameter at most half the way.
  double diameter = 0.0;
  for (const auto& a : this->Corners)
  {
    for (const auto& b : this->Corners)
    {
      diameter = std::max(diameter, std::hypot(a[0] - b[0], a[1] - b[1]));
    }
  }
  std::vector<double> largest(this->Separate.size(), 0.0);
  this->SeparatePoints.resize(this->Separate.size());
  for (std::size_t s = 0; s < this->Separate.size(); ++s)
  {
    this->SeparatePoints[s] = fine.Points[this->Separate[s]];
  }
  for (const std::array<int, 3>& t : fine.Triangles)
  {
    const double area = Length(
      Cross(fine.Points[t[1]] - fine.Points[t[0]], fine.Points[t[2]] - fine.Points[t[0]]));
    const Vec3 centroid = (fine.Points[t[0]] + fine.Points[t[1]] + fine.Points[t[2]]) * (1.0 / 3.0);
    for (const int corner : t)
    {
      const int s = this->SeparateIndex[corner];
      if (s >= 0 && area > largest[s])
      {
        largest[s] = area;
        const Vec3 p = fine.Points[corner];
        const double distance = Length(centroid - p);
        const double step = std::min(1e-4 * diameter, 0.5 * distance);
        this->SeparatePoints[s] = distance > 0.0 ? p + (centroid - p) * (step / distance) : p;
      }
    }
  }
  return this->Separate.size();
}

SurfaceSamples IndirectLevel::Restrict(const SurfaceSamples& fine) const
{
  SurfaceSamples coarse;
  coarse.LinearPower = true;
  coarse.Points = this->Points;
  coarse.Triangles = this->Triangles;
  const std::size_t count = this->Points.size();
  std::vector<RGB> totalLoad(count), unshotLoad(count);
  std::vector<double> quadratureMass(count, 0.0);
  RGB totalIntegral, unshotIntegral;
  for (const std::array<int, 3>& tri : fine.Triangles)
  {
    const Vec3 p[3] = { fine.Points[tri[0]], fine.Points[tri[1]], fine.Points[tri[2]] };
    const double area = 0.5 * Length(Cross(p[1] - p[0], p[2] - p[0]));
    if (!(area > 0.0))
    {
      continue;
    }
    totalIntegral += (fine.Total[tri[0]] + fine.Total[tri[1]] + fine.Total[tri[2]]) * (area / 3.0);
    unshotIntegral +=
      (fine.Unshot[tri[0]] + fine.Unshot[tri[1]] + fine.Unshot[tri[2]]) * (area / 3.0);
    const double longest =
      std::max({ Length(p[1] - p[0]), Length(p[2] - p[1]), Length(p[0] - p[2]) });
    const int q = static_cast<int>(std::max(1.0,
      std::min(std::ceil(longest / this->QuadratureSize), static_cast<double>(MaximumQuadrature))));
    const double weight = area / (static_cast<double>(q) * q);
    // Midpoint rule on the q x q sub-triangles, for the loads int f phi_k
    // and for the masses int phi_k alike, so that a constant is kept.
    const auto add = [&](double a, double b) {
      const Vec3 x = p[0] + (p[1] - p[0]) * a + (p[2] - p[0]) * b;
      const RGB total =
        fine.Total[tri[0]] * (1.0 - a - b) + fine.Total[tri[1]] * a + fine.Total[tri[2]] * b;
      const RGB unshot =
        fine.Unshot[tri[0]] * (1.0 - a - b) + fine.Unshot[tri[1]] * a + fine.Unshot[tri[2]] * b;
      const Location where = this->Locate(x);
      for (int k = 0; k < 3; ++k)
      {
        const double w = weight * where.Weights[k];
        totalLoad[where.Corners[k]] += total * w;
        unshotLoad[where.Corners[k]] += unshot * w;
        quadratureMass[where.Corners[k]] += w;
      }
    };
    for (int i = 0; i < q; ++i)
    {
      for (int j = 0; i + j < q; ++j)
      {
        add((i + 1.0 / 3.0) / q, (j + 1.0 / 3.0) / q);
        if (i + j < q - 1)
        {
          add((i + 2.0 / 3.0) / q, (j + 2.0 / 3.0) / q);
        }
      }
    }
  }
  coarse.Total.resize(count);
  coarse.Unshot.resize(count);
  std::vector<char> known(count, 0);
  for (std::size_t k = 0; k < count; ++k)
  {
    if (quadratureMass[k] > 0.0)
    {
      coarse.Total[k] = totalLoad[k] * (1.0 / quadratureMass[k]);
      coarse.Unshot[k] = unshotLoad[k] * (1.0 / quadratureMass[k]);
      known[k] = 1;
    }
  }
  // Points no quadrature point reached (the fine mesh is coarser than the
  // lattice there): the mean of their known neighbours, spread ring by ring.
  for (bool changed = true; changed;)
  {
    changed = false;
    std::vector<RGB> totalSum(count), unshotSum(count);
    std::vector<int> neighbours(count, 0);
    for (const std::array<int, 3>& t : this->Triangles)
    {
      for (int a = 0; a < 3; ++a)
      {
        for (int b = 0; b < 3; ++b)
        {
          if (!known[t[a]] && known[t[b]])
          {
            totalSum[t[a]] += coarse.Total[t[b]];
            unshotSum[t[a]] += coarse.Unshot[t[b]];
            ++neighbours[t[a]];
          }
        }
      }
    }
    for (std::size_t k = 0; k < count; ++k)
    {
      if (!known[k] && neighbours[k] > 0)
      {
        coarse.Total[k] = totalSum[k] * (1.0 / neighbours[k]);
        coarse.Unshot[k] = unshotSum[k] * (1.0 / neighbours[k]);
        known[k] = 1;
        changed = true;
      }
    }
  }
  // The quadrature's masses are not exactly int phi_k: scale each channel so
  // that the coarse integral equals the fine one (the power to shoot).
  RGB coarseTotal, coarseUnshot;
  for (std::size_t k = 0; k < count; ++k)
  {
    coarseTotal += coarse.Total[k] * this->Mass[k];
    coarseUnshot += coarse.Unshot[k] * this->Mass[k];
  }
  for (int c = 0; c < 3; ++c)
  {
    const double totalScale = coarseTotal[c] > 0.0 ? totalIntegral[c] / coarseTotal[c] : 1.0;
    const double unshotScale = coarseUnshot[c] > 0.0 ? unshotIntegral[c] / coarseUnshot[c] : 1.0;
    for (std::size_t k = 0; k < count; ++k)
    {
      coarse.Total[k][c] *= totalScale;
      coarse.Unshot[k][c] *= unshotScale;
    }
  }
  for (std::size_t s = 0; s < this->Separate.size(); ++s)
  {
    const int k = this->Separate[s];
    coarse.Points.push_back(this->SeparatePoints[s]);
    coarse.Total.push_back(fine.Total[k]);
    coarse.Unshot.push_back(fine.Unshot[k]);
  }
  return coarse;
}

void IndirectLevel::Prolong(
  const SurfaceSamples& before, const SurfaceSamples& after, SurfaceSamples& fine) const
{
  const std::size_t coarseCount = this->Points.size() + this->Separate.size();
  if (before.Total.size() != coarseCount || after.Total.size() != coarseCount ||
    fine.Total.size() != this->FineLocations.size())
  {
    throw InputError("IndirectLevel::Prolong: the samples are not those of this level");
  }
  for (std::size_t k = 0; k < this->FineLocations.size(); ++k)
  {
    if (!this->SeparateIndex.empty() && this->SeparateIndex[k] >= 0)
    {
      const std::size_t own = this->Points.size() + this->SeparateIndex[k];
      fine.Total[k] += after.Total[own] + before.Total[own] * -1.0;
      continue;
    }
    const Location& where = this->FineLocations[k];
    for (int c = 0; c < 3; ++c)
    {
      const int id = where.Corners[c];
      fine.Total[k] += (after.Total[id] + before.Total[id] * -1.0) * where.Weights[c];
    }
  }
}

double IndirectSpacing(
  const Scene& scene, const std::vector<std::size_t>& finePoints, std::size_t budget)
{
  std::size_t total = 0;
  for (const std::size_t count : finePoints)
  {
    total += count;
  }
  if (total <= budget)
  {
    return 0.0;
  }
  struct Shape
  {
    std::size_t Fine, Ears;
    double Longest;
  };
  std::vector<Shape> shapes;
  for (std::size_t i = 0; i < finePoints.size() && i < scene.Surfaces.size(); ++i)
  {
    if (finePoints[i] > 0)
    {
      Vec3 normal;
      std::vector<std::array<int, 3>> ears;
      const double longest = EarTriangles(scene.Surfaces[i], normal, ears);
      shapes.push_back({ finePoints[i], ears.size(), longest });
    }
  }
  const auto count = [&](double spacing) {
    std::size_t sum = 0;
    for (const Shape& s : shapes)
    {
      sum += std::min(s.Fine, LatticeCount(s.Ears, ResolutionFor(s.Longest, spacing)));
    }
    return sum;
  };
  // count() falls as the spacing grows; bisect on its logarithm for the
  // smallest spacing within the budget.
  double hi = 2.0 * std::max(scene.Size(), 1e-300);
  double lo = hi / MaximumResolution / 4.0;
  if (count(hi) > budget)
  {
    return hi;
  }
  for (int iteration = 0; iteration < 60; ++iteration)
  {
    const double mid = std::sqrt(lo * hi);
    (count(mid) > budget ? lo : hi) = mid;
  }
  return hi;
}

} // namespace penumbra
