// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDisplayDecimation.cxx
 * @brief DecimateDisplay: its checks, the decimator's set-up (tolerances, features,
 * test points), the collapse loop and the compacted output.
 */
#include "penumbraDecimator.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra
{
namespace detail
{

//------------------------------------------------------------------------------
Decimator::Decimator(ResampledMesh& mesh, const DecimationOptions& options)
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

//------------------------------------------------------------------------------
void Decimator::AddEdgeMidpoints(const std::vector<std::uint64_t>& edges,
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

//------------------------------------------------------------------------------
DecimationStatistics Decimator::Run()
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

//------------------------------------------------------------------------------
void Decimator::Compact()
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

//------------------------------------------------------------------------------
void Decimator::JoinLines(std::vector<std::vector<int>>& polylines) const
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

} // namespace detail

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
  detail::Decimator decimator(mesh, options);
  return decimator.Run();
}

DecimationStatistics DecimateDisplay(ResampledMesh& mesh, double tolerance)
{
  DecimationOptions options;
  options.Tolerance = tolerance;
  return DecimateDisplay(mesh, options);
}

} // namespace penumbra
