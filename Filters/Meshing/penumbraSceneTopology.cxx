// SPDX-License-Identifier: GPL-3.0-or-later
// Shared vertices, shared edges and connected components of the scene's polygons.
#include "penumbraSceneTopology.h"

#include "penumbraMeshingTolerances.h"
#include "penumbraUnionFind.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace penumbra
{
namespace detail
{

void SceneTopology::Build(const Scene& scene)
{
  this->Size = std::max(scene.Size(), 1e-300);
  this->BuildVertexClusters(scene);
  this->BuildEdges();
  this->BuildComponents();
}

void SceneTopology::EdgeEnds(int e, Vec3& a, Vec3& b) const
{
  a = this->ClusterPoint[this->EdgeClusters[e][0]];
  b = this->ClusterPoint[this->EdgeClusters[e][1]];
}

void SceneTopology::BuildVertexClusters(const Scene& scene)
{
  const std::size_t count = scene.Surfaces.size();
  this->Polygons.resize(count);
  // Vertex clusters: vertices within kVertexMatch of each other are one
  // feature (shared by several polygons of a solid).
  const double match = kVertexMatch * this->Size;
  const double cell = 2.0 * match;
  struct Key
  {
    long long X, Y, Z;
    bool operator==(const Key& o) const { return X == o.X && Y == o.Y && Z == o.Z; }
  };
  struct KeyHash
  {
    std::size_t operator()(const Key& k) const
    {
      return std::hash<long long>()(k.X * 73856093LL ^ k.Y * 19349663LL ^ k.Z * 83492791LL);
    }
  };
  std::unordered_map<Key, std::vector<int>, KeyHash> grid;
  auto keyOf = [cell](const Vec3& p) {
    return Key{ static_cast<long long>(std::floor(p.X / cell)),
      static_cast<long long>(std::floor(p.Y / cell)),
      static_cast<long long>(std::floor(p.Z / cell)) };
  };
  for (std::size_t k = 0; k < count; ++k)
  {
    PolygonData& p = this->Polygons[k];
    p.V = scene.Surfaces[k].Vertices;
    const PolygonGeometry g = ComputePolygonGeometry(p.V);
    p.N = g.Normal;
    p.D = g.Offset;
    p.Centroid = g.Centroid;
    p.Diameter = g.Diameter;
    p.Area = g.Area;
    p.Cluster.assign(p.V.size(), -1);
    for (std::size_t i = 0; i < p.V.size(); ++i)
    {
      const Key key = keyOf(p.V[i]);
      int found = -1;
      for (long long dx = -1; dx <= 1 && found < 0; ++dx)
      {
        for (long long dy = -1; dy <= 1 && found < 0; ++dy)
        {
          for (long long dz = -1; dz <= 1 && found < 0; ++dz)
          {
            auto it = grid.find(Key{ key.X + dx, key.Y + dy, key.Z + dz });
            if (it == grid.end())
            {
              continue;
            }
            for (int c : it->second)
            {
              if (Length(this->ClusterPoint[c] - p.V[i]) <= match)
              {
                found = c;
                break;
              }
            }
          }
        }
      }
      if (found < 0)
      {
        found = static_cast<int>(this->ClusterPoint.size());
        this->ClusterPoint.push_back(p.V[i]);
        this->ClusterUses.emplace_back();
        grid[key].push_back(found);
      }
      p.Cluster[i] = found;
      this->ClusterUses[found].push_back({ static_cast<int>(k), static_cast<int>(i) });
    }
  }
}

void SceneTopology::BuildEdges()
{
  const std::size_t count = this->Polygons.size();
  // Edges: identified by their (unordered) pair of end clusters.
  std::unordered_map<long long, int> edgeIds;
  for (std::size_t k = 0; k < count; ++k)
  {
    PolygonData& p = this->Polygons[k];
    const std::size_t n = p.V.size();
    p.Edge.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
    {
      const int a = p.Cluster[i], b = p.Cluster[(i + 1) % n];
      const long long key = static_cast<long long>(std::min(a, b)) * 4294967296LL +
        static_cast<long long>(std::max(a, b));
      auto it = edgeIds.find(key);
      int id;
      if (it == edgeIds.end())
      {
        id = static_cast<int>(this->EdgeUses.size());
        edgeIds.emplace(key, id);
        this->EdgeUses.emplace_back();
        this->EdgeClusters.push_back({ std::min(a, b), std::max(a, b) });
      }
      else
      {
        id = it->second;
      }
      p.Edge[i] = id;
      this->EdgeUses[id].push_back({ static_cast<int>(k), static_cast<int>(i) });
    }
  }
}

void SceneTopology::BuildComponents()
{
  const std::size_t count = this->Polygons.size();
  // Connected components through shared edges, and their open edges.
  UnionFind comps(count);
  for (const auto& uses : this->EdgeUses)
  {
    for (std::size_t u = 1; u < uses.size(); ++u)
    {
      comps.Union(uses[0].Polygon, uses[u].Polygon);
    }
  }
  std::unordered_map<int, int> compIndex;
  for (std::size_t k = 0; k < count; ++k)
  {
    const int root = comps.Find(static_cast<int>(k));
    auto it = compIndex.find(root);
    if (it == compIndex.end())
    {
      it = compIndex.emplace(root, static_cast<int>(this->ComponentPolygons.size())).first;
      this->ComponentPolygons.emplace_back();
      this->ComponentOpenEdges.emplace_back();
    }
    this->Polygons[k].Component = it->second;
    this->ComponentPolygons[it->second].push_back(static_cast<int>(k));
  }
  const std::size_t components = this->ComponentPolygons.size();
  this->ComponentCentre.assign(components, Vec3());
  this->ComponentRadius.assign(components, 0.0);
  for (std::size_t c = 0; c < components; ++c)
  {
    Vec3 lo = this->Polygons[this->ComponentPolygons[c][0]].V[0];
    Vec3 hi = lo;
    for (const int k : this->ComponentPolygons[c])
    {
      for (const Vec3& v : this->Polygons[k].V)
      {
        lo = { std::min(lo.X, v.X), std::min(lo.Y, v.Y), std::min(lo.Z, v.Z) };
        hi = { std::max(hi.X, v.X), std::max(hi.Y, v.Y), std::max(hi.Z, v.Z) };
      }
    }
    const Vec3 centre = (lo + hi) * 0.5;
    double radius = 0.0;
    for (const int k : this->ComponentPolygons[c])
    {
      for (const Vec3& v : this->Polygons[k].V)
      {
        radius = std::max(radius, Length(v - centre));
      }
    }
    this->ComponentCentre[c] = centre;
    this->ComponentRadius[c] = radius;
  }
  for (std::size_t e = 0; e < this->EdgeUses.size(); ++e)
  {
    if (this->EdgeUses[e].size() != 2)
    {
      const int c = this->Polygons[this->EdgeUses[e][0].Polygon].Component;
      this->ComponentOpenEdges[c].push_back(static_cast<int>(e));
    }
  }
}

} // namespace detail
} // namespace penumbra
