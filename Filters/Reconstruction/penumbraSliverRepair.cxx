// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSliverRepair.cxx
 * @brief RepairSlivers: clockwise slivers merged into their neighbours.
 */
#include "penumbraSliverRepair.h"

#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace penumbra
{
namespace
{

/// A sliver's height may be at most this fraction of its longest edge:
/// rounding leaves heights near 1e-16 of it, a clockwise triangle of real
/// size is an error of the input, not a sliver.
constexpr double MaximumRelativeHeight = 1e-9;

std::uint64_t DirectedKey(int a, int b)
{
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
    static_cast<std::uint32_t>(b);
}

std::uint64_t UndirectedKey(int a, int b)
{
  return a < b ? DirectedKey(a, b) : DirectedKey(b, a);
}

/// Twice the signed area of the triangle of points a, b, c (positive: counter-clockwise).
double TwiceArea(const SampleMesh& m, int a, int b, int c)
{
  const double* pa = m.Points.data() + 2 * a;
  const double* pb = m.Points.data() + 2 * b;
  const double* pc = m.Points.data() + 2 * c;
  return (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
}

/// The result of a repair that changes nothing: identity maps.
SliverRepairResult Unchanged(const SampleMesh& m)
{
  SliverRepairResult result;
  result.TriangleMap.resize(static_cast<std::size_t>(m.GetNumberOfTriangles()));
  std::iota(result.TriangleMap.begin(), result.TriangleMap.end(), 0);
  result.EdgeOrigin.resize(m.EdgeOrders.size());
  std::iota(result.EdgeOrigin.begin(), result.EdgeOrigin.end(), 0);
  return result;
}

class Repairer
{
public:
  explicit Repairer(SampleMesh& mesh)
    : Mesh(mesh)
    , Dropped(static_cast<std::size_t>(mesh.GetNumberOfTriangles()), false)
    , Result(Unchanged(mesh))
  {
    const int nt = mesh.GetNumberOfTriangles();
    for (int t = 0; t < nt; ++t)
    {
      this->Link(t);
    }
    for (std::size_t e = 0; e < mesh.EdgeOrders.size(); ++e)
    {
      this->Constraints[UndirectedKey(mesh.ConstrainedEdges[2 * e],
                          mesh.ConstrainedEdges[2 * e + 1])]
        .push_back(static_cast<int>(e));
    }
  }

  SliverRepairResult Run()
  {
    const int nt = this->Mesh.GetNumberOfTriangles();
    // A repair can leave a neighbouring sliver repairable; a few passes settle it.
    for (int pass = 0; pass < 4; ++pass)
    {
      bool changed = false;
      for (int t = 0; t < nt; ++t)
      {
        if (!this->Dropped[static_cast<std::size_t>(t)] && this->Area2(t) <= 0.0)
        {
          changed = this->Repair(t) || changed;
        }
      }
      if (!changed)
      {
        break;
      }
    }
    this->Compact();
    return std::move(this->Result);
  }

private:
  int* Corners(int t) { return this->Mesh.Triangles.data() + 3 * t; }
  const double* Point(int p) const { return this->Mesh.Points.data() + 2 * p; }

  double Area2(int a, int b, int c) const { return TwiceArea(this->Mesh, a, b, c); }
  double Area2(int t)
  {
    const int* p = this->Corners(t);
    return this->Area2(p[0], p[1], p[2]);
  }

  void Link(int t)
  {
    const int* p = this->Corners(t);
    for (int i = 0; i < 3; ++i)
    {
      this->Owner[DirectedKey(p[i], p[(i + 1) % 3])] = t;
    }
  }
  void Unlink(int t)
  {
    const int* p = this->Corners(t);
    for (int i = 0; i < 3; ++i)
    {
      auto found = this->Owner.find(DirectedKey(p[i], p[(i + 1) % 3]));
      if (found != this->Owner.end() && found->second == t)
      {
        this->Owner.erase(found);
      }
    }
  }

  /// Replace every constrained edge a-b by a-c and c-b.
  void SplitConstraints(int a, int b, int c)
  {
    auto found = this->Constraints.find(UndirectedKey(a, b));
    if (found == this->Constraints.end())
    {
      return;
    }
    const std::vector<int> edges = std::move(found->second);
    this->Constraints.erase(found);
    SampleMesh& m = this->Mesh;
    for (int e : edges)
    {
      const int from = m.ConstrainedEdges[2 * e];
      const int to = m.ConstrainedEdges[2 * e + 1];
      m.ConstrainedEdges[2 * e + 1] = c;
      m.ConstrainedEdges.push_back(c);
      m.ConstrainedEdges.push_back(to);
      m.EdgeOrders.push_back(m.EdgeOrders[e]);
      if (!m.EdgeLabels.empty())
      {
        m.EdgeLabels.push_back(m.EdgeLabels[e]);
      }
      const int piece = static_cast<int>(m.EdgeOrders.size()) - 1;
      this->Result.EdgeOrigin.push_back(this->Result.EdgeOrigin[e]);
      this->Constraints[UndirectedKey(from, c)].push_back(e);
      this->Constraints[UndirectedKey(c, to)].push_back(piece);
    }
  }

  bool Repair(int t)
  {
    int* p = this->Corners(t);
    // The longest edge a-b and the apex c.
    int longest = 0;
    double longestLength2 = -1.0;
    for (int i = 0; i < 3; ++i)
    {
      const double* u = this->Point(p[i]);
      const double* v = this->Point(p[(i + 1) % 3]);
      const double l2 = (v[0] - u[0]) * (v[0] - u[0]) + (v[1] - u[1]) * (v[1] - u[1]);
      if (l2 > longestLength2)
      {
        longestLength2 = l2;
        longest = i;
      }
    }
    const int a = p[longest], b = p[(longest + 1) % 3], c = p[(longest + 2) % 3];
    const double* pa = this->Point(a);
    const double* pb = this->Point(b);
    const double* pc = this->Point(c);
    if (!(longestLength2 > 0.0))
    {
      return false;
    }
    const double along =
      ((pc[0] - pa[0]) * (pb[0] - pa[0]) + (pc[1] - pa[1]) * (pb[1] - pa[1])) / longestLength2;
    const double height = std::abs(this->Area2(a, b, c)) / std::sqrt(longestLength2);
    if (!(along > 0.0 && along < 1.0) ||
      !(height <= MaximumRelativeHeight * std::sqrt(longestLength2)))
    {
      return false;
    }
    auto across = this->Owner.find(DirectedKey(b, a));
    if (across == this->Owner.end())
    {
      // On the outline: the sliver goes, c becomes a point of the outline.
      this->Unlink(t);
      this->Dropped[static_cast<std::size_t>(t)] = true;
      this->SplitConstraints(a, b, c);
      ++this->Result.Dropped;
      return true;
    }
    const int n = across->second;
    int* q = this->Corners(n);
    int d = -1;
    for (int i = 0; i < 3; ++i)
    {
      if (q[i] != a && q[i] != b)
      {
        d = q[i];
      }
    }
    if (d < 0 || d == c || !(this->Area2(a, d, c) > 0.0) || !(this->Area2(d, b, c) > 0.0))
    {
      return false;
    }
    this->Unlink(t);
    this->Unlink(n);
    p[0] = a, p[1] = d, p[2] = c;
    q[0] = d, q[1] = b, q[2] = c;
    this->Link(t);
    this->Link(n);
    this->SplitConstraints(a, b, c);
    ++this->Result.Split;
    return true;
  }

  void Compact()
  {
    SampleMesh& m = this->Mesh;
    const int nt = m.GetNumberOfTriangles();
    this->Result.TriangleMap.assign(static_cast<std::size_t>(nt), -1);
    int kept = 0;
    for (int t = 0; t < nt; ++t)
    {
      if (this->Dropped[static_cast<std::size_t>(t)])
      {
        continue;
      }
      for (int i = 0; i < 3; ++i)
      {
        m.Triangles[3 * kept + i] = m.Triangles[3 * t + i];
      }
      this->Result.TriangleMap[static_cast<std::size_t>(t)] = kept++;
    }
    m.Triangles.resize(3 * static_cast<std::size_t>(kept));
    for (int t = 0; t < kept; ++t)
    {
      if (!(this->Area2(t) > 0.0))
      {
        ++this->Result.Unrepaired;
      }
    }
  }

  SampleMesh& Mesh;
  std::vector<bool> Dropped;
  std::unordered_map<std::uint64_t, int> Owner; ///< directed edge -> triangle
  std::unordered_map<std::uint64_t, std::vector<int>> Constraints;
  SliverRepairResult Result;
};

} // namespace

//------------------------------------------------------------------------------
SliverRepairResult RepairSlivers(SampleMesh& mesh)
{
  for (int t = 0; t < mesh.GetNumberOfTriangles(); ++t)
  {
    const int* p = mesh.Triangles.data() + 3 * t;
    if (!(TwiceArea(mesh, p[0], p[1], p[2]) > 0.0))
    {
      return Repairer(mesh).Run();
    }
  }
  return Unchanged(mesh);
}

} // namespace penumbra
