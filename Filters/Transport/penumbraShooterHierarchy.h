// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShooterHierarchy.h
 * @brief The fast method's hierarchy over a shooter's pieces (private): the
 * leaves with the moments of their linear unshot radiance, the nodes with
 * their multipole moments, normal cones and plane ranges, the second-order
 * expansion of a node's irradiance, and the cut of the hierarchy at a point
 * (Documentation/design/transport.md, "The fast shot" and "Group shots").
 */
#ifndef penumbraShooterHierarchy_h
#define penumbraShooterHierarchy_h

#include "penumbraVector.h"

#include <algorithm>
#include <vector>

namespace penumbra
{

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
  /// Add the symmetric part of w * a b^T.
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
/// with the moments of its unshot radiance about the hierarchy's origin.
struct Leaf
{
  Vec3 Points[3];
  RGB Values[3]; ///< unshot radiance at the points (linear in between)
  RawMoments Moments; ///< about the hierarchy's origin
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
  /// Leaves facing different ways: index of its AxisMoments in the hierarchy, else -1.
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

/// A node whose leaves' normals spread wider than this (radians, from
/// their mean) is split by normal before space (ShooterHierarchy::Build).
constexpr double MaximumConeAngle = 0.5;

/// The four midpoint children of a triangle with per-corner values (linear in between).
void SplitTriangle(const Vec3 p[3], const RGB v[3], Vec3 cp[4][3], RGB cv[4][3]);

/// Power-weighted centroid of a triangle with linear radiance (corner
/// values v); its centroid when the power nearly cancels.
Vec3 PowerCentroid(const Vec3 p[3], const RGB v[3]);

/// A leaf: the triangle, its power, power-weighted centroid and moments about `origin`.
Leaf MakeLeaf(const Vec3 p[3], const RGB v[3], const Vec3& origin);

/// Split a triangle with per-corner values in four until its longest edge
/// is at most `size` (at most 12 levels), appending the leaves to `out`.
void SplitToLeaves(const Vec3 p[3], const RGB v[3], double size, const Vec3& origin, int depth,
  std::vector<Leaf>& out);

/**
 * The node of `count` leaves (power, centroid, radius, moments about the
 * centroid, normal cone) from their moments about `origin`; with `mixed`,
 * the per-axis moments when the normals differ. Children are not set.
 */
Node Aggregate(const Leaf* const* leaves, int count, const Vec3& origin, AxisMoments* mixed);

/// Where x lies relative to the planes of a node's leaves.
enum class Side
{
  Behind,   ///< behind (or on) every plane: the node sends nothing to x
  Front,    ///< strictly in front of every plane
  Straddle  ///< possibly in front of some and behind others
};

/**
 * Side of x: exact from the plane range for one normal; for a cone of
 * normals from the cone and the bounding sphere. With `spread` > 0 the
 * answer holds for every point within that distance of x (a receiver
 * cluster's bounding sphere).
 */
Side SideOf(const Node& node, const Vec3& x, double spread = 0.0);

/**
 * Second-order multipole expansion of int L k dA about a node's centroid c
 * for a shooter normal m, one term per channel, at x (receiver normal n),
 * d = c - x; see the definition for the formulas.
 */
RGB Expansion(const Vec3& m, const RGB& power, const Vec3 dipole[3], const Symmetric quadrupole[3],
  const Vec3& d, const Vec3& n);

/// A non-negative radiance gives a non-negative irradiance; grazing nodes'
/// expansions may dip below 0.
inline RGB NonNegative(const RGB& e)
{
  return { std::max(e.R, 0.0), std::max(e.G, 0.0), std::max(e.B, 0.0) };
}

/// Points go through the batched expansion in blocks of this many (one
/// vector register of doubles); batches are padded to whole blocks.
constexpr std::size_t BatchBlock = 4;

/// `count` rounded up to whole blocks.
inline std::size_t BatchStride(std::size_t count)
{
  return (count + BatchBlock - 1) / BatchBlock * BatchBlock;
}

/**
 * Receiving points in structure-of-arrays form, with the irradiance summed
 * at each: the expansions of one node at many points at once run as
 * vector instructions (ShooterHierarchy::AddIrradiance). The arrays hold
 * BatchStride(Size()) entries; the padding is never used.
 */
struct PointBatch
{
  std::vector<double> X, Y, Z;    ///< positions
  std::vector<double> NX, NY, NZ; ///< receiver normals
  std::vector<double> R, G, B;    ///< irradiance summed so far
  std::vector<unsigned char> All; ///< 1 for every point, 0 for the padding
  /// `count` points, their sums zero (positions and normals to be filled).
  void Reset(std::size_t count);
  std::size_t Size() const { return this->Count; }

private:
  std::size_t Count = 0;
};

/**
 * The hierarchy (a k-d tree) over a shooter's (or a group's) leaves. Fill
 * Origin and Leaves (moments about Origin), then Build.
 */
struct ShooterHierarchy
{
  std::vector<Leaf> Leaves;
  std::vector<Node> Nodes;          ///< root = 0
  std::vector<AxisMoments> Moments; ///< of the nodes facing several ways
  Vec3 Origin;                      ///< the leaves' moments are about this point

  /// Build Nodes (and Moments) over Leaves: median splits, by normal while a
  /// node's cone is wider than MaximumConeAngle, then by space.
  void Build();

  /// The expansion of node's irradiance at x (receiver normal n), 0 when
  /// its centroid is behind the receiver or x behind the centroid's plane.
  RGB Irradiance(const Node& node, const Vec3& x, const Vec3& n) const;

  /// Irradiance(node, x, n) added at every point of `points` (with `use`,
  /// BatchStride(points.Size()) flags, at those whose flag is 1), term by
  /// term as Irradiance computes it.
  void AddIrradiance(
    const Node& node, PointBatch& points, const unsigned char* use = nullptr) const;

  /**
   * The cut of the subtrees rooted at `roots` at x: the nodes (in a fixed
   * order) that are small from x (radius < theta * distance) or leaves, in
   * front of some of their planes and not of the receiver's own surface.
   * `stack` is scratch; the result replaces `cut`.
   */
  void Cut(const Vec3& x, int receiver, double theta, const std::vector<int>& roots,
    std::vector<int>& stack, std::vector<int>& cut) const;

  /// Every node's moments about its (kept) centroid from the leaves'
  /// current moments: the recorded transport re-weights its hierarchy so.
  void RefreshMoments();

private:
  struct SubtreeMoments
  {
    RawMoments Plain;
    RawMoments Axis[3];
  };
  int BuildNode(std::vector<int>& order, int first, int count);
  void RefreshNode(int id, SubtreeMoments& out);
};

} // namespace penumbra

#endif
