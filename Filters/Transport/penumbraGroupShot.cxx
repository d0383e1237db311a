// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraGroupShot.h"

#include "penumbraOccluderSet.h"
#include "penumbraSampleSet.h"
#include "penumbraScene.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

/// The fast method's leaves of surface j (its triangles with unshot
/// radiance, projected onto its plane, split until no longer than `size`),
/// moments about `origin`. With `basis`, every triangle with an area, and
/// instead of the unshot radiance the barycentric coordinates of the
/// triangle's corners in the three channels (the transport's leaves: a
/// result's channels are then the weights of the three corners).
void AddLeaves(const SampleSet& samples, int j, const Vec3& origin, double size, bool basis,
  std::vector<Leaf>& leaves)
{
  const PreparedPolygon& poly = samples.Polygon(j);
  const SurfaceSamples& s = samples.Surfaces[j];
  const RGB corners[3] = { RGB(1.0, 0.0, 0.0), RGB(0.0, 1.0, 0.0), RGB(0.0, 0.0, 1.0) };
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    if ((!basis && s.Unshot[tri[0]].IsZero() && s.Unshot[tri[1]].IsZero() &&
          s.Unshot[tri[2]].IsZero()) ||
      !(samples.Areas[j][t] > 2e-12 * poly.Diameter * poly.Diameter))
    {
      continue;
    }
    Vec3 p[3];
    RGB v[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = s.Points[tri[k]] - poly.Normal * (Dot(poly.Normal, s.Points[tri[k]]) - poly.Offset);
      v[k] = basis ? corners[k] : s.Unshot[tri[k]];
    }
    const std::size_t first = leaves.size();
    SplitToLeaves(p, v, size, origin, 0, leaves);
    for (std::size_t k = first; k < leaves.size(); ++k)
    {
      leaves[k].Surface = j;
      leaves[k].Triangle = static_cast<int>(t);
      leaves[k].Normal = poly.Normal;
    }
  }
}

/// Whether the members' triangles split to `leafSize` times their
/// surface's diameter make at most MaximumGroupLeaves leaves.
bool SplitLeaves(const SampleSet& samples, const std::vector<int>& members, double leafSize)
{
  double leaves = 0.0;
  for (int j : members)
  {
    const SurfaceSamples& s = samples.Surfaces[j];
    const double size = leafSize * samples.Polygon(j).Diameter;
    for (const std::array<int, 3>& tri : s.Triangles)
    {
      const double longest = std::max({ Length(s.Points[tri[1]] - s.Points[tri[0]]),
        Length(s.Points[tri[2]] - s.Points[tri[1]]), Length(s.Points[tri[0]] - s.Points[tri[2]]) });
      const double levels =
        longest > size ? std::min(12.0, std::ceil(std::log2(longest / size))) : 0.0;
      leaves += std::pow(4.0, levels);
    }
  }
  return leaves <= MaximumGroupLeaves;
}

} // namespace

std::vector<int> SelectGroup(const SampleSet& samples, int j, bool acrossOrientations,
  const std::function<bool(double power)>& weak)
{
  std::vector<int> members(1, j);
  const double least = GroupPowerFraction * samples.UnshotPower[j].Mean();
  const Vec3& normal = samples.Polygon(j).Normal;
  for (int k = 0; k < samples.GetNumberOfSurfaces(); ++k)
  {
    const double power = samples.UnshotPower[k].Mean();
    if (k != j && power > 0.0 && !samples.Surfaces[k].Triangles.empty() && weak(power) &&
      ((acrossOrientations && power >= least) ||
        Dot(samples.Polygon(k).Normal, normal) > 1.0 - 1e-12))
    {
      members.push_back(k);
    }
  }
  return members;
}

Leaf Reweighted(
  const SampleSet& samples, const Leaf& leaf, const std::array<RGB, 3>& basis, const Vec3& origin)
{
  const SurfaceSamples& s = samples.Surfaces[leaf.Surface];
  const std::array<int, 3>& tri = s.Triangles[leaf.Triangle];
  RGB values[3];
  for (int k = 0; k < 3; ++k)
  {
    values[k] = s.Unshot[tri[0]] * basis[k].R + s.Unshot[tri[1]] * basis[k].G +
      s.Unshot[tri[2]] * basis[k].B;
  }
  Leaf result = MakeLeaf(leaf.Points, values, origin);
  result.Surface = leaf.Surface;
  result.Triangle = leaf.Triangle;
  result.Normal = leaf.Normal;
  return result;
}

void PrepareGroupShot(const SampleSet& samples, const std::vector<int>& members,
  double openingAngle, double leafSize, Shot& shot, std::vector<std::array<RGB, 3>>* basis)
{
  shot.OpeningAngle = openingAngle;
  shot.Shooter = -1;
  shot.Members = members;
  shot.Method = ShotMethod::Fast;
  shot.Normal = samples.Polygon(members[0]).Normal;
  shot.Offset = HUGE_VAL;
  shot.Empty = true;
  shot.Mixed = false;
  ShooterHierarchy& tree = shot.Hierarchy;
  tree.Nodes.clear();
  tree.Moments.clear();
  tree.Leaves.clear();
  Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
  for (int j : members)
  {
    const PreparedPolygon& poly = samples.Polygon(j);
    shot.Mixed = shot.Mixed || !(Dot(poly.Normal, shot.Normal) > 1.0 - 1e-12);
    shot.Offset = std::min(shot.Offset, Dot(shot.Normal, poly.Centroid));
    const Vec3& c = poly.Centroid;
    lo = { std::min(lo.X, c.X), std::min(lo.Y, c.Y), std::min(lo.Z, c.Z) };
    hi = { std::max(hi.X, c.X), std::max(hi.Y, c.Y), std::max(hi.Z, c.Z) };
  }
  // Moments about the middle of the group keep the subtractions in
  // Aggregate well conditioned.
  tree.Origin = (lo + hi) * 0.5;
  // Leaves split to the leaf size as in a single shot, unless that makes
  // more than MaximumGroupLeaves (a group may hold most of a large scene):
  // then the sample triangles themselves; near leaves are refined anyway.
  const bool split = SplitLeaves(samples, members, leafSize);
  for (int j : members)
  {
    AddLeaves(samples, j, tree.Origin,
      split ? leafSize * samples.Polygon(j).Diameter : HUGE_VAL, basis != nullptr, tree.Leaves);
  }
  if (basis)
  {
    basis->resize(tree.Leaves.size());
    for (std::size_t l = 0; l < tree.Leaves.size(); ++l)
    {
      std::copy(tree.Leaves[l].Values, tree.Leaves[l].Values + 3, (*basis)[l].begin());
      tree.Leaves[l] = Reweighted(samples, tree.Leaves[l], (*basis)[l], tree.Origin);
    }
  }
  if (tree.Leaves.empty())
  {
    return;
  }
  shot.Empty = false;
  tree.Build();
  if (basis)
  {
    for (std::size_t l = 0; l < tree.Leaves.size(); ++l)
    {
      std::copy((*basis)[l].begin(), (*basis)[l].end(), tree.Leaves[l].Values);
    }
  }
}

bool GroupMayReach(const Scene& scene, const SampleSet& samples, const Shot& shot, int receiver)
{
  const PreparedPolygon& plane = samples.Polygon(receiver);
  bool front = false, facing = false;
  for (const Vec3& p : scene.Surfaces[receiver].Vertices)
  {
    front = front || Dot(shot.Normal, p) > shot.Offset;
  }
  for (int j : shot.Members)
  {
    for (const Vec3& y : scene.Surfaces[j].Vertices)
    {
      facing = facing || Dot(plane.Normal, y) > plane.Offset;
    }
  }
  return front && facing;
}

} // namespace penumbra
