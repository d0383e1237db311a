// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraExactEvaluator.h"

#include "penumbraFormFactor.h"
#include "penumbraLambertBatch.h"
#include "penumbraMath.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra
{

namespace
{

// Pieces below this fraction of the shooter's area are dropped.
constexpr double PieceAreaFraction = 1e-14;
// Vertices closer than this fraction of the shooter's diameter to a shadow
// line count as on it, so that no sliver is created.
constexpr double LineEpsilonFraction = 1e-13;

// Everything one query needs about the shooter and the point, in the
// shooter's frame: x = centroid + xu*U + xv*V + hx*N, receiver normal nl.
struct QueryFrame
{
  const PreparedPolygon* Shooter;
  Vec3 X;
  double Xu, Xv, Hx;
  Vec3 Nl;
  double MinArea;
  double LineEps;
};

using PieceBuffer = VisibilityWorkspace::PieceBuffer;

// Grow a scratch vector (never shrinks, so the query stays allocation-free
// once the buffers are large enough). Invalidates pointers into it.
template<typename T>
inline T* Reserve(std::vector<T>& v, std::size_t n)
{
  if (v.size() < n)
  {
    v.resize(std::max(n, 2 * v.size()));
  }
  return v.data();
}

// Room for `morePieces` more index entries and `moreDoubles` more coordinates.
inline void ReservePieces(PieceBuffer& b, int indexEnd, int morePieces, int moreDoubles)
{
  Reserve(b.Points, static_cast<std::size_t>(b.Used + moreDoubles));
  Reserve(b.Starts, static_cast<std::size_t>(indexEnd + morePieces));
  Reserve(b.Sizes, static_cast<std::size_t>(indexEnd + morePieces));
  Reserve(b.Boxes, static_cast<std::size_t>(4 * (indexEnd + morePieces)));
}

// Register the polygon just written at Points[Used ...] as index entry `index`.
inline void CommitPiece(PieceBuffer& b, int index, int count, const double box[4])
{
  std::copy(box, box + 4, b.Boxes.data() + 4 * index);
  b.Starts[index] = b.Used;
  b.Sizes[index] = count;
  b.Used += 2 * count;
}

// Bounds and twice the signed area of a 2D polygon.
inline double BoundsAndArea(const double* p, int count, double box[4])
{
  box[0] = box[1] = p[0];
  box[2] = box[3] = p[1];
  double twice = 0.0;
  double px = p[2 * (count - 1)], py = p[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    const double x = p[2 * k], y = p[2 * k + 1];
    box[0] = std::min(box[0], x);
    box[1] = std::max(box[1], x);
    box[2] = std::min(box[2], y);
    box[3] = std::max(box[3], y);
    twice += px * y - py * x;
    px = x;
    py = y;
  }
  return twice;
}

// Twice the signed area of a 2D polygon.
inline double TwiceArea(const double* p, int count)
{
  double twice = 0.0;
  double px = p[2 * (count - 1)], py = p[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    twice += px * p[2 * k + 1] - py * p[2 * k];
    px = p[2 * k];
    py = p[2 * k + 1];
  }
  return twice;
}

inline bool BoxesDisjoint(const double* a, const double* b)
{
  return a[1] < b[0] || a[0] > b[1] || a[3] < b[2] || a[2] > b[3];
}

// Drop removed pieces (Sizes == 0) from [0, indexEnd) and recompute Bounds.
void CompactPieces(PieceBuffer& b, int indexEnd)
{
  int count = 0;
  double* bounds = b.Bounds;
  bounds[0] = bounds[2] = std::numeric_limits<double>::max();
  bounds[1] = bounds[3] = -std::numeric_limits<double>::max();
  for (int k = 0; k < indexEnd; ++k)
  {
    if (b.Sizes[k] == 0)
    {
      continue;
    }
    const double* box = b.Boxes.data() + 4 * k;
    bounds[0] = std::min(bounds[0], box[0]);
    bounds[1] = std::max(bounds[1], box[1]);
    bounds[2] = std::min(bounds[2], box[2]);
    bounds[3] = std::max(bounds[3], box[3]);
    if (count != k)
    {
      b.Starts[count] = b.Starts[k];
      b.Sizes[count] = b.Sizes[k];
      std::copy(box, box + 4, b.Boxes.data() + 4 * count);
    }
    ++count;
  }
  b.Count = count;
}

// Whether the convex piece and the convex shadow polygon are separated by a
// line: one of the shadow's lines, or one of the piece's edges (separating
// axis theorem for convex polygons, with tolerance eps).
bool Separated(const double* pts, int count, const double* box, const double* lines,
  int numberOfLines, const double* shadow, int shadowCount, double eps)
{
  // Cheap first: a shadow line with the piece's whole bounding box outside.
  for (int l = 0; l < numberOfLines; ++l)
  {
    const double a = lines[3 * l], b = lines[3 * l + 1], c = lines[3 * l + 2] - eps;
    if (c + std::max(a * box[0], a * box[1]) + std::max(b * box[2], b * box[3]) <= 0.0)
    {
      return true;
    }
  }
  for (int l = 0; l < numberOfLines; ++l)
  {
    const double a = lines[3 * l], b = lines[3 * l + 1], c = lines[3 * l + 2] - eps;
    int k = 0;
    while (k < count && a * pts[2 * k] + b * pts[2 * k + 1] + c <= 0.0)
    {
      ++k;
    }
    if (k == count)
    {
      return true; // no vertex of the piece inside this line
    }
  }
  double px = pts[2 * (count - 1)], py = pts[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    const double cx = pts[2 * k], cy = pts[2 * k + 1];
    // Inward normal of the counter-clockwise edge p -> c is (py - cy, cx - px);
    // the L1 norm stands in for the length in the tolerance.
    const double nx = py - cy, ny = cx - px;
    const double limit = eps * (std::abs(nx) + std::abs(ny)) + (nx * px + ny * py);
    int j = 0;
    while (j < shadowCount && nx * shadow[2 * j] + ny * shadow[2 * j + 1] <= limit)
    {
      ++j;
    }
    if (j == shadowCount)
    {
      return true; // no vertex of the shadow inside this edge
    }
    px = cx;
    py = cy;
  }
  return false;
}

// Subtract the shadow {p : a*u + b*v + c >= 0 for every line} from the
// visible pieces; `shadow` is a convex polygon containing the part of that
// region in the visible hull, and shadowBox its bounds. Pieces the shadow
// does not meet stay where they are; a piece it meets is replaced by its
// parts outside the shadow (one per line that cuts it). Returns the number
// of pieces left.
int SubtractShadow(VisibilityWorkspace& ws, const double* lines, int numberOfLines,
  const double* shadow, int shadowCount, const double shadowBox[4], double minArea, double eps)
{
  PieceBuffer& b = ws.Pieces;
  const double twiceMinArea = 2.0 * minArea;
  const int original = b.Count;
  int indexEnd = original; // new pieces are appended after the original ones
  bool changed = false;
  for (int piece = 0; piece < original; ++piece)
  {
    const int count = b.Sizes[piece];
    const double* box = b.Boxes.data() + 4 * piece;
    if (BoxesDisjoint(box, shadowBox) ||
      Separated(b.Points.data() + b.Starts[piece], count, box, lines, numberOfLines, shadow,
        shadowCount, eps))
    {
      continue; // untouched: stays in place
    }
    // Each split of a convex polygon adds at most one vertex and emits at
    // most one piece; the bound is doubled in case rounding makes a piece
    // slightly non-convex, plus one slot for the branch-free writes.
    const int maxPoints = 2 * (count + numberOfLines) + 2;
    ReservePieces(b, indexEnd, numberOfLines, 2 * numberOfLines * maxPoints);
    double* rem = Reserve(ws.Remainder, static_cast<std::size_t>(2 * maxPoints));
    double* split = Reserve(ws.Split, static_cast<std::size_t>(2 * maxPoints));
    double* dist = Reserve(ws.Distances, static_cast<std::size_t>(maxPoints));
    const double* pts = b.Points.data() + b.Starts[piece];
    std::copy(pts, pts + 2 * count, rem);
    int m = count;
    const int markEnd = indexEnd;
    const int markUsed = b.Used;
    bool untouched = false;
    for (int l = 0; l < numberOfLines; ++l)
    {
      const double la = lines[3 * l], lb = lines[3 * l + 1], lc = lines[3 * l + 2];
      bool anyIn = false, anyOut = false;
      for (int k = 0; k < m; ++k)
      {
        const double d = la * rem[2 * k] + lb * rem[2 * k + 1] + lc;
        dist[k] = d;
        anyIn |= d > eps;
        anyOut |= d < -eps;
      }
      if (!anyIn)
      {
        untouched = true; // the remainder misses the shadow after all
        break;
      }
      if (!anyOut)
      {
        continue; // the remainder lies on the shadow's side of this line
      }
      // Split: the outer part is visible, the inner part goes on. Vertices
      // within eps of the line go to both parts, so no sliver is created.
      double* o = b.Points.data() + b.Used;
      int no = 0, ni = 0;
      double px = rem[2 * (m - 1)], py = rem[2 * (m - 1) + 1];
      double ps = dist[m - 1];
      int pc = (ps > eps) - (ps < -eps);
      for (int k = 0; k < m; ++k)
      {
        const double cx = rem[2 * k], cy = rem[2 * k + 1];
        const double cs = dist[k];
        const int cc = (cs > eps) - (cs < -eps);
        // Branch-free: every candidate vertex is written, and kept by
        // advancing the count or not (the buffers have room for it).
        const double denom = ps - cs;
        const double t = denom != 0.0 ? ps / denom : 0.0;
        const double ix = px + (cx - px) * t, iy = py + (cy - py) * t;
        const int crossing = pc * cc < 0;
        o[2 * no] = ix;
        o[2 * no + 1] = iy;
        no += crossing;
        split[2 * ni] = ix;
        split[2 * ni + 1] = iy;
        ni += crossing;
        o[2 * no] = cx;
        o[2 * no + 1] = cy;
        no += cc <= 0;
        split[2 * ni] = cx;
        split[2 * ni + 1] = cy;
        ni += cc >= 0;
        px = cx;
        py = cy;
        ps = cs;
        pc = cc;
      }
      double outBox[4];
      if (no >= 3 && BoundsAndArea(o, no, outBox) > twiceMinArea)
      {
        CommitPiece(b, indexEnd++, no, outBox);
      }
      std::swap(rem, split);
      m = ni;
      if (m < 3)
      {
        untouched = true; // the shadow only grazes the piece
        break;
      }
    }
    if (untouched || TwiceArea(rem, m) <= twiceMinArea)
    {
      // Nothing (or a negligible sliver) is hidden: keep the piece as it was.
      indexEnd = markEnd;
      b.Used = markUsed;
      continue;
    }
    b.Sizes[piece] = 0; // replaced by its visible parts
    changed = true;
  }
  if (changed)
  {
    CompactPieces(b, indexEnd);
  }
  return b.Count;
}

// Shadow of one convex occluder piece lying entirely between x's level and
// the shooter's plane, not too close to x's level: its central projection
// from x, a convex polygon. Writes the polygon to ws.Shadow and its edge
// lines (inward unit normals) to ws.Lines, numberOfLines of them. Returns
// the vertex count, 0 when the projection is degenerate (occluder seen
// edge-on) or negligible.
int ProjectedShadow(
  const Vec3* local, int count, const QueryFrame& q, VisibilityWorkspace& ws, int& numberOfLines)
{
  double* shadow = Reserve(ws.Shadow, static_cast<std::size_t>(2 * count));
  double* lines = Reserve(ws.Lines, static_cast<std::size_t>(3 * count));
  double twice = 0.0;
  for (int k = 0; k < count; ++k)
  {
    const double t = q.Hx / -local[k].Z;
    shadow[2 * k] = q.Xu + local[k].X * t;
    shadow[2 * k + 1] = q.Xv + local[k].Y * t;
  }
  double px = shadow[2 * (count - 1)], py = shadow[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    twice += px * shadow[2 * k + 1] - py * shadow[2 * k];
    px = shadow[2 * k];
    py = shadow[2 * k + 1];
  }
  if (!(std::abs(twice) > 2.0 * q.MinArea))
  {
    return 0;
  }
  if (twice < 0.0)
  {
    // Seen from the back: make it counter-clockwise.
    for (int i = 0, j = count - 1; i < j; ++i, --j)
    {
      std::swap(shadow[2 * i], shadow[2 * j]);
      std::swap(shadow[2 * i + 1], shadow[2 * j + 1]);
    }
  }
  numberOfLines = 0;
  px = shadow[2 * (count - 1)];
  py = shadow[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    const double cx = shadow[2 * k], cy = shadow[2 * k + 1];
    const double nx = py - cy, ny = cx - px;
    const double len = std::sqrt(nx * nx + ny * ny);
    if (len > 0.0)
    {
      const double inv = 1.0 / len;
      const double a = nx * inv, b = ny * inv;
      lines[3 * numberOfLines] = a;
      lines[3 * numberOfLines + 1] = b;
      lines[3 * numberOfLines + 2] = -(a * px + b * py);
      ++numberOfLines;
    }
    px = cx;
    py = cy;
  }
  return numberOfLines >= 3 ? count : 0;
}

// Shadow of one convex occluder piece in general position (straddling the
// shooter's plane or x's level, or close to x): the half-planes "the ray
// from x crosses the plane through x and an edge on the inner side" and "y
// is strictly beyond the occluder's plane", each clipped against the visible
// hull; lines that cut nothing off the hull are dropped. Writes the clipped
// shadow to ws.Shadow and the lines to ws.Lines. Returns the shadow's vertex
// count, or 0 if the shadow misses the hull, or -1 if it covers all of it.
int GeneralShadow(const Vec3* local, int count, const PreparedPolygon& o, double side,
  const OccluderSet& set, const QueryFrame& q, VisibilityWorkspace& ws, int& numberOfLines)
{
  const PreparedPolygon& s = *q.Shooter;
  const int hullCount = static_cast<int>(ws.Hull.size()) / 2;
  double* lines = Reserve(ws.Lines, static_cast<std::size_t>(3 * (count + 1)));
  std::vector<double>* shadowBuffer = &ws.Shadow;
  std::vector<double>* swapBuffer = &ws.ShadowSwap;
  double* shadow = Reserve(*shadowBuffer, static_cast<std::size_t>(2 * hullCount));
  std::copy(ws.Hull.begin(), ws.Hull.end(), shadow);
  int shadowCount = hullCount;
  numberOfLines = 0;
  bool empty = false;
  auto addLine = [&](double a, double b, double c) {
    bool anyIn = false, anyOut = false;
    for (int k = 0; k < shadowCount; ++k)
    {
      const double d = a * shadow[2 * k] + b * shadow[2 * k + 1] + c;
      anyIn |= d > q.LineEps;
      anyOut |= d < -q.LineEps;
    }
    if (!anyIn)
    {
      empty = true;
      return;
    }
    if (!anyOut)
    {
      return;
    }
    // Clipping output is bounded by twice the input (room for rounding).
    double* swap = Reserve(*swapBuffer, static_cast<std::size_t>(4 * shadowCount));
    shadowCount = ClipPolygon2D(shadow, shadowCount, a, b, c, swap);
    std::swap(shadowBuffer, swapBuffer);
    shadow = swap;
    if (shadowCount < 3)
    {
      empty = true;
      return;
    }
    lines[3 * numberOfLines] = a;
    lines[3 * numberOfLines + 1] = b;
    lines[3 * numberOfLines + 2] = c;
    ++numberOfLines;
  };

  // "Strictly beyond the occluder's plane, seen from x", as a half-plane of
  // the shooter's plane: -side * Dot(nO, y - cO) >= rounding level. (Occluders
  // coplanar with the shooter were culled with the larger tolerance.)
  double fa = -side * Dot(o.Normal, s.AxisU);
  double fb = -side * Dot(o.Normal, s.AxisV);
  double fc = -side * Dot(o.Normal, s.Centroid - o.Centroid) - set.GetPlaneTolerance();
  const double flen = std::sqrt(fa * fa + fb * fb);
  if (flen <= 1e-14)
  {
    // Occluder parallel to the shooter: all of it or none of it is beyond.
    if (fc <= 0.0)
    {
      return 0;
    }
  }
  else
  {
    addLine(fa / flen, fb / flen, fc / flen);
  }
  for (int k = 0; k < count && !empty; ++k)
  {
    const Vec3& r0 = local[k];
    const Vec3& r1 = local[k + 1 == count ? 0 : k + 1];
    // Inward normal of the cone face through x and this edge.
    const Vec3 nk = side > 0.0 ? Cross(r1, r0) : Cross(r0, r1);
    // Restricted to the shooter's plane (local z = -hx relative to x).
    const double a = nk.X, b = nk.Y;
    const double c = -(nk.X * q.Xu + nk.Y * q.Xv + nk.Z * q.Hx);
    const double len = std::sqrt(a * a + b * b);
    if (!(len > 1e-14 * Length(nk)))
    {
      // Face parallel to the shooter's plane: everything or nothing.
      empty = c < 0.0;
      continue;
    }
    addLine(a / len, b / len, c / len);
  }
  if (empty)
  {
    return 0;
  }
  if (numberOfLines == 0)
  {
    return -1;
  }
  // Leave the clipped shadow in ws.Shadow.
  if (shadowBuffer != &ws.Shadow)
  {
    double* target = Reserve(ws.Shadow, static_cast<std::size_t>(2 * shadowCount));
    std::copy(shadow, shadow + 2 * shadowCount, target);
  }
  return shadowCount;
}

// Subtract the shadows of every convex piece of occluder `id`. Returns the
// number of visible pieces left.
int CastShadows(const OccluderSet& set, int id, const QueryFrame& q, VisibilityWorkspace& ws)
{
  const PreparedPolygon& o = set.GetPolygon(id);
  const PreparedPolygon& s = *q.Shooter;
  int left = ws.Pieces.Count;
  // Signed distance of x from the occluder's plane: which side x sees.
  const double sigma = Dot(o.Normal, q.X - o.Centroid);
  if (std::abs(sigma) <= set.GetPlaneTolerance())
  {
    return left; // x lies in the occluder's plane: rays only graze it
  }
  const double side = sigma > 0.0 ? 1.0 : -1.0;
  // Projection is used when every vertex is at least this far below x's
  // level (towards the shooter): it magnifies by at most 1/ProjectionDepth.
  constexpr double ProjectionDepth = 0.05;
  const double minDepth = ProjectionDepth * q.Hx;

  const std::vector<ConvexPiece>& pieces = set.GetPieces();
  const Vec3* vertices = set.GetPieceVertices().data();
  for (int pi = o.FirstPiece; pi < o.FirstPiece + o.NumberOfPieces && left > 0; ++pi)
  {
    const ConvexPiece& piece = pieces[pi];
    const Vec3* v = vertices + piece.First;
    if (o.NumberOfPieces > 1)
    {
      // Pieces of a concave occluder: cull each against the pyramid.
      bool outside = false;
      for (const Plane& plane : ws.Frustum.Planes)
      {
        outside = true;
        for (int k = 0; k < piece.Count && outside; ++k)
        {
          outside = Dot(plane.Normal, v[k]) < plane.Offset;
        }
        if (outside)
        {
          break;
        }
      }
      if (outside)
      {
        continue;
      }
    }
    Vec3* local = Reserve(ws.Local, static_cast<std::size_t>(piece.Count));
    bool projectable = true;
    for (int k = 0; k < piece.Count; ++k)
    {
      const Vec3 d = v[k] - q.X;
      local[k] = Vec3(Dot(d, s.AxisU), Dot(d, s.AxisV), Dot(d, s.Normal));
      // Between x's level and the shooter's plane: -hx <= z <= -minDepth.
      projectable &= local[k].Z <= -minDepth && local[k].Z >= -q.Hx;
    }
    int numberOfLines = 0;
    int shadowCount = 0;
    if (projectable)
    {
      shadowCount = ProjectedShadow(local, piece.Count, q, ws, numberOfLines);
    }
    else
    {
      shadowCount = GeneralShadow(local, piece.Count, o, side, set, q, ws, numberOfLines);
      if (shadowCount < 0)
      {
        ws.Pieces.Count = 0; // the shadow covers the whole visible hull
        return 0;
      }
    }
    if (shadowCount < 3)
    {
      continue;
    }
    double shadowBox[4];
    BoundsAndArea(ws.Shadow.data(), shadowCount, shadowBox);
    shadowBox[0] -= q.LineEps;
    shadowBox[1] += q.LineEps;
    shadowBox[2] -= q.LineEps;
    shadowBox[3] += q.LineEps;
    if (BoxesDisjoint(shadowBox, ws.Pieces.Bounds))
    {
      continue; // falls where nothing is visible any more
    }
    ++ws.ShadowCount;
    left = SubtractShadow(ws, ws.Lines.data(), numberOfLines, ws.Shadow.data(), shadowCount,
      shadowBox, q.MinArea, q.LineEps);
  }
  return left;
}

/// Shaft candidate lists longer than this are replaced by the BVH traversal (see Evaluate).
constexpr int LongCandidateList = 64;

/**
 * The tile cache. A query without a candidate list traverses the occluders'
 * BVH with its pyramid; on a large scene that traversal, repeated for every
 * point and every light, costs more than the shadows. Instead the points of
 * a square tile of the receiver's plane (its diameter / TilesPerDiameter on
 * a side) share one traversal with the shaft from the tile to the shooter,
 * and each point filters that list with its own pyramid. That keeps every
 * occluder the traversal finds, and at most a few more that miss the
 * pyramid (the traversal's capsule test on a node's box also drops some
 * that the test on their own box keeps), which cast nothing. A tile list
 * longer than LongTileList is dropped for the traversal; the cache is
 * emptied at MaximumTiles entries.
 */
constexpr double TilesPerDiameter = 16.0;
constexpr std::size_t LongTileList = 256;
constexpr std::size_t MaximumTiles = 1u << 16;

/// The candidate list of x's tile, or null where the traversal is used
/// (x off the receiver's plane, n not its normal, a long list).
const std::vector<int>* TileList(const OccluderSet& set, const Vec3& x, const Vec3& n,
  int shooterId, int receiverId, VisibilityWorkspace& ws)
{
  if (receiverId < 0 || receiverId >= set.GetNumberOfPolygons())
  {
    return nullptr;
  }
  const PreparedPolygon& r = set.GetPolygon(receiverId);
  const double tol = set.GetTolerance();
  if (!r.Valid || !(std::abs(Dot(r.Normal, x) - r.Offset) <= tol) ||
    !(Dot(n, r.Normal) >= 1.0 - 1e-12))
  {
    return nullptr;
  }
  const double size = r.Diameter / TilesPerDiameter;
  const Vec3 d = x - r.Centroid;
  const double i = std::floor(Dot(d, r.AxisU) / size);
  const double j = std::floor(Dot(d, r.AxisV) / size);
  if (!(std::abs(i) < 1e9 && std::abs(j) < 1e9))
  {
    return nullptr;
  }
  const VisibilityWorkspace::TileKey key{ set.GetIdentity(), receiverId, shooterId,
    static_cast<long long>(i), static_cast<long long>(j) };
  auto found = ws.Tiles.find(key);
  if (found == ws.Tiles.end())
  {
    if (ws.Tiles.size() >= MaximumTiles)
    {
      ws.Tiles.clear();
    }
    const Vec3 corner = r.Centroid + r.AxisU * (i * size) + r.AxisV * (j * size);
    const Vec3 tile[4] = { corner, corner + r.AxisU * size,
      corner + r.AxisU * size + r.AxisV * size, corner + r.AxisV * size };
    VisibilityWorkspace::TileEntry entry;
    entry.Usable =
      set.TileCandidates(tile, shooterId, receiverId, entry.Candidates, ws.TileShaft) &&
      entry.Candidates.size() <= LongTileList;
    if (!entry.Usable)
    {
      entry.Candidates.clear();
      entry.Candidates.shrink_to_fit();
    }
    found = ws.Tiles.emplace(key, std::move(entry)).first;
  }
  return found->second.Usable ? &found->second.Candidates : nullptr;
}

// Lambert's sum over the first `count` pieces.
double LambertSum(const PieceBuffer& pieces, int count, const QueryFrame& q)
{
  detail::LambertBatch batch(-q.Hx, q.Nl);
  for (int piece = 0; piece < count; ++piece)
  {
    const double* pts = pieces.Points.data() + pieces.Starts[piece];
    const int m = pieces.Sizes[piece];
    double pu = pts[2 * (m - 1)] - q.Xu, pv = pts[2 * (m - 1) + 1] - q.Xv;
    for (int k = 0; k < m; ++k)
    {
      const double cu = pts[2 * k] - q.Xu, cv = pts[2 * k + 1] - q.Xv;
      batch.Add(pu, pv, cu, cv);
      pu = cu;
      pv = cv;
    }
  }
  return batch.Sum();
}

double Evaluate(const OccluderSet& set, const Vec3& x, const Vec3& n, int shooterId, int receiverId,
  const int* candidates, int numberOfCandidates, bool traverse, VisibilityWorkspace& ws,
  VisibleRegion* region)
{
  if (region)
  {
    region->Points.clear();
    region->Offsets.clear();
  }
  if (shooterId < 0 || shooterId >= set.GetNumberOfPolygons())
  {
    return 0.0;
  }
  const PreparedPolygon& s = set.GetPolygon(shooterId);
  if (!s.Valid)
  {
    return 0.0;
  }
  QueryFrame q;
  q.Shooter = &s;
  q.X = x;
  const Vec3 dx = x - s.Centroid;
  q.Hx = Dot(dx, s.Normal);
  if (!(q.Hx > 0.0) || !IsFinite(x) || !IsFinite(n))
  {
    return 0.0; // x is not in front of the shooter, which emits from its front only
  }
  q.Xu = Dot(dx, s.AxisU);
  q.Xv = Dot(dx, s.AxisV);
  q.Nl = Vec3(Dot(n, s.AxisU), Dot(n, s.AxisV), Dot(n, s.Normal));
  q.MinArea = PieceAreaFraction * s.Area;
  q.LineEps = LineEpsilonFraction * s.Diameter;

  // The shooter's convex pieces clipped to x's front half-space.
  const double hc = -(q.Nl.X * q.Xu + q.Nl.Y * q.Xv + q.Nl.Z * q.Hx);
  PieceBuffer& pieces = ws.Pieces;
  pieces.Used = 0;
  pieces.Count = 0;
  const std::vector<ConvexPiece>& shooterPieces = set.GetPieces();
  const double* p2 = set.GetPiecePoints2D().data();
  for (int pi = s.FirstPiece; pi < s.FirstPiece + s.NumberOfPieces; ++pi)
  {
    const ConvexPiece& piece = shooterPieces[pi];
    ReservePieces(pieces, pieces.Count, 1, 4 * piece.Count);
    double* dst = pieces.Points.data() + pieces.Used;
    const int m = ClipPolygon2D(p2 + 2 * piece.First, piece.Count, q.Nl.X, q.Nl.Y, hc, dst);
    const double box[4] = { 0.0, 0.0, 0.0, 0.0 }; // set below if there are occluders
    if (m >= 3 && TwiceArea(dst, m) > 2.0 * q.MinArea)
    {
      CommitPiece(pieces, pieces.Count++, m, box);
    }
  }
  int left = pieces.Count;
  // A long shaft list (a large receiver, e.g. the floor of a room full of
  // furniture, sees most of the scene in its shaft) costs more to filter
  // point by point than the BVH traversal of the pyramid, which only visits
  // what is near it. Either way the same occluders meet the pyramid, and
  // they are sorted below, so the result does not depend on the choice.
  const bool tiles = traverse; // no list given (a long one is traversed point by point)
  traverse = traverse || numberOfCandidates > LongCandidateList;

  if (left > 0 && (traverse || numberOfCandidates > 0))
  {
    if (!set.BuildFrustum(x, n, shooterId, ws.Frustum, &ws.Hull))
    {
      pieces.Count = 0;
      left = 0;
    }
    else
    {
      for (int k = 0; k < pieces.Count; ++k)
      {
        BoundsAndArea(
          pieces.Points.data() + pieces.Starts[k], pieces.Sizes[k], pieces.Boxes.data() + 4 * k);
      }
      CompactPieces(pieces, pieces.Count); // computes the union of the boxes
      const std::vector<int>* tileList =
        tiles ? TileList(set, x, n, shooterId, receiverId, ws) : nullptr;
      if (tileList)
      {
        ws.Candidates.clear();
        set.FilterCandidates(ws.Frustum, tileList->data(), static_cast<int>(tileList->size()),
          shooterId, receiverId, ws.Candidates);
      }
      else if (traverse)
      {
        set.VolumeCandidates(ws.Frustum, shooterId, receiverId, ws.Candidates);
      }
      else
      {
        ws.Candidates.clear();
        set.FilterCandidates(
          ws.Frustum, candidates, numberOfCandidates, shooterId, receiverId, ws.Candidates);
      }
      // Largest solid angle first (area / distance^2): big shadows shrink
      // the visible region early, so later shadows meet fewer pieces.
      const std::size_t numberOfOccluders = ws.Candidates.size();
      if (numberOfOccluders > 1)
      {
        Reserve(ws.Order, numberOfOccluders);
        for (std::size_t i = 0; i < numberOfOccluders; ++i)
        {
          const PreparedPolygon& o = set.GetPolygon(ws.Candidates[i]);
          const Vec3 d = o.Centroid - x;
          ws.Order[i] = { -o.Area / Dot(d, d), ws.Candidates[i] };
        }
        const auto last = ws.Order.begin() + static_cast<std::ptrdiff_t>(numberOfOccluders);
        std::sort(ws.Order.begin(), last);
        for (std::size_t i = 0; i < numberOfOccluders; ++i)
        {
          ws.Candidates[i] = ws.Order[i].second;
        }
      }
      for (std::size_t i = 0; i < numberOfOccluders && left > 0; ++i)
      {
        left = CastShadows(set, ws.Candidates[i], q, ws);
      }
    }
  }

  double f = LambertSum(pieces, left, q) * (0.5 / Pi);
  // Rounding can leave a hair below 0 (grazing pieces) or above 1.
  f = f > 0.0 ? std::min(f, 1.0) : 0.0;

  if (region)
  {
    for (int piece = 0; piece < left; ++piece)
    {
      region->Offsets.push_back(static_cast<int>(region->Points.size()));
      const double* pts = pieces.Points.data() + pieces.Starts[piece];
      for (int k = 0; k < pieces.Sizes[piece]; ++k)
      {
        region->Points.push_back(s.Centroid + s.AxisU * pts[2 * k] + s.AxisV * pts[2 * k + 1]);
      }
    }
    if (left > 0)
    {
      region->Offsets.push_back(static_cast<int>(region->Points.size()));
    }
  }
  return f;
}

} // namespace

double VisibleRegion::GetArea() const
{
  double area = 0.0;
  for (int piece = 0; piece < this->GetNumberOfPieces(); ++piece)
  {
    Vec3 twice;
    const Vec3& o = this->Points[this->Offsets[piece]];
    for (int k = this->Offsets[piece] + 1; k + 1 < this->Offsets[piece + 1]; ++k)
    {
      twice += Cross(this->Points[k] - o, this->Points[k + 1] - o);
    }
    area += 0.5 * Length(twice);
  }
  return area;
}

double VisibleFormFactor(const OccluderSet& occluders, const Vec3& x, const Vec3& n, int shooterId,
  int receiverId, const int* candidates, int numberOfCandidates, VisibilityWorkspace& workspace,
  VisibleRegion* region)
{
  return Evaluate(occluders, x, n, shooterId, receiverId, candidates, numberOfCandidates, false,
    workspace, region);
}

ExactEvaluator::ExactEvaluator(const Scene& scene)
  : Occluders(std::make_shared<const OccluderSet>(scene))
{
  this->CopyMaterials(scene);
}

ExactEvaluator::ExactEvaluator(const std::shared_ptr<const PreparedScene>& scene)
  : Occluders(scene->GetOccluders())
{
  this->CopyMaterials(scene->GetScene());
}

void ExactEvaluator::CopyMaterials(const Scene& scene)
{
  for (const Surface& s : scene.Surfaces)
  {
    this->Reflectance.push_back(s.Reflectance);
    this->Emission.push_back(s.Emission);
  }
}

double ExactEvaluator::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
  VisibilityWorkspace& workspace, VisibleRegion* region) const
{
  return Evaluate(
    *this->Occluders, x, n, shooterId, receiverId, nullptr, 0, true, workspace, region);
}

double ExactEvaluator::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
  const std::vector<int>& shaftCandidates, VisibilityWorkspace& workspace,
  VisibleRegion* region) const
{
  return Evaluate(*this->Occluders, x, n, shooterId, receiverId, shaftCandidates.data(),
    static_cast<int>(shaftCandidates.size()), false, workspace, region);
}

RGB ExactEvaluator::ContributedRadiance(
  const Vec3& x, const Vec3& n, int receiverId, int shooterId, VisibilityWorkspace& workspace) const
{
  if (receiverId < 0 || shooterId < 0 || shooterId >= this->Occluders->GetNumberOfPolygons() ||
    receiverId >= this->Occluders->GetNumberOfPolygons())
  {
    return RGB();
  }
  const double f = this->FormFactor(x, n, receiverId, shooterId, workspace);
  return this->Reflectance[receiverId] * this->Emission[shooterId] * f;
}

} // namespace penumbra
