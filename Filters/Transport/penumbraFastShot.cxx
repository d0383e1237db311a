// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraFastShot.h"

#include "penumbraFormFactor.h"
#include "penumbraLinearSource.h"
#include "penumbraRecordedTransport.h"

#include <cmath>
#include <utility>

namespace penumbra
{

namespace
{

/**
 * Step 2 of EvaluateFast, visibility of the cut ws.Current, refined where
 * it varies: a far leaf is tested by one ray to its target; an inner node
 * by one ray to each child's target, and if the two disagree (a shadow edge
 * may cross it) its children are handled the same way, in the next round.
 * Rays of a round are traced together. Near leaves (radius >=
 * OpeningAngle * distance) go to ws.Near. Returns the sum of the visible
 * nodes' expansions (or records them).
 */
RGB VisibleFarNodes(const Shot& shot, const Vec3& x, const Vec3& origin, const Vec3& n,
  int receiver, const RayCaster& caster, FastWorkspace& ws, long long& rays,
  TransportUnit* record)
{
  const ShooterHierarchy& tree = shot.Hierarchy;
  const double theta = shot.OpeningAngle;
  RGB sum;
  const auto take = [&](int id) {
    if (record)
    {
      record->Nodes.push_back(id);
    }
    else
    {
      sum += tree.Irradiance(tree.Nodes[id], x, n);
    }
  };
  ws.Near.clear();
  const auto isNear = [&](const Node& node) {
    return node.Radius * node.Radius >= theta * theta * SquaredLength(node.Centroid - x);
  };
  while (!ws.Current.empty())
  {
    ws.Rays.QueueNodes(tree.Nodes, ws.Current, [&](const Node& leaf) { return !isNear(leaf); });
    const int count = static_cast<int>(ws.Rays.Size());
    if (count > 0)
    {
      ws.Rays.Trace(caster, origin, receiver);
      rays += count;
    }
    ws.Next.clear();
    int ray = 0;
    for (const int id : ws.Current)
    {
      const Node& node = tree.Nodes[id];
      if (node.Left < 0)
      {
        if (isNear(node))
        {
          ws.Near.push_back(node.LeafIndex);
        }
        else if (!ws.Rays.Occluded[ray++])
        {
          take(id);
        }
        continue;
      }
      const bool left = !ws.Rays.Occluded[ray++];
      const bool right = !ws.Rays.Occluded[ray++];
      if (left == right)
      {
        if (left)
        {
          take(id);
        }
        continue;
      }
      // Mixed: each child on its own; a visible far leaf child is done.
      const int children[2] = { node.Left, node.Right };
      const bool visible[2] = { left, right };
      for (int c = 0; c < 2; ++c)
      {
        const Node& child = tree.Nodes[children[c]];
        if (child.Left >= 0)
        {
          ws.Next.push_back(children[c]);
        }
        else if (isNear(child))
        {
          ws.Near.push_back(child.LeafIndex);
        }
        else if (visible[c])
        {
          take(children[c]);
        }
      }
    }
    std::swap(ws.Current, ws.Next);
  }
  return sum;
}

/**
 * Step 3 of EvaluateFast for near leaf `index`: split in four while x is
 * within a piece's radius of its centroid (down to NearDepth levels, and
 * not below 4 times `originShift`, the distance between x and the ray
 * origin, from where finer visibility would be wrong anyway). Each piece is
 * weighted by the expansion, or, if it still looks large (radius >=
 * OpeningAngle * distance), by its closed-form integral over its part in
 * front of x (the plane Dot(n, y) = offset), and queued with the target of
 * its ray: its centroid, or the centroid of that part.
 */
void QueueNearLeaf(const Shot& shot, int index, const Vec3& x, const Vec3& n, double originShift,
  double offset, FastWorkspace& ws)
{
  const double theta = shot.OpeningAngle;
  const Leaf& leaf = shot.Hierarchy.Leaves[index];
  ws.Pieces.clear();
  ws.Pieces.push_back({ { leaf.Points[0], leaf.Points[1], leaf.Points[2] },
    { leaf.Values[0], leaf.Values[1], leaf.Values[2] }, 0 });
  while (!ws.Pieces.empty())
  {
    const Piece piece = ws.Pieces.back();
    ws.Pieces.pop_back();
    // The piece's centroid and radius as Aggregate would give them; its
    // moments only where the expansion is used.
    const Vec3 centroid = PowerCentroid(piece.Points, piece.Values);
    double radius = 0.0;
    for (const Vec3& p : piece.Points)
    {
      radius = std::max(radius, SquaredLength(p - centroid));
    }
    radius = std::sqrt(radius);
    const double r2 = SquaredLength(centroid - x);
    if (radius * radius >= r2 && piece.Depth < NearDepth && radius > 4.0 * originShift)
    {
      Vec3 cp[4][3];
      RGB cv[4][3];
      SplitTriangle(piece.Points, piece.Values, cp, cv);
      for (int c = 3; c >= 0; --c)
      {
        ws.Pieces.push_back({ { cp[c][0], cp[c][1], cp[c][2] },
          { cv[c][0], cv[c][1], cv[c][2] }, piece.Depth + 1 });
      }
      continue;
    }
    if (radius * radius < theta * theta * r2)
    {
      const Vec3 centre = (piece.Points[0] + piece.Points[1] + piece.Points[2]) / 3.0;
      Leaf part = MakeLeaf(piece.Points, piece.Values, centre);
      part.Normal = leaf.Normal;
      const Leaf* parts[1] = { &part };
      const Node node = Aggregate(parts, 1, centre, nullptr);
      const RGB e = shot.Hierarchy.Irradiance(node, x, n);
      if (!e.IsZero())
      {
        ws.Rays.Add(node.Centroid, leaf.Surface);
        ws.Weights.push_back(e);
        ws.TargetLeaves.push_back(index);
      }
      continue;
    }
    Vec3 clipped[6];
    const int count = ClipPolygonToHalfSpace(piece.Points, 3, n, offset, clipped);
    if (count < 3)
    {
      continue;
    }
    const RGB e = LinearPolygonIrradiance(x, n, clipped, count, leaf.Normal,
      LinearRadiance::FromTriangle(piece.Points, piece.Values));
    if (!e.IsZero())
    {
      Vec3 target;
      for (int k = 0; k < count; ++k)
      {
        target += clipped[k];
      }
      ws.Rays.Add(target / static_cast<double>(count), leaf.Surface);
      ws.Weights.push_back(e);
      ws.TargetLeaves.push_back(index);
    }
  }
}

} // namespace

void PrepareFastShooter(const SurfaceSamples& s, const std::vector<Vec3>& points,
  const std::vector<std::array<int, 3>>& kept, double size, int j, const Vec3& normal,
  ShooterHierarchy& hierarchy)
{
  std::vector<Leaf>& leaves = hierarchy.Leaves;
  leaves.clear();
  for (const std::array<int, 3>& tri : kept)
  {
    const Vec3 p[3] = { points[tri[0]], points[tri[1]], points[tri[2]] };
    const RGB v[3] = { s.Unshot[tri[0]], s.Unshot[tri[1]], s.Unshot[tri[2]] };
    SplitToLeaves(p, v, size, hierarchy.Origin, 0, leaves);
  }
  for (Leaf& leaf : leaves)
  {
    leaf.Surface = j;
    leaf.Normal = normal;
  }
  hierarchy.Build();
}

RGB EvaluateFast(const Shot& shot, const Vec3& x, const Vec3& origin, const Vec3& n, int receiver,
  const std::vector<int>& roots, const RayCaster& caster, FastWorkspace& ws, long long& rays,
  TransportUnit* record)
{
  // 1. Cut the hierarchy where nodes look small from x.
  shot.Hierarchy.Cut(x, receiver, shot.OpeningAngle, roots, ws.Stack, ws.Current);
  // 2. Visibility of the cut, refined where it varies.
  RGB sum = VisibleFarNodes(shot, x, origin, n, receiver, caster, ws, rays, record);
  // 3. Near leaves, split and each piece tested by its own ray. Near the
  // foot of x (a receiver touching the shooter's plane, a contact) the
  // visibility then follows the geometry instead of one ray per leaf
  // deciding for all.
  ws.Rays.Clear();
  ws.TargetLeaves.clear();
  ws.Weights.clear();
  const double originShift = Length(origin - x);
  const double offset = Dot(n, x);
  for (const int index : ws.Near)
  {
    const Leaf& leaf = shot.Hierarchy.Leaves[index];
    if (!(Dot(leaf.Normal, x) > Dot(leaf.Normal, leaf.Points[0])))
    {
      continue; // behind this leaf's shooter (a group shot)
    }
    QueueNearLeaf(shot, index, x, n, originShift, offset, ws);
  }
  if (ws.Rays.Size() == 0)
  {
    return sum;
  }
  const int count = static_cast<int>(ws.Rays.Size());
  ws.Rays.Trace(caster, origin, receiver);
  rays += count;
  for (int k = 0; k < count; ++k)
  {
    if (!ws.Rays.Occluded[k] && record)
    {
      record->Near.push_back({ ws.TargetLeaves[k], ws.Weights[k] });
    }
    else if (!ws.Rays.Occluded[k])
    {
      sum += ws.Weights[k];
    }
  }
  return sum;
}

} // namespace penumbra
