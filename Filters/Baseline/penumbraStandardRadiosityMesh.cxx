// SPDX-License-Identifier: GPL-3.0-or-later
// The uniform mesh of standard radiosity: patches and elements on a lattice
// of each surface's ear triangles.
#include "penumbraStandardRadiosityInternals.h"

#include "penumbraMath.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra
{

using baseline::Element;
using baseline::LatticeTriangle;
using baseline::Patch;
using baseline::SurfaceLattice;
using baseline::Vertex;

namespace
{

double TriangleArea(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return 0.5 * Length(Cross(b - a, c - a));
}

/// Sub-triangles of a uniform n x n subdivision of a triangle, as lattice
/// coordinates (i, j) of their corners (point = A + (B - A) i / n + (C - A) j / n),
/// all with the orientation of (A, B, C).
std::vector<LatticeTriangle> UniformSubdivision(int n)
{
  std::vector<LatticeTriangle> out;
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

} // namespace

/**
 * The ear triangles' corners are copies of the polygon's vertices: their
 * indices into the polygon (so that points on shared edges are made once)
 * into `ears`; returns the longest ear edge.
 */
double StandardRadiosity::Internals::EarCorners(
  int surface, std::vector<std::array<int, 3>>& ears) const
{
  const Surface& s = this->SceneCopy.Surfaces[surface];
  const int first = this->Caster->GetFirstTriangle(surface);
  const int count = this->Caster->GetNumberOfSurfaceTriangles(surface);
  ears.assign(count, std::array<int, 3>());
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
  return longest;
}

/**
 * The vertex id of lattice point (i, j) of an ear, made on first use. The
 * key is such that a point on an ear's edge or corner gets the same id (and
 * bit-identical position) from both ears.
 */
int StandardRadiosity::Internals::LatticeVertex(SurfaceLattice& lattice, int ear, int i, int j)
{
  const Surface& s = this->SceneCopy.Surfaces[lattice.Surface];
  const std::array<int, 3>& c = lattice.Ears[ear];
  const std::vector<Vec3>& v = s.Vertices;
  const int n = lattice.N;
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
  const auto inserted = lattice.Ids.emplace(key, static_cast<int>(this->Vertices.size()));
  if (inserted.second)
  {
    Vertex vertex;
    vertex.Position = position;
    vertex.Evaluation = this->InwardPoint(position, lattice.Surface);
    vertex.Surface = lattice.Surface;
    vertex.Total = s.Emission;
    this->Vertices.push_back(vertex);
  }
  return inserted.first->second;
}

/**
 * The patch with corners `a` (lattice points of an ear), counter-clockwise
 * about the surface's front normal (a is reordered to match), with its
 * visibility samples; no elements yet.
 */
Patch StandardRadiosity::Internals::MakePatch(SurfaceLattice& lattice, int ear,
  LatticeTriangle& a, const std::vector<LatticeTriangle>& sampleCells)
{
  const Vec3 normal = this->Geometry[lattice.Surface].Normal;
  const double samples = this->Settings.ShooterSamples;
  Patch patch;
  patch.Surface = lattice.Surface;
  for (int q = 0; q < 3; ++q)
  {
    patch.Corners[q] = this->Vertices[this->LatticeVertex(lattice, ear, a[q][0], a[q][1])].Position;
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
  return patch;
}

/**
 * The elements of `patch` (the next patch id), corners `a` in the ear's
 * lattice: the k x k subdivision `elementCells`, each with the surface's
 * emission as its unshot radiance, added to the patch's unshot power.
 */
void StandardRadiosity::Internals::AddPatchElements(SurfaceLattice& lattice, int ear,
  const LatticeTriangle& a, int k, const std::vector<LatticeTriangle>& elementCells, Patch& patch)
{
  const Surface& s = this->SceneCopy.Surfaces[lattice.Surface];
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
      e.Corners[q] = this->LatticeVertex(lattice, ear, i, j);
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
}

/**
 * The uniform mesh of one surface: each ear triangle is cut into m x m
 * patches of at most PatchSize, each patch into k x k elements of at most
 * ElementSize (scene-relative), on one lattice of resolution m k per ear.
 */
void StandardRadiosity::Internals::BuildSurfaceMesh(int surface)
{
  SurfaceLattice lattice;
  lattice.Surface = surface;
  const double longest = this->EarCorners(surface, lattice.Ears);
  const int count = static_cast<int>(lattice.Ears.size());
  if (count == 0)
  {
    return;
  }
  const double size = this->SceneCopy.Size();
  const int m = std::max(1, static_cast<int>(std::ceil(longest / (this->Settings.PatchSize * size))));
  const int k = std::max(
    1, static_cast<int>(std::ceil(longest / m / (this->Settings.ElementSize * size))));
  lattice.N = m * k; // lattice resolution of each ear triangle

  const auto patchCells = UniformSubdivision(m);
  const auto elementCells = UniformSubdivision(k);
  const auto sampleCells = UniformSubdivision(this->Settings.ShooterSamples);
  for (int ear = 0; ear < count; ++ear)
  {
    for (const auto& cell : patchCells)
    {
      // Patch corners in the ear's lattice (scaled by k).
      LatticeTriangle a;
      for (int q = 0; q < 3; ++q)
      {
        a[q] = { cell[q][0] * k, cell[q][1] * k };
      }
      Patch patch = this->MakePatch(lattice, ear, a, sampleCells);
      this->AddPatchElements(lattice, ear, a, k, elementCells, patch);
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

} // namespace penumbra
