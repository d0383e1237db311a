// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraDisplayDecimation.h"

#include "penumbraReconstruction.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <queue>
#include <string>
#include <vector>

namespace penumbra
{

namespace
{

/**
 * A collapse is refused when a resulting triangle would hold more removed
 * points than this: the check of a collapse reads every removed point of
 * the triangles it changes, and without a bound a region of constant value
 * (an unlit face) would merge into a few triangles holding all its points,
 * each later check reading all of them. It caps the merging at about this
 * many points per triangle. The edge midpoints add about one and a half test
 * points per input triangle, so with them the cap is twice as high.
 */
constexpr std::size_t MaximumRemovedPerTriangle = 32;
constexpr std::size_t MaximumTestedPerTriangle = 64;
/// Smallest area of a resulting triangle, relative to its longest edge squared.
constexpr double MinimumShape = 1e-8;
/// Barycentric slack of the point location (relative).
constexpr double LocationSlack = 1e-9;
/// A point this far inside a triangle of a fan (barycentric) is in no other.
constexpr double InsideMargin = 1e-9;

struct Candidate
{
  double Cost;
  int From;
  int To;
  int Version;
  bool operator<(const Candidate& other) const { return this->Cost > other.Cost; } // min-heap
};

std::uint64_t EdgeKey(int a, int b)
{
  const std::uint32_t lo = static_cast<std::uint32_t>(std::min(a, b));
  const std::uint32_t hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

class Decimator
{
public:
  Decimator(ResampledMesh& mesh, const DecimationOptions& options)
    : Mesh(mesh)
    , Channels(mesh.NumberOfChannels)
    , Points(mesh.GetNumberOfPoints())
    , Cap(options.TestEdgeMidpoints ? MaximumTestedPerTriangle : MaximumRemovedPerTriangle)
    , LocalFraction(options.LocalFraction)
  {
    const int points = mesh.GetNumberOfPoints();
    const int triangles = mesh.GetNumberOfTriangles();
    this->Triangles.resize(static_cast<std::size_t>(triangles));
    this->Alive.assign(static_cast<std::size_t>(triangles), 1);
    this->Removed.assign(static_cast<std::size_t>(triangles), {});
    this->Stars.assign(static_cast<std::size_t>(points), {});
    this->Gone.assign(static_cast<std::size_t>(points), 0);
    this->Version.assign(static_cast<std::size_t>(points), 0);
    this->Queued.assign(static_cast<std::size_t>(points), 0);
    this->Features.assign(static_cast<std::size_t>(points), {});
    std::vector<double> sum(static_cast<std::size_t>(this->Channels), 0.0);
    double area = 0.0;
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * static_cast<std::size_t>(triangles));
    for (int t = 0; t < triangles; ++t)
    {
      std::array<int, 3>& tri = this->Triangles[static_cast<std::size_t>(t)];
      for (int k = 0; k < 3; ++k)
      {
        tri[k] = mesh.Triangles[3 * static_cast<std::size_t>(t) + k];
        this->Stars[static_cast<std::size_t>(tri[k])].push_back(t);
      }
      for (int k = 0; k < 3; ++k)
      {
        edges.push_back(EdgeKey(tri[k], tri[(k + 1) % 3]));
      }
      const double a = this->Area(tri[0], tri[1], tri[2]);
      area += a;
      for (int c = 0; c < this->Channels; ++c)
      {
        double mean = 0.0;
        for (int k = 0; k < 3; ++k)
        {
          mean += std::abs(this->Value(tri[k], c)) / 3.0;
        }
        sum[static_cast<std::size_t>(c)] += a * mean;
      }
    }
    this->Tolerance.resize(static_cast<std::size_t>(this->Channels));
    for (int c = 0; c < this->Channels; ++c)
    {
      const double mean = area > 0.0 ? sum[static_cast<std::size_t>(c)] / area : 0.0;
      const double absolute = options.AbsoluteTolerance.empty()
        ? 0.0
        : options.AbsoluteTolerance[static_cast<std::size_t>(c)];
      this->Relative.push_back(std::max(options.Tolerance * mean, 1e-300));
      this->Absolute.push_back(absolute);
      // A channel that is zero throughout (a black one) must stay exact.
      this->Tolerance[static_cast<std::size_t>(c)] =
        std::max(std::max(options.Tolerance * mean, absolute), 1e-300);
    }
    // Features: the outline and holes (edges of one triangle, or of more
    // than two), and the discontinuity lines.
    std::vector<std::uint64_t> features;
    std::sort(edges.begin(), edges.end());
    for (std::size_t k = 0; k < edges.size();)
    {
      std::size_t end = k + 1;
      while (end < edges.size() && edges[end] == edges[k])
      {
        ++end;
      }
      if (end - k != 2)
      {
        features.push_back(edges[k]);
      }
      k = end;
    }
    // A line's ends stay (it is written as its own polyline from one to the
    // other), unless two lines of a group meet there alone: a joint, which
    // may move along their run once they are joined into one polyline.
    const std::size_t lines = mesh.LineOffsets.empty() ? 0 : mesh.LineOffsets.size() - 1;
    this->LineEnds.assign(2 * lines, -1);
    std::vector<std::vector<int>> endsAt(static_cast<std::size_t>(points));
    for (std::size_t line = 0; line < lines; ++line)
    {
      const int first = mesh.LineOffsets[line], last = mesh.LineOffsets[line + 1];
      if (last > first)
      {
        for (int side = 0; side < 2; ++side)
        {
          const int p = mesh.LinePoints[static_cast<std::size_t>(side ? last - 1 : first)];
          this->LineEnds[2 * line + static_cast<std::size_t>(side)] = p;
          endsAt[static_cast<std::size_t>(p)].push_back(static_cast<int>(line));
        }
      }
      for (int k = first; k + 1 < last; ++k)
      {
        const int a = mesh.LinePoints[static_cast<std::size_t>(k)];
        const int b = mesh.LinePoints[static_cast<std::size_t>(k) + 1];
        if (a != b)
        {
          features.push_back(EdgeKey(a, b));
        }
      }
    }
    this->Pinned.assign(static_cast<std::size_t>(points), 0);
    this->Joint.assign(static_cast<std::size_t>(points), 0);
    const std::vector<int>& groups = options.LineGroups;
    for (std::size_t p = 0; p < endsAt.size(); ++p)
    {
      const std::vector<int>& at = endsAt[p];
      const bool joint = !groups.empty() && at.size() == 2 && at[0] != at[1] &&
        groups[static_cast<std::size_t>(at[0])] == groups[static_cast<std::size_t>(at[1])];
      this->Joint[p] = joint ? 1 : 0;
      this->Pinned[p] = !at.empty() && !joint ? 1 : 0;
    }
    std::sort(features.begin(), features.end());
    features.erase(std::unique(features.begin(), features.end()), features.end());
    for (const std::uint64_t key : features)
    {
      const int a = static_cast<int>(key & 0xffffffffu);
      const int b = static_cast<int>(key >> 32);
      this->Features[static_cast<std::size_t>(a)].push_back(b);
      this->Features[static_cast<std::size_t>(b)].push_back(a);
    }
    for (std::size_t k = 0; k < options.TestTriangles.size(); ++k)
    {
      const int id = this->Points + static_cast<int>(this->Midpoints.size() / 2);
      this->Midpoints.insert(this->Midpoints.end(), options.TestPoints.begin() + 2 * k,
        options.TestPoints.begin() + 2 * k + 2);
      this->MidpointValues.insert(this->MidpointValues.end(),
        options.TestValues.begin() + k * this->Channels,
        options.TestValues.begin() + (k + 1) * this->Channels);
      this->Removed[static_cast<std::size_t>(options.TestTriangles[k])].push_back(id);
    }
    if (options.TestEdgeMidpoints)
    {
      this->AddEdgeMidpoints(edges, features);
    }
  }

  DecimationStatistics Run()
  {
    DecimationStatistics stats;
    stats.PointsBefore = this->Mesh.GetNumberOfPoints();
    stats.TrianglesBefore = this->Mesh.GetNumberOfTriangles();
    for (int u = 0; u < stats.PointsBefore; ++u)
    {
      this->Push(u);
    }
    while (!this->Queue.empty())
    {
      const Candidate top = this->Queue.top();
      this->Queue.pop();
      this->Queued[static_cast<std::size_t>(top.From)] = 0;
      if (this->Gone[static_cast<std::size_t>(top.From)])
      {
        continue;
      }
      if (top.Version != this->Version[static_cast<std::size_t>(top.From)])
      {
        // Its neighbourhood changed since: estimated again only now, once
        // however many times it changed.
        this->Push(top.From);
        continue;
      }
      // The queue holds the error at the point itself; check every point
      // the collapse moves (and the target's neighbourhood, which may have
      // changed since), then the other targets, best estimate first.
      int to = top.To;
      double cost = this->Cost(top.From, to, true);
      if (cost > 1.0)
      {
        std::vector<std::pair<double, int>> others;
        std::vector<int> targets;
        this->Targets(top.From, targets);
        for (const int v : targets)
        {
          const double estimate = v == top.To ? 2.0 : this->Cost(top.From, v, false);
          if (estimate <= 1.0)
          {
            others.emplace_back(estimate, v);
          }
        }
        std::sort(others.begin(), others.end());
        if (others.size() > 2)
        {
          others.resize(2);
        }
        for (const auto& other : others)
        {
          cost = this->Cost(top.From, other.second, true);
          if (cost <= 1.0)
          {
            to = other.second;
            break;
          }
        }
      }
      if (cost > 1.0)
      {
        continue; // pushed again when its neighbourhood changes
      }
      stats.LargestError = std::max(stats.LargestError, cost);
      this->Collapse(top.From, to);
    }
    this->Compact();
    stats.PointsAfter = this->Mesh.GetNumberOfPoints();
    stats.TrianglesAfter = this->Mesh.GetNumberOfTriangles();
    return stats;
  }

private:
  // Test points past the mesh's points (ids from Points on) are edge
  // midpoints, held by the triangles like removed points.
  double U(int p) const
  {
    return p < this->Points ? this->Mesh.Points[2 * static_cast<std::size_t>(p)]
                            : this->Midpoints[2 * static_cast<std::size_t>(p - this->Points)];
  }
  double V(int p) const
  {
    return p < this->Points ? this->Mesh.Points[2 * static_cast<std::size_t>(p) + 1]
                            : this->Midpoints[2 * static_cast<std::size_t>(p - this->Points) + 1];
  }
  double Value(int p, int c) const
  {
    return p < this->Points
      ? this->Mesh.Values[static_cast<std::size_t>(p) * this->Channels + c]
      : this->MidpointValues[static_cast<std::size_t>(p - this->Points) * this->Channels + c];
  }

  /// The midpoint of every edge that is no feature (`edges`: the sorted keys
  /// of all triangles' edges, with repeats; `features`: sorted, unique),
  /// held by the first triangle of that edge. Along features the display is
  /// one-dimensional and its points suffice.
  void AddEdgeMidpoints(const std::vector<std::uint64_t>& edges,
    const std::vector<std::uint64_t>& features)
  {
    std::vector<std::uint64_t> inner;
    inner.reserve(edges.size() / 2);
    for (std::size_t k = 0; k < edges.size(); ++k)
    {
      if ((k == 0 || edges[k] != edges[k - 1]) &&
        !std::binary_search(features.begin(), features.end(), edges[k]))
      {
        inner.push_back(edges[k]);
      }
    }
    const std::size_t count = inner.size();
    this->Midpoints.reserve(2 * count);
    this->MidpointValues.reserve(count * static_cast<std::size_t>(this->Channels));
    std::vector<char> done(count, 0);
    for (std::size_t t = 0; t < this->Triangles.size(); ++t)
    {
      const std::array<int, 3>& tri = this->Triangles[t];
      for (int k = 0; k < 3; ++k)
      {
        const int a = tri[k], b = tri[(k + 1) % 3];
        const auto found = std::lower_bound(inner.begin(), inner.end(), EdgeKey(a, b));
        if (found == inner.end() || *found != EdgeKey(a, b))
        {
          continue;
        }
        const std::size_t index = static_cast<std::size_t>(found - inner.begin());
        if (done[index])
        {
          continue;
        }
        done[index] = 1;
        const int id = this->Points + static_cast<int>(this->Midpoints.size() / 2);
        this->Midpoints.push_back(0.5 * (this->U(a) + this->U(b)));
        this->Midpoints.push_back(0.5 * (this->V(a) + this->V(b)));
        for (int c = 0; c < this->Channels; ++c)
        {
          this->MidpointValues.push_back(0.5 * (this->Value(a, c) + this->Value(b, c)));
        }
        this->Removed[t].push_back(id);
      }
    }
  }

  double Area(int a, int b, int c) const
  {
    return 0.5 * ((this->U(b) - this->U(a)) * (this->V(c) - this->V(a)) -
      (this->V(b) - this->V(a)) * (this->U(c) - this->U(a)));
  }

  /// Whether the triangle is counter-clockwise with an area above
  /// MinimumShape times its longest edge squared.
  bool HasShape(const std::array<int, 3>& tri) const
  {
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const double du = this->U(tri[(k + 1) % 3]) - this->U(tri[k]);
      const double dv = this->V(tri[(k + 1) % 3]) - this->V(tri[k]);
      longest = std::max(longest, du * du + dv * dv);
    }
    return this->Area(tri[0], tri[1], tri[2]) > MinimumShape * longest;
  }

  /// Triangle t of u's star once u has moved into v: false when it goes (it
  /// has v), else its corners in `tri`.
  bool Moved(int t, int u, int v, std::array<int, 3>& tri) const
  {
    tri = this->Triangles[static_cast<std::size_t>(t)];
    if (tri[0] == v || tri[1] == v || tri[2] == v)
    {
      return false;
    }
    for (int& w : tri)
    {
      w = w == u ? v : w;
    }
    return true;
  }

  /// Barycentric coordinates of point p in triangle (a, b, c).
  void Barycentric(int p, int a, int b, int c, double w[3]) const
  {
    const double area = this->Area(a, b, c);
    w[0] = this->Area(p, b, c) / area;
    w[1] = this->Area(a, p, c) / area;
    w[2] = 1.0 - w[0] - w[1];
  }

  /// The other vertices of x's triangles, without repetition.
  void Neighbours(int x, std::vector<int>& out) const
  {
    out.clear();
    for (const int t : this->Stars[static_cast<std::size_t>(x)])
    {
      for (const int w : this->Triangles[static_cast<std::size_t>(t)])
      {
        if (w != x && std::find(out.begin(), out.end(), w) == out.end())
        {
          out.push_back(w);
        }
      }
    }
  }

  /// The targets u may move into: any neighbour if it lies on no feature;
  /// along a straight run of features, its two neighbours there; none for
  /// corners, junctions and the ends of lines, nor when one of u's
  /// triangles has no shape (a star with a degenerate triangle, as where the
  /// two sides of a discontinuity meet, does not cover its region once:
  /// moving u could fold the mesh unseen).
  void Targets(int u, std::vector<int>& out) const
  {
    const std::vector<int>& f = this->Features[static_cast<std::size_t>(u)];
    out.clear();
    if (this->Pinned[static_cast<std::size_t>(u)])
    {
      return;
    }
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      if (!this->HasShape(this->Triangles[static_cast<std::size_t>(t)]))
      {
        return;
      }
    }
    if (f.empty())
    {
      this->Neighbours(u, out);
      return;
    }
    if (f.size() != 2)
    {
      return;
    }
    const double ax = this->U(f[0]) - this->U(u), ay = this->V(f[0]) - this->V(u);
    const double bx = this->U(f[1]) - this->U(u), by = this->V(f[1]) - this->V(u);
    const double cross = ax * by - ay * bx;
    const double dot = ax * bx + ay * by;
    const double scale = std::sqrt((ax * ax + ay * ay) * (bx * bx + by * by));
    if (dot < 0.0 && std::abs(cross) <= 1e-9 * scale)
    {
      out = f;
    }
  }

  /// The cost of moving u into v: the largest error relative to the
  /// tolerance over u and the points its triangles hold, or a value above 1
  /// when the collapse is not allowed; without `all`, the queue's estimate:
  /// the error at u alone (the link condition is not checked).
  double Cost(int u, int v, bool all)
  {
    // Link condition (checked for the collapse itself, not for the queue's
    // estimate): the common neighbours of u and v are the vertices opposite
    // their edge, else the collapse would fold the mesh.
    if (all)
    {
      this->HomesOf = { { -1, -1 } };
      std::vector<int>& nu = this->Scratch0;
      std::vector<int>& nv = this->Scratch1;
      this->Neighbours(u, nu);
      this->Neighbours(v, nv);
      int opposite = 0;
      for (const int t : this->Stars[static_cast<std::size_t>(u)])
      {
        const std::array<int, 3>& tri = this->Triangles[static_cast<std::size_t>(t)];
        opposite += (tri[0] == v || tri[1] == v || tri[2] == v) ? 1 : 0;
      }
      if (opposite == 0)
      {
        return 2.0;
      }
      int common = 0;
      for (const int w : nu)
      {
        common += std::find(nv.begin(), nv.end(), w) != nv.end() ? 1 : 0;
      }
      if (common != opposite)
      {
        return 2.0;
      }
    }
    // The new triangles keep their orientation and a shape.
    std::size_t held = 1;
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      std::array<int, 3> tri;
      held += this->Removed[static_cast<std::size_t>(t)].size();
      if (this->Moved(t, u, v, tri) && !this->HasShape(tri))
      {
        return 2.0;
      }
    }
    if (held > this->Cap * (this->Stars[static_cast<std::size_t>(u)].size()))
    {
      return 2.0;
    }
    if (!all)
    {
      int home = -1;
      return this->PointCost(u, u, v, -1, home);
    }
    this->Fan.clear();
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      std::array<int, 3> tri;
      if (this->Moved(t, u, v, tri))
      {
        this->Fan.push_back({ t, tri, this->Area(tri[0], tri[1], tri[2]) });
      }
    }
    int home = -1;
    double cost = this->PointCost(u, u, v, -1, home);
    // Where every point lands, for Collapse (the same location it would
    // compute again).
    this->Homes.clear();
    this->Homes.emplace_back(u, home);
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      for (const int p : this->Removed[static_cast<std::size_t>(t)])
      {
        if (cost > 1.0)
        {
          this->Fan.clear();
          return cost;
        }
        cost = std::max(cost, this->PointCost(p, u, v, t, home));
        this->Homes.emplace_back(p, home);
      }
    }
    this->Fan.clear();
    if (cost <= 1.0)
    {
      this->HomesOf = { { u, v } };
    }
    return cost;
  }

  /// The new triangle (u's star with u moved to v) holding p, or -1; the
  /// triangle `hint` (or -1) is tried first.
  int Locate(int p, int u, int v, double w[3], int hint) const
  {
    if (!this->Fan.empty())
    {
      return this->LocateInFan(p, w, hint);
    }
    std::array<int, 3> tri;
    if (hint >= 0 && this->Moved(hint, u, v, tri))
    {
      this->Barycentric(p, tri[0], tri[1], tri[2], w);
      if (std::min(w[0], std::min(w[1], w[2])) >= 0.0)
      {
        return hint;
      }
    }
    int best = -1;
    double bestMargin = -1e300;
    double bestW[3] = { 0.0, 0.0, 0.0 };
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      if (!this->Moved(t, u, v, tri))
      {
        continue;
      }
      double b[3];
      this->Barycentric(p, tri[0], tri[1], tri[2], b);
      const double margin = std::min(b[0], std::min(b[1], b[2]));
      if (margin > bestMargin)
      {
        bestMargin = margin;
        best = t;
        std::copy(b, b + 3, bestW);
      }
    }
    std::copy(bestW, bestW + 3, w);
    return bestMargin >= -LocationSlack ? best : -1;
  }

  /// Locate in the checked collapse's new triangles (Fan): the same result
  /// as Locate, sooner. The fan covers its region once (Cost checked the
  /// link condition and the orientations), so a point well inside one of
  /// its triangles lies in no other.
  int LocateInFan(int p, double w[3], int hint) const
  {
    const auto barycentric = [this, p](const FanTriangle& f, double b[3]) {
      b[0] = this->Area(p, f.Corners[1], f.Corners[2]) / f.Area;
      b[1] = this->Area(f.Corners[0], p, f.Corners[2]) / f.Area;
      b[2] = 1.0 - b[0] - b[1];
    };
    if (hint >= 0)
    {
      for (const FanTriangle& f : this->Fan)
      {
        if (f.Triangle == hint)
        {
          barycentric(f, w);
          if (std::min(w[0], std::min(w[1], w[2])) >= 0.0)
          {
            return hint;
          }
          break;
        }
      }
    }
    int best = -1;
    double bestMargin = -1e300;
    double bestW[3] = { 0.0, 0.0, 0.0 };
    for (const FanTriangle& f : this->Fan)
    {
      double b[3];
      barycentric(f, b);
      const double margin = std::min(b[0], std::min(b[1], b[2]));
      if (margin > bestMargin)
      {
        bestMargin = margin;
        best = f.Triangle;
        std::copy(b, b + 3, bestW);
        if (margin > InsideMargin)
        {
          break;
        }
      }
    }
    std::copy(bestW, bestW + 3, w);
    return bestMargin >= -LocationSlack ? best : -1;
  }

  /// |display - value| of p after moving u into v, relative to the
  /// tolerance (`hint`: the triangle holding p now, or -1); `home` gets the
  /// triangle holding p then (-1 if none).
  /// The tolerance at test point p, channel c.
  double PointTolerance(int p, int c) const
  {
    const std::size_t k = static_cast<std::size_t>(c);
    if (!(this->LocalFraction > 0.0))
    {
      return this->Tolerance[k];
    }
    return std::max(this->Relative[k],
      std::min(this->Absolute[k], this->LocalFraction * std::abs(this->Value(p, c))));
  }

  double PointCost(int p, int u, int v, int hint, int& home) const
  {
    double w[3];
    const int t = this->Locate(p, u, v, w, hint);
    home = t;
    if (t < 0)
    {
      return 2.0;
    }
    std::array<int, 3> tri;
    this->Moved(t, u, v, tri); // Locate returns triangles that stay
    double cost = 0.0;
    for (int c = 0; c < this->Channels; ++c)
    {
      const double display = w[0] * this->Value(tri[0], c) + w[1] * this->Value(tri[1], c) +
        w[2] * this->Value(tri[2], c);
      const double error =
        std::abs(display - this->Value(p, c)) / this->PointTolerance(p, c);
      if (!(error <= 1.0))
      {
        return 2.0; // also when not finite
      }
      cost = std::max(cost, error);
    }
    return cost;
  }

  void Push(int u)
  {
    std::vector<int> targets;
    this->Targets(u, targets);
    double best = 2.0;
    int to = -1;
    for (const int v : targets)
    {
      const double cost = this->Cost(u, v, false);
      if (cost < best || (cost == best && to >= 0 && v < to))
      {
        best = cost;
        to = v;
      }
    }
    if (to >= 0 && best <= 1.0)
    {
      this->Queue.push({ best, u, to, this->Version[static_cast<std::size_t>(u)] });
      this->Queued[static_cast<std::size_t>(u)] = 1;
    }
  }

  void Collapse(int u, int v)
  {
    // The homes were found by the check of this collapse, before the
    // triangles change (Locate reads the old star).
    std::vector<std::pair<int, int>> homes;
    if (this->HomesOf[0] == u && this->HomesOf[1] == v)
    {
      homes.swap(this->Homes);
    }
    else
    {
      double w[3];
      homes.emplace_back(u, this->Locate(u, u, v, w, -1));
      for (const int t : this->Stars[static_cast<std::size_t>(u)])
      {
        for (const int p : this->Removed[static_cast<std::size_t>(t)])
        {
          homes.emplace_back(p, this->Locate(p, u, v, w, t));
        }
      }
    }
    this->HomesOf = { { -1, -1 } };
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      this->Removed[static_cast<std::size_t>(t)].clear();
    }
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      std::array<int, 3>& tri = this->Triangles[static_cast<std::size_t>(t)];
      if (tri[0] == v || tri[1] == v || tri[2] == v)
      {
        this->Alive[static_cast<std::size_t>(t)] = 0;
        for (const int w : tri)
        {
          if (w != u)
          {
            std::vector<int>& star = this->Stars[static_cast<std::size_t>(w)];
            star.erase(std::remove(star.begin(), star.end(), t), star.end());
          }
        }
        continue;
      }
      for (int& w : tri)
      {
        w = w == u ? v : w;
      }
      this->Stars[static_cast<std::size_t>(v)].push_back(t);
    }
    for (const auto& home : homes)
    {
      // Cost() accepted every point, so every one has a home.
      this->Removed[static_cast<std::size_t>(home.second)].push_back(home.first);
    }
    this->Stars[static_cast<std::size_t>(u)].clear();
    this->Gone[static_cast<std::size_t>(u)] = 1;
    // Along a feature run: v and the run's other neighbour w become neighbours.
    std::vector<int>& fu = this->Features[static_cast<std::size_t>(u)];
    if (fu.size() == 2)
    {
      const int w = fu[0] == v ? fu[1] : fu[0];
      for (int& x : this->Features[static_cast<std::size_t>(v)])
      {
        x = x == u ? w : x;
      }
      for (int& x : this->Features[static_cast<std::size_t>(w)])
      {
        x = x == u ? v : x;
      }
    }
    fu.clear();
    // Everything around v changed.
    std::vector<int> around;
    this->Neighbours(v, around);
    around.push_back(v);
    for (const int x : around)
    {
      ++this->Version[static_cast<std::size_t>(x)];
      if (!this->Queued[static_cast<std::size_t>(x)])
      {
        this->Push(x);
      }
    }
  }

  /// Write the kept points and live triangles back, in their old order.
  void Compact()
  {
    ResampledMesh& m = this->Mesh;
    const int points = m.GetNumberOfPoints();
    std::vector<int> index(static_cast<std::size_t>(points), -1);
    int next = 0;
    for (int p = 0; p < points; ++p)
    {
      if (!this->Gone[static_cast<std::size_t>(p)])
      {
        const std::size_t from = static_cast<std::size_t>(p);
        const std::size_t to = static_cast<std::size_t>(next);
        m.Points[2 * to] = m.Points[2 * from];
        m.Points[2 * to + 1] = m.Points[2 * from + 1];
        for (int c = 0; c < this->Channels; ++c)
        {
          m.Values[to * this->Channels + c] = m.Values[from * this->Channels + c];
          if (!m.ErrorEstimate.empty())
          {
            m.ErrorEstimate[to * this->Channels + c] = m.ErrorEstimate[from * this->Channels + c];
          }
        }
        if (!m.SourcePoint.empty())
        {
          m.SourcePoint[to] = m.SourcePoint[from];
        }
        index[from] = next++;
      }
    }
    const std::size_t kept = static_cast<std::size_t>(next);
    m.Points.resize(2 * kept);
    m.Values.resize(kept * this->Channels);
    if (!m.ErrorEstimate.empty())
    {
      m.ErrorEstimate.resize(kept * this->Channels);
    }
    if (!m.SourcePoint.empty())
    {
      m.SourcePoint.resize(kept);
    }
    std::vector<int> triangles;
    std::vector<int> sources;
    for (std::size_t t = 0; t < this->Triangles.size(); ++t)
    {
      if (this->Alive[t])
      {
        for (const int w : this->Triangles[t])
        {
          triangles.push_back(index[static_cast<std::size_t>(w)]);
        }
        if (!m.SourceTriangle.empty())
        {
          sources.push_back(m.SourceTriangle[t]);
        }
      }
    }
    m.Triangles = std::move(triangles);
    if (!m.SourceTriangle.empty())
    {
      m.SourceTriangle = std::move(sources);
    }
    const std::size_t lines = m.LineOffsets.empty() ? 0 : m.LineOffsets.size() - 1;
    std::vector<std::vector<int>> polylines(lines);
    for (std::size_t line = 0; line < lines; ++line)
    {
      for (int k = m.LineOffsets[line]; k < m.LineOffsets[line + 1]; ++k)
      {
        const int p = index[static_cast<std::size_t>(m.LinePoints[static_cast<std::size_t>(k)])];
        if (p >= 0)
        {
          polylines[line].push_back(p);
        }
      }
    }
    this->JoinLines(polylines);
    std::vector<int> offsets(1, 0);
    std::vector<int> linePoints;
    for (const std::vector<int>& polyline : polylines)
    {
      linePoints.insert(linePoints.end(), polyline.begin(), polyline.end());
      offsets.push_back(static_cast<int>(linePoints.size()));
    }
    m.LineOffsets = std::move(offsets);
    m.LinePoints = std::move(linePoints);
  }

  /// The lines that met at removed joints become one polyline each, from
  /// one kept end to the other, held by the lowest-numbered of them.
  void JoinLines(std::vector<std::vector<int>>& polylines) const
  {
    const std::size_t lines = polylines.size();
    // The end `side` of `line` when it is a removed joint, else -1.
    const auto joint = [this](std::size_t line, int side) {
      const int p = this->LineEnds[2 * line + static_cast<std::size_t>(side)];
      return p >= 0 && this->Joint[static_cast<std::size_t>(p)] &&
          this->Gone[static_cast<std::size_t>(p)]
        ? p
        : -1;
    };
    std::vector<std::vector<int>> at(static_cast<std::size_t>(this->Points));
    for (std::size_t line = 0; line < lines; ++line)
    {
      for (int side = 0; side < 2; ++side)
      {
        const int p = joint(line, side);
        if (p >= 0)
        {
          at[static_cast<std::size_t>(p)].push_back(static_cast<int>(line));
        }
      }
    }
    std::vector<char> done(lines, 0);
    for (std::size_t start = 0; start < lines; ++start)
    {
      if (done[start] || (joint(start, 0) >= 0 && joint(start, 1) >= 0))
      {
        continue; // not a chain's first line
      }
      // Walk from the kept end: `entry` is the side the walk enters by.
      std::size_t line = start;
      int entry = joint(line, 0) >= 0 ? 1 : 0;
      std::vector<int> chain;
      std::size_t keep = start;
      while (!done[line])
      {
        done[line] = 1;
        keep = std::min(keep, line);
        std::vector<int>& part = polylines[line];
        if (entry == 1)
        {
          std::reverse(part.begin(), part.end());
        }
        chain.insert(chain.end(), part.begin(), part.end());
        part.clear();
        const int exit = joint(line, 1 - entry);
        if (exit < 0)
        {
          break;
        }
        const std::vector<int>& pair = at[static_cast<std::size_t>(exit)];
        const std::size_t next = static_cast<std::size_t>(
          pair[0] == static_cast<int>(line) ? pair[1] : pair[0]);
        entry = this->LineEnds[2 * next] == exit ? 0 : 1;
        line = next;
      }
      polylines[keep] = std::move(chain);
    }
  }

  ResampledMesh& Mesh;
  const int Channels;
  const int Points; ///< points of the mesh; test points past them are edge midpoints
  const std::size_t Cap;
  std::vector<double> Relative, Absolute; ///< per channel: the two parts of the tolerance
  const double LocalFraction;
  std::vector<double> Midpoints;      ///< (u, v) per test point (given, then edge midpoints)
  std::vector<double> MidpointValues; ///< Channels per test point
  std::vector<int> LineEnds;          ///< per line: its first and last point (or -1)
  std::vector<char> Joint;            ///< per point: two lines of a group meet there alone
  std::vector<std::pair<int, int>> Homes; ///< the last full check's (point, triangle)
  /// A triangle of the checked collapse's star after the move: its id, its
  /// corners and its area.
  struct FanTriangle
  {
    int Triangle;
    std::array<int, 3> Corners;
    double Area;
  };
  std::vector<FanTriangle> Fan;
  std::array<int, 2> HomesOf = { { -1, -1 } }; ///< the collapse Homes belongs to
  std::vector<double> Tolerance;
  std::vector<std::array<int, 3>> Triangles;
  std::vector<char> Alive;
  std::vector<std::vector<int>> Removed; ///< per triangle: removed points inside it
  std::vector<std::vector<int>> Stars;   ///< per point: its live triangles
  std::vector<std::vector<int>> Features; ///< per point: its neighbours along features
  std::vector<char> Gone;
  std::vector<char> Pinned; ///< per point: the end of a line, not a joint
  std::vector<int> Version;
  std::vector<char> Queued; ///< per point: whether it has an entry in Queue
  std::priority_queue<Candidate> Queue;
  std::vector<int> Scratch0, Scratch1;
};

} // namespace

DecimationStatistics DecimateDisplay(ResampledMesh& mesh, const DecimationOptions& options)
{
  if (!(options.Tolerance >= 0.0 && options.Tolerance <= 1.0))
  {
    throw InputError("display decimation: the tolerance is " + std::to_string(options.Tolerance) +
      ", must be in [0, 1]");
  }
  bool absolute = false;
  if (!options.AbsoluteTolerance.empty())
  {
    if (options.AbsoluteTolerance.size() != static_cast<std::size_t>(mesh.NumberOfChannels))
    {
      throw InputError("display decimation: AbsoluteTolerance has " +
        std::to_string(options.AbsoluteTolerance.size()) + " entries for " +
        std::to_string(mesh.NumberOfChannels) + " channels");
    }
    for (const double t : options.AbsoluteTolerance)
    {
      if (!(t >= 0.0 && std::isfinite(t)))
      {
        throw InputError("display decimation: an absolute tolerance is " + std::to_string(t) +
          ", must be finite and >= 0");
      }
      absolute = absolute || t > 0.0;
    }
  }
  if (!(options.LocalFraction >= 0.0 && std::isfinite(options.LocalFraction)))
  {
    throw InputError("display decimation: LocalFraction must be finite and >= 0");
  }
  const std::size_t tests = options.TestTriangles.size();
  if (options.TestPoints.size() != 2 * tests ||
    options.TestValues.size() != tests * static_cast<std::size_t>(mesh.NumberOfChannels))
  {
    throw InputError("display decimation: TestPoints and TestValues do not match TestTriangles");
  }
  for (const int t : options.TestTriangles)
  {
    if (t < 0 || t >= mesh.GetNumberOfTriangles())
    {
      throw InputError("display decimation: a test point's triangle is out of range");
    }
  }
  const std::size_t lines = mesh.LineOffsets.empty() ? 0 : mesh.LineOffsets.size() - 1;
  if (!options.LineGroups.empty() && options.LineGroups.size() != lines)
  {
    throw InputError("display decimation: LineGroups has " +
      std::to_string(options.LineGroups.size()) + " entries for " + std::to_string(lines) +
      " lines");
  }
  if ((options.Tolerance == 0.0 && !absolute) || mesh.GetNumberOfTriangles() == 0)
  {
    DecimationStatistics none;
    none.PointsBefore = none.PointsAfter = mesh.GetNumberOfPoints();
    none.TrianglesBefore = none.TrianglesAfter = mesh.GetNumberOfTriangles();
    return none;
  }
  Decimator decimator(mesh, options);
  return decimator.Run();
}

DecimationStatistics DecimateDisplay(ResampledMesh& mesh, double tolerance)
{
  DecimationOptions options;
  options.Tolerance = tolerance;
  return DecimateDisplay(mesh, options);
}

} // namespace penumbra
