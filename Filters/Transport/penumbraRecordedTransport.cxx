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
      for (std::size_t c = first + begin; c < first + end; ++c)
      {
        TransportUnit& unit = this->Units[c];
        clusters.Evaluate(
          this->Sweep, clusters.Clusters[c], samples, caster, {}, ws, nullptr, rays[c], &unit);
        unit.Shared.shrink_to_fit();
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
    for (std::size_t c = begin; c < end; ++c)
    {
      const ReceiverCluster& cluster = clusters.Clusters[c];
      const TransportUnit& unit = this->Units[c];
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
        RGB sum;
        for (const int id : unit.Shared)
        {
          sum += tree.Irradiance(tree.Nodes[id], x, n);
        }
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
