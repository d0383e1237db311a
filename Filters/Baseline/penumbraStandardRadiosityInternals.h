// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraStandardRadiosityInternals.h
 * @brief The state of a standard radiosity solution (StandardRadiosity::Internals):
 * its vertices, elements and patches, and the steps that build and refine
 * them. Private to Penumbra::Baseline: the uniform mesh is built in
 * penumbraStandardRadiosityMesh.cxx, shot and subdivided in
 * penumbraStandardRadiosity.cxx.
 */
#ifndef penumbraStandardRadiosityInternals_h
#define penumbraStandardRadiosityInternals_h

#include "penumbraRayCastEvaluator.h"
#include "penumbraScene.h"
#include "penumbraStandardRadiosity.h"

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

namespace penumbra
{
namespace baseline
{

/// A mesh vertex, where the radiosity (Total) is computed.
struct Vertex
{
  Vec3 Position;
  Vec3 Evaluation; ///< where its radiance is computed (see InwardPoint)
  int Surface = -1;
  RGB Total;
  RGB IncidentOverPi; ///< irradiance / pi gathered so far (black surfaces too)
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

/// A triangle of lattice points (i, j).
using LatticeTriangle = std::array<std::array<int, 2>, 3>;

/// The lattice points of one surface's ear triangles, N x N per ear.
struct SurfaceLattice
{
  int Surface = -1;
  int N = 1;
  std::vector<std::array<int, 3>> Ears; ///< polygon vertex ids of each ear
  std::map<std::array<int, 4>, int> Ids; ///< lattice point key -> vertex id
};

} // namespace baseline

struct StandardRadiosity::Internals
{
  Scene SceneCopy;
  std::vector<PolygonGeometry> Geometry;
  std::unique_ptr<RayCaster> Caster;
  StandardRadiositySettings Settings;
  ParallelFor Loop;

  std::vector<baseline::Vertex> Vertices;
  std::vector<baseline::Element> Elements;
  std::vector<baseline::Patch> Patches;
  std::unordered_map<std::uint64_t, int> Midpoints; ///< edge (vertex ids) -> its midpoint
  std::vector<baseline::PastShot> History;
  double ReferenceRadiance = 0.0;
  int SubdividedElements = 0;
  long long Rays = 0;
  ShootingEnergy Energy;

  void Reset();
  double EarCorners(int surface, std::vector<std::array<int, 3>>& ears) const;
  int LatticeVertex(baseline::SurfaceLattice& lattice, int ear, int i, int j);
  baseline::Patch MakePatch(baseline::SurfaceLattice& lattice, int ear,
    baseline::LatticeTriangle& a, const std::vector<baseline::LatticeTriangle>& sampleCells);
  void AddPatchElements(baseline::SurfaceLattice& lattice, int ear,
    const baseline::LatticeTriangle& a, int k,
    const std::vector<baseline::LatticeTriangle>& elementCells, baseline::Patch& patch);
  void BuildSurfaceMesh(int surface);
  void BuildMesh();
  double FormFactor(const Vec3& x, const Vec3& n, int receiver, int patch, long long& rays) const;
  RGB TotalUnshotPower() const;
  int SelectPatch() const;
  ShotRecord Shoot(int patch);
  void CollectHanging(int a, int b, std::vector<int>& out) const;
  bool NeedsSplit(const baseline::Element& e, std::vector<int>& ring) const;
  int Midpoint(int a, int b, std::vector<int>& created);
  void Subdivide(const std::vector<char>& changed);
  Vec3 InwardPoint(const Vec3& p, int surface) const;
};

} // namespace penumbra

#endif
