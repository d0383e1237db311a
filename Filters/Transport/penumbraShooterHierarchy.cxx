// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraShooterHierarchy.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

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

/*
 * For a cone of normals (axis a, half-angle alpha) and the bounding sphere
 * (c, R): m.(x - y) = m.(x - c) + m.(c - y), the first term between
 * |x - c| cos(phi + alpha) and |x - c| cos(phi - alpha) (phi the angle
 * between a and x - c), the second within [-R, R].
 */
Side SideOf(const Node& node, const Vec3& x, double spread)
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

/*
 * With the kernel k(y) = a b / s^2 (d = y - x, s = |d|^2, a = n.d,
 * b = -m.d):
 *   E_c = P_c k + grad k . D_c + 1/2 H : M_c,
 *   grad k = u / s^2 - 4 a b d / s^3,  u = b n - a m,
 *   H = -(n m^T + m n^T) / s^2 - 4 (u d^T + d u^T) / s^3 - 4 a b I / s^3
 *       + 24 a b d d^T / s^4.
 * Linear in m, so also valid term by term for m = e_i (AxisMoments).
 */
RGB Expansion(const Vec3& m, const RGB& power, const Vec3 dipole[3], const Symmetric quadrupole[3],
  const Vec3& d, const Vec3& n)
{
  // One division: the powers of 1 / s from its reciprocal.
  const double inverse = 1.0 / SquaredLength(d);
  const double inverse2 = inverse * inverse;
  const double inverse3 = inverse2 * inverse;
  const double a = Dot(n, d);
  const double b = -Dot(m, d);
  const double ab = a * b;
  const Vec3 u = n * b - m * a;
  const double k = ab * inverse2;
  const Vec3 gradient = u * inverse2 - d * (4.0 * ab * inverse3);
  // The Hessian, once for the three channels (M_c : H each).
  Symmetric hessian;
  hessian.AddOuter(n, m, -2.0 * inverse2);
  hessian.AddOuter(u, d, -8.0 * inverse3);
  hessian.AddOuter(d, d, 24.0 * ab * inverse3 * inverse);
  const double diagonal = -4.0 * ab * inverse3;
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

void ShooterHierarchy::Build()
{
  if (this->Leaves.empty())
  {
    return;
  }
  std::vector<int> order(this->Leaves.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    order[k] = static_cast<int>(k);
  }
  this->Nodes.reserve(2 * this->Leaves.size());
  this->BuildNode(order, 0, static_cast<int>(this->Leaves.size()));
}

int ShooterHierarchy::BuildNode(std::vector<int>& order, int first, int count)
{
  const std::vector<Leaf>& leaves = this->Leaves;
  std::vector<Node>& nodes = this->Nodes;
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
  Node node = Aggregate(range.data(), count, this->Origin, &moments);
  if (node.ConeCos < 1.0 || node.ConeSin > 0.0)
  {
    node.Mixed = static_cast<int>(this->Moments.size());
    this->Moments.push_back(moments);
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
    node.Left = this->BuildNode(order, first, half);
    node.Right = this->BuildNode(order, first + half, count - half);
  }
  else
  {
    node.LeafIndex = order[first];
  }
  nodes[id] = node;
  return id;
}

RGB ShooterHierarchy::Irradiance(const Node& node, const Vec3& x, const Vec3& n) const
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
  const AxisMoments& moments = this->Moments[node.Mixed];
  RGB e;
  for (int i = 0; i < 3; ++i)
  {
    const Vec3 axis(i == 0 ? 1.0 : 0.0, i == 1 ? 1.0 : 0.0, i == 2 ? 1.0 : 0.0);
    e += Expansion(axis, moments.Power[i], moments.Dipole[i], moments.Quadrupole[i], d, n);
  }
  return e;
}

void PointBatch::Reset(std::size_t count)
{
  this->Count = count;
  const std::size_t stride = BatchStride(count);
  // The padding is a point at the origin facing +z, masked out.
  for (std::vector<double>* v : { &this->X, &this->Y, &this->Z, &this->NX, &this->NY, &this->NZ })
  {
    v->assign(stride, 0.0);
  }
  std::fill(this->NZ.begin() + static_cast<std::ptrdiff_t>(count), this->NZ.end(), 1.0);
  for (std::vector<double>* v : { &this->R, &this->G, &this->B })
  {
    v->assign(stride, 0.0);
  }
  this->All.assign(stride, 0);
  std::fill(this->All.begin(), this->All.begin() + static_cast<std::ptrdiff_t>(count), 1);
}

namespace
{

#if defined(__GNUC__)

/// One block of points' values, and a block of comparison results (the
/// GCC/Clang vector extension: one register where the processor has
/// 4-wide vectors, two of 2 on any x86-64).
typedef double Block __attribute__((vector_size(BatchBlock * sizeof(double))));
typedef long long Mask __attribute__((vector_size(BatchBlock * sizeof(long long))));
/// A block of a batch's arrays, read and written in place.
typedef double BlockInPlace
  __attribute__((vector_size(BatchBlock * sizeof(double)), aligned(sizeof(double)), may_alias));

inline const BlockInPlace& BlockAt(const double* p)
{
  return *reinterpret_cast<const BlockInPlace*>(p);
}

inline BlockInPlace& BlockAt(double* p)
{
  return *reinterpret_cast<BlockInPlace*>(p);
}

// The batched expansion is most of a sweep's work; with GCC on x86-64 it
// is built twice and the processor picks: with 4-wide vectors and fused
// multiply-adds (x86-64-v3), or for any x86-64.
#if defined(__x86_64__) && !defined(__clang__)
#define PENUMBRA_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PENUMBRA_VECTOR_CLONES
#endif

/**
 * Expansion() at every point of the batch whose `use` flag is 1,
 * branch-free so that it vectorises: a point behind the centroid's plane
 * (when `shooterSide`) or with the centroid behind it gets nothing.
 */
PENUMBRA_VECTOR_CLONES
void AddExpansions(const Vec3& m, const RGB& power, const Vec3 dipole[3],
  const Symmetric quadrupole[3], const Vec3& centroid, bool shooterSide, std::size_t count,
  const double* __restrict px, const double* __restrict py, const double* __restrict pz,
  const double* __restrict nx, const double* __restrict ny, const double* __restrict nz,
  const unsigned char* __restrict use, double* __restrict sr, double* __restrict sg,
  double* __restrict sb)
{
  using Lanes = Block;
  const double mx = m.X, my = m.Y, mz = m.Z;
  const Lanes zero = {};
  for (std::size_t i = 0; i < count; i += BatchBlock)
  {
    const Lanes nxi = BlockAt(nx + i), nyi = BlockAt(ny + i), nzi = BlockAt(nz + i);
    const Lanes dx = centroid.X - BlockAt(px + i);
    const Lanes dy = centroid.Y - BlockAt(py + i);
    const Lanes dz = centroid.Z - BlockAt(pz + i);
    const Lanes a = nxi * dx + nyi * dy + nzi * dz;
    const Lanes b = -(mx * dx + my * dy + mz * dz);
    Mask lit = a > 0.0;
    if (shooterSide)
    {
      lit = lit & (b > 0.0);
    }
    for (std::size_t k = 0; k < BatchBlock; ++k)
    {
      lit[k] = use[i + k] ? lit[k] : 0;
    }
    const Lanes inverse = 1.0 / (dx * dx + dy * dy + dz * dz);
    const Lanes inverse2 = inverse * inverse;
    const Lanes inverse3 = inverse2 * inverse;
    const Lanes ab = a * b;
    const Lanes ux = nxi * b - mx * a;
    const Lanes uy = nyi * b - my * a;
    const Lanes uz = nzi * b - mz * a;
    const Lanes k = ab * inverse2;
    const Lanes g = 4.0 * ab * inverse3;
    const Lanes gx = ux * inverse2 - dx * g;
    const Lanes gy = uy * inverse2 - dy * g;
    const Lanes gz = uz * inverse2 - dz * g;
    // The Hessian as Expansion() builds it (Symmetric::AddOuter).
    const Lanes wn = -2.0 * inverse2;
    const Lanes wu = -8.0 * inverse3;
    const Lanes wd = 24.0 * ab * inverse3 * inverse;
    const Lanes diagonal = -4.0 * ab * inverse3;
    const Lanes hxx = wn * nxi * mx + wu * ux * dx + wd * dx * dx + diagonal;
    const Lanes hyy = wn * nyi * my + wu * uy * dy + wd * dy * dy + diagonal;
    const Lanes hzz = wn * nzi * mz + wu * uz * dz + wd * dz * dz + diagonal;
    const Lanes hxy = 0.5 * wn * (nxi * my + nyi * mx) + 0.5 * wu * (ux * dy + uy * dx) +
      0.5 * wd * (dx * dy + dy * dx);
    const Lanes hxz = 0.5 * wn * (nxi * mz + nzi * mx) + 0.5 * wu * (ux * dz + uz * dx) +
      0.5 * wd * (dx * dz + dz * dx);
    const Lanes hyz = 0.5 * wn * (nyi * mz + nzi * my) + 0.5 * wu * (uy * dz + uz * dy) +
      0.5 * wd * (dy * dz + dz * dy);
    double* const sums[3] = { sr, sg, sb };
    for (int c = 0; c < 3; ++c)
    {
      const Vec3& d = dipole[c];
      const Symmetric& q = quadrupole[c];
      const Lanes e = power[c] * k + (gx * d.X + gy * d.Y + gz * d.Z) +
        0.5 * (q.XX * hxx + q.YY * hyy + q.ZZ * hzz + 2.0 * (q.XY * hxy + q.XZ * hxz + q.YZ * hyz));
      BlockAt(sums[c] + i) += lit ? e : zero;
    }
  }
}

#else

/// Expansion() at every point of the batch whose `use` flag is 1 (as
/// Irradiance() decides), one point at a time.
void AddExpansions(const Vec3& m, const RGB& power, const Vec3 dipole[3],
  const Symmetric quadrupole[3], const Vec3& centroid, bool shooterSide, std::size_t count,
  const double* px, const double* py, const double* pz, const double* nx, const double* ny,
  const double* nz, const unsigned char* use, double* sr, double* sg, double* sb)
{
  for (std::size_t i = 0; i < count; ++i)
  {
    const Vec3 d = centroid - Vec3(px[i], py[i], pz[i]);
    const Vec3 n(nx[i], ny[i], nz[i]);
    if (use[i] && Dot(n, d) > 0.0 && (!shooterSide || -Dot(m, d) > 0.0))
    {
      const RGB e = Expansion(m, power, dipole, quadrupole, d, n);
      sr[i] += e.R;
      sg[i] += e.G;
      sb[i] += e.B;
    }
  }
}

#endif

} // namespace

void ShooterHierarchy::AddIrradiance(
  const Node& node, PointBatch& points, const unsigned char* use) const
{
  const std::size_t count = BatchStride(points.Size());
  use = use ? use : points.All.data();
  // One expansion's terms added to the sums r, g, b.
  const auto add = [&](const Vec3& m, const RGB& power, const Vec3 dipole[3],
                     const Symmetric quadrupole[3], bool shooterSide, double* r, double* g,
                     double* b) {
    AddExpansions(m, power, dipole, quadrupole, node.Centroid, shooterSide, count,
      points.X.data(), points.Y.data(), points.Z.data(), points.NX.data(), points.NY.data(),
      points.NZ.data(), use, r, g, b);
  };
  if (node.Mixed < 0)
  {
    add(node.Normal, node.Power, node.Dipole, node.Quadrupole, true, points.R.data(),
      points.G.data(), points.B.data());
    return;
  }
  // Leaves facing different ways: the three axes' expansions, summed
  // before they are added, as Irradiance does.
  const AxisMoments& moments = this->Moments[node.Mixed];
  thread_local std::vector<double> sums[3];
  for (std::vector<double>& v : sums)
  {
    v.assign(count, 0.0);
  }
  for (int i = 0; i < 3; ++i)
  {
    const Vec3 axis(i == 0 ? 1.0 : 0.0, i == 1 ? 1.0 : 0.0, i == 2 ? 1.0 : 0.0);
    add(axis, moments.Power[i], moments.Dipole[i], moments.Quadrupole[i], false, sums[0].data(),
      sums[1].data(), sums[2].data());
  }
  for (std::size_t k = 0; k < count; ++k)
  {
    points.R[k] += sums[0][k];
    points.G[k] += sums[1][k];
    points.B[k] += sums[2][k];
  }
}

void ShooterHierarchy::Cut(const Vec3& x, int receiver, double theta,
  const std::vector<int>& roots, std::vector<int>& stack, std::vector<int>& cut) const
{
  cut.clear();
  stack.assign(roots.rbegin(), roots.rend());
  while (!stack.empty())
  {
    const int id = stack.back();
    stack.pop_back();
    const Node& node = this->Nodes[id];
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
      stack.push_back(node.Right);
      stack.push_back(node.Left);
      continue;
    }
    cut.push_back(id);
  }
}

void ShooterHierarchy::RefreshMoments()
{
  if (this->Nodes.empty())
  {
    return;
  }
  SubtreeMoments root;
  this->RefreshNode(0, root);
}

/**
 * The moments of node `id`'s subtree about Origin from its leaves' current
 * moments (and per axis i, of L m_i for leaves facing m), and on the way
 * every node's moments about its centroid.
 */
void ShooterHierarchy::RefreshNode(int id, SubtreeMoments& out)
{
  const int left = this->Nodes[id].Left, right = this->Nodes[id].Right;
  if (left < 0)
  {
    const Leaf& leaf = this->Leaves[this->Nodes[id].LeafIndex];
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
  Node& node = this->Nodes[id];
  const Vec3 e = node.Centroid - this->Origin;
  node.Power = out.Plain.Power;
  out.Plain.Central(e, node.Dipole, node.Quadrupole);
  if (node.Mixed >= 0)
  {
    AxisMoments& moments = this->Moments[node.Mixed];
    for (int i = 0; i < 3; ++i)
    {
      moments.Power[i] = out.Axis[i].Power;
      out.Axis[i].Central(e, moments.Dipole[i], moments.Quadrupole[i]);
    }
  }
}

} // namespace penumbra
