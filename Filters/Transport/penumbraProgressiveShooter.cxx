// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraProgressiveShooter.h"

#include "penumbraExactEvaluator.h"
#include "penumbraFormFactor.h"
#include "penumbraLinearSource.h"
#include "penumbraOccluderSet.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraShooterRadiance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace penumbra
{

namespace
{

constexpr double Pi = 3.141592653589793238462643383279502884;

double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string SurfaceName(int id)
{
  return "surface " + std::to_string(id);
}

bool IsFinite(const RGB& v)
{
  return std::isfinite(v.R) && std::isfinite(v.G) && std::isfinite(v.B);
}

RGB Difference(const RGB& a, const RGB& b)
{
  return { a.R - b.R, a.G - b.G, a.B - b.B };
}

/// Integral of the linear interpolant of `values` over the triangles, per channel.
RGB IntegrateLinear(const SurfaceSamples& s, const std::vector<double>& areas,
  const std::vector<RGB>& values)
{
  RGB sum;
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    const RGB mean = (values[tri[0]] + values[tri[1]] + values[tri[2]]) * (1.0 / 3.0);
    sum += mean * areas[t];
  }
  return sum;
}

/// Angle of triangle `tri` at its corner k.
double AngleAt(const SurfaceSamples& s, const std::array<int, 3>& tri, int k)
{
  const Vec3 u = s.Points[tri[(k + 1) % 3]] - s.Points[tri[k]];
  const Vec3 v = s.Points[tri[(k + 2) % 3]] - s.Points[tri[k]];
  return std::atan2(Length(Cross(u, v)), Dot(u, v));
}

/// A symmetric 3x3 matrix (second moments).
struct Symmetric
{
  double XX = 0.0, YY = 0.0, ZZ = 0.0, XY = 0.0, XZ = 0.0, YZ = 0.0;

  Symmetric& operator+=(const Symmetric& o)
  {
    XX += o.XX;
    YY += o.YY;
    ZZ += o.ZZ;
    XY += o.XY;
    XZ += o.XZ;
    YZ += o.YZ;
    return *this;
  }
  /// Add w * a b^T + w * b a^T / 2 ... i.e. the symmetric part of w * a b^T.
  void AddOuter(const Vec3& a, const Vec3& b, double w)
  {
    XX += w * a.X * b.X;
    YY += w * a.Y * b.Y;
    ZZ += w * a.Z * b.Z;
    XY += 0.5 * w * (a.X * b.Y + a.Y * b.X);
    XZ += 0.5 * w * (a.X * b.Z + a.Z * b.X);
    YZ += 0.5 * w * (a.Y * b.Z + a.Z * b.Y);
  }
  /// M : G = sum_ij M_ij G_ij for a symmetric G.
  double Contract(const Symmetric& g) const
  {
    return XX * g.XX + YY * g.YY + ZZ * g.ZZ + 2.0 * (XY * g.XY + XZ * g.XZ + YZ * g.YZ);
  }
};

/// Moments of a radiance L over a set of triangles about an origin o, per
/// channel c; sums over sets add.
struct RawMoments
{
  RGB Power;           ///< int L_c dA
  Vec3 First[3];       ///< int L_c (y - o) dA
  Symmetric Second[3]; ///< int L_c (y - o)(y - o)^T dA

  /// Add `scale` times o's moments.
  void Add(const RawMoments& o, double scale = 1.0)
  {
    Power += o.Power * scale;
    for (int c = 0; c < 3; ++c)
    {
      First[c] += o.First[c] * scale;
      Symmetric s = o.Second[c];
      s.XX *= scale;
      s.YY *= scale;
      s.ZZ *= scale;
      s.XY *= scale;
      s.XZ *= scale;
      s.YZ *= scale;
      Second[c] += s;
    }
  }

  /// The moments about o + e: D = S1 - P e, M = S2 - (e S1^T + S1 e^T) + P e e^T.
  void Central(const Vec3& e, Vec3 dipole[3], Symmetric quadrupole[3]) const
  {
    for (int c = 0; c < 3; ++c)
    {
      dipole[c] = First[c] - e * Power[c];
      quadrupole[c] = Second[c];
      quadrupole[c].AddOuter(e, First[c], -2.0);
      quadrupole[c].AddOuter(e, e, Power[c]);
    }
  }
};

/// One leaf of the fast method's hierarchy: a (piece of a) shooter triangle,
/// with the moments of its unshot radiance about the shooter's origin o.
struct Leaf
{
  Vec3 Points[3];
  RGB Values[3]; ///< unshot radiance at the points (linear in between)
  RawMoments Moments; ///< about o
  double Area = 0.0;
  Vec3 Centroid; ///< power-weighted (mean channel), area centroid as a fallback
  double Weight = 0.0; ///< scalar power (mean of RGB)
  int Surface = -1;    ///< the shooter it is a piece of
  int Triangle = -1;   ///< the sample triangle of that shooter it is a piece of
  Vec3 Normal;         ///< the front normal of that shooter
};

/// Moments of a node whose leaves face different ways, one set per axis i
/// of the normal m: the moments of L_c m_i (index [i][c]). The irradiance
/// kernel is linear in m, so the node's expansion is the sum over the axes
/// of the one-normal expansion with m = e_i and these moments.
struct AxisMoments
{
  RGB Power[3];
  Vec3 Dipole[3][3];
  Symmetric Quadrupole[3][3];
};

/// A node of the hierarchy: an aggregate of a range of leaves, with the
/// moments of its radiance about its centroid c (the multipole expansion).
struct Node
{
  RGB Power;      ///< P_c = int L_c dA
  Vec3 Dipole[3]; ///< D_c = int L_c (y - c) dA (zero for the mean of the channels)
  Symmetric Quadrupole[3]; ///< M_c = int L_c (y - c)(y - c)^T dA
  Vec3 Centroid;  ///< c, power-weighted (mean channel)
  double Radius = 0.0; ///< largest distance from c to the node's triangles
  int Left = -1;  ///< inner node: children (Left, Right); leaf: -1
  int Right = -1;
  int LeafIndex = -1; ///< leaf node: index of its leaf
  /// The front normal of all its leaves, or when they differ the
  /// (area-weighted) mean direction: the axis of a cone of half-angle
  /// alpha (cos, sin below) holding every leaf's normal.
  Vec3 Normal;
  double ConeCos = 1.0, ConeSin = 0.0;
  /// Range of Dot(Normal, y) over the node's triangles (one normal only):
  /// the planes of its shooters. A point x with Dot(Normal, x) at most
  /// FrontMin is behind all of them.
  double FrontMin = 0.0, FrontMax = 0.0;
  /// Leaves facing different ways: index of its AxisMoments in the shot, else -1.
  int Mixed = -1;
  /// The shooter all its leaves belong to, or -1 (a group shot's cluster).
  int Surface = -1;
  /// Where visibility rays aim for the node as a whole, and the surface
  /// there (ignored by the rays, as a single shot ignores its shooter): the
  /// centroid of a one-shooter node; for a cluster of several shooters,
  /// whose centroid may lie in the air or inside a box, the centroid of its
  /// leaf nearest to it (a point that emits).
  Vec3 Target;
  int TargetSurface = -1;
};

/// Group shots: a node whose leaves' normals spread wider than this (radians,
/// from their mean) is split by normal before space (BuildNode).
constexpr double MaximumConeAngle = 0.5;

/// Group shots: the weakest members have this fraction of the shooter's power (Run).
constexpr double GroupPowerFraction = 0.1;

/// Group shots: most leaves split to LeafSize (PrepareGroupShot).
constexpr double MaximumGroupLeaves = 250000.0;

/// Receiver clusters: rays from this many of a cluster's points decide
/// the visibility of a node for the whole cluster when they agree.
constexpr int ClusterOrigins = 4;

/// Deepest split of a near leaf by the fast method (pieces 1/2^NearDepth of the leaf).
constexpr int NearDepth = 10;

/// A piece of a near leaf being refined.
struct Piece
{
  Vec3 Points[3];
  RGB Values[3];
  int Depth;
};

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
  std::vector<int> Nodes;   ///< visible nodes of each point, one after the other
  std::vector<int> NodeEnd; ///< per point: end of its nodes in Nodes
  std::vector<NearWeight> Near;
  std::vector<int> NearEnd; ///< per point: end of its near leaves in Near
};

/// Scratch memory of one chunk of a shot's parallel loop.
struct ChunkWorkspace
{
  std::vector<int> Near;      ///< near leaves of the current sample
  std::vector<Piece> Pieces;  ///< refinement stack of a near leaf
  std::vector<RGB> Weights;   ///< irradiance of each piece, if visible
  LinearSourceWorkspace Linear;
  std::vector<int> Stack;
  std::vector<int> Current; ///< nodes whose visibility is tested in this round
  std::vector<int> Next;
  std::vector<Vec3> Targets;
  std::vector<int> TargetSurfaces; ///< the surface each target lies on (ignored by its ray), or -1
  std::vector<int> TargetLeaves;   ///< near pieces: the leaf each target lies on
  std::vector<unsigned char> Occluded;
  std::vector<int> Roots;   ///< receiver cluster: nodes each point handles on its own
  std::vector<int> Visible; ///< receiver cluster: visible nodes far from every point
  std::vector<unsigned char> Flags; ///< receiver cluster: per target, the origins that see it
};

/// Trace from `origin` to every target of ws, each ray ignoring the
/// receiver and its target's surface.
void TraceTargets(const RayCaster& caster, const Vec3& origin, int receiver, ChunkWorkspace& ws)
{
  ws.Occluded.resize(ws.Targets.size());
  caster.TraceFrom(origin, ws.Targets.data(), ws.TargetSurfaces.data(),
    static_cast<int>(ws.Targets.size()), ws.Occluded.data(), receiver);
}

/// A non-negative radiance gives a non-negative irradiance; grazing nodes'
/// expansions may dip below 0.
RGB NonNegative(const RGB& e)
{
  return { std::max(e.R, 0.0), std::max(e.G, 0.0), std::max(e.B, 0.0) };
}

/// Queue the rays of a round of visibility tests: one to the target of
/// each leaf of `ids` that `testLeaf` accepts, and one to the target of
/// each child of each inner node.
template <typename LeafTest>
void QueueTargets(const std::vector<Node>& nodes, const std::vector<int>& ids,
  const LeafTest& testLeaf, ChunkWorkspace& ws)
{
  ws.Targets.clear();
  ws.TargetSurfaces.clear();
  for (const int id : ids)
  {
    const Node& node = nodes[id];
    if (node.Left < 0)
    {
      if (testLeaf(node))
      {
        ws.Targets.push_back(node.Target);
        ws.TargetSurfaces.push_back(node.TargetSurface);
      }
      continue;
    }
    for (const int child : { node.Left, node.Right })
    {
      ws.Targets.push_back(nodes[child].Target);
      ws.TargetSurfaces.push_back(nodes[child].TargetSurface);
    }
  }
}

/// The four midpoint children of a triangle with per-corner values (linear in between).
void SplitTriangle(const Vec3 p[3], const RGB v[3], Vec3 cp[4][3], RGB cv[4][3])
{
  const Vec3 m[3] = { (p[0] + p[1]) * 0.5, (p[1] + p[2]) * 0.5, (p[2] + p[0]) * 0.5 };
  const RGB w[3] = { (v[0] + v[1]) * 0.5, (v[1] + v[2]) * 0.5, (v[2] + v[0]) * 0.5 };
  const Vec3 points[4][3] = { { p[0], m[0], m[2] }, { m[0], p[1], m[1] }, { m[2], m[1], p[2] },
    { m[0], m[1], m[2] } };
  const RGB values[4][3] = { { v[0], w[0], w[2] }, { w[0], v[1], w[1] }, { w[2], w[1], v[2] },
    { w[0], w[1], w[2] } };
  for (int c = 0; c < 4; ++c)
  {
    for (int k = 0; k < 3; ++k)
    {
      cp[c][k] = points[c][k];
      cv[c][k] = values[c][k];
    }
  }
}

/// Power-weighted centroid of a triangle with linear radiance (corner
/// values v); its centroid when the power nearly cancels.
Vec3 PowerCentroid(const Vec3 p[3], const RGB v[3])
{
  // For a linear L over a triangle, int y L dA = A/12 (sum L)(sum p) + A/12 sum L_k p_k.
  const double l[3] = { v[0].Mean(), v[1].Mean(), v[2].Mean() };
  const double sum = l[0] + l[1] + l[2];
  const double scale = std::abs(l[0]) + std::abs(l[1]) + std::abs(l[2]);
  if (sum > 1e-9 * scale && sum > 0.0)
  {
    const Vec3 moment = (p[0] + p[1] + p[2]) * sum + p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
    return moment / (4.0 * sum);
  }
  return (p[0] + p[1] + p[2]) / 3.0;
}

/// A leaf: the triangle, its power, power-weighted centroid and moments about `origin`.
Leaf MakeLeaf(const Vec3 p[3], const RGB v[3], const Vec3& origin)
{
  Leaf leaf;
  for (int k = 0; k < 3; ++k)
  {
    leaf.Points[k] = p[k];
    leaf.Values[k] = v[k];
  }
  leaf.Area = 0.5 * Length(Cross(p[1] - p[0], p[2] - p[0]));
  leaf.Moments.Power = (v[0] + v[1] + v[2]) * (leaf.Area / 3.0);
  leaf.Weight = leaf.Moments.Power.Mean();
  leaf.Centroid = PowerCentroid(p, v);
  // Exact moments of a linear L = sum_k L_k lambda_k over the triangle, with
  // y - o = sum_i q_i lambda_i: int lambda_i lambda_k dA = A/12 (1 + [i=k]),
  // int lambda_i lambda_j lambda_k dA = A/60, A/30 or A/10 for 0, 2 or 3
  // equal indices.
  const Vec3 q[3] = { p[0] - origin, p[1] - origin, p[2] - origin };
  for (int c = 0; c < 3; ++c)
  {
    for (int i = 0; i < 3; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        leaf.Moments.First[c] += q[i] * (v[k][c] * leaf.Area / 12.0 * (i == k ? 2.0 : 1.0));
        for (int j = 0; j < 3; ++j)
        {
          const int equal = (i == j) + (j == k) + (i == k);
          const double w = equal == 0 ? 1.0 / 60.0 : (equal == 1 ? 1.0 / 30.0 : 1.0 / 10.0);
          leaf.Moments.Second[c].AddOuter(q[i], q[j], v[k][c] * leaf.Area * w);
        }
      }
    }
  }
  return leaf;
}

/// Split a triangle with per-corner values in four until its longest edge is at most `size`.
void SplitToLeaves(const Vec3 p[3], const RGB v[3], double size, const Vec3& origin, int depth,
  std::vector<Leaf>& out)
{
  const double longest = std::max(
    { SquaredLength(p[1] - p[0]), SquaredLength(p[2] - p[1]), SquaredLength(p[0] - p[2]) });
  if (longest > size * size && depth < 12)
  {
    Vec3 cp[4][3];
    RGB cv[4][3];
    SplitTriangle(p, v, cp, cv);
    for (int c = 0; c < 4; ++c)
    {
      SplitToLeaves(cp[c], cv[c], size, origin, depth + 1, out);
    }
    return;
  }
  out.push_back(MakeLeaf(p, v, origin));
}

/**
 * The node of `count` leaves (power, centroid, radius, moments about the
 * centroid) from their moments about `origin`. Children are not set.
 */
Node Aggregate(const Leaf* const* leaves, int count, const Vec3& origin, AxisMoments* mixed)
{
  Node node;
  double weight = 0.0;
  double absWeight = 0.0;
  double area = 0.0;
  Vec3 weighted;
  Vec3 areaWeighted;
  RawMoments raw;
  for (int k = 0; k < count; ++k)
  {
    const Leaf& leaf = *leaves[k];
    raw.Add(leaf.Moments);
    area += leaf.Area;
    weight += leaf.Weight;
    absWeight += std::abs(leaf.Weight);
    weighted += leaf.Centroid * leaf.Weight;
    areaWeighted += leaf.Centroid * leaf.Area;
  }
  // Power-weighted centroid; the area centroid when the power nearly cancels.
  node.Centroid =
    (weight > 1e-9 * absWeight && weight > 0.0) ? weighted / weight : areaWeighted / area;
  node.Power = raw.Power;
  raw.Central(node.Centroid - origin, node.Dipole, node.Quadrupole);
  for (int k = 0; k < count; ++k)
  {
    for (const Vec3& p : leaves[k]->Points)
    {
      node.Radius = std::max(node.Radius, SquaredLength(p - node.Centroid));
    }
  }
  node.Radius = std::sqrt(node.Radius);
  // The normal cone; per-axis moments when the normals differ.
  bool oneNormal = true;
  Vec3 axis;
  for (int k = 0; k < count; ++k)
  {
    oneNormal = oneNormal && Dot(leaves[k]->Normal, leaves[0]->Normal) > 1.0 - 1e-12;
    axis += leaves[k]->Normal * leaves[k]->Area;
  }
  node.Normal = leaves[0]->Normal;
  if (oneNormal || Length(axis) == 0.0)
  {
    node.ConeCos = oneNormal ? 1.0 : -1.0;
    node.ConeSin = 0.0;
  }
  else
  {
    node.Normal = Normalized(axis);
    node.ConeCos = 1.0;
    for (int k = 0; k < count; ++k)
    {
      node.ConeCos = std::min(node.ConeCos, Dot(leaves[k]->Normal, node.Normal));
    }
    node.ConeCos = std::max(-1.0, node.ConeCos);
    node.ConeSin = std::sqrt(std::max(0.0, 1.0 - node.ConeCos * node.ConeCos));
  }
  if (!oneNormal && mixed)
  {
    *mixed = AxisMoments();
    for (int i = 0; i < 3; ++i)
    {
      RawMoments axisRaw;
      for (int k = 0; k < count; ++k)
      {
        axisRaw.Add(leaves[k]->Moments, leaves[k]->Normal[i]);
      }
      mixed->Power[i] = axisRaw.Power;
      axisRaw.Central(node.Centroid - origin, mixed->Dipole[i], mixed->Quadrupole[i]);
    }
  }
  return node;
}

/// Where x lies relative to the planes of a node's leaves.
enum class Side
{
  Behind,   ///< behind (or on) every plane: the node sends nothing to x
  Front,    ///< strictly in front of every plane
  Straddle  ///< possibly in front of some and behind others
};

/**
 * Side of x: exact from the plane range for one normal; for a cone of
 * normals (axis a, half-angle alpha) and the bounding sphere (c, R), from
 * m.(x - y) = m.(x - c) + m.(c - y), the first term between
 * |x - c| cos(phi + alpha) and |x - c| cos(phi - alpha) (phi the angle
 * between a and x - c), the second within [-R, R]. With `spread` > 0 the
 * answer holds for every point within that distance of x (a receiver
 * cluster's bounding sphere).
 */
Side SideOf(const Node& node, const Vec3& x, double spread = 0.0)
{
  if (node.ConeSin == 0.0 && node.ConeCos == 1.0)
  {
    const double front = Dot(node.Normal, x);
    return !(front + spread > node.FrontMin)
      ? Side::Behind
      : (front - spread > node.FrontMax ? Side::Front : Side::Straddle);
  }
  const Vec3 d = x - node.Centroid;
  const double distance = Length(d);
  const double radius = node.Radius + spread;
  if (!(distance > radius))
  {
    return Side::Straddle;
  }
  // cos(phi +- alpha) from cos and sin of both; phi + alpha > pi when
  // cos(phi) < -cos(alpha), phi < alpha when cos(phi) > cos(alpha).
  const double c = std::max(-1.0, std::min(1.0, Dot(node.Normal, d) / distance));
  const double s = std::sqrt(1.0 - c * c);
  const double lowest = c < -node.ConeCos ? -1.0 : c * node.ConeCos - s * node.ConeSin;
  if (distance * lowest > radius)
  {
    return Side::Front;
  }
  const double highest = c > node.ConeCos ? 1.0 : c * node.ConeCos + s * node.ConeSin;
  return distance * highest < -radius ? Side::Behind : Side::Straddle;
}

/**
 * Second-order multipole expansion of int L k dA about a node's centroid c
 * for a shooter normal m, one term per channel, at x (receiver normal n),
 * d = c - x. With the kernel k(y) = a b / s^2 (d = y - x, s = |d|^2,
 * a = n.d, b = -m.d):
 *   E_c = P_c k + grad k . D_c + 1/2 H : M_c,
 *   grad k = u / s^2 - 4 a b d / s^3,  u = b n - a m,
 *   H = -(n m^T + m n^T) / s^2 - 4 (u d^T + d u^T) / s^3 - 4 a b I / s^3
 *       + 24 a b d d^T / s^4.
 * Linear in m, so also valid term by term for m = e_i (AxisMoments).
 */
RGB Expansion(const Vec3& m, const RGB& power, const Vec3 dipole[3], const Symmetric quadrupole[3],
  const Vec3& d, const Vec3& n)
{
  const double r2 = SquaredLength(d);
  const double a = Dot(n, d);
  const double b = -Dot(m, d);
  const Vec3 u = n * b - m * a;
  const double s2 = r2 * r2;
  const double s3 = s2 * r2;
  const double k = a * b / s2;
  const Vec3 gradient = u / s2 - d * (4.0 * a * b / s3);
  // The Hessian, once for the three channels (M_c : H each).
  Symmetric hessian;
  hessian.AddOuter(n, m, -2.0 / s2);
  hessian.AddOuter(u, d, -8.0 / s3);
  hessian.AddOuter(d, d, 24.0 * a * b / (s2 * s2));
  const double diagonal = -4.0 * a * b / s3;
  hessian.XX += diagonal;
  hessian.YY += diagonal;
  hessian.ZZ += diagonal;
  RGB e;
  for (int c = 0; c < 3; ++c)
  {
    e[c] = power[c] * k + Dot(gradient, dipole[c]) + 0.5 * quadrupole[c].Contract(hessian);
  }
  return e;
}

} // namespace

void ProgressiveShooterSettings::Validate() const
{
  const auto fail = [](const std::string& what) {
    throw InputError("progressive shooter: " + what);
  };
  if (!(this->UnshotFraction >= 0.0 && this->UnshotFraction <= 1.0))
  {
    fail("UnshotFraction must be in [0, 1], got " + std::to_string(this->UnshotFraction));
  }
  if (this->MaximumShots < 0)
  {
    fail("MaximumShots must be >= 0, got " + std::to_string(this->MaximumShots));
  }
  if (!(this->ExactPowerFraction >= 0.0))
  {
    fail("ExactPowerFraction must be in [0, inf], got " + std::to_string(this->ExactPowerFraction));
  }
  if (!(this->CoarseShotFraction >= 0.0 && this->CoarseShotFraction <= 1.0))
  {
    fail("CoarseShotFraction must be in [0, 1], got " + std::to_string(this->CoarseShotFraction));
  }
  if (!(this->OpeningAngle > 0.0 && this->OpeningAngle <= 2.0))
  {
    fail("OpeningAngle must be in (0, 2], got " + std::to_string(this->OpeningAngle));
  }
  if (!(this->ReceiverClusterSize >= 0 && this->ReceiverClusterSize <= 4096))
  {
    fail("ReceiverClusterSize must be in [0, 4096], got " +
      std::to_string(this->ReceiverClusterSize));
  }
  if (!(this->LeafSize > 0.0 && this->LeafSize <= 1.0))
  {
    fail("LeafSize must be in (0, 1], got " + std::to_string(this->LeafSize));
  }
  if (!(this->BoundaryOffset >= 0.0 && this->BoundaryOffset <= 1e-2))
  {
    fail("BoundaryOffset must be in [0, 1e-2], got " + std::to_string(this->BoundaryOffset));
  }
  if (!(this->RayOriginOffset >= 0.0 && this->RayOriginOffset <= 1e-2))
  {
    fail("RayOriginOffset must be in [0, 1e-2], got " + std::to_string(this->RayOriginOffset));
  }
}

struct ProgressiveShooter::Internal
{
  explicit Internal(const Scene& scene)
    : Exact(scene)
    , SceneCopy(scene)
  {
    const std::size_t n = scene.Surfaces.size();
    this->Samples.resize(n);
    this->EvaluationPoints.resize(n);
    this->RayOrigins.resize(n);
    this->Areas.resize(n);
    this->UnshotPower.resize(n);
    this->Emitted = scene.EmittedPower();
  }

  /// Everything one shot needs about its shooter, built once per shot.
  struct Shot
  {
    int Shooter = -1;  ///< the shooter, or -1 for a group shot
    std::vector<int> Members; ///< the shooting surfaces (one, or a parallel group)
    ShotMethod Method = ShotMethod::Exact;
    Vec3 Normal;   ///< shooter's front normal
    double Offset = 0.0; ///< shooter's plane: Dot(Normal, p) == Offset (a group: the lowest)
    bool Empty = true;   ///< no triangle carries unshot radiance
    ShooterRadiance Radiance; ///< exact method: the triangles with unshot radiance
    std::vector<Leaf> Leaves; ///< fast method: the pieces of the shooter
    std::vector<Node> Nodes;  ///< fast method: the hierarchy (root = 0)
    std::vector<AxisMoments> Moments; ///< fast method: of the nodes facing several ways
    bool Mixed = false; ///< a group shot of surfaces facing different ways
    double OpeningAngle = 0.3; ///< fast method: this shot's opening angle
    Vec3 Origin; ///< fast method: the leaves' moments are about this point

    /// x is behind the shooter, which emits from its front only (a group
    /// facing several ways: decided node by node instead).
    bool Behind(const Vec3& x) const { return !Mixed && !(Dot(Normal, x) - Offset > 0.0); }
  };

  const OccluderSet& Occluders() const { return this->Exact.GetOccluders(); }

  const RayCaster& Caster()
  {
    if (!this->Rays)
    {
      this->Rays.reset(new RayCaster(this->SceneCopy));
    }
    return *this->Rays;
  }

  void PrepareShot(int j, ShotMethod method, Shot& shot) const;
  void PrepareGroupShot(const std::vector<int>& members, Shot& shot,
    std::vector<std::array<RGB, 3>>* basis = nullptr) const;
  Leaf Reweighted(const Leaf& leaf, const std::array<RGB, 3>& basis, const Vec3& origin) const;
  void AddLeaves(
    int j, const Vec3& origin, double size, bool basis, std::vector<Leaf>& leaves) const;
  int BuildNode(const std::vector<Leaf>& leaves, std::vector<int>& order, int first, int count,
    const Vec3& origin, Shot& shot) const;
  ShotRecord ShootSurfaces(
    const std::vector<int>& members, ShotMethod method, double reference, bool sweep = false);
  RGB Evaluate(const Shot& shot, const Vec3& x, const Vec3& origin, const Vec3& n, int receiver,
    const std::vector<int>* candidates, const RayCaster* caster, ChunkWorkspace& ws,
    long long& rays) const;
  RGB EvaluateFast(const Shot& shot, const Vec3& x, const Vec3& origin, const Vec3& n,
    int receiver, const std::vector<int>& roots, const RayCaster& caster, ChunkWorkspace& ws,
    long long& rays, TransportUnit* record = nullptr) const;

  /// Fast method, receiver clusters: nearby points of one plane, possibly
  /// on several (coplanar) surfaces.
  struct ReceiverCluster
  {
    Vec3 Centre;         ///< centre of the points' bounding box
    double Radius = 0.0; ///< largest distance from Centre to a point
    int First = 0;       ///< the points are ClusterPoints[First, First + Count)
    int Count = 0;
    int Surface = -1;    ///< the surface of every point, or -1 if several
    /// Where its rays start (indices in ClusterPoints): the point nearest
    /// Centre, then each the point farthest from those before.
    int Origins[ClusterOrigins] = { 0, 0, 0, 0 };
    int OriginCount = 0;
  };
  void BuildClusters();
  void EvaluateCluster(const Shot& shot, const ReceiverCluster& cluster, const RayCaster& caster,
    const std::vector<long long>& firstItem, ChunkWorkspace& ws, RGB* irradiance,
    long long& rays, TransportUnit* record = nullptr) const;
  std::vector<ReceiverCluster> Clusters;
  std::vector<std::pair<int, int>> ClusterPoints; ///< (surface, point) of each cluster's points
  bool ClustersValid = false;

  /// ReuseTransport: the group shot of every surface, refreshed with the
  /// unshot radiance before each sweep, and what each receiver cluster
  /// uses of it.
  struct Transport
  {
    Shot Sweep;
    std::vector<std::array<RGB, 3>> Basis; ///< per leaf: its corners' barycentric coordinates
    std::vector<TransportUnit> Units;      ///< per receiver cluster
    long long Rays = 0;                    ///< traced to record it
  };
  std::unique_ptr<Transport> Recorded; ///< null until the first sweep, and when invalidated
  void RecordTransport();
  struct SubtreeMoments
  {
    RawMoments Plain;
    RawMoments Axis[3];
  };
  void RefreshNode(int id, SubtreeMoments& out);
  void RefreshTransport();
  void Replay(const std::vector<long long>& firstItem, RGB* irradiance) const;
  /// body over [0, count) through Loop (serial without one).
  void For(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) const
  {
    if (this->Loop)
    {
      this->Loop(0, count, body);
    }
    else
    {
      body(0, count);
    }
  }
  void EnsureEnergy();
  void UpdateEvaluationPoints(int surfaceId);
  RGB NodeIrradiance(const Shot& shot, const Node& node, const Vec3& x, const Vec3& n) const;
  ShootingEnergy InitialEnergy() const;

  ExactEvaluator Exact;
  Scene SceneCopy;
  std::unique_ptr<RayCaster> Rays;
  ProgressiveShooterSettings Settings;
  ParallelFor Loop;
  ShotProgressCallback ShotProgress;
  std::vector<SurfaceSamples> Samples;
  std::vector<std::vector<Vec3>> EvaluationPoints;
  std::vector<std::vector<Vec3>> RayOrigins; ///< fast method: where visibility rays start
  std::vector<std::vector<double>> Areas;
  std::vector<RGB> UnshotPower;
  RGB Emitted;
  bool EnergyValid = false;
  ShootingEnergy Energy;
  double Reference = 0.0;
};

void ProgressiveShooter::Internal::PrepareShot(int j, ShotMethod method, Shot& shot) const
{
  shot.OpeningAngle = this->Settings.OpeningAngle;
  const PreparedPolygon& poly = this->Occluders().GetPolygon(j);
  const SurfaceSamples& s = this->Samples[j];
  shot.Shooter = j;
  shot.Members.assign(1, j);
  shot.Method = method;
  shot.Normal = poly.Normal;
  shot.Offset = poly.Offset;
  shot.Origin = poly.Centroid;
  shot.Empty = true;
  shot.Mixed = false;
  shot.Nodes.clear();
  shot.Moments.clear();
  // Triangles that carry unshot radiance and have an area (the others add nothing).
  Vec3 lo = s.Points.empty() ? Vec3() : s.Points[0];
  Vec3 hi = lo;
  for (const Vec3& p : s.Points)
  {
    lo = { std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z) };
    hi = { std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z) };
  }
  const double diagonal = Length(hi - lo);
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    if (s.Unshot[tri[0]].IsZero() && s.Unshot[tri[1]].IsZero() && s.Unshot[tri[2]].IsZero())
    {
      continue;
    }
    if (!(this->Areas[j][t] > 2e-12 * diagonal * diagonal))
    {
      continue;
    }
    kept.push_back(tri);
  }
  if (kept.empty())
  {
    return;
  }
  shot.Empty = false;
  // Points projected onto the shooter's plane exactly (input points may be
  // off it by rounding), so that the integrals are over the shooter itself.
  std::vector<Vec3> points(s.Points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    points[k] = s.Points[k] - poly.Normal * (Dot(poly.Normal, s.Points[k]) - poly.Offset);
  }
  if (method == ShotMethod::Exact)
  {
    // A uniform unshot radiance over the whole mesh (an emitter not shot
    // yet) is passed as a constant: Lambert's formula, 25 times cheaper.
    bool uniform = kept.size() == s.Triangles.size();
    for (std::size_t k = 1; k < s.Unshot.size() && uniform; ++k)
    {
      uniform = s.Unshot[k].R == s.Unshot[0].R && s.Unshot[k].G == s.Unshot[0].G &&
        s.Unshot[k].B == s.Unshot[0].B;
    }
    shot.Radiance = uniform ? ShooterRadiance(s.Unshot[0])
                            : ShooterRadiance(std::move(points), std::move(kept), s.Unshot);
    return;
  }
  std::vector<Leaf>& leaves = shot.Leaves;
  leaves.clear();
  const double size = this->Settings.LeafSize * poly.Diameter;
  for (const std::array<int, 3>& tri : kept)
  {
    const Vec3 p[3] = { points[tri[0]], points[tri[1]], points[tri[2]] };
    const RGB v[3] = { s.Unshot[tri[0]], s.Unshot[tri[1]], s.Unshot[tri[2]] };
    SplitToLeaves(p, v, size, poly.Centroid, 0, leaves);
  }
  for (Leaf& leaf : leaves)
  {
    leaf.Surface = j;
    leaf.Normal = poly.Normal;
  }
  std::vector<int> order(leaves.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    order[k] = static_cast<int>(k);
  }
  shot.Nodes.reserve(2 * leaves.size());
  this->BuildNode(leaves, order, 0, static_cast<int>(leaves.size()), poly.Centroid, shot);
}

/// The fast method's leaves of surface j (its triangles with unshot
/// radiance, projected onto its plane, split until no longer than `size`),
/// moments about `origin`. With `basis`, every triangle with an area, and
/// instead of the unshot radiance the barycentric coordinates of the
/// triangle's corners in the three channels (the transport's leaves: a
/// result's channels are then the weights of the three corners).
void ProgressiveShooter::Internal::AddLeaves(
  int j, const Vec3& origin, double size, bool basis, std::vector<Leaf>& leaves) const
{
  const PreparedPolygon& poly = this->Occluders().GetPolygon(j);
  const SurfaceSamples& s = this->Samples[j];
  const RGB corners[3] = { RGB(1.0, 0.0, 0.0), RGB(0.0, 1.0, 0.0), RGB(0.0, 0.0, 1.0) };
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    if ((!basis && s.Unshot[tri[0]].IsZero() && s.Unshot[tri[1]].IsZero() &&
          s.Unshot[tri[2]].IsZero()) ||
      !(this->Areas[j][t] > 2e-12 * poly.Diameter * poly.Diameter))
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

/// The leaf with the unshot radiance of its triangle's corners, from its
/// corners' barycentric coordinates `basis` in that triangle.
Leaf ProgressiveShooter::Internal::Reweighted(
  const Leaf& leaf, const std::array<RGB, 3>& basis, const Vec3& origin) const
{
  const SurfaceSamples& s = this->Samples[leaf.Surface];
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

/// A fast shot of several surfaces at once (see
/// ProgressiveShooterSettings::GroupWeakShots): one hierarchy over all
/// their leaves, so that a far cluster of them costs one expansion and one
/// ray. With `basis` (the transport): every triangle with an area, the
/// hierarchy built on the current unshot radiance (power-weighted
/// centroids), and each leaf's corners' barycentric coordinates in its
/// triangle returned in `basis` and left as its Values (see AddLeaves).
void ProgressiveShooter::Internal::PrepareGroupShot(
  const std::vector<int>& members, Shot& shot, std::vector<std::array<RGB, 3>>* basis) const
{
  shot.OpeningAngle = this->Settings.OpeningAngle;
  shot.Shooter = -1;
  shot.Members = members;
  shot.Method = ShotMethod::Fast;
  shot.Normal = this->Occluders().GetPolygon(members[0]).Normal;
  shot.Offset = HUGE_VAL;
  shot.Empty = true;
  shot.Mixed = false;
  shot.Nodes.clear();
  shot.Moments.clear();
  shot.Leaves.clear();
  Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
  for (int j : members)
  {
    const PreparedPolygon& poly = this->Occluders().GetPolygon(j);
    shot.Mixed = shot.Mixed || !(Dot(poly.Normal, shot.Normal) > 1.0 - 1e-12);
    shot.Offset = std::min(shot.Offset, Dot(shot.Normal, poly.Centroid));
    const Vec3& c = poly.Centroid;
    lo = { std::min(lo.X, c.X), std::min(lo.Y, c.Y), std::min(lo.Z, c.Z) };
    hi = { std::max(hi.X, c.X), std::max(hi.Y, c.Y), std::max(hi.Z, c.Z) };
  }
  // Moments about the middle of the group keep the subtractions in
  // Aggregate well conditioned.
  const Vec3 origin = (lo + hi) * 0.5;
  shot.Origin = origin;
  // Leaves split to LeafSize as in a single shot, unless that makes more
  // than MaximumGroupLeaves (a group may hold most of a large scene): then
  // the sample triangles themselves; near leaves are refined anyway.
  double leaves = 0.0;
  for (int j : members)
  {
    const SurfaceSamples& s = this->Samples[j];
    const double size = this->Settings.LeafSize * this->Occluders().GetPolygon(j).Diameter;
    for (const std::array<int, 3>& tri : s.Triangles)
    {
      const double longest = std::max({ Length(s.Points[tri[1]] - s.Points[tri[0]]),
        Length(s.Points[tri[2]] - s.Points[tri[1]]), Length(s.Points[tri[0]] - s.Points[tri[2]]) });
      const double levels = longest > size ? std::min(12.0, std::ceil(std::log2(longest / size))) : 0.0;
      leaves += std::pow(4.0, levels);
    }
  }
  const bool split = leaves <= MaximumGroupLeaves;
  for (int j : members)
  {
    this->AddLeaves(j, origin,
      split ? this->Settings.LeafSize * this->Occluders().GetPolygon(j).Diameter : HUGE_VAL,
      basis != nullptr, shot.Leaves);
  }
  if (basis)
  {
    basis->resize(shot.Leaves.size());
    for (std::size_t l = 0; l < shot.Leaves.size(); ++l)
    {
      std::copy(shot.Leaves[l].Values, shot.Leaves[l].Values + 3, (*basis)[l].begin());
      shot.Leaves[l] = this->Reweighted(shot.Leaves[l], (*basis)[l], origin);
    }
  }
  if (shot.Leaves.empty())
  {
    return;
  }
  shot.Empty = false;
  std::vector<int> order(shot.Leaves.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    order[k] = static_cast<int>(k);
  }
  shot.Nodes.reserve(2 * shot.Leaves.size());
  this->BuildNode(shot.Leaves, order, 0, static_cast<int>(shot.Leaves.size()), origin, shot);
  if (basis)
  {
    for (std::size_t l = 0; l < shot.Leaves.size(); ++l)
    {
      std::copy((*basis)[l].begin(), (*basis)[l].end(), shot.Leaves[l].Values);
    }
  }
}

int ProgressiveShooter::Internal::BuildNode(const std::vector<Leaf>& leaves,
  std::vector<int>& order, int first, int count, const Vec3& origin, Shot& shot) const
{
  std::vector<Node>& nodes = shot.Nodes;
  const int id = static_cast<int>(nodes.size());
  nodes.emplace_back();
  std::vector<const Leaf*> range(static_cast<std::size_t>(count));
  Vec3 lo = leaves[order[first]].Centroid;
  Vec3 hi = lo;
  for (int k = 0; k < count; ++k)
  {
    range[k] = &leaves[order[first + k]];
    const Vec3& c = range[k]->Centroid;
    lo = { std::min(lo.X, c.X), std::min(lo.Y, c.Y), std::min(lo.Z, c.Z) };
    hi = { std::max(hi.X, c.X), std::max(hi.Y, c.Y), std::max(hi.Z, c.Z) };
  }
  AxisMoments moments;
  Node node = Aggregate(range.data(), count, origin, &moments);
  if (node.ConeCos < 1.0 || node.ConeSin > 0.0)
  {
    node.Mixed = static_cast<int>(shot.Moments.size());
    shot.Moments.push_back(moments);
  }
  const Vec3& normal = node.Normal;
  node.FrontMin = HUGE_VAL;
  node.FrontMax = -HUGE_VAL;
  node.Surface = range[0]->Surface;
  const Leaf* nearest = range[0];
  for (const Leaf* leaf : range)
  {
    node.Surface = leaf->Surface == node.Surface ? node.Surface : -1;
    if (SquaredLength(leaf->Centroid - node.Centroid) <
      SquaredLength(nearest->Centroid - node.Centroid))
    {
      nearest = leaf;
    }
    for (const Vec3& p : leaf->Points)
    {
      node.FrontMin = std::min(node.FrontMin, Dot(normal, p));
      node.FrontMax = std::max(node.FrontMax, Dot(normal, p));
    }
  }
  node.Target = node.Surface >= 0 ? node.Centroid : nearest->Centroid;
  node.TargetSurface = nearest->Surface;
  if (count > 1)
  {
    // Median split (ties by leaf index: deterministic): of the leaves'
    // normals along their widest axis while the normal cone is wider than
    // MaximumConeAngle (so that clusters face one way, and x is in front of
    // all of a cluster's planes or behind them), else of the leaf centroids
    // along the longest axis.
    const bool byNormal = node.ConeCos < std::cos(MaximumConeAngle);
    Vec3 low = lo, high = hi;
    if (byNormal)
    {
      low = high = range[0]->Normal;
      for (const Leaf* leaf : range)
      {
        const Vec3& m = leaf->Normal;
        low = { std::min(low.X, m.X), std::min(low.Y, m.Y), std::min(low.Z, m.Z) };
        high = { std::max(high.X, m.X), std::max(high.Y, m.Y), std::max(high.Z, m.Z) };
      }
    }
    const Vec3 extent = high - low;
    const int axis =
      extent.X >= extent.Y ? (extent.X >= extent.Z ? 0 : 2) : (extent.Y >= extent.Z ? 1 : 2);
    const int half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half,
      order.begin() + first + count, [axis, byNormal, &leaves](int a, int b) {
        const double ca = byNormal ? leaves[a].Normal[axis] : leaves[a].Centroid[axis];
        const double cb = byNormal ? leaves[b].Normal[axis] : leaves[b].Centroid[axis];
        return ca < cb || (ca == cb && a < b);
      });
    node.Left = this->BuildNode(leaves, order, first, half, origin, shot);
    node.Right = this->BuildNode(leaves, order, first + half, count - half, origin, shot);
  }
  else
  {
    node.LeafIndex = order[first];
  }
  nodes[id] = node;
  return id;
}

RGB ProgressiveShooter::Internal::Evaluate(const Shot& shot, const Vec3& x, const Vec3& origin,
  const Vec3& n, int receiver, const std::vector<int>* candidates, const RayCaster* caster,
  ChunkWorkspace& ws, long long& rays) const
{
  if (shot.Empty || shot.Behind(x))
  {
    return RGB();
  }
  if (shot.Method == ShotMethod::Exact)
  {
    VisibleRegion& region = ws.Linear.Region;
    if (candidates)
    {
      this->Exact.FormFactor(
        x, n, receiver, shot.Shooter, *candidates, ws.Linear.Visibility, &region);
    }
    else
    {
      this->Exact.FormFactor(x, n, receiver, shot.Shooter, ws.Linear.Visibility, &region);
    }
    // Each visible piece intersected with each triangle that may meet it,
    // integrated in closed form for the triangle's linear radiance.
    return VisibleShooterIrradiance(x, n, shot.Radiance, region, shot.Normal, ws.Linear);
  }
  ws.Roots.assign(1, 0);
  return NonNegative(
    this->EvaluateFast(shot, x, origin, n, receiver, ws.Roots, *caster, ws, rays));
}

/// The fast method at x over the subtrees of the hierarchy rooted at
/// `roots` (the root alone for the whole shooter). Unclamped.
RGB ProgressiveShooter::Internal::EvaluateFast(const Shot& shot, const Vec3& x,
  const Vec3& origin, const Vec3& n, int receiver, const std::vector<int>& roots,
  const RayCaster& caster, ChunkWorkspace& ws, long long& rays, TransportUnit* record) const
{
  // 1. Cut the hierarchy where nodes look small from x.
  const double theta = shot.OpeningAngle;
  ws.Current.clear();
  ws.Stack.assign(roots.rbegin(), roots.rend());
  while (!ws.Stack.empty())
  {
    const int id = ws.Stack.back();
    ws.Stack.pop_back();
    const Node& node = shot.Nodes[id];
    if (node.Surface == receiver)
    {
      continue; // a plane does not light itself (a group shot may hold the receiver)
    }
    const Side side = SideOf(node, x);
    if (side == Side::Behind)
    {
      continue; // behind every shooter plane of the node
    }
    const Vec3 d = node.Centroid - x;
    if (node.Left >= 0 &&
      (node.Radius * node.Radius >= theta * theta * SquaredLength(d) || side == Side::Straddle))
    {
      // Right first so that the left child is handled first (a fixed order).
      ws.Stack.push_back(node.Right);
      ws.Stack.push_back(node.Left);
      continue;
    }
    ws.Current.push_back(id);
  }
  // 2. Visibility, refined where it varies: a far leaf is tested by one ray
  // to its centroid; an inner node by one ray to each child's centroid, and
  // if the two disagree (a shadow edge may cross it) its children are
  // handled the same way, in the next round. Rays of a round are traced
  // together. Near leaves (radius >= OpeningAngle * distance) go to step 3.
  RGB sum;
  const auto take = [&](int id) {
    if (record)
    {
      record->Nodes.push_back(id);
    }
    else
    {
      sum += this->NodeIrradiance(shot, shot.Nodes[id], x, n);
    }
  };
  ws.Near.clear();
  const auto isNear = [&](const Node& node) {
    return node.Radius * node.Radius >= theta * theta * SquaredLength(node.Centroid - x);
  };
  while (!ws.Current.empty())
  {
    QueueTargets(shot.Nodes, ws.Current, [&](const Node& leaf) { return !isNear(leaf); }, ws);
    const int count = static_cast<int>(ws.Targets.size());
    if (count > 0)
    {
      TraceTargets(caster, origin, receiver, ws);
      rays += count;
    }
    ws.Next.clear();
    int ray = 0;
    for (const int id : ws.Current)
    {
      const Node& node = shot.Nodes[id];
      if (node.Left < 0)
      {
        if (isNear(node))
        {
          ws.Near.push_back(node.LeafIndex);
        }
        else if (!ws.Occluded[ray++])
        {
          take(id);
        }
        continue;
      }
      const bool left = !ws.Occluded[ray++];
      const bool right = !ws.Occluded[ray++];
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
        const Node& child = shot.Nodes[children[c]];
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
  // 3. Near leaves: split in four while x is within a piece's radius of its
  // centroid (down to NearDepth levels, and not below 4 times the distance
  // between x and the ray origin, from where finer visibility would be
  // wrong anyway). Each piece is tested by its own ray and weighted by the
  // expansion, or, if it still looks large (radius >= OpeningAngle *
  // distance), by its closed-form integral over its part in front of x,
  // the ray aimed at that part. Near the foot of x (a receiver touching the
  // shooter's plane, a contact) the visibility then follows the geometry
  // instead of one ray per leaf deciding for all.
  ws.Targets.clear();
  ws.TargetSurfaces.clear();
  ws.TargetLeaves.clear();
  ws.Weights.clear();
  const double originShift = Length(origin - x);
  const double offset = Dot(n, x);
  for (const int index : ws.Near)
  {
    const Leaf& leaf = shot.Leaves[index];
    if (!(Dot(leaf.Normal, x) > Dot(leaf.Normal, leaf.Points[0])))
    {
      continue; // behind this leaf's shooter (a group shot)
    }
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
        const RGB e = this->NodeIrradiance(shot, node, x, n);
        if (!e.IsZero())
        {
          ws.Targets.push_back(node.Centroid);
          ws.Weights.push_back(e);
          ws.TargetSurfaces.push_back(leaf.Surface);
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
        ws.Targets.push_back(target / static_cast<double>(count));
        ws.Weights.push_back(e);
        ws.TargetSurfaces.push_back(leaf.Surface);
        ws.TargetLeaves.push_back(index);
      }
    }
  }
  if (!ws.Targets.empty())
  {
    const int count = static_cast<int>(ws.Targets.size());
    TraceTargets(caster, origin, receiver, ws);
    rays += count;
    for (int k = 0; k < count; ++k)
    {
      if (!ws.Occluded[k] && record)
      {
        record->Near.push_back({ ws.TargetLeaves[k], ws.Weights[k] });
      }
      else if (!ws.Occluded[k])
      {
        sum += ws.Weights[k];
      }
    }
  }
  return sum;
}

void ProgressiveShooter::Internal::BuildClusters()
{
  this->Clusters.clear();
  this->ClusterPoints.clear();
  this->ClustersValid = true;
  // ReuseTransport records per cluster: single points stand for no clusters.
  const int size = std::max(1, this->Settings.ReceiverClusterSize);
  // Surfaces grouped by plane (normals within 1e-6, offsets within 1e-6 of
  // the diameters), in id order: points of one plane see past the same
  // occluders; a box's top and the floor around it do not.
  std::vector<Vec3> normals;
  std::vector<double> offsets, diameters;
  std::vector<std::vector<int>> groups;
  for (int i = 0; i < static_cast<int>(this->Samples.size()); ++i)
  {
    if (this->EvaluationPoints[i].empty())
    {
      continue;
    }
    const Vec3& normal = this->Occluders().GetPolygon(i).Normal;
    const double offset = this->Occluders().GetPolygon(i).Offset;
    const double diameter = this->Occluders().GetPolygon(i).Diameter;
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
  // Each group's points split at the median of the longest side of their
  // bounding box until at most `size` remain (ties broken by surface and
  // index, so that the clusters do not depend on the library's sort).
  const auto point = [this](const std::pair<int, int>& p) -> const Vec3& {
    return this->EvaluationPoints[p.first][p.second];
  };
  // The spacing of a surface's points, sqrt(area / points): a cluster
  // wider than sqrt(size) spacings (sparse points, e.g. small faces far
  // apart) is split further, else nothing would be far from it.
  const auto spacing = [this](int i) {
    return std::sqrt(this->Occluders().GetPolygon(i).Area /
      static_cast<double>(this->EvaluationPoints[i].size()));
  };
  for (std::size_t g = 0; g < groups.size(); ++g)
  {
    const int begin = static_cast<int>(this->ClusterPoints.size());
    for (int i : groups[g])
    {
      for (int k = 0; k < static_cast<int>(this->EvaluationPoints[i].size()); ++k)
      {
        this->ClusterPoints.emplace_back(i, k);
      }
    }
    std::vector<std::pair<int, int>> ranges{ { begin,
      static_cast<int>(this->ClusterPoints.size()) - begin } };
    while (!ranges.empty())
    {
      const std::pair<int, int> range = ranges.back();
      ranges.pop_back();
      auto first = this->ClusterPoints.begin() + range.first;
      auto last = first + range.second;
      Vec3 low = point(*first), high = low;
      double widest = 0.0;
      for (auto it = first; it != last; ++it)
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
        const int axis = extent.X >= extent.Y && extent.X >= extent.Z ? 0 : (extent.Y >= extent.Z ? 1 : 2);
        const auto coordinate = [axis](const Vec3& p) {
          return axis == 0 ? p.X : (axis == 1 ? p.Y : p.Z);
        };
        const int half = range.second / 2;
        std::nth_element(first, first + half, last,
          [&](const std::pair<int, int>& a, const std::pair<int, int>& b) {
            const double ca = coordinate(point(a)), cb = coordinate(point(b));
            return ca < cb || (ca == cb && a < b);
          });
        ranges.emplace_back(range.first + half, range.second - half);
        ranges.emplace_back(range.first, half);
        continue;
      }
      ReceiverCluster cluster;
      cluster.Centre = (low + high) * 0.5;
      cluster.First = range.first;
      cluster.Count = range.second;
      cluster.Surface = first->first;
      double nearest = HUGE_VAL;
      for (auto it = first; it != last; ++it)
      {
        const double r = Length(point(*it) - cluster.Centre);
        cluster.Radius = std::max(cluster.Radius, r);
        cluster.Surface = it->first == cluster.Surface ? cluster.Surface : -1;
        if (r < nearest)
        {
          nearest = r;
          cluster.Origins[0] = static_cast<int>(it - this->ClusterPoints.begin());
        }
      }
      cluster.OriginCount = 1;
      while (cluster.OriginCount < std::min(ClusterOrigins, cluster.Count))
      {
        double farthest = -1.0;
        int chosen = cluster.Origins[0];
        for (auto it = first; it != last; ++it)
        {
          double distance = HUGE_VAL;
          for (int o = 0; o < cluster.OriginCount; ++o)
          {
            distance = std::min(
              distance, SquaredLength(point(*it) - point(this->ClusterPoints[cluster.Origins[o]])));
          }
          if (distance > farthest)
          {
            farthest = distance;
            chosen = static_cast<int>(it - this->ClusterPoints.begin());
          }
        }
        cluster.Origins[cluster.OriginCount++] = chosen;
      }
      this->Clusters.push_back(cluster);
    }
  }
}

/**
 * The fast method at every point of a receiver cluster: point p of surface
 * i goes to irradiance[firstItem[i] + p], and is skipped if firstItem[i] < 0.
 * Nodes far from the whole cluster (radius < OpeningAngle * (distance to
 * its centre - its radius)) and in front of all its points are found once
 * and tested for visibility from the cluster's origins, refined as in
 * EvaluateFast; each one visible from all of them is expanded at every
 * point. The rest of the hierarchy (nodes too near, or seen by some
 * origins only) is evaluated point by point.
 */
void ProgressiveShooter::Internal::EvaluateCluster(const Shot& shot,
  const ReceiverCluster& cluster, const RayCaster& caster, const std::vector<long long>& firstItem,
  ChunkWorkspace& ws, RGB* irradiance, long long& rays, TransportUnit* record) const
{
  bool any = record != nullptr; // recording: every point, firstItem unused
  for (int k = 0; k < cluster.Count && !any; ++k)
  {
    any = firstItem[this->ClusterPoints[cluster.First + k].first] >= 0;
  }
  if (!any)
  {
    return;
  }
  const double theta = shot.OpeningAngle;
  const Vec3& centre = cluster.Centre;
  const double spread = cluster.Radius;
  const auto far = [&](const Node& node) {
    const double distance = Length(node.Centroid - centre) - spread;
    return distance > 0.0 && node.Radius < theta * distance;
  };
  // 1. The cut for the whole cluster. A node neither far from all of it nor
  // opened at its centre (where a point there would open it) goes to the
  // points, which would mostly take it whole.
  ws.Roots.clear();
  ws.Current.clear();
  ws.Stack.assign(1, 0);
  while (!ws.Stack.empty())
  {
    const int id = ws.Stack.back();
    ws.Stack.pop_back();
    const Node& node = shot.Nodes[id];
    if (cluster.Surface >= 0 && node.Surface == cluster.Surface)
    {
      continue; // a plane does not light itself
    }
    const Side side = SideOf(node, centre, spread);
    if (side == Side::Behind)
    {
      continue;
    }
    if (side == Side::Front && far(node))
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
  // 2. Visibility of the far nodes, by rays from each of the cluster's
  // origins. Where they agree they decide for the whole cluster (refined
  // as in EvaluateFast where a node's children disagree); where they do
  // not, a shadow edge crosses the cluster and the node goes to the points.
  ws.Visible.clear();
  const int origins = cluster.OriginCount;
  ws.Flags.clear();
  while (!ws.Current.empty())
  {
    QueueTargets(shot.Nodes, ws.Current, [](const Node&) { return true; }, ws);
    // Per target: bit o set if visible from origin o.
    ws.Flags.assign(ws.Targets.size(), 0);
    for (int o = 0; o < origins; ++o)
    {
      const std::pair<int, int>& from = this->ClusterPoints[cluster.Origins[o]];
      TraceTargets(caster, this->RayOrigins[from.first][from.second], from.first, ws);
      rays += static_cast<long long>(ws.Targets.size());
      for (std::size_t t = 0; t < ws.Targets.size(); ++t)
      {
        ws.Flags[t] |= ws.Occluded[t] ? 0 : (1 << o);
      }
    }
    const unsigned char all = static_cast<unsigned char>((1 << origins) - 1);
    ws.Next.clear();
    int ray = 0;
    for (const int id : ws.Current)
    {
      const Node& node = shot.Nodes[id];
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
        const Node& child = shot.Nodes[children[c]];
        if (flags[c] != 0 && flags[c] != all)
        {
          ws.Roots.push_back(children[c]);
        }
        else if (child.Left >= 0)
        {
          ws.Next.push_back(children[c]);
        }
        else if (!far(child))
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
  // 3. Every point: the visible far nodes' expansions, and the rest on its own.
  if (record)
  {
    record->Shared = ws.Visible;
  }
  for (int k = 0; k < cluster.Count; ++k)
  {
    const std::pair<int, int>& p = this->ClusterPoints[cluster.First + k];
    const Vec3& x = this->EvaluationPoints[p.first][p.second];
    const Vec3& n = this->Occluders().GetPolygon(p.first).Normal;
    if (record)
    {
      if (!shot.Behind(x) && !ws.Roots.empty())
      {
        this->EvaluateFast(shot, x, this->RayOrigins[p.first][p.second], n, p.first, ws.Roots,
          caster, ws, rays, record);
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
    RGB sum;
    for (const int id : ws.Visible)
    {
      sum += this->NodeIrradiance(shot, shot.Nodes[id], x, n);
    }
    if (!ws.Roots.empty())
    {
      sum += this->EvaluateFast(
        shot, x, this->RayOrigins[p.first][p.second], n, p.first, ws.Roots, caster, ws, rays);
    }
    out = NonNegative(sum);
  }
}

/**
 * Record the transport: the hierarchy over every surface's triangles
 * (centroids weighted by the current unshot power, as a group shot's), cut
 * and tested for visibility at every receiving point as a fast shot would
 * (EvaluateCluster), with the nodes and near pieces used stored instead of
 * summed. The leaves carry basis values meanwhile, so that a near piece's
 * irradiance is the weights of its triangle's corners.
 */
void ProgressiveShooter::Internal::RecordTransport()
{
  std::unique_ptr<Transport> transport(new Transport);
  std::vector<int> all;
  for (int j = 0; j < static_cast<int>(this->Samples.size()); ++j)
  {
    if (!this->Samples[j].Triangles.empty())
    {
      all.push_back(j);
    }
  }
  if (!all.empty())
  {
    this->PrepareGroupShot(all, transport->Sweep, &transport->Basis);
  }
  Shot& shot = transport->Sweep;
  if (!this->ClustersValid)
  {
    this->BuildClusters();
  }
  transport->Units.resize(this->Clusters.size());
  if (!shot.Empty)
  {
    const RayCaster& caster = this->Caster();
    std::vector<long long> rays(this->Clusters.size(), 0);
    // In parts, each a parallel loop, so that progress is reported from
    // this thread between them.
    const std::size_t clusters = this->Clusters.size();
    const std::size_t parts = this->ShotProgress ? std::min<std::size_t>(clusters, 50) : 1;
    for (std::size_t part = 0; part < parts; ++part)
    {
      const std::size_t first = clusters * part / parts;
      const std::size_t last = clusters * (part + 1) / parts;
      this->For(last - first, [&](std::size_t begin, std::size_t end) {
        ChunkWorkspace ws;
        for (std::size_t c = first + begin; c < first + end; ++c)
        {
          this->EvaluateCluster(shot, this->Clusters[c], caster, {}, ws, nullptr, rays[c],
            &transport->Units[c]);
          TransportUnit& unit = transport->Units[c];
          unit.Shared.shrink_to_fit();
          unit.Nodes.shrink_to_fit();
          unit.Near.shrink_to_fit();
        }
      });
      if (this->ShotProgress)
      {
        this->ShotProgress(static_cast<double>(last) / static_cast<double>(clusters));
      }
    }
    for (const long long count : rays)
    {
      transport->Rays += count;
    }
  }
  this->Recorded = std::move(transport);
}

/**
 * The moments of node `id`'s subtree about the sweep's origin from its
 * leaves' current moments (and per axis i, of L m_i for leaves facing m),
 * and on the way every node's moments about its recorded centroid.
 */
void ProgressiveShooter::Internal::RefreshNode(int id, SubtreeMoments& out)
{
  Shot& shot = this->Recorded->Sweep;
  const int left = shot.Nodes[id].Left, right = shot.Nodes[id].Right;
  if (left < 0)
  {
    const Leaf& leaf = shot.Leaves[shot.Nodes[id].LeafIndex];
    out.Plain = leaf.Moments;
    for (int i = 0; i < 3; ++i)
    {
      out.Axis[i] = RawMoments();
      out.Axis[i].Add(leaf.Moments, leaf.Normal[i]);
    }
  }
  else
  {
    this->RefreshNode(left, out);
    SubtreeMoments other;
    this->RefreshNode(right, other);
    out.Plain.Add(other.Plain);
    for (int i = 0; i < 3; ++i)
    {
      out.Axis[i].Add(other.Axis[i]);
    }
  }
  Node& node = shot.Nodes[id];
  const Vec3 e = node.Centroid - shot.Origin;
  node.Power = out.Plain.Power;
  out.Plain.Central(e, node.Dipole, node.Quadrupole);
  if (node.Mixed >= 0)
  {
    AxisMoments& moments = shot.Moments[node.Mixed];
    for (int i = 0; i < 3; ++i)
    {
      moments.Power[i] = out.Axis[i].Power;
      out.Axis[i].Central(e, moments.Dipole[i], moments.Quadrupole[i]);
    }
  }
}

/// The leaves' values and moments from the current unshot radiance, then every node's.
void ProgressiveShooter::Internal::RefreshTransport()
{
  Shot& shot = this->Recorded->Sweep;
  if (shot.Empty)
  {
    return;
  }
  this->For(shot.Leaves.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t l = begin; l < end; ++l)
    {
      shot.Leaves[l] = this->Reweighted(shot.Leaves[l], this->Recorded->Basis[l], shot.Origin);
    }
  });
  SubtreeMoments root;
  this->RefreshNode(0, root);
}

/**
 * A sweep through the recorded transport: at every point of every receiver
 * cluster, the expansions of its recorded nodes with their current moments
 * and its near leaves' weights times their corners' unshot radiance.
 * Point p of surface i goes to irradiance[firstItem[i] + p].
 */
void ProgressiveShooter::Internal::Replay(
  const std::vector<long long>& firstItem, RGB* irradiance) const
{
  const Transport& transport = *this->Recorded;
  const Shot& shot = transport.Sweep;
  if (shot.Empty)
  {
    return;
  }
  this->For(this->Clusters.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
    {
      const ReceiverCluster& cluster = this->Clusters[c];
      const TransportUnit& unit = transport.Units[c];
      for (int k = 0; k < cluster.Count; ++k)
      {
        const std::pair<int, int>& p = this->ClusterPoints[cluster.First + k];
        const Vec3& x = this->EvaluationPoints[p.first][p.second];
        RGB& out = irradiance[firstItem[p.first] + p.second];
        if (shot.Behind(x))
        {
          out = RGB();
          continue;
        }
        const Vec3& n = this->Occluders().GetPolygon(p.first).Normal;
        RGB sum;
        for (const int id : unit.Shared)
        {
          sum += this->NodeIrradiance(shot, shot.Nodes[id], x, n);
        }
        for (int i = k == 0 ? 0 : unit.NodeEnd[k - 1]; i < unit.NodeEnd[k]; ++i)
        {
          sum += this->NodeIrradiance(shot, shot.Nodes[unit.Nodes[i]], x, n);
        }
        for (int i = k == 0 ? 0 : unit.NearEnd[k - 1]; i < unit.NearEnd[k]; ++i)
        {
          const NearWeight& near = unit.Near[i];
          const Leaf& leaf = shot.Leaves[near.Leaf];
          const SurfaceSamples& s = this->Samples[leaf.Surface];
          const std::array<int, 3>& tri = s.Triangles[leaf.Triangle];
          sum += s.Unshot[tri[0]] * near.W.R + s.Unshot[tri[1]] * near.W.G +
            s.Unshot[tri[2]] * near.W.B;
        }
        out = NonNegative(sum);
      }
    }
  });
}

RGB ProgressiveShooter::Internal::NodeIrradiance(
  const Shot& shot, const Node& node, const Vec3& x, const Vec3& n) const
{
  const Vec3 d = node.Centroid - x;
  if (!(Dot(n, d) > 0.0))
  {
    return RGB(); // the centroid is behind the receiver
  }
  if (node.Mixed < 0)
  {
    if (!(-Dot(node.Normal, d) > 0.0))
    {
      return RGB(); // x is behind the centroid's plane
    }
    return Expansion(node.Normal, node.Power, node.Dipole, node.Quadrupole, d, n);
  }
  // Leaves facing different ways (x in front of all of them, see SideOf).
  const AxisMoments& moments = shot.Moments[node.Mixed];
  RGB e;
  for (int i = 0; i < 3; ++i)
  {
    const Vec3 axis(i == 0 ? 1.0 : 0.0, i == 1 ? 1.0 : 0.0, i == 2 ? 1.0 : 0.0);
    e += Expansion(axis, moments.Power[i], moments.Dipole[i], moments.Quadrupole[i], d, n);
  }
  return e;
}

void ProgressiveShooter::Internal::UpdateEvaluationPoints(int surfaceId)
{
  // Evaluation points: boundary samples moved inside (see the file comment).
  const SurfaceSamples& samples = this->Samples[surfaceId];
  const std::vector<double>& areas = this->Areas[surfaceId];
  const std::size_t n = samples.Points.size();
  std::vector<Vec3>& eval = this->EvaluationPoints[surfaceId];
  std::vector<Vec3>& origins = this->RayOrigins[surfaceId];
  if (samples.Uniform && !samples.Triangles.empty())
  {
    // One point: the centroid of the triangles' area, or if that lies in
    // none of them (a concave surface) the centroid of the largest.
    Vec3 centroid;
    double total = 0.0;
    std::size_t largest = 0;
    for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
    {
      const std::array<int, 3>& tri = samples.Triangles[t];
      centroid += (samples.Points[tri[0]] + samples.Points[tri[1]] + samples.Points[tri[2]]) *
        (areas[t] / 3.0);
      total += areas[t];
      largest = areas[t] > areas[largest] ? t : largest;
    }
    const std::array<int, 3>& big = samples.Triangles[largest];
    const Vec3 fallback =
      (samples.Points[big[0]] + samples.Points[big[1]] + samples.Points[big[2]]) / 3.0;
    centroid = total > 0.0 ? centroid / total : fallback;
    bool inside = false;
    for (std::size_t t = 0; t < samples.Triangles.size() && !inside; ++t)
    {
      const std::array<int, 3>& tri = samples.Triangles[t];
      const Vec3 a = samples.Points[tri[0]], b = samples.Points[tri[1]], c = samples.Points[tri[2]];
      const Vec3 normal = Cross(b - a, c - a);
      inside = Dot(Cross(b - a, centroid - a), normal) >= 0.0 &&
        Dot(Cross(c - b, centroid - b), normal) >= 0.0 &&
        Dot(Cross(a - c, centroid - c), normal) >= 0.0;
    }
    eval.assign(1, inside ? centroid : fallback);
    origins = eval;
    return;
  }
  eval = samples.Points;
  origins = samples.Points;
  const double rayOffset =
    n > 0 ? this->Settings.RayOriginOffset * this->Occluders().GetPolygon(surfaceId).Diameter : 0.0;
  const double offset =
    n > 0 ? this->Settings.BoundaryOffset * this->Occluders().GetPolygon(surfaceId).Diameter : 0.0;
  if (offset > 0.0 || rayOffset > 0.0)
  {
    std::vector<std::pair<int, int>> edges;
    edges.reserve(3 * samples.Triangles.size());
    for (const std::array<int, 3>& tri : samples.Triangles)
    {
      for (int k = 0; k < 3; ++k)
      {
        const int a = tri[k];
        const int b = tri[(k + 1) % 3];
        edges.emplace_back(std::min(a, b), std::max(a, b));
      }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<char> boundary(n, 0);
    for (std::size_t e = 0; e < edges.size();)
    {
      std::size_t f = e + 1;
      while (f < edges.size() && edges[f] == edges[e])
      {
        ++f;
      }
      if (f - e == 1)
      {
        boundary[edges[e].first] = 1;
        boundary[edges[e].second] = 1;
      }
      e = f;
    }
    // Incident triangles of every point (CSR), degenerate ones left out.
    std::vector<int> start(n + 1, 0);
    for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
    {
      for (int k = 0; k < 3 && areas[t] > 0.0; ++k)
      {
        ++start[samples.Triangles[t][k] + 1];
      }
    }
    for (std::size_t k = 0; k < n; ++k)
    {
      start[k + 1] += start[k];
    }
    std::vector<int> incident(static_cast<std::size_t>(start[n]));
    std::vector<int> corner(incident.size());
    {
      std::vector<int> fill(start.begin(), start.end() - 1);
      for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
      {
        for (int k = 0; k < 3 && areas[t] > 0.0; ++k)
        {
          const int slot = fill[samples.Triangles[t][k]]++;
          incident[slot] = static_cast<int>(t);
          corner[slot] = k;
        }
      }
    }
    // Target of a boundary point: the centroid of its incident triangle with
    // the largest angle there; on a tie (within 1e-9) the mean of the tied
    // centroids, so that the rule does not depend on the triangles' order
    // (mirror-symmetric meshes give mirror-symmetric points), unless that
    // mean lies outside every incident corner (a reflex fan): then the first.
    for (std::size_t k = 0; k < n; ++k)
    {
      if (!boundary[k] || start[k] == start[k + 1])
      {
        continue;
      }
      const Vec3& p = samples.Points[k];
      double largest = -1.0;
      for (int slot = start[k]; slot < start[k + 1]; ++slot)
      {
        largest =
          std::max(largest, AngleAt(samples, samples.Triangles[incident[slot]], corner[slot]));
      }
      Vec3 sum;
      Vec3 first;
      int ties = 0;
      for (int slot = start[k]; slot < start[k + 1]; ++slot)
      {
        const std::array<int, 3>& tri = samples.Triangles[incident[slot]];
        if (AngleAt(samples, tri, corner[slot]) >= largest * (1.0 - 1e-9))
        {
          const Vec3 centroid =
            (samples.Points[tri[0]] + samples.Points[tri[1]] + samples.Points[tri[2]]) / 3.0;
          first = ties == 0 ? centroid : first;
          sum += centroid;
          ++ties;
        }
      }
      Vec3 target = sum / static_cast<double>(ties);
      if (ties > 1)
      {
        bool inside = false;
        for (int slot = start[k]; slot < start[k + 1] && !inside; ++slot)
        {
          // Inside the corner at p: d = alpha u + beta v with alpha, beta >= 0.
          const std::array<int, 3>& tri = samples.Triangles[incident[slot]];
          const Vec3 u = samples.Points[tri[(corner[slot] + 1) % 3]] - p;
          const Vec3 v = samples.Points[tri[(corner[slot] + 2) % 3]] - p;
          const Vec3 d = target - p;
          const Vec3 normal = Cross(u, v);
          inside = Dot(Cross(d, v), normal) >= 0.0 && Dot(Cross(u, d), normal) >= 0.0;
        }
        target = inside ? target : first;
      }
      const Vec3 d = target - p;
      const double length = Length(d);
      if (length > 0.0)
      {
        eval[k] = p + d * std::min(0.5, offset / length);
        origins[k] = p + d * std::min(0.5, rayOffset / length);
      }
    }
  }
}

ShootingEnergy ProgressiveShooter::Internal::InitialEnergy() const
{
  ShootingEnergy e;
  e.Emitted = this->Emitted;
  for (std::size_t i = 0; i < this->Samples.size(); ++i)
  {
    const SurfaceSamples& s = this->Samples[i];
    if (s.Triangles.empty())
    {
      continue;
    }
    e.InitialUnshot += this->UnshotPower[i];
    // Reflected radiance received so far (direct light): Total - L^e.
    const Surface& surface = this->SceneCopy.Surfaces[i];
    std::vector<RGB> reflected(s.Total.size());
    for (std::size_t k = 0; k < reflected.size(); ++k)
    {
      reflected[k] = Difference(s.Total[k], surface.Emission);
    }
    const RGB power = IntegrateLinear(s, this->Areas[i], reflected) * Pi;
    for (int c = 0; c < 3; ++c)
    {
      const double rho = surface.Reflectance[c];
      if (rho > 0.0)
      {
        e.PriorAbsorbed[c] += (1.0 - rho) / rho * power[c];
      }
    }
  }
  e.PriorEscaped = Difference(Difference(e.Emitted, e.InitialUnshot), e.PriorAbsorbed);
  e.Unshot = e.InitialUnshot;
  return e;
}

void ProgressiveShooter::Internal::EnsureEnergy()
{
  if (!this->EnergyValid)
  {
    this->Energy = this->InitialEnergy();
    this->Reference =
      this->Emitted.Mean() > 0.0 ? this->Emitted.Mean() : this->Energy.InitialUnshot.Mean();
    this->EnergyValid = true;
  }
}

ProgressiveShooter::ProgressiveShooter(const Scene& scene)
  : P(new Internal(scene))
{
}

ProgressiveShooter::~ProgressiveShooter() = default;

int ProgressiveShooter::GetNumberOfSurfaces() const
{
  return static_cast<int>(this->P->Samples.size());
}

void ProgressiveShooter::SetSettings(const ProgressiveShooterSettings& settings)
{
  settings.Validate();
  const bool moved = settings.BoundaryOffset != this->P->Settings.BoundaryOffset ||
    settings.RayOriginOffset != this->P->Settings.RayOriginOffset;
  this->P->ClustersValid = this->P->ClustersValid && !moved &&
    settings.ReceiverClusterSize == this->P->Settings.ReceiverClusterSize;
  const ProgressiveShooterSettings& old = this->P->Settings;
  if (!this->P->ClustersValid || settings.OpeningAngle != old.OpeningAngle ||
    settings.LeafSize != old.LeafSize)
  {
    this->P->Recorded.reset();
  }
  this->P->Settings = settings;
  if (moved)
  {
    for (int i = 0; i < this->GetNumberOfSurfaces(); ++i)
    {
      this->P->UpdateEvaluationPoints(i);
    }
  }
}

const ProgressiveShooterSettings& ProgressiveShooter::GetSettings() const
{
  return this->P->Settings;
}

void ProgressiveShooter::SetShotProgressCallback(ShotProgressCallback callback)
{
  this->P->ShotProgress = std::move(callback);
}

void ProgressiveShooter::SetParallelFor(ParallelFor parallelFor)
{
  this->P->Loop = std::move(parallelFor);
}

void ProgressiveShooter::SetSurfaceSamples(int surfaceId, SurfaceSamples samples)
{
  Internal& I = *this->P;
  if (surfaceId < 0 || surfaceId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: surface id " + std::to_string(surfaceId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  const std::string where = "progressive shooter: " + SurfaceName(surfaceId) + ": ";
  const std::size_t n = samples.Points.size();
  if (samples.Total.size() != n || samples.Unshot.size() != n)
  {
    throw InputError(where + std::to_string(n) + " points but " +
      std::to_string(samples.Total.size()) + " total and " + std::to_string(samples.Unshot.size()) +
      " unshot values");
  }
  if (!samples.Triangles.empty() || n > 0)
  {
    const PreparedPolygon& poly = I.Occluders().GetPolygon(surfaceId);
    if (!poly.Valid)
    {
      throw InputError(where + "the scene polygon is degenerate and cannot take samples");
    }
    for (std::size_t k = 0; k < n; ++k)
    {
      const Vec3& p = samples.Points[k];
      if (!IsFinite(p))
      {
        throw InputError(where + "point " + std::to_string(k) + " has non-finite coordinates");
      }
      if (!IsFinite(samples.Total[k]) || !IsFinite(samples.Unshot[k]))
      {
        throw InputError(where + "point " + std::to_string(k) + " has a non-finite radiance");
      }
      if (std::abs(Dot(poly.Normal, p) - poly.Offset) > 1e-6 * poly.Diameter)
      {
        throw InputError(where + "point " + std::to_string(k) + " lies off the surface's plane");
      }
    }
    for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
    {
      for (const int id : samples.Triangles[t])
      {
        if (id < 0 || static_cast<std::size_t>(id) >= n)
        {
          throw InputError(where + "triangle " + std::to_string(t) + " refers to point " +
            std::to_string(id) + ", out of range [0, " + std::to_string(n) + ")");
        }
      }
    }
  }
  // Triangle areas.
  std::vector<double>& areas = I.Areas[surfaceId];
  areas.resize(samples.Triangles.size());
  for (std::size_t t = 0; t < samples.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = samples.Triangles[t];
    const Vec3& a = samples.Points[tri[0]];
    areas[t] = 0.5 * Length(Cross(samples.Points[tri[1]] - a, samples.Points[tri[2]] - a));
  }
  I.Samples[surfaceId] = std::move(samples);
  I.UpdateEvaluationPoints(surfaceId);
  I.ClustersValid = false;
  I.Recorded.reset();
  const SurfaceSamples& s = I.Samples[surfaceId];
  I.UnshotPower[surfaceId] = IntegrateLinear(s, areas, s.Unshot) * Pi;
  I.EnergyValid = false;
}

const SurfaceSamples& ProgressiveShooter::GetSurfaceSamples(int surfaceId) const
{
  return this->P->Samples.at(static_cast<std::size_t>(surfaceId));
}

const std::vector<Vec3>& ProgressiveShooter::GetEvaluationPoints(int surfaceId) const
{
  return this->P->EvaluationPoints.at(static_cast<std::size_t>(surfaceId));
}

RGB ProgressiveShooter::GetUnshotPower(int surfaceId) const
{
  return this->P->UnshotPower.at(static_cast<std::size_t>(surfaceId));
}

RGB ProgressiveShooter::GetTotalUnshotPower() const
{
  RGB sum;
  for (const RGB& p : this->P->UnshotPower)
  {
    sum += p;
  }
  return sum;
}

int ProgressiveShooter::SelectShooter() const
{
  int best = -1;
  double bestPower = 0.0;
  for (int i = 0; i < this->GetNumberOfSurfaces(); ++i)
  {
    const double power = this->P->UnshotPower[i].Mean();
    if (power > bestPower)
    {
      best = i;
      bestPower = power;
    }
  }
  return best;
}

double ProgressiveShooter::GetReferencePower() const
{
  if (this->P->EnergyValid)
  {
    return this->P->Reference;
  }
  const double emitted = this->P->Emitted.Mean();
  return emitted > 0.0 ? emitted : this->GetTotalUnshotPower().Mean();
}

ShotMethod ProgressiveShooter::ChooseMethod(double power) const
{
  const double fraction = this->P->Settings.ExactPowerFraction;
  if (std::isinf(fraction))
  {
    return ShotMethod::Fast;
  }
  return power >= fraction * this->GetReferencePower() ? ShotMethod::Exact : ShotMethod::Fast;
}

ShootingEnergy ProgressiveShooter::GetEnergy() const
{
  return this->P->EnergyValid ? this->P->Energy : this->P->InitialEnergy();
}

std::vector<RGB> ProgressiveShooter::ComputeIrradiance(int shooterId, ShotMethod method,
  const Vec3* points, std::size_t count, const Vec3& normal, int receiverId) const
{
  Internal& I = *this->P;
  if (shooterId < 0 || shooterId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: shooter id " + std::to_string(shooterId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  if (receiverId < -1 || receiverId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: receiver id " + std::to_string(receiverId) +
      " out of range [-1, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  std::vector<RGB> result(count);
  if (I.Samples[shooterId].Triangles.empty() || receiverId == shooterId)
  {
    return result;
  }
  Internal::Shot shot;
  I.PrepareShot(shooterId, method, shot);
  std::vector<int> candidates;
  const std::vector<int>* list = nullptr;
  if (receiverId >= 0 && method == ShotMethod::Exact)
  {
    if (!I.Exact.ShaftCandidates(shooterId, receiverId, candidates))
    {
      return result;
    }
    list = &candidates;
  }
  const RayCaster* caster = method == ShotMethod::Fast ? &I.Caster() : nullptr;
  ChunkWorkspace ws;
  long long rays = 0;
  for (std::size_t k = 0; k < count; ++k)
  {
    result[k] = I.Evaluate(shot, points[k], points[k], normal, receiverId, list, caster, ws, rays);
  }
  return result;
}

ShotRecord ProgressiveShooter::Shoot(int shooterId, ShotMethod method)
{
  Internal& I = *this->P;
  if (shooterId < 0 || shooterId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: shooter id " + std::to_string(shooterId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  I.EnsureEnergy();
  return I.ShootSurfaces({ shooterId }, method, this->GetReferencePower());
}

/**
 * Shoot the members' unshot radiance (one surface, or a group) at every
 * receiver that can see them. With `sweep` (ReuseTransport) the members are
 * every surface with triangles and the irradiance comes from the recorded
 * transport (recorded on the first sweep).
 */
ShotRecord ProgressiveShooter::Internal::ShootSurfaces(
  const std::vector<int>& members, ShotMethod method, double reference, bool sweep)
{
  Internal& I = *this;
  const int numberOfSurfaces = static_cast<int>(I.Samples.size());
  const bool group = members.size() > 1;
  const int shooterId = members[0];
  const auto start = std::chrono::steady_clock::now();
  ShotRecord record;
  record.Shooter = shooterId;
  record.Method = method;
  record.GroupSize = static_cast<int>(members.size());
  std::vector<char> isMember(I.Samples.size(), 0);
  bool anyTriangles = false;
  for (int j : members)
  {
    record.Power += I.UnshotPower[j];
    isMember[j] = 1;
    anyTriangles = anyTriangles || !I.Samples[j].Triangles.empty();
  }
  if (anyTriangles)
  {
    Internal::Shot shot;
    if (sweep)
    {
      shot.Empty = false; // the transport's hierarchy holds the members
    }
    else if (group)
    {
      I.PrepareGroupShot(members, shot);
    }
    else
    {
      I.PrepareShot(shooterId, method, shot);
    }
    const double coarse = I.Settings.CoarseShotFraction * reference;
    if (!sweep && record.Power.Mean() > 0.0 && record.Power.Mean() < coarse)
    {
      shot.OpeningAngle *= std::min(2.0, std::sqrt(coarse / record.Power.Mean()));
    }

    // Receivers that can exchange light with the shooter, their shaft
    // candidates, and one work item per sample.
    struct Receiver
    {
      int Id;
      std::size_t First; ///< first work item
      std::vector<int> Candidates;
    };
    std::vector<Receiver> receivers;
    std::size_t items = 0;
    if (!shot.Empty)
    {
      std::vector<int> candidates;
      for (int i = 0; i < numberOfSurfaces; ++i)
      {
        if ((isMember[i] && !shot.Mixed && !sweep) || I.EvaluationPoints[i].empty())
        {
          continue;
        }
        if (shot.Mixed || sweep)
        {
          // Members light each other; the hierarchy culls what is behind.
          candidates.clear();
        }
        else if (group)
        {
          // The receiver reaches in front of the lowest shooter plane, and
          // some shooter reaches in front of the receiver's plane (polygon
          // vertices: conservative, and cheap next to every sample or leaf).
          const PreparedPolygon& receiver = I.Occluders().GetPolygon(i);
          bool front = false, facing = false;
          for (const Vec3& p : I.SceneCopy.Surfaces[i].Vertices)
          {
            front = front || Dot(shot.Normal, p) > shot.Offset;
          }
          for (int j : members)
          {
            for (const Vec3& y : I.SceneCopy.Surfaces[j].Vertices)
            {
              facing = facing || Dot(receiver.Normal, y) > receiver.Offset;
            }
          }
          if (!front || !facing)
          {
            continue;
          }
          candidates.clear();
        }
        else if (!I.Exact.ShaftCandidates(shooterId, i, candidates))
        {
          continue;
        }
        receivers.push_back({ i, items, candidates });
        items += I.EvaluationPoints[i].size();
      }
    }
    record.Receivers = static_cast<int>(receivers.size());
    record.Samples = static_cast<long long>(items);
    std::vector<RGB> irradiance(items);
    std::vector<long long> rays; // per work item (fast method)
    const bool clustered = method == ShotMethod::Fast && I.Settings.ReceiverClusterSize > 1;
    if (items > 0 && sweep)
    {
      if (!I.Recorded)
      {
        I.RecordTransport();
        record.Rays += I.Recorded->Rays;
      }
      I.RefreshTransport();
      std::vector<long long> firstItem(I.Samples.size(), -1);
      for (const Receiver& rec : receivers)
      {
        firstItem[rec.Id] = static_cast<long long>(rec.First);
      }
      I.Replay(firstItem, irradiance.data());
    }
    else if (items > 0 && clustered)
    {
      if (!I.ClustersValid)
      {
        I.BuildClusters();
      }
      std::vector<long long> firstItem(I.Samples.size(), -1);
      for (const Receiver& rec : receivers)
      {
        firstItem[rec.Id] = static_cast<long long>(rec.First);
      }
      const RayCaster& caster = I.Caster();
      rays.assign(I.Clusters.size(), 0);
      I.For(I.Clusters.size(), [&](std::size_t begin, std::size_t end) {
        ChunkWorkspace ws;
        for (std::size_t c = begin; c < end; ++c)
        {
          I.EvaluateCluster(
            shot, I.Clusters[c], caster, firstItem, ws, irradiance.data(), rays[c]);
        }
      });
    }
    else if (items > 0)
    {
      const RayCaster* caster = method == ShotMethod::Fast ? &I.Caster() : nullptr;
      rays.assign(method == ShotMethod::Fast ? items : 0, 0);
      // Work item -> receiver by binary search on First.
      I.For(items, [&](std::size_t begin, std::size_t end) {
        ChunkWorkspace ws;
        std::size_t r = static_cast<std::size_t>(
          std::upper_bound(receivers.begin(), receivers.end(), begin,
            [](std::size_t item, const Receiver& rec) { return item < rec.First; }) -
          receivers.begin() - 1);
        for (std::size_t item = begin; item < end; ++item)
        {
          while (r + 1 < receivers.size() && item >= receivers[r + 1].First)
          {
            ++r;
          }
          const Receiver& rec = receivers[r];
          const std::size_t k = item - rec.First;
          const Vec3& normal = I.Occluders().GetPolygon(rec.Id).Normal;
          long long count = 0;
          irradiance[item] = I.Evaluate(shot, I.EvaluationPoints[rec.Id][k],
            I.RayOrigins[rec.Id][k], normal, rec.Id,
            &rec.Candidates, caster, ws, count);
          if (!rays.empty())
          {
            rays[item] = count;
          }
        }
      });
    }
    // The members' unshot radiance has been shot (before the updates: in a
    // group facing several ways members also receive).
    for (int j : members)
    {
      std::fill(I.Samples[j].Unshot.begin(), I.Samples[j].Unshot.end(), RGB());
      I.UnshotPower[j] = RGB();
    }
    // Fixed-order updates and sums.
    for (const Receiver& rec : receivers)
    {
      SurfaceSamples& s = I.Samples[rec.Id];
      const RGB rho = I.SceneCopy.Surfaces[rec.Id].Reflectance;
      std::vector<RGB> e(irradiance.begin() + static_cast<std::ptrdiff_t>(rec.First),
        irradiance.begin() + static_cast<std::ptrdiff_t>(rec.First + I.EvaluationPoints[rec.Id].size()));
      if (e.size() != s.Points.size())
      {
        e.assign(s.Points.size(), e[0]); // a uniform receiver
      }
      const RGB incident = IntegrateLinear(s, I.Areas[rec.Id], e);
      record.Incident += incident;
      record.Absorbed += RGB(1.0 - rho.R, 1.0 - rho.G, 1.0 - rho.B) * incident;
      const RGB factor = rho * (1.0 / Pi);
      for (std::size_t k = 0; k < e.size(); ++k)
      {
        const RGB dl = factor * e[k];
        s.Total[k] += dl;
        s.Unshot[k] += dl;
      }
      I.UnshotPower[rec.Id] = IntegrateLinear(s, I.Areas[rec.Id], s.Unshot) * Pi;
    }
    for (const long long count : rays)
    {
      record.Rays += count;
    }
  }
  record.Escaped = Difference(record.Power, record.Incident);
  I.Energy.ShotAbsorbed += record.Absorbed;
  I.Energy.ShotEscaped += record.Escaped;
  RGB unshot;
  for (const RGB& p : I.UnshotPower)
  {
    unshot += p;
  }
  I.Energy.Unshot = unshot;
  record.UnshotAfter = I.Energy.Unshot.Mean();
  record.Seconds = Seconds(start);
  return record;
}

bool ShootingDone(double unshot, double target, int shots, int maximumShots, StopReason& reason)
{
  if (unshot <= target)
  {
    reason = StopReason::Converged;
    return true;
  }
  if (shots >= maximumShots)
  {
    reason = StopReason::MaximumShots;
    return true;
  }
  return false;
}

double ShootingProgress(
  double unshotAfter, double initial, double target, int shots, int maximumShots)
{
  double progress;
  if (target > 0.0 && initial > target)
  {
    progress = std::log(std::max(unshotAfter, target) / initial) / std::log(target / initial);
  }
  else
  {
    progress = maximumShots > 0 ? static_cast<double>(shots) / maximumShots : 1.0;
  }
  return std::min(1.0, std::max(0.0, progress));
}

ShootingSummary ProgressiveShooter::Run(const ShotCallback& callback)
{
  Internal& I = *this->P;
  I.EnsureEnergy();
  const auto start = std::chrono::steady_clock::now();
  ShootingSummary summary;
  summary.ReferencePower = I.Reference;
  const double initial = this->GetTotalUnshotPower().Mean();
  const double target = I.Settings.UnshotFraction * I.Reference;
  while (!ShootingDone(this->GetTotalUnshotPower().Mean(), target, summary.Shots,
    I.Settings.MaximumShots, summary.Reason))
  {
    const int j = this->SelectShooter();
    if (j < 0)
    {
      summary.Reason = StopReason::NothingToShoot;
      break;
    }
    const ShotMethod method = this->ChooseMethod(I.UnshotPower[j].Mean());
    std::vector<int> members(1, j);
    const bool sweep = method == ShotMethod::Fast && I.Settings.ReuseTransport;
    if (sweep)
    {
      // Every surface (j, the strongest, first): its unshot radiance shoots
      // through the transport, zero or not.
      for (int k = 0; k < this->GetNumberOfSurfaces(); ++k)
      {
        if (k != j && !I.Samples[k].Triangles.empty())
        {
          members.push_back(k);
        }
      }
    }
    else if (method == ShotMethod::Fast && I.Settings.GroupWeakShots)
    {
      // The weak surfaces facing the shooter's way (which never light each
      // other), and if GroupAcrossOrientations those with at least
      // GroupPowerFraction of the shooter's power.
      const double least = GroupPowerFraction * I.UnshotPower[j].Mean();
      const Vec3& normal = I.Occluders().GetPolygon(j).Normal;
      for (int k = 0; k < this->GetNumberOfSurfaces(); ++k)
      {
        const double power = I.UnshotPower[k].Mean();
        if (k != j && power > 0.0 && !I.Samples[k].Triangles.empty() &&
          this->ChooseMethod(power) == ShotMethod::Fast &&
          ((I.Settings.GroupAcrossOrientations && power >= least) ||
            Dot(I.Occluders().GetPolygon(k).Normal, normal) > 1.0 - 1e-12))
        {
          members.push_back(k);
        }
      }
    }
    ShotRecord record = I.ShootSurfaces(members, method, this->GetReferencePower(), sweep);
    ++summary.Shots;
    if (method == ShotMethod::Exact)
    {
      ++summary.ExactShots;
      summary.ExactSeconds += record.Seconds;
    }
    else
    {
      ++summary.FastShots;
      summary.FastSeconds += record.Seconds;
    }
    summary.History.push_back(record);
    if (callback)
    {
      if (!callback(record,
            ShootingProgress(record.UnshotAfter, initial, target, summary.Shots,
              I.Settings.MaximumShots)))
      {
        summary.Reason = StopReason::Aborted;
        break;
      }
    }
  }
  summary.Energy = I.Energy;
  summary.UnshotFraction =
    I.Reference > 0.0 ? this->GetTotalUnshotPower().Mean() / I.Reference : 0.0;
  summary.Seconds = Seconds(start);
  return summary;
}

} // namespace penumbra
