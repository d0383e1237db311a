// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraStandardRadiosity.h"

#include "penumbraFormFactor.h"
#include "penumbraMath.h"
#include "penumbraParallel.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraTimer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>

namespace penumbra
{
namespace
{
struct Vertex
{
  Vec3 Position;
  Vec3 Evaluation; ///< where its radiance is computed (see InwardPoint)
  int Surface = -1;
  RGB Total;
};

/// A constant-radiosity receiving element: a triangle of vertex ids.
struct Element
{
  std::array<int, 3> Corners;
  int Patch = -1;
  int Depth = 0;
  bool Leaf = true;
  double Area = 0.0;
  RGB Unshot; ///< unshot radiance, constant over the element
};

/// A shooting patch: a triangle with its visibility sample points.
struct Patch
{
  int Surface = -1;
  std::array<Vec3, 3> Corners;
  double Area = 0.0;
  std::vector<Vec3> Samples; ///< centroids of a uniform s x s subdivision
  double SampleArea = 0.0;
  std::vector<int> Elements; ///< every element ever made in it (leaves and parents)
  RGB UnshotPower;           ///< pi * sum of its leaf elements' unshot radiance * area
};

/// One past shot: which patch shot which constant radiance.
struct PastShot
{
  int Patch;
  RGB Radiance;
};

double TriangleArea(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return 0.5 * Length(Cross(b - a, c - a));
}

RGB Difference(const RGB& a, const RGB& b)
{
  return RGB(a.R - b.R, a.G - b.G, a.B - b.B);
}

std::uint64_t EdgeKey(int a, int b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

/// Sub-triangles of a uniform n x n subdivision of a triangle, as lattice
/// coordinates (i, j) of their corners (point = A + (B - A) i / n + (C - A) j / n),
/// all with the orientation of (A, B, C).
std::vector<std::array<std::array<int, 2>, 3>> UniformSubdivision(int n)
{
  std::vector<std::array<std::array<int, 2>, 3>> out;
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j + i < n; ++j)
    {
      out.push_back({ { { i, j }, { i + 1, j }, { i, j + 1 } } });
      if (i + j < n - 1)
      {
        out.push_back({ { { i + 1, j }, { i + 1, j + 1 }, { i, j + 1 } } });
      }
    }
  }
  return out;
}
}

void StandardRadiositySettings::Validate() const
{
  auto fail = [](const std::string& what) { throw InputError(what); };
  if (!(this->PatchSize > 0.0 && this->PatchSize <= 1.0))
  {
    fail("PatchSize must be in (0, 1], got " + std::to_string(this->PatchSize));
  }
  if (!(this->ElementSize > 0.0 && this->ElementSize <= 1.0))
  {
    fail("ElementSize must be in (0, 1], got " + std::to_string(this->ElementSize));
  }
  if (this->ShooterSamples < 1 || this->ShooterSamples > 32)
  {
    fail("ShooterSamples must be in [1, 32], got " + std::to_string(this->ShooterSamples));
  }
  if (!(this->SubdivisionThreshold > 0.0))
  {
    fail("SubdivisionThreshold must be positive, got " + std::to_string(this->SubdivisionThreshold));
  }
  if (this->MaximumSubdivisionDepth < 0 || this->MaximumSubdivisionDepth > 12)
  {
    fail("MaximumSubdivisionDepth must be in [0, 12], got " +
      std::to_string(this->MaximumSubdivisionDepth));
  }
  if (!(this->UnshotFraction >= 0.0 && this->UnshotFraction <= 1.0))
  {
    fail("UnshotFraction must be in [0, 1], got " + std::to_string(this->UnshotFraction));
  }
  if (this->MaximumShots < 0)
  {
    fail("MaximumShots must be >= 0, got " + std::to_string(this->MaximumShots));
  }
}

struct StandardRadiosity::Internals
{
  Scene SceneCopy;
  std::vector<PolygonGeometry> Geometry;
  std::unique_ptr<RayCaster> Caster;
  StandardRadiositySettings Settings;
  ParallelFor Loop;

  std::vector<Vertex> Vertices;
  std::vector<Element> Elements;
  std::vector<Patch> Patches;
  std::unordered_map<std::uint64_t, int> Midpoints; ///< edge (vertex ids) -> its midpoint
  std::vector<PastShot> History;
  double ReferenceRadiance = 0.0;
  int SubdividedElements = 0;
  long long Rays = 0;
  ShootingEnergy Energy;

  void Reset();
  void BuildSurfaceMesh(int surface);
  void BuildMesh();
  double FormFactor(const Vec3& x, const Vec3& n, int receiver, int patch, long long& rays) const;
  RGB TotalUnshotPower() const;
  int SelectPatch() const;
  ShotRecord Shoot(int patch);
  void CollectHanging(int a, int b, std::vector<int>& out) const;
  bool NeedsSplit(const Element& e, std::vector<int>& ring) const;
  int Midpoint(int a, int b, std::vector<int>& created);
  void Subdivide(const std::vector<char>& changed);
  Vec3 InwardPoint(const Vec3& p, int surface) const;
};

/**
 * A vertex on its surface's outline lies in the plane of a neighbouring
 * surface that meets it there (a wall on the floor's edge), which it would
 * then not see at all, although the limit from inside sees half a
 * hemisphere of it. It is evaluated as that limit: moved inside along the
 * sum of the inward normals of the outline edges through it, by 1e-4 of the
 * scene's size (far above Embree's single-precision resolution, far below
 * any element). Other vertices are evaluated where they are.
 */
Vec3 StandardRadiosity::Internals::InwardPoint(const Vec3& p, int surface) const
{
  const std::vector<Vec3>& v = this->SceneCopy.Surfaces[surface].Vertices;
  const Vec3& normal = this->Geometry[surface].Normal;
  const double size = this->SceneCopy.Size();
  Vec3 inward;
  for (std::size_t q = 0; q < v.size(); ++q)
  {
    const Vec3& a = v[q];
    const Vec3 edge = v[(q + 1) % v.size()] - a;
    const double t = std::min(1.0, std::max(0.0, Dot(p - a, edge) / SquaredLength(edge)));
    if (Length(a + edge * t - p) <= 1e-9 * size)
    {
      inward += Normalized(Cross(normal, edge)); // counter-clockwise: inside is on the left
    }
  }
  return SquaredLength(inward) > 0.0 ? p + Normalized(inward) * (1e-4 * size) : p;
}

void StandardRadiosity::Internals::Reset()
{
  this->Vertices.clear();
  this->Elements.clear();
  this->Patches.clear();
  this->Midpoints.clear();
  this->History.clear();
  this->SubdividedElements = 0;
  this->Rays = 0;
  this->Energy = ShootingEnergy();
}

void StandardRadiosity::Internals::BuildSurfaceMesh(int surface)
{
  const Surface& s = this->SceneCopy.Surfaces[surface];
  const Vec3 normal = this->Geometry[surface].Normal;
  const int first = this->Caster->GetFirstTriangle(surface);
  const int count = this->Caster->GetNumberOfSurfaceTriangles(surface);
  if (count == 0)
  {
    return;
  }
  // The ear triangles' corners are copies of the polygon's vertices: recover
  // their indices, so that points on shared edges are made once.
  std::vector<std::array<int, 3>> ears(count);
  double longest = 0.0;
  for (int t = 0; t < count; ++t)
  {
    Vec3 c[3];
    this->Caster->GetTriangle(first + t, c);
    for (int k = 0; k < 3; ++k)
    {
      const auto found = std::find_if(s.Vertices.begin(), s.Vertices.end(),
        [&](const Vec3& v) { return v.X == c[k].X && v.Y == c[k].Y && v.Z == c[k].Z; });
      ears[t][k] = static_cast<int>(found - s.Vertices.begin());
      longest = std::max(longest, Length(c[(k + 1) % 3] - c[k]));
    }
  }
  const double size = this->SceneCopy.Size();
  const int m = std::max(1, static_cast<int>(std::ceil(longest / (this->Settings.PatchSize * size))));
  const int k = std::max(
    1, static_cast<int>(std::ceil(longest / m / (this->Settings.ElementSize * size))));
  const int n = m * k; // lattice resolution of each ear triangle

  // Lattice point -> vertex id, keyed so that a point on an ear's edge or
  // corner gets the same id (and bit-identical position) from both ears.
  std::map<std::array<int, 4>, int> ids;
  auto vertexAt = [&](int ear, int i, int j) {
    const std::array<int, 3>& c = ears[ear];
    const std::vector<Vec3>& v = s.Vertices;
    std::array<int, 4> key;
    Vec3 position;
    auto onEdge = [&](int a, int b, int p) {
      if (a > b)
      {
        std::swap(a, b);
        p = n - p;
      }
      key = { 1, a, b, p };
      position = v[a] + (v[b] - v[a]) * (static_cast<double>(p) / n);
    };
    const int l = n - i - j;
    if (i == 0 && j == 0)
    {
      key = { 0, c[0], 0, 0 };
      position = v[c[0]];
    }
    else if (i == n || j == n)
    {
      const int corner = i == n ? c[1] : c[2];
      key = { 0, corner, 0, 0 };
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
    else if (l == 0)
    {
      onEdge(c[1], c[2], j);
    }
    else
    {
      key = { 2, ear, i, j };
      position = v[c[0]] + (v[c[1]] - v[c[0]]) * (static_cast<double>(i) / n) +
        (v[c[2]] - v[c[0]]) * (static_cast<double>(j) / n);
    }
    const auto inserted = ids.emplace(key, static_cast<int>(this->Vertices.size()));
    if (inserted.second)
    {
      Vertex vertex;
      vertex.Position = position;
      vertex.Evaluation = this->InwardPoint(position, surface);
      vertex.Surface = surface;
      vertex.Total = s.Emission;
      this->Vertices.push_back(vertex);
    }
    return inserted.first->second;
  };

  const auto patchCells = UniformSubdivision(m);
  const auto elementCells = UniformSubdivision(k);
  const auto sampleCells = UniformSubdivision(this->Settings.ShooterSamples);
  const double samples = this->Settings.ShooterSamples;
  for (int ear = 0; ear < count; ++ear)
  {
    for (const auto& cell : patchCells)
    {
      // Patch corners in the ear's lattice (scaled by k).
      std::array<std::array<int, 2>, 3> a;
      for (int q = 0; q < 3; ++q)
      {
        a[q] = { cell[q][0] * k, cell[q][1] * k };
      }
      Patch patch;
      patch.Surface = surface;
      for (int q = 0; q < 3; ++q)
      {
        patch.Corners[q] = this->Vertices[vertexAt(ear, a[q][0], a[q][1])].Position;
      }
      // Keep every triangle counter-clockwise about the front normal.
      const bool flip =
        Dot(Cross(patch.Corners[1] - patch.Corners[0], patch.Corners[2] - patch.Corners[0]),
          normal) < 0.0;
      if (flip)
      {
        std::swap(patch.Corners[1], patch.Corners[2]);
        std::swap(a[1], a[2]);
      }
      patch.Area = TriangleArea(patch.Corners[0], patch.Corners[1], patch.Corners[2]);
      const Vec3 du = (patch.Corners[1] - patch.Corners[0]) / samples;
      const Vec3 dv = (patch.Corners[2] - patch.Corners[0]) / samples;
      for (const auto& sub : sampleCells)
      {
        const double u = (sub[0][0] + sub[1][0] + sub[2][0]) / 3.0;
        const double w = (sub[0][1] + sub[1][1] + sub[2][1]) / 3.0;
        patch.Samples.push_back(patch.Corners[0] + du * u + dv * w);
      }
      patch.SampleArea = patch.Area / static_cast<double>(patch.Samples.size());
      const int patchId = static_cast<int>(this->Patches.size());
      for (const auto& sub : elementCells)
      {
        Element e;
        e.Patch = patchId;
        for (int q = 0; q < 3; ++q)
        {
          // a[0] + (a[1] - a[0]) u / k + (a[2] - a[0]) w / k, exact in integers.
          const int i = a[0][0] + ((a[1][0] - a[0][0]) * sub[q][0] + (a[2][0] - a[0][0]) * sub[q][1]) / k;
          const int j = a[0][1] + ((a[1][1] - a[0][1]) * sub[q][0] + (a[2][1] - a[0][1]) * sub[q][1]) / k;
          e.Corners[q] = vertexAt(ear, i, j);
        }
        const Vec3& p0 = this->Vertices[e.Corners[0]].Position;
        const Vec3& p1 = this->Vertices[e.Corners[1]].Position;
        const Vec3& p2 = this->Vertices[e.Corners[2]].Position;
        e.Area = TriangleArea(p0, p1, p2);
        e.Unshot = s.Emission;
        patch.UnshotPower += s.Emission * (Pi * e.Area);
        patch.Elements.push_back(static_cast<int>(this->Elements.size()));
        this->Elements.push_back(e);
      }
      this->Patches.push_back(std::move(patch));
    }
  }
}

void StandardRadiosity::Internals::BuildMesh()
{
  double area = 0.0;
  for (int s = 0; s < static_cast<int>(this->SceneCopy.Surfaces.size()); ++s)
  {
    this->BuildSurfaceMesh(s);
    area += this->Geometry[s].Area;
  }
  const double emitted = this->SceneCopy.EmittedPower().Mean();
  this->ReferenceRadiance = area > 0.0 ? emitted / (Pi * area) : 0.0;
}

double StandardRadiosity::Internals::FormFactor(
  const Vec3& x, const Vec3& n, int receiver, int patchId, long long& rays) const
{
  const Patch& patch = this->Patches[patchId];
  if (receiver == patch.Surface)
  {
    return 0.0; // a planar surface does not see itself
  }
  const Vec3& m = this->Geometry[patch.Surface].Normal;
  if (!(Dot(m, x - patch.Corners[0]) > 0.0))
  {
    return 0.0; // x is behind the patch, which emits from its front only
  }
  thread_local std::vector<Vec3> targets;
  thread_local std::vector<double> weights;
  thread_local std::vector<unsigned char> occluded;
  targets.clear();
  weights.clear();
  double weightSum = 0.0;
  for (const Vec3& y : patch.Samples)
  {
    const Vec3 d = y - x;
    const double r2 = SquaredLength(d);
    const double r = std::sqrt(r2);
    const double cx = Dot(n, d) / r;
    const double cy = -Dot(m, d) / r;
    if (!(cx > 0.0 && cy > 0.0))
    {
      continue;
    }
    const double w = cx * cy * patch.SampleArea / (Pi * r2 + patch.SampleArea);
    targets.push_back(y);
    weights.push_back(w);
    weightSum += w;
  }
  const bool analytic = this->Settings.FormFactor == FormFactorMode::AnalyticVisibility;
  double unoccluded = 0.0;
  if (analytic)
  {
    Vec3 clipped[8];
    const int count = ClipPolygonToHalfSpace(patch.Corners.data(), 3, n, Dot(n, x), clipped);
    unoccluded = count >= 3 ? PointPolygonFormFactor(x, n, clipped, count) : 0.0;
    if (!(unoccluded > 0.0))
    {
      return 0.0;
    }
    if (targets.empty())
    {
      // Only a sliver of the patch, without samples, is in front of x: one
      // ray to that sliver's vertex average decides its visibility.
      Vec3 centre;
      for (int q = 0; q < count; ++q)
      {
        centre += clipped[q];
      }
      targets.push_back(centre / count);
      weights.push_back(1.0);
      weightSum = 1.0;
    }
  }
  if (targets.empty())
  {
    return 0.0;
  }
  occluded.resize(targets.size());
  this->Caster->TraceFrom(x, targets.data(), static_cast<int>(targets.size()), occluded.data(),
    receiver, patch.Surface);
  rays += static_cast<long long>(targets.size());
  double visible = 0.0;
  for (std::size_t q = 0; q < targets.size(); ++q)
  {
    if (!occluded[q])
    {
      visible += weights[q];
    }
  }
  return analytic ? unoccluded * (visible / weightSum) : visible;
}

RGB StandardRadiosity::Internals::TotalUnshotPower() const
{
  RGB total;
  for (const Patch& p : this->Patches)
  {
    total += p.UnshotPower;
  }
  return total;
}

int StandardRadiosity::Internals::SelectPatch() const
{
  int best = -1;
  double bestPower = 0.0;
  for (int p = 0; p < static_cast<int>(this->Patches.size()); ++p)
  {
    const double power = this->Patches[p].UnshotPower.Mean();
    if (power > bestPower)
    {
      best = p;
      bestPower = power;
    }
  }
  return best;
}

ShotRecord StandardRadiosity::Internals::Shoot(int patchId)
{
  const auto start = std::chrono::steady_clock::now();
  Patch& patch = this->Patches[patchId];
  ShotRecord record;
  record.Shooter = patch.Surface;
  record.Power = patch.UnshotPower;
  const RGB radiance = patch.UnshotPower * (1.0 / (Pi * patch.Area));

  // Receivers: surfaces partly in front of the patch with the patch partly
  // in front of them.
  const int surfaces = static_cast<int>(this->SceneCopy.Surfaces.size());
  std::vector<char> receives(surfaces, 0);
  const PolygonGeometry& shooter = this->Geometry[patch.Surface];
  for (int s = 0; s < surfaces; ++s)
  {
    const PolygonGeometry& g = this->Geometry[s];
    if (s == patch.Surface || !(g.Area > 0.0))
    {
      continue;
    }
    bool patchInFront = false;
    for (const Vec3& c : patch.Corners)
    {
      patchInFront = patchInFront || Dot(g.Normal, c) > g.Offset;
    }
    bool receiverInFront = false;
    for (const Vec3& v : this->SceneCopy.Surfaces[s].Vertices)
    {
      receiverInFront = receiverInFront || Dot(shooter.Normal, v) > shooter.Offset;
    }
    receives[s] = patchInFront && receiverInFront;
    record.Receivers += receives[s];
  }

  const std::size_t count = this->Vertices.size();
  std::vector<double> factors(count, 0.0);
  std::vector<long long> rays(count, 0);
  RunParallel(this->Loop, count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
    {
      const Vertex& vertex = this->Vertices[v];
      if (receives[vertex.Surface])
      {
        factors[v] = this->FormFactor(vertex.Evaluation, this->Geometry[vertex.Surface].Normal,
          vertex.Surface, patchId, rays[v]);
      }
    }
  });
  for (std::size_t v = 0; v < count; ++v)
  {
    Vertex& vertex = this->Vertices[v];
    if (receives[vertex.Surface])
    {
      ++record.Samples;
      record.Rays += rays[v];
      vertex.Total += this->SceneCopy.Surfaces[vertex.Surface].Reflectance * radiance * factors[v];
    }
  }
  this->Rays += record.Rays;
  for (Element& e : this->Elements)
  {
    const int surface = this->Patches[e.Patch].Surface;
    if (!e.Leaf || !receives[surface])
    {
      continue;
    }
    const double f = (factors[e.Corners[0]] + factors[e.Corners[1]] + factors[e.Corners[2]]) / 3.0;
    if (!(f > 0.0))
    {
      continue;
    }
    const RGB& rho = this->SceneCopy.Surfaces[surface].Reflectance;
    const RGB incident = radiance * (Pi * f * e.Area);
    record.Incident += incident;
    record.Absorbed += RGB(1.0 - rho.R, 1.0 - rho.G, 1.0 - rho.B) * incident;
    const RGB reflected = rho * radiance * f;
    e.Unshot += reflected;
    this->Patches[e.Patch].UnshotPower += reflected * (Pi * e.Area);
  }
  for (int e : patch.Elements)
  {
    this->Elements[e].Unshot = RGB();
  }
  patch.UnshotPower = RGB();
  this->History.push_back({ patchId, radiance });

  record.Escaped = Difference(record.Power, record.Incident);
  this->Energy.ShotAbsorbed += record.Absorbed;
  this->Energy.ShotEscaped += record.Escaped;
  this->Subdivide(receives);
  this->Energy.Unshot = this->TotalUnshotPower();
  record.UnshotAfter = this->Energy.Unshot.Mean();
  record.Seconds = Seconds(start);
  return record;
}

void StandardRadiosity::Internals::CollectHanging(int a, int b, std::vector<int>& out) const
{
  const auto found = this->Midpoints.find(EdgeKey(a, b));
  if (found == this->Midpoints.end())
  {
    return;
  }
  this->CollectHanging(a, found->second, out);
  out.push_back(found->second);
  this->CollectHanging(found->second, b, out);
}

bool StandardRadiosity::Internals::NeedsSplit(const Element& e, std::vector<int>& ring) const
{
  ring.clear();
  for (int q = 0; q < 3; ++q)
  {
    ring.push_back(e.Corners[q]);
    this->CollectHanging(e.Corners[q], e.Corners[(q + 1) % 3], ring);
  }
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (int v : ring)
  {
    const double value = this->Vertices[v].Total.Mean();
    low = std::min(low, value);
    high = std::max(high, value);
  }
  // Relative to the element's brightest vertex, but never below the scene's
  // reference radiance: differences in dark regions do not matter as much.
  return high - low > this->Settings.SubdivisionThreshold * std::max(high, this->ReferenceRadiance);
}

int StandardRadiosity::Internals::Midpoint(int a, int b, std::vector<int>& created)
{
  const auto inserted = this->Midpoints.emplace(EdgeKey(a, b), static_cast<int>(this->Vertices.size()));
  if (inserted.second)
  {
    Vertex vertex;
    vertex.Position = (this->Vertices[a].Position + this->Vertices[b].Position) * 0.5;
    vertex.Surface = this->Vertices[a].Surface;
    vertex.Evaluation = this->InwardPoint(vertex.Position, vertex.Surface);
    this->Vertices.push_back(vertex);
    created.push_back(inserted.first->second);
  }
  return inserted.first->second;
}

void StandardRadiosity::Internals::Subdivide(const std::vector<char>& changed)
{
  if (this->Settings.MaximumSubdivisionDepth == 0 ||
    !std::isfinite(this->Settings.SubdivisionThreshold))
  {
    return;
  }
  std::vector<int> ring;
  std::vector<int> split;
  std::vector<int> created;
  while (true)
  {
    split.clear();
    for (int e = 0; e < static_cast<int>(this->Elements.size()); ++e)
    {
      // Only the surfaces the shot changed can have new differences.
      const Element& element = this->Elements[e];
      if (element.Leaf && element.Depth < this->Settings.MaximumSubdivisionDepth &&
        changed[this->Vertices[element.Corners[0]].Surface] &&
        this->NeedsSplit(element, ring))
      {
        split.push_back(e);
      }
    }
    if (split.empty())
    {
      return;
    }
    created.clear();
    for (int e : split)
    {
      const Element parent = this->Elements[e];
      const std::array<int, 3>& c = parent.Corners;
      const int ab = this->Midpoint(c[0], c[1], created);
      const int bc = this->Midpoint(c[1], c[2], created);
      const int ca = this->Midpoint(c[2], c[0], created);
      const std::array<std::array<int, 3>, 4> children = {
        { { c[0], ab, ca }, { ab, c[1], bc }, { ca, bc, c[2] }, { ab, bc, ca } }
      };
      this->Elements[e].Leaf = false;
      for (const auto& corners : children)
      {
        Element child;
        child.Corners = corners;
        child.Patch = parent.Patch;
        child.Depth = parent.Depth + 1;
        child.Area = parent.Area / 4.0; // midpoint split: four congruent quarters
        child.Unshot = parent.Unshot;   // constant: the patch's power is unchanged
        this->Patches[parent.Patch].Elements.push_back(static_cast<int>(this->Elements.size()));
        this->Elements.push_back(child);
      }
    }
    this->SubdividedElements += static_cast<int>(split.size());
    // New vertices gather every past shot, as if they had existed from the start.
    std::vector<long long> rays(created.size(), 0);
    RunParallel(this->Loop, created.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t q = begin; q < end; ++q)
      {
        Vertex& vertex = this->Vertices[created[q]];
        const Surface& s = this->SceneCopy.Surfaces[vertex.Surface];
        const Vec3& n = this->Geometry[vertex.Surface].Normal;
        RGB total = s.Emission;
        for (const PastShot& shot : this->History)
        {
          const double f = this->FormFactor(vertex.Evaluation, n, vertex.Surface, shot.Patch, rays[q]);
          total += s.Reflectance * shot.Radiance * f;
        }
        vertex.Total = total;
      }
    });
    for (long long r : rays)
    {
      this->Rays += r;
    }
  }
}

StandardRadiosity::StandardRadiosity(const Scene& scene)
  : Internal(new Internals)
{
  ValidateScene(scene);
  this->Internal->SceneCopy = scene;
  for (const Surface& s : scene.Surfaces)
  {
    this->Internal->Geometry.push_back(ComputePolygonGeometry(s.Vertices));
  }
  this->Internal->Caster.reset(new RayCaster(scene));
}

StandardRadiosity::~StandardRadiosity() = default;

void StandardRadiosity::SetSettings(const StandardRadiositySettings& settings)
{
  settings.Validate();
  this->Internal->Settings = settings;
}

const StandardRadiositySettings& StandardRadiosity::GetSettings() const
{
  return this->Internal->Settings;
}

void StandardRadiosity::SetParallelFor(ParallelFor parallelFor)
{
  this->Internal->Loop = std::move(parallelFor);
}

StandardRadiositySummary StandardRadiosity::Run(const ShotCallback& callback)
{
  Internals& I = *this->Internal;
  const auto start = std::chrono::steady_clock::now();
  I.Reset();
  I.BuildMesh();
  StandardRadiositySummary summary;
  I.Energy.Emitted = I.SceneCopy.EmittedPower();
  I.Energy.InitialUnshot = I.TotalUnshotPower();
  // Rounding only: the elements' areas sum to the polygons' areas.
  I.Energy.PriorEscaped = Difference(I.Energy.Emitted, I.Energy.InitialUnshot);
  I.Energy.Unshot = I.Energy.InitialUnshot;
  const double emitted = I.Energy.Emitted.Mean();
  const double initial = I.Energy.InitialUnshot.Mean();
  const double target = I.Settings.UnshotFraction * emitted;
  while (!ShootingDone(
    I.TotalUnshotPower().Mean(), target, summary.Shots, I.Settings.MaximumShots, summary.Reason))
  {
    const int patch = I.SelectPatch();
    if (patch < 0)
    {
      summary.Reason = StopReason::NothingToShoot;
      break;
    }
    const ShotRecord record = I.Shoot(patch);
    ++summary.Shots;
    if (callback &&
      !callback(record,
        ShootingProgress(record.UnshotAfter, initial, target, summary.Shots, I.Settings.MaximumShots)))
    {
      summary.Reason = StopReason::Aborted;
      break;
    }
  }
  I.Energy.Unshot = I.TotalUnshotPower();
  summary.UnshotFraction = emitted > 0.0 ? I.Energy.Unshot.Mean() / emitted : 0.0;
  summary.Patches = static_cast<int>(I.Patches.size());
  summary.Elements = static_cast<int>(
    std::count_if(I.Elements.begin(), I.Elements.end(), [](const Element& e) { return e.Leaf; }));
  summary.Vertices = static_cast<int>(I.Vertices.size());
  summary.SubdividedElements = I.SubdividedElements;
  summary.Rays = I.Rays;
  summary.Energy = I.Energy;
  summary.Seconds = Seconds(start);
  return summary;
}

StandardRadiosityMesh StandardRadiosity::GetMesh() const
{
  const Internals& I = *this->Internal;
  StandardRadiosityMesh mesh;
  for (const Vertex& v : I.Vertices)
  {
    mesh.Points.push_back(v.Position);
    mesh.Radiance.push_back(v.Total);
  }
  std::vector<int> ring;
  for (const Element& e : I.Elements)
  {
    if (!e.Leaf)
    {
      continue;
    }
    const int surface = I.Patches[e.Patch].Surface;
    ring.clear();
    for (int q = 0; q < 3; ++q)
    {
      ring.push_back(e.Corners[q]);
      I.CollectHanging(e.Corners[q], e.Corners[(q + 1) % 3], ring);
    }
    if (ring.size() == 3)
    {
      mesh.Triangles.push_back(e.Corners);
      mesh.TriangleSurface.push_back(surface);
      continue;
    }
    // T-vertices: fan from the centroid, valued as the element's linear
    // interpolant there, so the display has no cracks.
    const int centre = static_cast<int>(mesh.Points.size());
    Vec3 position;
    RGB value;
    for (int q = 0; q < 3; ++q)
    {
      position += I.Vertices[e.Corners[q]].Position;
      value += I.Vertices[e.Corners[q]].Total;
    }
    mesh.Points.push_back(position / 3.0);
    mesh.Radiance.push_back(value * (1.0 / 3.0));
    for (std::size_t q = 0; q < ring.size(); ++q)
    {
      mesh.Triangles.push_back({ centre, ring[q], ring[(q + 1) % ring.size()] });
      mesh.TriangleSurface.push_back(surface);
    }
  }
  // Outline: directed edges whose reverse no triangle of the surface uses
  // (surfaces have separate vertices, so edges never pair across surfaces).
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& t : mesh.Triangles)
  {
    for (int q = 0; q < 3; ++q)
    {
      ++uses[EdgeKey(t[q], t[(q + 1) % 3])];
    }
  }
  for (std::size_t t = 0; t < mesh.Triangles.size(); ++t)
  {
    const auto& tri = mesh.Triangles[t];
    for (int q = 0; q < 3; ++q)
    {
      if (uses[EdgeKey(tri[q], tri[(q + 1) % 3])] == 1)
      {
        mesh.BoundaryEdges.push_back({ tri[q], tri[(q + 1) % 3] });
        mesh.BoundaryEdgeSurface.push_back(mesh.TriangleSurface[t]);
      }
    }
  }
  return mesh;
}

namespace
{
void CheckPatchId(int patchId, int count)
{
  if (patchId < 0 || patchId >= count)
  {
    throw InputError(
      "patch " + std::to_string(patchId) + " out of range (" + std::to_string(count) + " patches)");
  }
}
}

double StandardRadiosity::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int patchId) const
{
  CheckPatchId(patchId, this->GetNumberOfPatches());
  long long rays = 0;
  return this->Internal->FormFactor(x, n, receiverId, patchId, rays);
}

int StandardRadiosity::GetNumberOfPatches() const
{
  return static_cast<int>(this->Internal->Patches.size());
}

std::array<Vec3, 3> StandardRadiosity::GetPatch(int patchId) const
{
  CheckPatchId(patchId, this->GetNumberOfPatches());
  return this->Internal->Patches[patchId].Corners;
}

} // namespace penumbra
