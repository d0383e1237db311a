// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraReceiverClusters.h"

#include "penumbraOccluderSet.h"
#include "penumbraRecordedTransport.h"
#include "penumbraSampleSet.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

/**
 * Surfaces with evaluation points grouped by plane (normals within 1e-6,
 * offsets within 1e-6 of the diameters), in id order: points of one plane
 * see past the same occluders; a box's top and the floor around it do not.
 */
std::vector<std::vector<int>> GroupByPlane(const SampleSet& samples)
{
  std::vector<Vec3> normals;
  std::vector<double> offsets, diameters;
  std::vector<std::vector<int>> groups;
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    if (samples.EvaluationPoints[i].empty())
    {
      continue;
    }
    const Vec3& normal = samples.Polygon(i).Normal;
    const double offset = samples.Polygon(i).Offset;
    const double diameter = samples.Polygon(i).Diameter;
    std::size_t g = 0;
    while (g < normals.size() &&
      !(Dot(normals[g], normal) > 1.0 - 1e-6 &&
        std::abs(offsets[g] - offset) <= 1e-6 * (diameters[g] + diameter)))
    {
      ++g;
    }
    if (g == normals.size())
    {
      normals.push_back(normal);
      offsets.push_back(offset);
      diameters.push_back(diameter);
      groups.emplace_back();
    }
    groups[g].push_back(i);
  }
  return groups;
}

/// Far from every point within `spread` of `centre` at opening angle theta.
bool IsFar(const Node& node, const Vec3& centre, double spread, double theta)
{
  const double distance = Length(node.Centroid - centre) - spread;
  return distance > 0.0 && node.Radius < theta * distance;
}

/**
 * Step 1 of ReceiverClusters::Evaluate, the cut for the whole cluster: the
 * nodes far from all of it and in front of all its points go to
 * ws.Current. A node neither far from all of it nor opened at its centre
 * (where a point there would open it) goes to the points (ws.Roots), which
 * would mostly take it whole.
 */
void CutForCluster(const Shot& shot, const ReceiverCluster& cluster, FastWorkspace& ws)
{
  const std::vector<Node>& nodes = shot.Hierarchy.Nodes;
  const double theta = shot.OpeningAngle;
  const Vec3& centre = cluster.Centre;
  const double spread = cluster.Radius;
  ws.Roots.clear();
  ws.Current.clear();
  ws.Stack.assign(1, 0);
  while (!ws.Stack.empty())
  {
    const int id = ws.Stack.back();
    ws.Stack.pop_back();
    const Node& node = nodes[id];
    if (cluster.Surface >= 0 && node.Surface == cluster.Surface)
    {
      continue; // a plane does not light itself
    }
    const Side side = SideOf(node, centre, spread);
    if (side == Side::Behind)
    {
      continue;
    }
    if (side == Side::Front && IsFar(node, centre, spread, theta))
    {
      ws.Current.push_back(id);
    }
    else if (node.Left >= 0 &&
      (node.Radius * node.Radius >= theta * theta * SquaredLength(node.Centroid - centre) ||
        SideOf(node, centre) == Side::Straddle))
    {
      ws.Stack.push_back(node.Right);
      ws.Stack.push_back(node.Left);
    }
    else
    {
      ws.Roots.push_back(id);
    }
  }
}

} // namespace

void ReceiverClusters::Build(const SampleSet& samples, int clusterSize)
{
  this->Clusters.clear();
  this->Points.clear();
  this->Valid = true;
  // The recorded transport records per cluster: single points stand for no clusters.
  const int size = std::max(1, clusterSize);
  for (const std::vector<int>& group : GroupByPlane(samples))
  {
    const int begin = static_cast<int>(this->Points.size());
    for (int i : group)
    {
      for (int k = 0; k < static_cast<int>(samples.EvaluationPoints[i].size()); ++k)
      {
        this->Points.emplace_back(i, k);
      }
    }
    this->Split(samples, begin, static_cast<int>(this->Points.size()) - begin, size);
  }
}

/**
 * The points [first, first + count) of one plane split at the median of
 * the longest side of their bounding box until at most `size` remain (ties
 * broken by surface and index, so that the clusters do not depend on the
 * library's sort), or while wider than sqrt(size) spacings of their
 * points, sqrt(area / points) of each surface (sparse points, e.g. small
 * faces far apart: else nothing would be far from them).
 */
void ReceiverClusters::Split(const SampleSet& samples, int first, int count, int size)
{
  const auto point = [&samples](const std::pair<int, int>& p) -> const Vec3& {
    return samples.EvaluationPoints[p.first][p.second];
  };
  const auto spacing = [&samples](int i) {
    return std::sqrt(samples.Polygon(i).Area /
      static_cast<double>(samples.EvaluationPoints[i].size()));
  };
  std::vector<std::pair<int, int>> ranges{ { first, count } };
  while (!ranges.empty())
  {
    const std::pair<int, int> range = ranges.back();
    ranges.pop_back();
    auto begin = this->Points.begin() + range.first;
    auto end = begin + range.second;
    Vec3 low = point(*begin), high = low;
    double widest = 0.0;
    for (auto it = begin; it != end; ++it)
    {
      const Vec3& p = point(*it);
      low = Vec3(std::min(low.X, p.X), std::min(low.Y, p.Y), std::min(low.Z, p.Z));
      high = Vec3(std::max(high.X, p.X), std::max(high.Y, p.Y), std::max(high.Z, p.Z));
      widest = std::max(widest, spacing(it->first));
    }
    if (range.second > size ||
      (range.second > 1 && 0.5 * Length(high - low) > std::sqrt(double(size)) * widest))
    {
      const Vec3 extent = high - low;
      const int axis =
        extent.X >= extent.Y && extent.X >= extent.Z ? 0 : (extent.Y >= extent.Z ? 1 : 2);
      const auto coordinate = [axis](const Vec3& p) {
        return axis == 0 ? p.X : (axis == 1 ? p.Y : p.Z);
      };
      const int half = range.second / 2;
      std::nth_element(begin, begin + half, end,
        [&](const std::pair<int, int>& a, const std::pair<int, int>& b) {
          const double ca = coordinate(point(a)), cb = coordinate(point(b));
          return ca < cb || (ca == cb && a < b);
        });
      ranges.emplace_back(range.first + half, range.second - half);
      ranges.emplace_back(range.first, half);
      continue;
    }
    this->Clusters.push_back(this->MakeCluster(samples, range.first, range.second, low, high));
  }
}

/// The cluster of Points[first, first + count), bounding box [low, high],
/// with its ray origins.
ReceiverCluster ReceiverClusters::MakeCluster(
  const SampleSet& samples, int first, int count, const Vec3& low, const Vec3& high) const
{
  const auto point = [&samples](const std::pair<int, int>& p) -> const Vec3& {
    return samples.EvaluationPoints[p.first][p.second];
  };
  const auto begin = this->Points.begin() + first;
  const auto end = begin + count;
  ReceiverCluster cluster;
  cluster.Centre = (low + high) * 0.5;
  cluster.First = first;
  cluster.Count = count;
  cluster.Surface = begin->first;
  double nearest = HUGE_VAL;
  for (auto it = begin; it != end; ++it)
  {
    const double r = Length(point(*it) - cluster.Centre);
    cluster.Radius = std::max(cluster.Radius, r);
    cluster.Surface = it->first == cluster.Surface ? cluster.Surface : -1;
    if (r < nearest)
    {
      nearest = r;
      cluster.Origins[0] = static_cast<int>(it - this->Points.begin());
    }
  }
  cluster.OriginCount = 1;
  while (cluster.OriginCount < std::min(ClusterOrigins, cluster.Count))
  {
    double farthest = -1.0;
    int chosen = cluster.Origins[0];
    for (auto it = begin; it != end; ++it)
    {
      double distance = HUGE_VAL;
      for (int o = 0; o < cluster.OriginCount; ++o)
      {
        distance = std::min(
          distance, SquaredLength(point(*it) - point(this->Points[cluster.Origins[o]])));
      }
      if (distance > farthest)
      {
        farthest = distance;
        chosen = static_cast<int>(it - this->Points.begin());
      }
    }
    cluster.Origins[cluster.OriginCount++] = chosen;
  }
  return cluster;
}

/**
 * Step 2 of Evaluate: visibility of the far nodes ws.Current, by rays from
 * each of the cluster's origins. Where they agree they decide for the whole
 * cluster (refined as in EvaluateFast where a node's children disagree):
 * visible nodes go to ws.Visible; where they do not, a shadow edge crosses
 * the cluster and the node goes to the points (ws.Roots).
 */
void ReceiverClusters::ClusterVisibility(const Shot& shot, const ReceiverCluster& cluster,
  const SampleSet& samples, const RayCaster& caster, FastWorkspace& ws, long long& rays) const
{
  const std::vector<Node>& nodes = shot.Hierarchy.Nodes;
  const double theta = shot.OpeningAngle;
  ws.Visible.clear();
  const int origins = cluster.OriginCount;
  ws.Flags.clear();
  while (!ws.Current.empty())
  {
    ws.Rays.QueueNodes(nodes, ws.Current, [](const Node&) { return true; });
    // Per target: bit o set if visible from origin o.
    ws.Flags.assign(ws.Rays.Size(), 0);
    for (int o = 0; o < origins; ++o)
    {
      const std::pair<int, int>& from = this->Points[cluster.Origins[o]];
      ws.Rays.Trace(caster, samples.RayOrigins[from.first][from.second], from.first);
      rays += static_cast<long long>(ws.Rays.Size());
      for (std::size_t t = 0; t < ws.Rays.Size(); ++t)
      {
        ws.Flags[t] |= ws.Rays.Occluded[t] ? 0 : (1 << o);
      }
    }
    const unsigned char all = static_cast<unsigned char>((1 << origins) - 1);
    ws.Next.clear();
    int ray = 0;
    for (const int id : ws.Current)
    {
      const Node& node = nodes[id];
      if (node.Left < 0)
      {
        const unsigned char flags = ws.Flags[ray++];
        if (flags == all)
        {
          ws.Visible.push_back(id);
        }
        else if (flags != 0)
        {
          ws.Roots.push_back(id);
        }
        continue;
      }
      const unsigned char left = ws.Flags[ray++];
      const unsigned char right = ws.Flags[ray++];
      if (left == right && (left == 0 || left == all))
      {
        if (left == all)
        {
          ws.Visible.push_back(id);
        }
        continue;
      }
      const int children[2] = { node.Left, node.Right };
      const unsigned char flags[2] = { left, right };
      for (int c = 0; c < 2; ++c)
      {
        const Node& child = nodes[children[c]];
        if (flags[c] != 0 && flags[c] != all)
        {
          ws.Roots.push_back(children[c]);
        }
        else if (child.Left >= 0)
        {
          ws.Next.push_back(children[c]);
        }
        else if (!IsFar(child, cluster.Centre, cluster.Radius, theta))
        {
          ws.Roots.push_back(children[c]);
        }
        else if (flags[c] == all)
        {
          ws.Visible.push_back(children[c]);
        }
      }
    }
    std::swap(ws.Current, ws.Next);
  }
}

void ReceiverClusters::LoadBatch(
  const ReceiverCluster& cluster, const SampleSet& samples, PointBatch& batch) const
{
  batch.Reset(static_cast<std::size_t>(cluster.Count));
  for (int k = 0; k < cluster.Count; ++k)
  {
    const std::pair<int, int>& p = this->Points[cluster.First + k];
    const Vec3& x = samples.EvaluationPoints[p.first][p.second];
    const Vec3& n = samples.Polygon(p.first).Normal;
    batch.X[k] = x.X;
    batch.Y[k] = x.Y;
    batch.Z[k] = x.Z;
    batch.NX[k] = n.X;
    batch.NY[k] = n.Y;
    batch.NZ[k] = n.Z;
  }
}

void ReceiverClusters::Evaluate(const Shot& shot, const ReceiverCluster& cluster,
  const SampleSet& samples, const RayCaster& caster, const std::vector<long long>& firstItem,
  FastWorkspace& ws, RGB* irradiance, long long& rays, TransportUnit* record) const
{
  bool any = record != nullptr; // recording: every point, firstItem unused
  for (int k = 0; k < cluster.Count && !any; ++k)
  {
    any = firstItem[this->Points[cluster.First + k].first] >= 0;
  }
  if (!any)
  {
    return;
  }
  CutForCluster(shot, cluster, ws);
  this->ClusterVisibility(shot, cluster, samples, caster, ws, rays);
  // 3. Every point: the visible far nodes' expansions, and the rest on its own.
  const ShooterHierarchy& tree = shot.Hierarchy;
  if (record)
  {
    record->Shared = ws.Visible;
  }
  else
  {
    // The visible far nodes node by node over all the points (vectorised).
    this->LoadBatch(cluster, samples, ws.Batch);
    for (const int id : ws.Visible)
    {
      tree.AddIrradiance(tree.Nodes[id], ws.Batch);
    }
  }
  for (int k = 0; k < cluster.Count; ++k)
  {
    const std::pair<int, int>& p = this->Points[cluster.First + k];
    const Vec3& x = samples.EvaluationPoints[p.first][p.second];
    const Vec3& origin = samples.RayOrigins[p.first][p.second];
    const Vec3& n = samples.Polygon(p.first).Normal;
    if (record)
    {
      if (!shot.Behind(x) && !ws.Roots.empty())
      {
        EvaluateFast(shot, x, origin, n, p.first, ws.Roots, caster, ws, rays, record);
      }
      record->NodeEnd.push_back(static_cast<int>(record->Nodes.size()));
      record->NearEnd.push_back(static_cast<int>(record->Near.size()));
      continue;
    }
    if (firstItem[p.first] < 0)
    {
      continue;
    }
    RGB& out = irradiance[firstItem[p.first] + p.second];
    if (shot.Behind(x))
    {
      out = RGB();
      continue;
    }
    RGB sum(ws.Batch.R[k], ws.Batch.G[k], ws.Batch.B[k]);
    if (!ws.Roots.empty())
    {
      sum += EvaluateFast(shot, x, origin, n, p.first, ws.Roots, caster, ws, rays);
    }
    out = NonNegative(sum);
  }
}

} // namespace penumbra
