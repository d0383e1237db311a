// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraRecordedTransport.h"

#include "penumbraFastShot.h"
#include "penumbraGroupShot.h"
#include "penumbraOccluderSet.h"
#include "penumbraReceiverClusters.h"
#include "penumbraSampleSet.h"

#include <algorithm>

namespace penumbra
{

void BatchCommonNodes(TransportUnit& unit, int count, std::vector<int>& uses, std::vector<int>& batch)
{
  if (count < 2 || unit.Nodes.empty())
  {
    return;
  }
  for (const int id : unit.Nodes)
  {
    if (static_cast<std::size_t>(id) >= uses.size())
    {
      uses.resize(static_cast<std::size_t>(id) + 1, 0);
      batch.resize(uses.size(), -1);
    }
    ++uses[id];
  }
  const std::size_t stride = BatchStride(static_cast<std::size_t>(count));
  std::vector<int> nodes, nodeEnd;
  nodes.reserve(unit.Nodes.size());
  for (int k = 0; k < count; ++k)
  {
    for (int i = k == 0 ? 0 : unit.NodeEnd[k - 1]; i < unit.NodeEnd[k]; ++i)
    {
      const int id = unit.Nodes[i];
      if (2 * uses[id] < count)
      {
        nodes.push_back(id);
        continue;
      }
      if (batch[id] == -1)
      {
        if (uses[id] == count)
        {
          batch[id] = -2; // every point's: shared
          unit.Shared.push_back(id);
        }
        else
        {
          batch[id] = static_cast<int>(unit.Partial.size());
          unit.Partial.push_back(id);
          unit.PartialUse.resize(unit.PartialUse.size() + stride, 0);
        }
      }
      if (batch[id] >= 0)
      {
        unit.PartialUse[static_cast<std::size_t>(batch[id]) * stride + k] = 1;
      }
    }
    nodeEnd.push_back(static_cast<int>(nodes.size()));
  }
  for (const int id : unit.Nodes)
  {
    uses[id] = 0;
    batch[id] = -1;
  }
  unit.Nodes = std::move(nodes);
  unit.NodeEnd = std::move(nodeEnd);
}

void RecordedTransport::Prepare(const SampleSet& samples, double openingAngle, double leafSize)
{
  std::vector<int> all;
  for (int j = 0; j < samples.GetNumberOfSurfaces(); ++j)
  {
    if (!samples.Surfaces[j].Triangles.empty())
    {
      all.push_back(j);
    }
  }
  if (!all.empty())
  {
    PrepareGroupShot(samples, all, openingAngle, leafSize, this->Sweep, &this->Basis);
  }
}

void RecordedTransport::Record(const SampleSet& samples, const ReceiverClusters& clusters,
  const RayCaster& caster, const ParallelFor& loop, const std::function<void(double)>& progress)
{
  const std::size_t count = clusters.Clusters.size();
  this->Units.resize(count);
  std::vector<long long> rays(count, 0);
  // In parts, each a parallel loop, so that progress is reported from
  // this thread between them.
  const std::size_t parts = progress ? std::min<std::size_t>(count, 50) : 1;
  for (std::size_t part = 0; part < parts; ++part)
  {
    const std::size_t first = count * part / parts;
    const std::size_t last = count * (part + 1) / parts;
    RunParallel(loop, last - first, [&](std::size_t begin, std::size_t end) {
      FastWorkspace ws;
      std::vector<int> uses, batch;
      for (std::size_t c = first + begin; c < first + end; ++c)
      {
        TransportUnit& unit = this->Units[c];
        clusters.Evaluate(
          this->Sweep, clusters.Clusters[c], samples, caster, {}, ws, nullptr, rays[c], &unit);
        BatchCommonNodes(unit, clusters.Clusters[c].Count, uses, batch);
        unit.Shared.shrink_to_fit();
        unit.Partial.shrink_to_fit();
        unit.PartialUse.shrink_to_fit();
        unit.Nodes.shrink_to_fit();
        unit.Near.shrink_to_fit();
      }
    });
    if (progress)
    {
      progress(static_cast<double>(last) / static_cast<double>(count));
    }
  }
  for (const long long r : rays)
  {
    this->Rays += r;
  }
}

void RecordedTransport::Refresh(const SampleSet& samples, const ParallelFor& loop)
{
  Shot& shot = this->Sweep;
  if (shot.Empty)
  {
    return;
  }
  ShooterHierarchy& tree = shot.Hierarchy;
  RunParallel(loop, tree.Leaves.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t l = begin; l < end; ++l)
    {
      tree.Leaves[l] = Reweighted(samples, tree.Leaves[l], this->Basis[l], tree.Origin);
    }
  });
  tree.RefreshMoments();
}

void RecordedTransport::Replay(const SampleSet& samples, const ReceiverClusters& clusters,
  const std::vector<long long>& firstItem, RGB* irradiance, const ParallelFor& loop) const
{
  const Shot& shot = this->Sweep;
  if (shot.Empty)
  {
    return;
  }
  const ShooterHierarchy& tree = shot.Hierarchy;
  RunParallel(loop, clusters.Clusters.size(), [&](std::size_t begin, std::size_t end) {
    PointBatch batch;
    for (std::size_t c = begin; c < end; ++c)
    {
      const ReceiverCluster& cluster = clusters.Clusters[c];
      const TransportUnit& unit = this->Units[c];
      // The shared and partial nodes node by node over all the points
      // (vectorised), then each point's own.
      clusters.LoadBatch(cluster, samples, batch);
      for (const int id : unit.Shared)
      {
        tree.AddIrradiance(tree.Nodes[id], batch);
      }
      const std::size_t stride = BatchStride(static_cast<std::size_t>(cluster.Count));
      for (std::size_t i = 0; i < unit.Partial.size(); ++i)
      {
        tree.AddIrradiance(tree.Nodes[unit.Partial[i]], batch, unit.PartialUse.data() + i * stride);
      }
      for (int k = 0; k < cluster.Count; ++k)
      {
        const std::pair<int, int>& p = clusters.Points[cluster.First + k];
        const Vec3& x = samples.EvaluationPoints[p.first][p.second];
        RGB& out = irradiance[firstItem[p.first] + p.second];
        if (shot.Behind(x))
        {
          out = RGB();
          continue;
        }
        const Vec3& n = samples.Polygon(p.first).Normal;
        RGB sum(batch.R[k], batch.G[k], batch.B[k]);
        for (int i = k == 0 ? 0 : unit.NodeEnd[k - 1]; i < unit.NodeEnd[k]; ++i)
        {
          sum += tree.Irradiance(tree.Nodes[unit.Nodes[i]], x, n);
        }
        for (int i = k == 0 ? 0 : unit.NearEnd[k - 1]; i < unit.NearEnd[k]; ++i)
        {
          const NearWeight& near = unit.Near[i];
          const Leaf& leaf = tree.Leaves[near.Leaf];
          const SurfaceSamples& s = samples.Surfaces[leaf.Surface];
          const std::array<int, 3>& tri = s.Triangles[leaf.Triangle];
          sum += s.Unshot[tri[0]] * near.W.R + s.Unshot[tri[1]] * near.W.G +
            s.Unshot[tri[2]] * near.W.B;
        }
        out = NonNegative(sum);
      }
    }
  });
}

} // namespace penumbra
