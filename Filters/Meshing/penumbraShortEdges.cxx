// SPDX-License-Identifier: GPL-3.0-or-later
// Merging of the points of a receiver mesh closer than a rounding error.
#include "penumbraShortEdges.h"

#include "penumbraUnionFind.h"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

namespace penumbra
{
namespace detail
{

MergeCounts MergeShortEdges(
  ReceiverMesh& mesh, const Vec3& normal, double length, const std::vector<Vec3>& keep)
{
  MergeCounts counts;
  const std::size_t count = mesh.Points.size();
  UnionFind groups(count);
  bool merged = false;
  for (const std::array<int, 3>& t : mesh.Triangles)
  {
    for (int i = 0; i < 3; ++i)
    {
      const int a = t[i], b = t[(i + 1) % 3];
      if (Length(mesh.Points[a] - mesh.Points[b]) < length)
      {
        groups.Union(a, b);
        merged = true;
      }
    }
  }
  // Points across an order-0 line share their geometric vertex: they must
  // keep sharing its position, so groups of vertices get one position each.
  int vertexCount = 0;
  for (const int g : mesh.PointVertex)
  {
    vertexCount = std::max(vertexCount, g + 1);
  }
  UnionFind vertexGroups(static_cast<std::size_t>(vertexCount));
  std::vector<int> representative(count);
  for (std::size_t k = 0; k < count; ++k)
  {
    representative[k] = merged ? groups.Find(static_cast<int>(k)) : static_cast<int>(k);
    vertexGroups.Union(mesh.PointVertex[k], mesh.PointVertex[representative[k]]);
  }
  // A group of vertices keeps the position of its member that is a kept
  // point, if any.
  std::vector<int> position(vertexCount, -1);
  std::vector<char> kept(count, 0);
  for (std::size_t k = 0; k < count; ++k)
  {
    const Vec3& p = mesh.Points[k];
    kept[k] = std::any_of(keep.begin(), keep.end(),
      [&](const Vec3& q) { return q.X == p.X && q.Y == p.Y && q.Z == p.Z; });
    const int g = vertexGroups.Find(mesh.PointVertex[k]);
    if (position[g] < 0 || (kept[k] && !kept[position[g]]))
    {
      position[g] = static_cast<int>(k);
    }
  }
  const auto at = [&](int point) -> int {
    return position[vertexGroups.Find(mesh.PointVertex[point])];
  };
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(mesh.Triangles.size());
  std::vector<int> used(count, 0);
  for (const std::array<int, 3>& t : mesh.Triangles)
  {
    const std::array<int, 3> m = { representative[t[0]], representative[t[1]],
      representative[t[2]] };
    const Vec3& a = mesh.Points[at(m[0])];
    const Vec3& b = mesh.Points[at(m[1])];
    const Vec3& c = mesh.Points[at(m[2])];
    if (m[0] == m[1] || m[1] == m[2] || m[2] == m[0])
    {
      ++counts.Collapsed;
      continue;
    }
    if (!(Dot(Cross(b - a, c - a), normal) > 0.0))
    {
      ++counts.Inverted;
      continue;
    }
    triangles.push_back(m);
    used[m[0]] = used[m[1]] = used[m[2]] = 1;
  }
  if (!merged && counts.Inverted == 0)
  {
    return counts;
  }
  // Compact the points that a triangle still uses.
  std::vector<int> index(count, -1);
  std::vector<Vec3> points;
  std::vector<int> vertices;
  for (std::size_t k = 0; k < count; ++k)
  {
    if (used[k])
    {
      index[k] = static_cast<int>(points.size());
      points.push_back(mesh.Points[at(static_cast<int>(k))]);
      vertices.push_back(mesh.PointVertex[at(static_cast<int>(k))]);
    }
  }
  for (std::array<int, 3>& t : triangles)
  {
    t = { index[t[0]], index[t[1]], index[t[2]] };
  }
  // Segments between two surviving points, one per edge (the lowest order).
  std::map<std::pair<int, int>, std::size_t> edges;
  std::vector<DiscontinuitySegment> segments;
  for (DiscontinuitySegment s : mesh.Segments)
  {
    const int a = index[representative[s.PointA]], b = index[representative[s.PointB]];
    if (a < 0 || b < 0 || a == b)
    {
      continue;
    }
    s.PointA = a;
    s.PointB = b;
    s.A = points[a];
    s.B = points[b];
    const auto found = edges.find({ std::min(a, b), std::max(a, b) });
    if (found == edges.end())
    {
      edges.emplace(std::make_pair(std::min(a, b), std::max(a, b)), segments.size());
      segments.push_back(s);
    }
    else if (s.Order < segments[found->second].Order)
    {
      segments[found->second] = s;
    }
  }
  mesh.Points = std::move(points);
  mesh.PointVertex = std::move(vertices);
  mesh.Triangles = std::move(triangles);
  mesh.Segments = std::move(segments);
  return counts;
}

} // namespace detail
} // namespace penumbra
