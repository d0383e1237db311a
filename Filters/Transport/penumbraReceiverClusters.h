// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverClusters.h
 * @brief Receiver clusters (private): the receiving points of each plane
 * split into small clusters, and the fast method evaluated per cluster: the
 * hierarchy cut once for the whole cluster, the far nodes' visibility
 * tested by rays from a few of its points, the rest point by point
 * (Documentation/design/transport.md, "Receiver clusters").
 */
#ifndef penumbraReceiverClusters_h
#define penumbraReceiverClusters_h

#include "penumbraFastShot.h"
#include "penumbraShot.h"
#include "penumbraVector.h"

#include <utility>
#include <vector>

namespace penumbra
{

class RayCaster;
struct SampleSet;
struct TransportUnit;

/// Rays from this many of a cluster's points decide the visibility of a
/// node for the whole cluster when they agree.
constexpr int ClusterOrigins = 4;

/// Nearby points of one plane, possibly on several (coplanar) surfaces.
struct ReceiverCluster
{
  Vec3 Centre;         ///< centre of the points' bounding box
  double Radius = 0.0; ///< largest distance from Centre to a point
  int First = 0;       ///< the points are ReceiverClusters::Points[First, First + Count)
  int Count = 0;
  int Surface = -1;    ///< the surface of every point, or -1 if several
  /// Where its rays start (indices in ReceiverClusters::Points): the point
  /// nearest Centre, then each the point farthest from those before.
  int Origins[ClusterOrigins] = { 0, 0, 0, 0 };
  int OriginCount = 0;
};

/// The receiver clusters of every evaluation point of a sample set.
struct ReceiverClusters
{
  std::vector<ReceiverCluster> Clusters;
  std::vector<std::pair<int, int>> Points; ///< (surface, point) of each cluster's points
  bool Valid = false; ///< built for the current samples and settings

  /**
   * Cluster the evaluation points of `samples`: the points of each plane
   * (normals within 1e-6, offsets within 1e-6 of the diameters) split at
   * the median of the longest side of their bounding box until a cluster
   * has at most `clusterSize` (at least 1) points and is at most
   * sqrt(clusterSize) point spacings wide. Sets Valid.
   */
  void Build(const SampleSet& samples, int clusterSize);

  /**
   * The fast method at every point of `cluster`: point p of surface i goes
   * to irradiance[firstItem[i] + p], and is skipped if firstItem[i] < 0.
   * Nodes far from the whole cluster (radius < OpeningAngle * (distance to
   * its centre - its radius)) and in front of all its points are found once
   * and tested for visibility from the cluster's origins, refined as in
   * EvaluateFast; each one visible from all of them is expanded at every
   * point. The rest of the hierarchy (nodes too near, or seen by some
   * origins only) is evaluated point by point. With `record`, every point
   * is evaluated and what it uses is recorded instead (firstItem and
   * irradiance are unused).
   */
  void Evaluate(const Shot& shot, const ReceiverCluster& cluster, const SampleSet& samples,
    const RayCaster& caster, const std::vector<long long>& firstItem, FastWorkspace& ws,
    RGB* irradiance, long long& rays, TransportUnit* record = nullptr) const;

  /// Reset `batch` to the points of `cluster` (positions and receiver
  /// normals), their sums zero.
  void LoadBatch(const ReceiverCluster& cluster, const SampleSet& samples, PointBatch& batch) const;

private:
  void Split(const SampleSet& samples, int first, int count, int size);
  ReceiverCluster MakeCluster(const SampleSet& samples, int first, int count, const Vec3& low,
    const Vec3& high) const;
  void ClusterVisibility(const Shot& shot, const ReceiverCluster& cluster,
    const SampleSet& samples, const RayCaster& caster, FastWorkspace& ws, long long& rays) const;
};

} // namespace penumbra

#endif
