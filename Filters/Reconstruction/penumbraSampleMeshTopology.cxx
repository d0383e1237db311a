// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSampleMeshTopology.cxx
 * @brief Unique edges of a SampleMesh with their kinds, the constrained edges and
 * triangles of each point, and the sectors around each point (corners joined
 * across smooth edges by a union-find).
 */
#include "penumbraReconstructionInternals.h"
#include "penumbraSampleMeshTopology.h"
#include "penumbraUnionFind.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace penumbra
{

using detail::BoundaryEdge;
using detail::ConstrainedEdge;
using detail::Next;
using detail::Prev;
using detail::SmoothEdge;

namespace
{

// Rank of an order for "lowest order wins" (-1 lowest).
int OrderRank(int order)
{
  return order == -1 ? 0 : order + 1;
}

} // namespace

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildEdges()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const std::uint64_t np = static_cast<std::uint64_t>(this->Mesh.GetNumberOfPoints());
  struct Entry
  {
    std::uint64_t Key;
    int Side; // 3 * t + k
  };
  std::vector<Entry> entries(3 * static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int k = 0; k < 3; ++k)
    {
      const std::uint64_t a = static_cast<std::uint64_t>(tri[Next(k)]);
      const std::uint64_t b = static_cast<std::uint64_t>(tri[Prev(k)]);
      entries[3 * t + k] = { std::min(a, b) * np + std::max(a, b), 3 * t + k };
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return x.Key < y.Key || (x.Key == y.Key && x.Side < y.Side);
  });

  // Constraint keys with their lowest order.
  const SampleMesh& m = this->Mesh;
  std::vector<std::pair<std::uint64_t, int>> constraints;
  constraints.reserve(m.EdgeOrders.size());
  for (std::size_t e = 0; e < m.EdgeOrders.size(); ++e)
  {
    const std::uint64_t a = static_cast<std::uint64_t>(m.ConstrainedEdges[2 * e]);
    const std::uint64_t b = static_cast<std::uint64_t>(m.ConstrainedEdges[2 * e + 1]);
    if (a == b)
    {
      continue;
    }
    constraints.emplace_back(std::min(a, b) * np + std::max(a, b), m.EdgeOrders[e]);
  }
  std::sort(constraints.begin(), constraints.end(),
    [](const std::pair<std::uint64_t, int>& x, const std::pair<std::uint64_t, int>& y) {
      return x.first < y.first || (x.first == y.first && OrderRank(x.second) < OrderRank(y.second));
    });

  this->TriangleEdge.assign(3 * static_cast<std::size_t>(nt), -1);
  this->EdgePoints.clear();
  this->EdgeSides.clear();
  this->EdgeKinds.clear();
  std::size_t c = 0;
  for (std::size_t i = 0; i < entries.size();)
  {
    std::size_t j = i;
    while (j < entries.size() && entries[j].Key == entries[i].Key)
    {
      ++j;
    }
    const int id = static_cast<int>(this->EdgeKinds.size());
    const int side0 = entries[i].Side;
    const int* tri0 = this->T(side0 / 3);
    const int a = tri0[Next(side0 % 3)];
    const int b = tri0[Prev(side0 % 3)];
    this->EdgePoints.push_back(std::min(a, b));
    this->EdgePoints.push_back(std::max(a, b));
    signed char kind = BoundaryEdge;
    int side1 = -1;
    if (j - i == 2)
    {
      side1 = entries[i + 1].Side;
      const int* tri1 = this->T(side1 / 3);
      // Consistently oriented neighbours traverse the edge in opposite directions.
      if (tri1[Next(side1 % 3)] == b && tri1[Prev(side1 % 3)] == a)
      {
        kind = SmoothEdge;
        while (c < constraints.size() && constraints[c].first < entries[i].Key)
        {
          ++c;
        }
        if (c < constraints.size() && constraints[c].first == entries[i].Key &&
          constraints[c].second != 2)
        {
          kind = ConstrainedEdge;
        }
      }
    }
    this->EdgeSides.push_back(side0);
    this->EdgeSides.push_back(kind == BoundaryEdge ? -1 : side1);
    this->EdgeKinds.push_back(kind);
    for (std::size_t k = i; k < j; ++k)
    {
      this->TriangleEdge[entries[k].Side] = id;
    }
    i = j;
  }
}

//------------------------------------------------------------------------------
// Constrained edges per point, and triangles per point (CSR).
void Reconstruction::Internals::BuildPointIncidences()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int npi = this->Mesh.GetNumberOfPoints();
  this->PointEdgeStart.assign(npi + 1, 0);
  const int ne = static_cast<int>(this->EdgeKinds.size());
  for (int e = 0; e < ne; ++e)
  {
    if (this->EdgeKinds[e] == ConstrainedEdge)
    {
      ++this->PointEdgeStart[this->EdgePoints[2 * e] + 1];
      ++this->PointEdgeStart[this->EdgePoints[2 * e + 1] + 1];
    }
  }
  for (int i = 0; i < npi; ++i)
  {
    this->PointEdgeStart[i + 1] += this->PointEdgeStart[i];
  }
  this->PointEdges.assign(this->PointEdgeStart[npi], -1);
  {
    std::vector<int> fill(this->PointEdgeStart.begin(), this->PointEdgeStart.end() - 1);
    for (int e = 0; e < ne; ++e)
    {
      if (this->EdgeKinds[e] == ConstrainedEdge)
      {
        this->PointEdges[fill[this->EdgePoints[2 * e]]++] = e;
        this->PointEdges[fill[this->EdgePoints[2 * e + 1]]++] = e;
      }
    }
  }
  this->PointTriangleStart.assign(npi + 1, 0);
  for (int t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      ++this->PointTriangleStart[this->T(t)[k] + 1];
    }
  }
  for (int i = 0; i < npi; ++i)
  {
    this->PointTriangleStart[i + 1] += this->PointTriangleStart[i];
  }
  this->PointTriangles.assign(this->PointTriangleStart[npi], -1);
  {
    std::vector<int> fill(this->PointTriangleStart.begin(), this->PointTriangleStart.end() - 1);
    for (int t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->PointTriangles[fill[this->T(t)[k]]++] = t;
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildSectors()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int ncorners = 3 * nt;
  detail::UnionFind corners(ncorners);
  auto cornerOf = [this](int t, int point) {
    const int* tri = this->T(t);
    return 3 * t + (tri[0] == point ? 0 : (tri[1] == point ? 1 : 2));
  };
  const int ne = static_cast<int>(this->EdgeKinds.size());
  for (int e = 0; e < ne; ++e)
  {
    if (this->EdgeKinds[e] != SmoothEdge)
    {
      continue;
    }
    const int t0 = this->EdgeSides[2 * e] / 3;
    const int t1 = this->EdgeSides[2 * e + 1] / 3;
    for (int end = 0; end < 2; ++end)
    {
      const int point = this->EdgePoints[2 * e + end];
      corners.Union(cornerOf(t0, point), cornerOf(t1, point));
    }
  }
  this->CornerSector.assign(ncorners, -1);
  this->SectorPoint.clear();
  std::vector<int> rootSector(ncorners, -1);
  for (int i = 0; i < ncorners; ++i)
  {
    const int r = corners.Find(i);
    if (rootSector[r] < 0)
    {
      rootSector[r] = static_cast<int>(this->SectorPoint.size());
      this->SectorPoint.push_back(this->T(i / 3)[i % 3]);
    }
    this->CornerSector[i] = rootSector[r];
  }
  const int ns = static_cast<int>(this->SectorPoint.size());
  this->SectorCornerStart.assign(ns + 1, 0);
  for (int i = 0; i < ncorners; ++i)
  {
    ++this->SectorCornerStart[this->CornerSector[i] + 1];
  }
  for (int s = 0; s < ns; ++s)
  {
    this->SectorCornerStart[s + 1] += this->SectorCornerStart[s];
  }
  this->SectorCorners.assign(ncorners, -1);
  std::vector<int> fill(this->SectorCornerStart.begin(), this->SectorCornerStart.end() - 1);
  for (int i = 0; i < ncorners; ++i)
  {
    this->SectorCorners[fill[this->CornerSector[i]]++] = i;
  }
  this->Statistics.Sectors = ns;
}

} // namespace penumbra
