// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraVisibilityQueue.h
 * @brief The fast method's visibility rays (private): targets queued for
 * one round and traced together from one origin through the Visibility
 * module's RayCaster (an Embree ray stream), each ray ignoring the receiver
 * and the surface its target lies on (Documentation/design/transport.md,
 * "The fast shot").
 */
#ifndef penumbraVisibilityQueue_h
#define penumbraVisibilityQueue_h

#include "penumbraShooterHierarchy.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

class RayCaster;

/// One round of occlusion rays from a common origin.
struct VisibilityQueue
{
  std::vector<Vec3> Targets;
  std::vector<int> TargetSurfaces; ///< the surface each target lies on (ignored by its ray), or -1
  std::vector<unsigned char> Occluded; ///< after Trace: per target, whether its ray is blocked

  void Clear()
  {
    this->Targets.clear();
    this->TargetSurfaces.clear();
  }
  void Add(const Vec3& target, int surface)
  {
    this->Targets.push_back(target);
    this->TargetSurfaces.push_back(surface);
  }
  std::size_t Size() const { return this->Targets.size(); }

  /// Trace from `origin` to every target, each ray ignoring `receiver` and
  /// its target's surface; sets Occluded.
  void Trace(const RayCaster& caster, const Vec3& origin, int receiver);

  /**
   * Replace the queue by the rays of a round of visibility tests of the
   * hierarchy's nodes `ids`: one to the target of each leaf that `testLeaf`
   * accepts, and one to the target of each child of each inner node, in
   * that order.
   */
  template <typename LeafTest>
  void QueueNodes(const std::vector<Node>& nodes, const std::vector<int>& ids,
    const LeafTest& testLeaf)
  {
    this->Clear();
    for (const int id : ids)
    {
      const Node& node = nodes[id];
      if (node.Left < 0)
      {
        if (testLeaf(node))
        {
          this->Add(node.Target, node.TargetSurface);
        }
        continue;
      }
      for (const int child : { node.Left, node.Right })
      {
        this->Add(nodes[child].Target, nodes[child].TargetSurface);
      }
    }
  }
};

} // namespace penumbra

#endif
