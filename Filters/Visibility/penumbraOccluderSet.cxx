// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraOccluderSet.h"

#include "penumbraConvexHull.h"
#include "penumbraMath.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace penumbra
{

int ClipPolygon2D(const double* xy, int count, double a, double b, double c, double* out)
{
  if (count <= 0)
  {
    return 0;
  }
  int m = 0;
  double px = xy[2 * (count - 1)];
  double py = xy[2 * (count - 1) + 1];
  double dp = a * px + b * py + c;
  for (int k = 0; k < count; ++k)
  {
    const double cx = xy[2 * k];
    const double cy = xy[2 * k + 1];
    const double dc = a * cx + b * cy + c;
    if ((dp > 0.0 && dc < 0.0) || (dp < 0.0 && dc > 0.0))
    {
      const double t = dp / (dp - dc);
      out[2 * m] = px + (cx - px) * t;
      out[2 * m + 1] = py + (cy - py) * t;
      ++m;
    }
    if (dc >= 0.0)
    {
      out[2 * m] = cx;
      out[2 * m + 1] = cy;
      ++m;
    }
    px = cx;
    py = cy;
    dp = dc;
  }
  return m >= 3 ? m : 0;
}

namespace
{

bool IsConvex(const std::vector<P2>& p, const std::vector<int>& cycle, double eps)
{
  const std::size_t n = cycle.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (Cross2(p[cycle[(i + n - 1) % n]], p[cycle[i]], p[cycle[(i + 1) % n]]) < -eps)
    {
      return false;
    }
  }
  return true;
}

// Drop vertices where the outline goes straight on: they add shadow lines
// and Lambert terms that contribute nothing.
void RemoveCollinear(const std::vector<P2>& p, std::vector<int>& cycle, double eps)
{
  bool changed = true;
  while (changed && cycle.size() > 3)
  {
    changed = false;
    const std::size_t n = cycle.size();
    for (std::size_t i = 0; i < n; ++i)
    {
      const P2& a = p[cycle[(i + n - 1) % n]];
      const P2& b = p[cycle[i]];
      const P2& c = p[cycle[(i + 1) % n]];
      const bool forward = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) >= 0.0;
      if (std::abs(Cross2(a, b, c)) <= eps && forward)
      {
        cycle.erase(cycle.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        break;
      }
    }
  }
}

bool PointInTriangle(const P2& q, const P2& a, const P2& b, const P2& c, double eps)
{
  return Cross2(a, b, q) >= -eps && Cross2(b, c, q) >= -eps && Cross2(c, a, q) >= -eps;
}

// Ear clipping of a simple counter-clockwise polygon. Degenerate input never
// loops forever: without a proper ear the flattest vertex is cut.
void EarClip(const std::vector<P2>& p, std::vector<std::vector<int>>& triangles, double eps)
{
  std::vector<int> v(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    v[i] = static_cast<int>(i);
  }
  while (v.size() > 3)
  {
    const std::size_t n = v.size();
    std::size_t ear = n;
    for (std::size_t i = 0; i < n && ear == n; ++i)
    {
      const int ia = v[(i + n - 1) % n], ib = v[i], ic = v[(i + 1) % n];
      if (Cross2(p[ia], p[ib], p[ic]) <= eps)
      {
        continue; // reflex or flat: not an ear
      }
      bool empty = true;
      for (std::size_t j = 0; j < n && empty; ++j)
      {
        const int iq = v[j];
        if (iq == ia || iq == ib || iq == ic)
        {
          continue;
        }
        const P2& q = p[iq];
        if ((q[0] == p[ia][0] && q[1] == p[ia][1]) || (q[0] == p[ic][0] && q[1] == p[ic][1]))
        {
          continue;
        }
        // Only reflex vertices can lie inside an ear of a simple polygon.
        const double turn = Cross2(p[v[(j + n - 1) % n]], q, p[v[(j + 1) % n]]);
        if (turn <= eps && PointInTriangle(q, p[ia], p[ib], p[ic], eps))
        {
          empty = false;
        }
      }
      if (empty)
      {
        ear = i;
      }
    }
    if (ear == n)
    {
      // No clean ear (numerically degenerate outline): cut the vertex with
      // the largest turn, which is the least harmful choice.
      double best = -std::numeric_limits<double>::max();
      for (std::size_t i = 0; i < n; ++i)
      {
        const double t = Cross2(p[v[(i + n - 1) % n]], p[v[i]], p[v[(i + 1) % n]]);
        if (t > best)
        {
          best = t;
          ear = i;
        }
      }
    }
    const int ia = v[(ear + n - 1) % n], ib = v[ear], ic = v[(ear + 1) % n];
    if (Cross2(p[ia], p[ib], p[ic]) > 0.0)
    {
      triangles.push_back({ ia, ib, ic });
    }
    v.erase(v.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  if (v.size() == 3 && Cross2(p[v[0]], p[v[1]], p[v[2]]) > 0.0)
  {
    triangles.push_back(v);
  }
}

// Hertel-Mehlhorn style greedy merge: join two pieces across a shared
// diagonal whenever the union stays convex (at most 4x the optimal count).
// An edge -> piece map finds the neighbour across a diagonal in O(1).
void MergeConvex(const std::vector<P2>& p, std::vector<std::vector<int>>& pieces, double eps)
{
  auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
      static_cast<std::uint32_t>(b);
  };
  std::unordered_map<std::uint64_t, int> owner;
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    const std::vector<int>& c = pieces[i];
    for (std::size_t k = 0; k < c.size(); ++k)
    {
      owner[key(c[k], c[(k + 1) % c.size()])] = static_cast<int>(i);
    }
  }
  std::vector<bool> alive(pieces.size(), true);
  bool merged = true;
  while (merged)
  {
    merged = false;
    for (std::size_t i = 0; i < pieces.size(); ++i)
    {
      if (!alive[i])
      {
        continue;
      }
      for (std::size_t ka = 0; ka < pieces[i].size(); ++ka)
      {
        const std::vector<int>& A = pieces[i];
        const int a = A[ka], b = A[(ka + 1) % A.size()];
        const auto it = owner.find(key(b, a));
        if (it == owner.end() || it->second == static_cast<int>(i) || !alive[it->second])
        {
          continue;
        }
        const int j = it->second;
        const std::vector<int>& B = pieces[j];
        std::size_t kb = 0;
        while (kb < B.size() && !(B[kb] == b && B[(kb + 1) % B.size()] == a))
        {
          ++kb;
        }
        if (kb == B.size())
        {
          continue;
        }
        // A walked from b round to a, then B's vertices strictly between a and b.
        std::vector<int> cycle;
        for (std::size_t t = 0; t < A.size(); ++t)
        {
          cycle.push_back(A[(ka + 1 + t) % A.size()]);
        }
        for (std::size_t t = 2; t < B.size(); ++t)
        {
          cycle.push_back(B[(kb + t) % B.size()]);
        }
        if (!IsConvex(p, cycle, eps))
        {
          continue;
        }
        owner.erase(key(a, b));
        owner.erase(key(b, a));
        pieces[i] = cycle;
        alive[j] = false;
        for (std::size_t k = 0; k < cycle.size(); ++k)
        {
          owner[key(cycle[k], cycle[(k + 1) % cycle.size()])] = static_cast<int>(i);
        }
        merged = true;
        ka = static_cast<std::size_t>(-1); // rescan the grown piece
      }
    }
  }
  std::vector<std::vector<int>> kept;
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    if (alive[i])
    {
      kept.push_back(std::move(pieces[i]));
    }
  }
  pieces.swap(kept);
}

// Largest value of Dot(normal, p) over an axis-aligned box.
inline double BoxSupport(const Vec3& normal, const Vec3& lo, const Vec3& hi)
{
  return (normal.X >= 0.0 ? normal.X * hi.X : normal.X * lo.X) +
    (normal.Y >= 0.0 ? normal.Y * hi.Y : normal.Y * lo.Y) +
    (normal.Z >= 0.0 ? normal.Z * hi.Z : normal.Z * lo.Z);
}

inline bool BoxOutside(const CullingVolume& volume, const Vec3& lo, const Vec3& hi)
{
  if (hi.X < volume.BoxMin.X || lo.X > volume.BoxMax.X || hi.Y < volume.BoxMin.Y ||
    lo.Y > volume.BoxMax.Y || hi.Z < volume.BoxMin.Z || lo.Z > volume.BoxMax.Z)
  {
    return true;
  }
  if (volume.CapsuleRadius >= 0.0)
  {
    // The box's bounding sphere against the capsule.
    const Vec3 centre = (lo + hi) * 0.5;
    const Vec3 d = centre - volume.CapsuleStart;
    const double along = Dot(d, volume.CapsuleAxis);
    const double length2 = SquaredLength(volume.CapsuleAxis);
    const double t = along <= 0.0 ? 0.0 : (along >= length2 ? 1.0 : along / length2);
    const double reach = volume.CapsuleRadius + 0.5 * Length(hi - lo);
    if (SquaredLength(d - volume.CapsuleAxis * t) > reach * reach)
    {
      return true;
    }
  }
  for (const Plane& plane : volume.Planes)
  {
    if (BoxSupport(plane.Normal, lo, hi) < plane.Offset)
    {
      return true;
    }
  }
  return false;
}

void ExpandBox(Vec3& lo, Vec3& hi, const Vec3& p)
{
  lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
  hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
}

constexpr double Huge = std::numeric_limits<double>::max();
const Vec3 EmptyLo(Huge, Huge, Huge);
const Vec3 EmptyHi = -EmptyLo;

} // namespace

OccluderSet::OccluderSet(const Scene& scene)
{
  this->Build(scene);
}

void OccluderSet::Build(const Scene& scene)
{
  static std::atomic<std::uint64_t> builds{ 0 };
  this->Identity = ++builds;
  this->Polygons.clear();
  this->Pieces.clear();
  this->PieceVertices.clear();
  this->PiecePoints2D.clear();
  this->HullVertices.clear();
  this->HullPoints2D.clear();
  this->Nodes.clear();
  this->Items.clear();

  // Scale of the scene, over finite vertices only (a polygon with a
  // non-finite vertex is invalid and ignored below).
  double maxAbs = 0.0;
  Vec3 lo = EmptyLo, hi = EmptyHi;
  for (const Surface& s : scene.Surfaces)
  {
    for (const Vec3& v : s.Vertices)
    {
      if (IsFinite(v))
      {
        maxAbs = std::max({ maxAbs, std::abs(v.X), std::abs(v.Y), std::abs(v.Z) });
        ExpandBox(lo, hi, v);
      }
    }
  }
  this->Extent = maxAbs > 0.0 ? std::max({ hi.X - lo.X, hi.Y - lo.Y, hi.Z - lo.Z }) : 0.0;
  this->Tolerance = 1e-12 * this->Extent + 64.0 * DBL_EPSILON * maxAbs;
  // Rounding level: the side of an occluder's plane a point is on only
  // matters when it is farther than this (closer, either side is a valid limit).
  this->PlaneTolerance = 1e-15 * this->Extent + 8.0 * DBL_EPSILON * maxAbs;

  std::vector<P2> p2;
  std::vector<int> hull;
  std::vector<std::vector<int>> pieces;
  for (const Surface& s : scene.Surfaces)
  {
    PreparedPolygon poly;
    const PolygonGeometry g = ComputePolygonGeometry(s.Vertices);
    poly.Normal = g.Normal;
    poly.Offset = g.Offset;
    poly.Area = g.Area;
    poly.Diameter = g.Diameter;
    poly.Centroid = g.Centroid;
    poly.BoundsMin = EmptyLo;
    poly.BoundsMax = EmptyHi;
    for (const Vec3& v : s.Vertices)
    {
      ExpandBox(poly.BoundsMin, poly.BoundsMax, v);
      poly.Radius = std::max(poly.Radius, Length(v - poly.Centroid));
    }
    poly.FirstPiece = static_cast<int>(this->Pieces.size());
    poly.FirstHullPoint = static_cast<int>(this->HullVertices.size());
    const std::size_t n = s.Vertices.size();
    bool finite = true;
    for (const Vec3& v : s.Vertices)
    {
      finite &= IsFinite(v);
    }
    poly.Valid = finite && n >= 3 && g.Area > 0.0 && std::isfinite(g.Area) &&
      g.Area > 1e-14 * g.Diameter * g.Diameter;
    if (!poly.Valid)
    {
      poly.Normal = Vec3();
      this->Polygons.push_back(poly);
      continue;
    }
    // In-plane frame from the longest edge, so that it is well conditioned.
    Vec3 edge;
    for (std::size_t i = 0; i < n; ++i)
    {
      const Vec3 e = s.Vertices[(i + 1) % n] - s.Vertices[i];
      if (SquaredLength(e) > SquaredLength(edge))
      {
        edge = e;
      }
    }
    poly.AxisU = Normalized(edge - poly.Normal * Dot(poly.Normal, edge));
    poly.AxisV = Cross(poly.Normal, poly.AxisU);

    p2.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const Vec3 d = s.Vertices[i] - poly.Centroid;
      p2[i] = { Dot(d, poly.AxisU), Dot(d, poly.AxisV) };
    }
    const double eps = 1e-12 * poly.Diameter * poly.Diameter;

    std::vector<int> all(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      all[i] = static_cast<int>(i);
    }
    pieces.clear();
    if (IsConvex(p2, all, eps))
    {
      pieces.push_back(all);
    }
    else
    {
      EarClip(p2, pieces, eps);
      MergeConvex(p2, pieces, eps);
    }
    for (std::vector<int>& piece : pieces)
    {
      RemoveCollinear(p2, piece, eps);
      ConvexPiece cp;
      cp.First = static_cast<int>(this->PieceVertices.size());
      cp.Count = static_cast<int>(piece.size());
      for (int i : piece)
      {
        // World coordinates rebuilt from the frame so that the 2D and 3D
        // copies describe exactly the same planar polygon.
        this->PieceVertices.push_back(
          poly.Centroid + poly.AxisU * p2[i][0] + poly.AxisV * p2[i][1]);
        this->PiecePoints2D.push_back(p2[i][0]);
        this->PiecePoints2D.push_back(p2[i][1]);
      }
      this->Pieces.push_back(cp);
    }
    poly.NumberOfPieces = static_cast<int>(this->Pieces.size()) - poly.FirstPiece;

    ConvexHull2(p2, hull);
    for (int i : hull)
    {
      this->HullVertices.push_back(poly.Centroid + poly.AxisU * p2[i][0] + poly.AxisV * p2[i][1]);
      this->HullPoints2D.push_back(p2[i][0]);
      this->HullPoints2D.push_back(p2[i][1]);
    }
    poly.NumberOfHullPoints = static_cast<int>(this->HullVertices.size()) - poly.FirstHullPoint;
    this->Polygons.push_back(poly);
  }

  std::vector<Vec3> centres;
  for (int i = 0; i < this->GetNumberOfPolygons(); ++i)
  {
    if (this->Polygons[i].Valid)
    {
      this->Items.push_back(i);
      centres.push_back((this->Polygons[i].BoundsMin + this->Polygons[i].BoundsMax) * 0.5);
    }
  }
  if (!this->Items.empty())
  {
    this->BuildNode(0, static_cast<int>(this->Items.size()), centres);
  }
}

int OccluderSet::BuildNode(int first, int count, std::vector<Vec3>& centres)
{
  const int index = static_cast<int>(this->Nodes.size());
  this->Nodes.emplace_back();
  Vec3 lo = EmptyLo, hi = EmptyHi, clo = EmptyLo, chi = EmptyHi;
  for (int i = first; i < first + count; ++i)
  {
    const PreparedPolygon& p = this->Polygons[this->Items[i]];
    ExpandBox(lo, hi, p.BoundsMin);
    ExpandBox(lo, hi, p.BoundsMax);
    ExpandBox(clo, chi, centres[i]);
  }
  this->Nodes[index].Min = lo;
  this->Nodes[index].Max = hi;
  constexpr int LeafSize = 4;
  if (count <= LeafSize)
  {
    this->Nodes[index].First = first;
    this->Nodes[index].Count = count;
    return index;
  }
  // Median split along the widest axis of the centres: balanced, so the
  // traversal stack stays shallow.
  const Vec3 ext = chi - clo;
  const int axis = (ext.X >= ext.Y && ext.X >= ext.Z) ? 0 : (ext.Y >= ext.Z ? 1 : 2);
  const int half = count / 2;
  std::vector<int> order(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
  {
    order[i] = first + i;
  }
  std::nth_element(order.begin(), order.begin() + half, order.end(),
    [&centres, axis](int a, int b) { return centres[a][axis] < centres[b][axis]; });
  std::vector<int> items(static_cast<std::size_t>(count));
  std::vector<Vec3> cs(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
  {
    items[i] = this->Items[order[i]];
    cs[i] = centres[order[i]];
  }
  std::copy(items.begin(), items.end(), this->Items.begin() + first);
  std::copy(cs.begin(), cs.end(), centres.begin() + first);
  this->BuildNode(first, half, centres);
  const int right = this->BuildNode(first + half, count - half, centres);
  this->Nodes[index].First = right;
  this->Nodes[index].Count = 0;
  return index;
}

bool OccluderSet::MayIntersect(const CullingVolume& volume, int id) const
{
  const PreparedPolygon& p = this->Polygons[id];
  if (!p.Valid || BoxOutside(volume, p.BoundsMin, p.BoundsMax))
  {
    return false;
  }
  // The hull vertices decide exactly whether the polygon is outside a plane.
  const Vec3* hull = this->HullVertices.data() + p.FirstHullPoint;
  for (const Plane& plane : volume.Planes)
  {
    bool outside = true;
    for (int k = 0; k < p.NumberOfHullPoints && outside; ++k)
    {
      outside = Dot(plane.Normal, hull[k]) < plane.Offset;
    }
    if (outside)
    {
      return false;
    }
  }
  return true;
}

void OccluderSet::VolumeCandidates(
  const CullingVolume& volume, int excludeA, int excludeB, std::vector<int>& candidates) const
{
  candidates.clear();
  if (this->Nodes.empty())
  {
    return;
  }
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = this->Nodes[stack[--top]];
    if (BoxOutside(volume, node.Min, node.Max))
    {
      continue;
    }
    if (node.Count > 0)
    {
      for (int i = node.First; i < node.First + node.Count; ++i)
      {
        const int id = this->Items[i];
        if (id != excludeA && id != excludeB && this->MayIntersect(volume, id))
        {
          candidates.push_back(id);
        }
      }
    }
    else
    {
      const int self = static_cast<int>(&node - this->Nodes.data());
      stack[top++] = node.First; // right child
      stack[top++] = self + 1;   // left child
    }
  }
}

void OccluderSet::FilterCandidates(const CullingVolume& volume, const int* ids, int count,
  int excludeA, int excludeB, std::vector<int>& candidates) const
{
  for (int i = 0; i < count; ++i)
  {
    const int id = ids[i];
    if (id != excludeA && id != excludeB && this->MayIntersect(volume, id))
    {
      candidates.push_back(id);
    }
  }
}

namespace
{

/// One end of a shaft: a convex polygon (its hull) and its plane.
struct ShaftEnd
{
  const Vec3* Hull;
  int Count;
  Vec3 Normal;
  double Offset;
  double Diameter;
};

/**
 * The shaft between two convex polygons: the half-spaces `sideS` and
 * `sideR` (usually their planes' fronts), the box of both and the faces of
 * their convex hull (planes through an edge of one and a vertex of the
 * other that have every point on one side), all loosened by `tol`. The
 * offset of a face is the extreme value over all points, so each plane is a
 * valid supporting plane whatever the rounding.
 */
void HullShaft(
  const ShaftEnd& s, const ShaftEnd& r, const Plane& sideS, const Plane& sideR, double tol,
  CullingVolume& shaft)
{
  const Vec3* sh = s.Hull;
  const Vec3* rh = r.Hull;
  const int ns = s.Count, nr = r.Count;
  shaft.Planes.clear();
  shaft.CapsuleRadius = -1.0;
  shaft.Planes.push_back(sideS);
  shaft.Planes.push_back(sideR);
  shaft.BoxMin = sh[0];
  shaft.BoxMax = sh[0];
  for (int k = 0; k < ns; ++k)
  {
    ExpandBox(shaft.BoxMin, shaft.BoxMax, sh[k]);
  }
  for (int k = 0; k < nr; ++k)
  {
    ExpandBox(shaft.BoxMin, shaft.BoxMax, rh[k]);
  }
  shaft.BoxMin -= Vec3(tol, tol, tol);
  shaft.BoxMax += Vec3(tol, tol, tol);
  const double faceEps = 1e-9 * (s.Diameter + r.Diameter);
  auto addFaces = [&](const Vec3* a, int na, const Vec3* b, int nb) {
    for (int i = 0; i < na; ++i)
    {
      const Vec3& p0 = a[i];
      const Vec3& p1 = a[(i + 1) % na];
      for (int j = 0; j < nb; ++j)
      {
        const Vec3 normal = Normalized(Cross(p1 - p0, b[j] - p0));
        if (SquaredLength(normal) == 0.0)
        {
          continue;
        }
        double lo = std::numeric_limits<double>::max(), hi = -lo;
        for (int k = 0; k < ns; ++k)
        {
          const double d = Dot(normal, sh[k]);
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
        for (int k = 0; k < nr; ++k)
        {
          const double d = Dot(normal, rh[k]);
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
        const double d0 = Dot(normal, p0);
        Plane plane;
        if (hi - d0 <= faceEps)
        {
          plane = { -normal, -hi - tol };
        }
        else if (d0 - lo <= faceEps)
        {
          plane = { normal, lo - tol };
        }
        else
        {
          continue;
        }
        bool duplicate = false;
        for (const Plane& q : shaft.Planes)
        {
          if (Dot(q.Normal, plane.Normal) > 1.0 - 1e-12 && std::abs(q.Offset - plane.Offset) <= tol)
          {
            duplicate = true;
            break;
          }
        }
        if (!duplicate)
        {
          shaft.Planes.push_back(plane);
        }
      }
    }
  };
  addFaces(sh, ns, rh, nr);
  addFaces(rh, nr, sh, ns);
}

} // namespace

bool OccluderSet::BuildShaft(int shooterId, int receiverId, CullingVolume& shaft) const
{
  const PreparedPolygon& s = this->Polygons[shooterId];
  const PreparedPolygon& r = this->Polygons[receiverId];
  if (!s.Valid || !r.Valid)
  {
    return false;
  }
  const Vec3* sh = this->HullVertices.data() + s.FirstHullPoint;
  const Vec3* rh = this->HullVertices.data() + r.FirstHullPoint;
  const int ns = s.NumberOfHullPoints, nr = r.NumberOfHullPoints;
  // The pair exchanges light only if part of the receiver is in front of the
  // shooter and part of the shooter in front of the receiver.
  double rFront = -std::numeric_limits<double>::max();
  for (int k = 0; k < nr; ++k)
  {
    rFront = std::max(rFront, Dot(s.Normal, rh[k]) - s.Offset);
  }
  double sFront = -std::numeric_limits<double>::max();
  for (int k = 0; k < ns; ++k)
  {
    sFront = std::max(sFront, Dot(r.Normal, sh[k]) - r.Offset);
  }
  if (rFront <= this->Tolerance || sFront <= this->Tolerance)
  {
    return false;
  }
  const double tol = this->Tolerance;
  HullShaft({ sh, ns, s.Normal, s.Offset, s.Diameter }, { rh, nr, r.Normal, r.Offset, r.Diameter },
    { s.Normal, s.Offset + tol }, { r.Normal, r.Offset + tol }, tol, shaft);
  return true;
}

bool OccluderSet::TileCandidates(const Vec3 tile[4], int shooterId, int receiverId,
  std::vector<int>& candidates, CullingVolume& shaft) const
{
  candidates.clear();
  const PreparedPolygon& s = this->Polygons[shooterId];
  const PreparedPolygon& r = this->Polygons[receiverId];
  if (!s.Valid || !r.Valid)
  {
    return false;
  }
  const Vec3* sh = this->HullVertices.data() + s.FirstHullPoint;
  const double tol = this->Tolerance;
  const double diameter = Length(tile[2] - tile[0]);
  // Looser than every pyramid from a point of the tile (BuildFrustum): the
  // shooter's front loosened by tol; the receiver's too when the whole
  // shooter is in front of it (else a pyramid of a query without tangent
  // plane may reach behind it).
  double behind = 0.0;
  for (int k = 0; k < s.NumberOfHullPoints; ++k)
  {
    behind = std::min(behind, Dot(r.Normal, sh[k]) - r.Offset);
  }
  const Plane receiverSide = behind >= 0.0
    ? Plane{ r.Normal, r.Offset - tol }
    : Plane{ r.Normal, std::numeric_limits<double>::lowest() };
  HullShaft({ sh, s.NumberOfHullPoints, s.Normal, s.Offset, s.Diameter },
    { tile, 4, r.Normal, r.Offset, diameter }, { s.Normal, s.Offset - tol }, receiverSide, tol,
    shaft);
  this->VolumeCandidates(shaft, shooterId, receiverId, candidates);
  std::sort(candidates.begin(), candidates.end());
  return true;
}

bool OccluderSet::ShaftCandidates(
  int shooterId, int receiverId, std::vector<int>& candidates, CullingVolume* shaft) const
{
  candidates.clear();
  CullingVolume local;
  CullingVolume& volume = shaft ? *shaft : local;
  if (!this->BuildShaft(shooterId, receiverId, volume))
  {
    return false;
  }
  this->VolumeCandidates(volume, shooterId, receiverId, candidates);
  std::sort(candidates.begin(), candidates.end());
  return true;
}

bool OccluderSet::BuildFrustum(const Vec3& x, const Vec3& n, int shooterId, CullingVolume& frustum,
  std::vector<double>* clippedHull) const
{
  const PreparedPolygon& s = this->Polygons[shooterId];
  if (!s.Valid)
  {
    return false;
  }
  const Vec3 dx = x - s.Centroid;
  const double hx = Dot(dx, s.Normal);
  if (!(hx > 0.0))
  {
    return false;
  }
  const double xu = Dot(dx, s.AxisU), xv = Dot(dx, s.AxisV);
  const double nu = Dot(n, s.AxisU), nv = Dot(n, s.AxisV), nw = Dot(n, s.Normal);
  // x's front half-space restricted to the shooter's plane, in its frame.
  const double c = -(nu * xu + nv * xv + nw * hx);

  constexpr int StackPoints = 64;
  double stackBuffer[2 * StackPoints];
  std::vector<double> heapBuffer;
  double* clipped = stackBuffer;
  const int nh = s.NumberOfHullPoints;
  if (clippedHull)
  {
    if (clippedHull->size() < static_cast<std::size_t>(4 * nh))
    {
      clippedHull->resize(static_cast<std::size_t>(4 * nh));
    }
    clipped = clippedHull->data();
  }
  else if (2 * nh > StackPoints)
  {
    heapBuffer.resize(static_cast<std::size_t>(4 * nh));
    clipped = heapBuffer.data();
  }
  // A convex polygon clipped by one half-plane has at most one more vertex
  // (the buffers allow twice as many, in case rounding bends the hull).
  const int m =
    ClipPolygon2D(this->HullPoints2D.data() + 2 * s.FirstHullPoint, nh, nu, nv, c, clipped);
  if (clippedHull)
  {
    clippedHull->resize(static_cast<std::size_t>(2 * m));
  }
  if (m < 3)
  {
    return false;
  }
  const double tol = this->Tolerance;
  frustum.Planes.clear();
  frustum.CapsuleRadius = -1.0;
  frustum.BoxMin = x;
  frustum.BoxMax = x;
  for (int k = 0; k < m; ++k)
  {
    const int k1 = (k + 1) % m;
    // Pyramid face through x and the edge k -> k1 (local x-relative coordinates).
    const Vec3 r0(clipped[2 * k] - xu, clipped[2 * k + 1] - xv, -hx);
    const Vec3 r1(clipped[2 * k1] - xu, clipped[2 * k1 + 1] - xv, -hx);
    const Vec3 local = Cross(r1, r0);
    const Vec3 normal = Normalized(s.AxisU * local.X + s.AxisV * local.Y + s.Normal * local.Z);
    if (SquaredLength(normal) > 0.0)
    {
      frustum.Planes.push_back({ normal, Dot(normal, x) - tol });
    }
    ExpandBox(frustum.BoxMin, frustum.BoxMax,
      s.Centroid + s.AxisU * clipped[2 * k] + s.AxisV * clipped[2 * k + 1]);
  }
  // The slab strictly between the shooter's plane and x, and x's front.
  frustum.Planes.push_back({ s.Normal, s.Offset + tol });
  frustum.Planes.push_back({ -s.Normal, -Dot(s.Normal, x) - tol });
  if (SquaredLength(n) > 0.0) // n = 0: a pure visibility query, no tangent plane
  {
    frustum.Planes.push_back({ n, Dot(n, x) + tol });
  }
  frustum.BoxMin -= Vec3(tol, tol, tol);
  frustum.BoxMax += Vec3(tol, tol, tol);
  // The pyramid's points are (1 - t) x + t q with q on the shooter, within
  // its radius of the centroid: within that of the segment x -> centroid.
  frustum.CapsuleStart = x;
  frustum.CapsuleAxis = s.Centroid - x;
  frustum.CapsuleRadius =
    s.Radius + 4.0 * tol + 1e-9 * (Length(frustum.CapsuleAxis) + s.Radius);
  return true;
}

} // namespace penumbra
