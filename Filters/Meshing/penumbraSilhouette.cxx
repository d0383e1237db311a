// SPDX-License-Identifier: GPL-3.0-or-later
// Local sides of polygons and shared features with respect to a plane.
#include "penumbraSilhouette.h"

#include "penumbraMeshingTolerances.h"

#include <cmath>

namespace penumbra
{
namespace detail
{

namespace
{

int Sign(double v, double tol)
{
  return v > tol ? 1 : (v < -tol ? -1 : 0);
}

// Combine per-polygon sides of a shared feature: the common side (+1/-1), 0
// when every polygon lies in the plane, 2 when they straddle or disagree.
int CombineSides(int a, int b)
{
  if (a == 2 || b == 2)
  {
    return 2;
  }
  if (a == 0)
  {
    return b;
  }
  if (b == 0)
  {
    return a;
  }
  return a == b ? a : 2;
}

} // namespace

int EdgeSide(const PolygonData& p, int i, const Vec3& m)
{
  const Vec3 a = p.V[i], b = p.V[(i + 1) % p.V.size()];
  const Vec3 inward = Normalized(Cross(p.N, b - a));
  return Sign(Dot(m, inward), kAngle);
}

int CornerSide(const PolygonData& p, int i, const Vec3& m)
{
  const std::size_t n = p.V.size();
  const Vec3 v = p.V[i];
  const Vec3 dNext = Normalized(p.V[(i + 1) % n] - v);
  const Vec3 dPrev = Normalized(p.V[(i + n - 1) % n] - v);
  const int s1 = Sign(Dot(m, dNext), kAngle), s2 = Sign(Dot(m, dPrev), kAngle);
  const double turn = Dot(p.N, Cross(dNext, dPrev));
  if (s1 == 0 && s2 == 0)
  {
    return 0;
  }
  if (std::abs(turn) <= kAngle && Dot(dNext, dPrev) < 0.0)
  {
    // Straight corner: a half-plane, one-sided only when its edge is in m's plane.
    return s1 == 0 ? Sign(Dot(m, Cross(p.N, dNext)), kAngle) : 2;
  }
  if (turn < 0.0)
  {
    return 2; // reflex corners straddle every plane through the vertex
  }
  if (s1 * s2 < 0)
  {
    return 2;
  }
  return s1 != 0 ? s1 : s2;
}

int EdgeFeatureSide(const SceneTopology& topology, int e, const Vec3& m)
{
  int side = 0;
  for (const Use& use : topology.EdgeUses[e])
  {
    side = CombineSides(side, EdgeSide(topology.Polygons[use.Polygon], use.Index, m));
  }
  return side;
}

int VertexFeatureSide(const SceneTopology& topology, int c, const Vec3& m, bool allowStraddle)
{
  int side = 0;
  const auto& uses = topology.ClusterUses[c];
  for (const Use& use : uses)
  {
    side = CombineSides(side, CornerSide(topology.Polygons[use.Polygon], use.Index, m));
  }
  // Interior events: a corner straddling the plane is still an event where
  // the line through it only grazes the solid; lines that pierce a solid
  // leave it through another face, which blocks them (faces sharing the
  // vertex are never hit again by a line through it).
  return side == 2 && allowStraddle ? 1 : side;
}

bool VertexHasEdgeInPlane(const SceneTopology& topology, int c, const Vec3& m)
{
  for (const Use& use : topology.ClusterUses[c])
  {
    const PolygonData& p = topology.Polygons[use.Polygon];
    const std::size_t n = p.V.size();
    const Vec3 v = p.V[use.Index];
    if (std::abs(Dot(m, Normalized(p.V[(use.Index + 1) % n] - v))) <= kAngle ||
      std::abs(Dot(m, Normalized(p.V[(use.Index + n - 1) % n] - v))) <= kAngle)
    {
      return true;
    }
  }
  return false;
}

} // namespace detail
} // namespace penumbra
