// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraRecordedTransport.h
 * @brief The recorded transport (private): a Jacobi sweep of every surface
 * through one hierarchy over all triangles, whose cut and visibility at
 * every receiving point are recorded on the first sweep, so that later
 * sweeps only re-weight the recorded terms with the current unshot
 * radiance, without a ray (Documentation/design/transport.md, "Recorded
 * transport").
 */
#ifndef penumbraRecordedTransport_h
#define penumbraRecordedTransport_h

#include "penumbraParallel.h"
#include "penumbraShot.h"
#include "penumbraVector.h"

#include <array>
#include <functional>
#include <vector>

namespace penumbra
{

class RayCaster;
struct ReceiverClusters;
struct SampleSet;

/// A leaf lighting a point at close range, recorded for the transport: the
/// irradiance is W.R u_0 + W.G u_1 + W.B u_2 for the unshot radiance u_k at
/// the corners of the leaf's sample triangle.
struct NearWeight
{
  int Leaf;
  RGB W;
};

/// The recorded transport to the points of one receiver cluster: what the
/// fast method used at each point (the cut of the hierarchy, the
/// visibility of its nodes and of the near pieces), so that a later sweep
/// only re-weights it.
struct TransportUnit
{
  std::vector<int> Shared;  ///< visible nodes far from every point, expanded at each
  /// Nodes of at least half of the points, expanded at all of them at once
  /// (the vectorised batch), where PartialUse (BatchStride(Count) flags per
  /// node) is 1.
  std::vector<int> Partial;
  std::vector<unsigned char> PartialUse;
  std::vector<int> Nodes;   ///< the other visible nodes of each point, one after the other
  std::vector<int> NodeEnd; ///< per point: end of its nodes in Nodes
  std::vector<NearWeight> Near;
  std::vector<int> NearEnd; ///< per point: end of its near leaves in Near
};

/**
 * Move the nodes that at least half of the unit's `count` points use from
 * their per-point lists to Partial (every point's to Shared): a batch over
 * all the points then costs less than one point at a time. `uses` and
 * `batch` are scratch indexed by node (grown as needed, left all 0 and -1).
 */
void BatchCommonNodes(TransportUnit& unit, int count, std::vector<int>& uses, std::vector<int>& batch);

/// The group shot of every surface, refreshed with the unshot radiance
/// before each sweep, and what each receiver cluster uses of it.
struct RecordedTransport
{
  Shot Sweep;
  std::vector<std::array<RGB, 3>> Basis; ///< per leaf: its corners' barycentric coordinates
  std::vector<TransportUnit> Units;      ///< per receiver cluster
  long long Rays = 0;                    ///< traced to record it

  /// The sweep's hierarchy over every triangle with an area of every
  /// surface with triangles (centroids weighted by the current unshot
  /// power, as a group shot's), its leaves carrying basis values.
  void Prepare(const SampleSet& samples, double openingAngle, double leafSize);

  /**
   * Record the prepared sweep (which must not be Empty) at every point of
   * every cluster as a fast shot would (ReceiverClusters::Evaluate), the
   * nodes and near pieces used stored instead of summed. `progress`
   * (optional) is called from this thread between parts of the work.
   */
  void Record(const SampleSet& samples, const ReceiverClusters& clusters,
    const RayCaster& caster, const ParallelFor& loop,
    const std::function<void(double)>& progress);

  /// The leaves' values and moments from the current unshot radiance, then every node's.
  void Refresh(const SampleSet& samples, const ParallelFor& loop);

  /**
   * A sweep through the recorded transport: at every point of every
   * receiver cluster, the expansions of its recorded nodes with their
   * current moments and its near leaves' weights times their corners'
   * unshot radiance. Point p of surface i goes to
   * irradiance[firstItem[i] + p].
   */
  void Replay(const SampleSet& samples, const ReceiverClusters& clusters,
    const std::vector<long long>& firstItem, RGB* irradiance, const ParallelFor& loop) const;
};

} // namespace penumbra

#endif
