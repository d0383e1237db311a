// SPDX-License-Identifier: GPL-3.0-or-later
// Discontinuity events (EV, VE, occluder EV), their exact visibility along the
// wedge, contacts, orders, clipping to the receiver and merging. No CGAL here:
// the triangulation is in penumbraReceiverTriangulation.cxx.
#include "penumbraDiscontinuityMesher.h"

#include "penumbraFormFactor.h"
#include "penumbraOccluderSet.h"
#include "penumbraReceiverTriangulation.h"
#include "penumbraUnionFind.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace penumbra
{

namespace
{

// Tolerances, relative to the scene size unless said otherwise.
constexpr double kVertexMatch = 1e-9; // vertices closer than this are one feature
constexpr double kLinear = 1e-10;     // side tests of points against planes
constexpr double kSnap = 1e-10;       // 2D snapping of constraint end points
constexpr double kMinPiece = 1e-7;    // shorter boundary pieces are dropped
constexpr double kChordMargin = 1e-6; // receiver chords lengthened by this before culling wedges
constexpr std::size_t kScanLimit = 64; // up to this many shaft candidates, scan them instead of the BVH
constexpr double kAngle = 1e-9;       // |sin| below which directions count as in a plane
constexpr double kMaxMinimumAngle = 20.6;

double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

int Sign(double v, double tol)
{
  return v > tol ? 1 : (v < -tol ? -1 : 0);
}

//------------------------------------------------------------------------------
// Intervals of the wedge parameter t in [0, 1].
struct Interval
{
  double Lo;
  double Hi;
};

// Restrict iv to { t : a + b t >= 0 }.
void Restrict(Interval& iv, double a, double b)
{
  if (b == 0.0)
  {
    if (a < 0.0)
    {
      iv.Hi = iv.Lo - 1.0;
    }
    return;
  }
  const double root = -a / b;
  if (b > 0.0)
  {
    iv.Lo = std::max(iv.Lo, root);
  }
  else
  {
    iv.Hi = std::min(iv.Hi, root);
  }
}

// Sort and merge a list of intervals in place.
void Normalize(std::vector<Interval>& list)
{
  std::sort(list.begin(), list.end(), [](const Interval& x, const Interval& y) { return x.Lo < y.Lo; });
  std::size_t n = 0;
  for (const Interval& iv : list)
  {
    if (!(iv.Hi > iv.Lo))
    {
      continue;
    }
    if (n > 0 && iv.Lo <= list[n - 1].Hi)
    {
      list[n - 1].Hi = std::max(list[n - 1].Hi, iv.Hi);
    }
    else
    {
      list[n++] = iv;
    }
  }
  list.resize(n);
}

// The intersection of two normalized lists.
void Intersect(const std::vector<Interval>& a, const std::vector<Interval>& b,
  std::vector<Interval>& out)
{
  out.clear();
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size())
  {
    const double lo = std::max(a[i].Lo, b[j].Lo), hi = std::min(a[i].Hi, b[j].Hi);
    if (hi > lo)
    {
      out.push_back({ lo, hi });
    }
    if (a[i].Hi < b[j].Hi)
    {
      ++i;
    }
    else
    {
      ++j;
    }
  }
}

// base minus the union of `blocked` (normalized).
void Subtract(const std::vector<Interval>& base, const std::vector<Interval>& blocked,
  std::vector<Interval>& out)
{
  out.clear();
  for (Interval iv : base)
  {
    double lo = iv.Lo;
    for (const Interval& b : blocked)
    {
      if (b.Hi <= lo)
      {
        continue;
      }
      if (b.Lo >= iv.Hi)
      {
        break;
      }
      if (b.Lo > lo)
      {
        out.push_back({ lo, b.Lo });
      }
      lo = std::max(lo, b.Hi);
    }
    if (iv.Hi > lo)
    {
      out.push_back({ lo, iv.Hi });
    }
  }
}

//------------------------------------------------------------------------------
// 2D helpers (receiver frame).
using P2 = std::array<double, 2>;

double Cross2(const P2& a, const P2& b, const P2& c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

double DistancePointSegment2(const P2& p, const P2& a, const P2& b)
{
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  double s = len2 > 0.0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
  s = std::max(0.0, std::min(1.0, s));
  const double ex = a[0] + s * dx - p[0], ey = a[1] + s * dy - p[1];
  return std::sqrt(ex * ex + ey * ey);
}

// 1 inside, 0 on the boundary (within tol), -1 outside; concave polygons too.
int PointInPolygon2(const P2& p, const std::vector<P2>& poly, double tol)
{
  const std::size_t n = poly.size();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    if (DistancePointSegment2(p, poly[j], poly[i]) <= tol)
    {
      return 0;
    }
    const P2& a = poly[j];
    const P2& b = poly[i];
    if ((a[1] > p[1]) != (b[1] > p[1]))
    {
      const double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x > p[0])
      {
        inside = !inside;
      }
    }
  }
  return inside ? 1 : -1;
}

// The parameter ranges of segment a-b inside the polygon (boundary included).
void ClipSegmentToPolygon2(const P2& a, const P2& b, const std::vector<P2>& poly, double tol,
  std::vector<Interval>& pieces)
{
  pieces.clear();
  std::vector<double> cuts = { 0.0, 1.0 };
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len = std::sqrt(dx * dx + dy * dy);
  if (!(len > 0.0))
  {
    return;
  }
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const P2& p = poly[i];
    const P2& q = poly[(i + 1) % n];
    const double ex = q[0] - p[0], ey = q[1] - p[1];
    const double den = dx * ey - dy * ex;
    const double elen = std::sqrt(ex * ex + ey * ey);
    if (std::abs(den) > 1e-14 * len * elen)
    {
      const double s = ((p[0] - a[0]) * ey - (p[1] - a[1]) * ex) / den;
      const double u = ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx) / den;
      if (s > 0.0 && s < 1.0 && u >= -1e-12 && u <= 1.0 + 1e-12)
      {
        cuts.push_back(s);
      }
    }
    // Polygon vertices on (or near) the segment also cut it: collinear
    // overlaps and grazing corners.
    if (DistancePointSegment2(p, a, b) <= tol)
    {
      const double s = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (len * len);
      if (s > 0.0 && s < 1.0)
      {
        cuts.push_back(s);
      }
    }
  }
  std::sort(cuts.begin(), cuts.end());
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
  {
    const double s0 = cuts[k], s1 = cuts[k + 1];
    if (!(s1 > s0))
    {
      continue;
    }
    const double sm = 0.5 * (s0 + s1);
    const P2 m = { a[0] + sm * dx, a[1] + sm * dy };
    if (PointInPolygon2(m, poly, tol) >= 0)
    {
      if (!pieces.empty() && pieces.back().Hi == s0)
      {
        pieces.back().Hi = s1;
      }
      else
      {
        pieces.push_back({ s0, s1 });
      }
    }
  }
}

//------------------------------------------------------------------------------
// A segment in the receiver's frame before merging.
struct Segment2
{
  P2 A;
  P2 B;
  int Order = 2;
  int SourceId = -1;
  bool Outline = false;
  bool Removal = false;
  int OccluderA = -1; ///< polygons used by the jump estimate
  int OccluderB = -1;
  int Priority() const { return this->Outline ? 0 : (this->Removal ? 1 : 2); }
};

using detail::UnionFind;

struct CellKey
{
  long long X;
  long long Y;
  bool operator==(const CellKey& o) const { return this->X == o.X && this->Y == o.Y; }
};
struct CellHash
{
  std::size_t operator()(const CellKey& k) const
  {
    return std::hash<long long>()(k.X * 73856093LL ^ k.Y * 19349663LL);
  }
};

/**
 * Snap and merge the receiver's segments into non-overlapping constraints:
 * 1. end points closer than `tol` become one point (outline vertices win,
 *    then footprint vertices, so the outline stays bit-exact);
 * 2. collinear segments (within tol) form one line; along it the pieces
 *    between consecutive end points (including end points of other lines
 *    lying on it: T-junctions) get the lowest order of the segments covering
 *    them, and the outline / footprint flags of any of them.
 * Crossings in the interior of two lines are left to the exact CDT.
 */
std::vector<detail::Constraint2D> MergeSegments(
  std::vector<Segment2> segments, double tol, double minLength)
{
  // 1. End point clustering on a grid of cell size tol.
  const std::size_t n = segments.size();
  std::vector<P2> points(2 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    points[2 * i] = segments[i].A;
    points[2 * i + 1] = segments[i].B;
  }
  UnionFind clusters(points.size());
  {
    std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
    const double cell = 2.0 * tol;
    auto keyOf = [cell](const P2& p) {
      return CellKey{ static_cast<long long>(std::floor(p[0] / cell)),
        static_cast<long long>(std::floor(p[1] / cell)) };
    };
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      grid[keyOf(points[i])].push_back(static_cast<int>(i));
    }
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const CellKey k = keyOf(points[i]);
      for (long long dx = -1; dx <= 1; ++dx)
      {
        for (long long dy = -1; dy <= 1; ++dy)
        {
          auto found = grid.find(CellKey{ k.X + dx, k.Y + dy });
          if (found == grid.end())
          {
            continue;
          }
          for (int j : found->second)
          {
            if (j > static_cast<int>(i) &&
              std::hypot(points[i][0] - points[j][0], points[i][1] - points[j][1]) <= tol)
            {
              clusters.Union(static_cast<int>(i), j);
            }
          }
        }
      }
    }
  }
  // Representative: best priority, then lowest index.
  std::vector<int> best(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const int root = clusters.Find(static_cast<int>(i));
    const int bi = best[root];
    if (bi < 0 || segments[i / 2].Priority() < segments[bi / 2].Priority())
    {
      best[root] = static_cast<int>(i);
    }
  }
  std::vector<int> pointRep(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    pointRep[i] = best[clusters.Find(static_cast<int>(i))];
  }
  std::vector<Segment2> kept;
  std::vector<std::array<int, 2>> keptRep;
  for (std::size_t i = 0; i < n; ++i)
  {
    Segment2 s = segments[i];
    const int ra = pointRep[2 * i], rb = pointRep[2 * i + 1];
    s.A = points[ra];
    s.B = points[rb];
    const double len = std::hypot(s.B[0] - s.A[0], s.B[1] - s.A[1]);
    if (ra == rb || !(len > 0.0) || (len < minLength && s.Priority() == 2))
    {
      continue;
    }
    kept.push_back(s);
    keptRep.push_back({ ra, rb });
  }
  segments.swap(kept);
  const std::size_t m = segments.size();

  // Distinct end points (for T-junctions), with their best priority.
  std::vector<int> uniqueReps;
  for (const auto& r : keptRep)
  {
    uniqueReps.push_back(r[0]);
    uniqueReps.push_back(r[1]);
  }
  std::sort(uniqueReps.begin(), uniqueReps.end());
  uniqueReps.erase(std::unique(uniqueReps.begin(), uniqueReps.end()), uniqueReps.end());

  // 2. Line grouping on a grid over (direction angle, offset): collinear
  // segments (within tol) fall in the same or neighbouring cells.
  std::vector<double> angle(m), offset(m), length(m);
  double shortest = std::numeric_limits<double>::max(), radius = 0.0;
  for (std::size_t i = 0; i < m; ++i)
  {
    const double dx = segments[i].B[0] - segments[i].A[0];
    const double dy = segments[i].B[1] - segments[i].A[1];
    double a = std::atan2(dy, dx);
    if (a < 0.0)
    {
      a += M_PI;
    }
    if (a >= M_PI)
    {
      a -= M_PI;
    }
    angle[i] = a;
    offset[i] = -std::sin(a) * segments[i].A[0] + std::cos(a) * segments[i].A[1];
    length[i] = std::hypot(dx, dy);
    shortest = std::min(shortest, length[i]);
    radius = std::max(radius, std::max(std::hypot(segments[i].A[0], segments[i].A[1]),
                                std::hypot(segments[i].B[0], segments[i].B[1])));
  }
  // Two collinear segments differ in angle by at most ~2 tol / length and in
  // offset by at most tol + (angle difference) * radius.
  const double window = m > 0 ? std::min(M_PI, 4.0 * tol / shortest + 1e-12) : M_PI;
  const long long angleBins = std::max(1LL, static_cast<long long>(std::floor(M_PI / window)));
  const double binWidth = M_PI / static_cast<double>(angleBins);
  const double offsetCell = 2.0 * tol + window * radius;
  auto angleBin = [&](double a) {
    return std::min(angleBins - 1, static_cast<long long>(std::floor(a / binWidth)));
  };
  auto offsetBin = [&](double c) { return static_cast<long long>(std::floor(c / offsetCell)); };
  std::unordered_map<CellKey, std::vector<int>, CellHash> lineGrid;
  for (std::size_t i = 0; i < m; ++i)
  {
    lineGrid[CellKey{ angleBin(angle[i]), offsetBin(offset[i]) }].push_back(static_cast<int>(i));
  }
  auto distanceToLine = [&](const P2& p, const Segment2& s, double len) {
    return std::abs(Cross2(s.A, s.B, p)) / len;
  };
  auto collinear = [&](int i, int j) {
    const Segment2& a = segments[i];
    const Segment2& b = segments[j];
    return distanceToLine(b.A, a, length[i]) <= tol && distanceToLine(b.B, a, length[i]) <= tol &&
      distanceToLine(a.A, b, length[j]) <= tol && distanceToLine(a.B, b, length[j]) <= tol;
  };
  UnionFind lines(m);
  for (std::size_t i = 0; i < m; ++i)
  {
    const long long ab = angleBin(angle[i]);
    long long visited[3];
    int nVisited = 0;
    for (long long da = -1; da <= 1; ++da)
    {
      long long b = ab + da;
      bool wrapped = false;
      if (b < 0)
      {
        b += angleBins;
        wrapped = true;
      }
      else if (b >= angleBins)
      {
        b -= angleBins;
        wrapped = true;
      }
      if (std::find(visited, visited + nVisited, b * 2 + wrapped) != visited + nVisited)
      {
        continue;
      }
      visited[nVisited++] = b * 2 + wrapped;
      // Across the wrap at angle pi the line's normal, hence its offset, flips.
      const long long ob = offsetBin(wrapped ? -offset[i] : offset[i]);
      for (long long dc = -1; dc <= 1; ++dc)
      {
        auto found = lineGrid.find(CellKey{ b, ob + dc });
        if (found == lineGrid.end())
        {
          continue;
        }
        for (int j : found->second)
        {
          if (j > static_cast<int>(i) && collinear(static_cast<int>(i), j))
          {
            lines.Union(static_cast<int>(i), j);
          }
        }
      }
    }
  }
  std::unordered_map<int, std::vector<int>> groups;
  for (std::size_t i = 0; i < m; ++i)
  {
    groups[lines.Find(static_cast<int>(i))].push_back(static_cast<int>(i));
  }
  std::vector<int> groupRoots;
  for (const auto& g : groups)
  {
    groupRoots.push_back(g.first);
  }
  std::sort(groupRoots.begin(), groupRoots.end()); // deterministic output order

  // Priority of each distinct end point (for choosing breakpoint coordinates).
  std::unordered_map<int, int> priorityOfRep;
  for (std::size_t i = 0; i < m; ++i)
  {
    for (int r : keptRep[i])
    {
      auto found = priorityOfRep.find(r);
      const int p = segments[i].Priority();
      if (found == priorityOfRep.end() || p < found->second)
      {
        priorityOfRep[r] = p;
      }
    }
  }

  // Grid of the distinct end points, for the T-junction search.
  double minX = std::numeric_limits<double>::max(), minY = minX, maxX = -minX, maxY = -minX;
  for (int r : uniqueReps)
  {
    minX = std::min(minX, points[r][0]);
    maxX = std::max(maxX, points[r][0]);
    minY = std::min(minY, points[r][1]);
    maxY = std::max(maxY, points[r][1]);
  }
  const double extent = uniqueReps.empty() ? 1.0 : std::max(maxX - minX, maxY - minY);
  const double repCell = std::max(
    extent / std::sqrt(static_cast<double>(std::max<std::size_t>(uniqueReps.size(), 1))), 4.0 * tol);
  // Dense grid (about one point per cell) stored as cell starts + items.
  const long long gridX = uniqueReps.empty() ? 1 : 1 + static_cast<long long>((maxX - minX) / repCell);
  const long long gridY = uniqueReps.empty() ? 1 : 1 + static_cast<long long>((maxY - minY) / repCell);
  auto cellOf = [&](double x, double y) {
    const long long i = std::max(0LL, std::min(gridX - 1, static_cast<long long>((x - minX) / repCell)));
    const long long j = std::max(0LL, std::min(gridY - 1, static_cast<long long>((y - minY) / repCell)));
    return std::array<long long, 2>{ i, j };
  };
  std::vector<int> cellStart(static_cast<std::size_t>(gridX * gridY + 1), 0);
  std::vector<int> cellItems(uniqueReps.size());
  for (int r : uniqueReps)
  {
    const auto c = cellOf(points[r][0], points[r][1]);
    ++cellStart[static_cast<std::size_t>(c[1] * gridX + c[0] + 1)];
  }
  for (std::size_t c = 1; c < cellStart.size(); ++c)
  {
    cellStart[c] += cellStart[c - 1];
  }
  {
    std::vector<int> fill(cellStart.begin(), cellStart.end() - 1);
    for (int r : uniqueReps)
    {
      const auto c = cellOf(points[r][0], points[r][1]);
      cellItems[static_cast<std::size_t>(fill[static_cast<std::size_t>(c[1] * gridX + c[0])]++)] = r;
    }
  }
  std::vector<int> nearReps;

  std::vector<detail::Constraint2D> out;
  struct Breakpoint
  {
    double S;
    int Rep;
  };
  std::vector<Breakpoint> breaks;
  for (int root : groupRoots)
  {
    const std::vector<int>& members = groups[root];
    int ref = members[0];
    for (int i : members)
    {
      const int pi = segments[i].Priority(), pr = segments[ref].Priority();
      if (pi < pr || (pi == pr && length[i] > length[ref]))
      {
        ref = i;
      }
    }
    const P2 o = segments[ref].A;
    const double dx = (segments[ref].B[0] - o[0]) / length[ref];
    const double dy = (segments[ref].B[1] - o[1]) / length[ref];
    auto param = [&](const P2& p) { return (p[0] - o[0]) * dx + (p[1] - o[1]) * dy; };
    auto offLine = [&](const P2& p) { return std::abs((p[0] - o[0]) * dy - (p[1] - o[1]) * dx); };
    breaks.clear();
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    std::vector<Interval> spans;
    for (int i : members)
    {
      const double sa = param(segments[i].A), sb = param(segments[i].B);
      breaks.push_back({ sa, keptRep[i][0] });
      breaks.push_back({ sb, keptRep[i][1] });
      spans.push_back({ std::min(sa, sb), std::max(sa, sb) });
      lo = std::min(lo, std::min(sa, sb));
      hi = std::max(hi, std::max(sa, sb));
    }
    // T-junctions: end points of other lines lying inside this one (found
    // through the grid cells along each member).
    nearReps.clear();
    for (int i : members)
    {
      const P2& a = segments[i].A;
      const P2& b = segments[i].B;
      // Cells within one cell of samples spaced one cell apart cover every
      // cell the segment crosses.
      const int steps = 1 + static_cast<int>(std::ceil(length[i] / repCell));
      std::array<long long, 2> last = { -2, -2 };
      for (int k = 0; k <= steps; ++k)
      {
        const double f = static_cast<double>(k) / steps;
        const auto c = cellOf(a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]));
        if (c == last)
        {
          continue;
        }
        last = c;
        for (long long dy = std::max(0LL, c[1] - 1); dy <= std::min(gridY - 1, c[1] + 1); ++dy)
        {
          for (long long dx = std::max(0LL, c[0] - 1); dx <= std::min(gridX - 1, c[0] + 1); ++dx)
          {
            const std::size_t cell = static_cast<std::size_t>(dy * gridX + dx);
            nearReps.insert(nearReps.end(), cellItems.begin() + cellStart[cell],
              cellItems.begin() + cellStart[cell + 1]);
          }
        }
      }
    }
    std::sort(nearReps.begin(), nearReps.end());
    nearReps.erase(std::unique(nearReps.begin(), nearReps.end()), nearReps.end());
    for (int r : nearReps)
    {
      const P2& p = points[r];
      if (offLine(p) > tol)
      {
        continue;
      }
      const double s = param(p);
      if (s <= lo + tol || s >= hi - tol)
      {
        continue;
      }
      for (const Interval& span : spans)
      {
        if (s > span.Lo + tol && s < span.Hi - tol)
        {
          breaks.push_back({ s, r });
          break;
        }
      }
    }
    std::sort(breaks.begin(), breaks.end(), [&](const Breakpoint& x, const Breakpoint& y) {
      return x.S < y.S || (x.S == y.S && priorityOfRep[x.Rep] < priorityOfRep[y.Rep]);
    });
    // Merge breakpoints closer than tol, keeping the best-priority point.
    std::vector<Breakpoint> merged;
    for (const Breakpoint& b : breaks)
    {
      if (!merged.empty() && b.S - merged.back().S <= tol)
      {
        if (priorityOfRep[b.Rep] < priorityOfRep[merged.back().Rep])
        {
          merged.back().Rep = b.Rep;
        }
        continue;
      }
      merged.push_back(b);
    }
    for (std::size_t k = 0; k + 1 < merged.size(); ++k)
    {
      const double s0 = merged[k].S, s1 = merged[k + 1].S;
      detail::Constraint2D c;
      c.Order = 3;
      bool covered = false;
      for (int i : members)
      {
        const double a = param(segments[i].A), b = param(segments[i].B);
        if (std::min(a, b) <= s0 + tol && std::max(a, b) >= s1 - tol)
        {
          const Segment2& s = segments[i];
          covered = true;
          c.Outline = c.Outline || s.Outline;
          c.Removal = c.Removal || s.Removal;
          if (s.Order < c.Order || (s.Order == c.Order && s.SourceId < c.SourceId))
          {
            c.Order = s.Order;
            c.SourceId = s.SourceId;
          }
        }
      }
      if (!covered || merged[k].Rep == merged[k + 1].Rep)
      {
        continue;
      }
      const P2& a = points[merged[k].Rep];
      const P2& b = points[merged[k + 1].Rep];
      c.A[0] = a[0];
      c.A[1] = a[1];
      c.B[0] = b[0];
      c.B[1] = b[1];
      if (c.Outline)
      {
        c.Order = -1;
        c.SourceId = -1;
      }
      out.push_back(c);
    }
  }
  return out;
}

//------------------------------------------------------------------------------
// Precomputed scene data.

struct PolygonData
{
  std::vector<Vec3> V;
  Vec3 N;
  double D = 0.0; ///< plane: Dot(N, x) == D
  Vec3 Centroid;
  double Diameter = 0.0;
  double Area = 0.0;
  std::vector<int> Cluster; ///< vertex cluster of each vertex
  std::vector<int> Edge;    ///< edge id of edge i (from V[i] to V[i+1])
  int Component = -1;       ///< connected component through shared edges
};

struct Use
{
  int Polygon;
  int Index;
};

// Side of polygon k, locally at its edge i, with respect to a plane of unit
// normal m through the edge: +1, -1, or 0 when the polygon lies in the plane.
int EdgeSide(const PolygonData& p, int i, const Vec3& m)
{
  const Vec3 a = p.V[i], b = p.V[(i + 1) % p.V.size()];
  const Vec3 inward = Normalized(Cross(p.N, b - a));
  return Sign(Dot(m, inward), kAngle);
}

// Side of polygon k, locally at its vertex i, with respect to a plane of unit
// normal m through the vertex: +1, -1, 0 (polygon in the plane), or 2 when
// the corner straddles the plane.
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

//------------------------------------------------------------------------------
DiscontinuityMeshStatistics& DiscontinuityMeshStatistics::operator+=(
  const DiscontinuityMeshStatistics& o)
{
  this->Receivers += o.Receivers;
  this->Pairs += o.Pairs;
  this->CandidateOccluders += o.CandidateOccluders;
  this->Wedges += o.Wedges;
  this->SegmentsGenerated += o.SegmentsGenerated;
  this->SegmentsKept += o.SegmentsKept;
  this->ContactSegments += o.ContactSegments;
  this->Constraints += o.Constraints;
  this->ConstraintFailures += o.ConstraintFailures;
  this->Points += o.Points;
  this->Triangles += o.Triangles;
  this->DroppedDegenerate += o.DroppedDegenerate;
  this->RemovedArea += o.RemovedArea;
  this->BoundarySeconds += o.BoundarySeconds;
  this->TriangulationSeconds += o.TriangulationSeconds;
  return *this;
}

struct DiscontinuityMesher::Internal
{
  Scene SceneCopy;
  OccluderSet Occluders;
  std::vector<PolygonData> Polygons;
  std::vector<std::vector<Use>> ClusterUses; ///< per vertex cluster
  std::vector<Vec3> ClusterPoint;
  std::vector<std::vector<Use>> EdgeUses;    ///< per edge id
  std::vector<std::array<int, 2>> EdgeClusters;
  std::vector<std::vector<int>> ComponentPolygons;
  std::vector<std::vector<int>> ComponentOpenEdges; ///< edges not shared by exactly two polygons
  /// (surface, emitted power) of every surface with positive power, and their
  /// total: computed once, as every receiver selects its shooters.
  std::vector<std::pair<int, double>> EmitterPower;
  double TotalPower = 0.0;
  double Size = 1.0;

  explicit Internal(const Scene& scene);

  struct Frame
  {
    Vec3 Origin, U, V, N;
    double D = 0.0;
    std::vector<P2> Outline;
    P2 To2D(const Vec3& p) const
    {
      const Vec3 d = p - this->Origin;
      return { Dot(d, this->U), Dot(d, this->V) };
    }
    Vec3 To3D(const P2& p) const { return this->Origin + p[0] * this->U + p[1] * this->V; }
  };

  void Check(int receiverId, const DiscontinuityMeshSettings& settings) const;
  std::vector<int> Select(const DiscontinuityMeshSettings& settings) const;
  Frame MakeFrame(int receiverId) const;
  std::vector<Segment2> Boundaries(int receiverId, const DiscontinuityMeshSettings& settings,
    const Frame& frame, DiscontinuityMeshStatistics& stats) const;
  void AddContacts(int receiverId, const DiscontinuityMeshSettings& settings, const Frame& frame,
    std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats) const;
  /// The radiance (mean of RGB) of a shooter used by the jump threshold.
  double JumpRadiance(const DiscontinuityMeshSettings& settings, int shooter) const;
  /// `minimumJump`: the jump below which shadows are dropped (< 0: none).
  void AddShadows(int receiverId, int shooterId, const DiscontinuityMeshSettings& settings,
    double minimumJump, const Frame& frame, std::vector<Segment2>& out,
    DiscontinuityMeshStatistics& stats) const;
  std::vector<detail::Constraint2D> Constraints(int receiverId,
    const DiscontinuityMeshSettings& settings, const Frame& frame,
    DiscontinuityMeshStatistics& stats) const;
};

DiscontinuityMesher::Internal::Internal(const Scene& scene)
  : SceneCopy(scene)
{
  ValidateScene(scene);
  this->Occluders.Build(scene);
  this->Size = std::max(scene.Size(), 1e-300);
  const std::size_t count = scene.Surfaces.size();
  this->Polygons.resize(count);
  // Vertex clusters: vertices within kVertexMatch of each other are one
  // feature (shared by several polygons of a solid).
  const double match = kVertexMatch * this->Size;
  const double cell = 2.0 * match;
  struct Key
  {
    long long X, Y, Z;
    bool operator==(const Key& o) const { return X == o.X && Y == o.Y && Z == o.Z; }
  };
  struct KeyHash
  {
    std::size_t operator()(const Key& k) const
    {
      return std::hash<long long>()(k.X * 73856093LL ^ k.Y * 19349663LL ^ k.Z * 83492791LL);
    }
  };
  std::unordered_map<Key, std::vector<int>, KeyHash> grid;
  auto keyOf = [cell](const Vec3& p) {
    return Key{ static_cast<long long>(std::floor(p.X / cell)),
      static_cast<long long>(std::floor(p.Y / cell)),
      static_cast<long long>(std::floor(p.Z / cell)) };
  };
  for (std::size_t k = 0; k < count; ++k)
  {
    PolygonData& p = this->Polygons[k];
    p.V = scene.Surfaces[k].Vertices;
    const PolygonGeometry g = ComputePolygonGeometry(p.V);
    p.N = g.Normal;
    p.D = g.Offset;
    p.Centroid = g.Centroid;
    p.Diameter = g.Diameter;
    p.Area = g.Area;
    p.Cluster.assign(p.V.size(), -1);
    for (std::size_t i = 0; i < p.V.size(); ++i)
    {
      const Key key = keyOf(p.V[i]);
      int found = -1;
      for (long long dx = -1; dx <= 1 && found < 0; ++dx)
      {
        for (long long dy = -1; dy <= 1 && found < 0; ++dy)
        {
          for (long long dz = -1; dz <= 1 && found < 0; ++dz)
          {
            auto it = grid.find(Key{ key.X + dx, key.Y + dy, key.Z + dz });
            if (it == grid.end())
            {
              continue;
            }
            for (int c : it->second)
            {
              if (Length(this->ClusterPoint[c] - p.V[i]) <= match)
              {
                found = c;
                break;
              }
            }
          }
        }
      }
      if (found < 0)
      {
        found = static_cast<int>(this->ClusterPoint.size());
        this->ClusterPoint.push_back(p.V[i]);
        this->ClusterUses.emplace_back();
        grid[key].push_back(found);
      }
      p.Cluster[i] = found;
      this->ClusterUses[found].push_back({ static_cast<int>(k), static_cast<int>(i) });
    }
  }
  for (std::size_t k = 0; k < count; ++k)
  {
    const double power = scene.Surfaces[k].Emission.Mean() * M_PI * this->Polygons[k].Area;
    this->TotalPower += power;
    if (power > 0.0)
    {
      this->EmitterPower.emplace_back(static_cast<int>(k), power);
    }
  }
  // Edges: identified by their (unordered) pair of end clusters.
  std::unordered_map<long long, int> edgeIds;
  for (std::size_t k = 0; k < count; ++k)
  {
    PolygonData& p = this->Polygons[k];
    const std::size_t n = p.V.size();
    p.Edge.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
    {
      const int a = p.Cluster[i], b = p.Cluster[(i + 1) % n];
      const long long key =
        static_cast<long long>(std::min(a, b)) * 4294967296LL + static_cast<long long>(std::max(a, b));
      auto it = edgeIds.find(key);
      int id;
      if (it == edgeIds.end())
      {
        id = static_cast<int>(this->EdgeUses.size());
        edgeIds.emplace(key, id);
        this->EdgeUses.emplace_back();
        this->EdgeClusters.push_back({ std::min(a, b), std::max(a, b) });
      }
      else
      {
        id = it->second;
      }
      p.Edge[i] = id;
      this->EdgeUses[id].push_back({ static_cast<int>(k), static_cast<int>(i) });
    }
  }
  // Connected components through shared edges, and their open edges.
  UnionFind comps(count);
  for (const auto& uses : this->EdgeUses)
  {
    for (std::size_t u = 1; u < uses.size(); ++u)
    {
      comps.Union(uses[0].Polygon, uses[u].Polygon);
    }
  }
  std::unordered_map<int, int> compIndex;
  for (std::size_t k = 0; k < count; ++k)
  {
    const int root = comps.Find(static_cast<int>(k));
    auto it = compIndex.find(root);
    if (it == compIndex.end())
    {
      it = compIndex.emplace(root, static_cast<int>(this->ComponentPolygons.size())).first;
      this->ComponentPolygons.emplace_back();
      this->ComponentOpenEdges.emplace_back();
    }
    this->Polygons[k].Component = it->second;
    this->ComponentPolygons[it->second].push_back(static_cast<int>(k));
  }
  for (std::size_t e = 0; e < this->EdgeUses.size(); ++e)
  {
    if (this->EdgeUses[e].size() != 2)
    {
      const int c = this->Polygons[this->EdgeUses[e][0].Polygon].Component;
      this->ComponentOpenEdges[c].push_back(static_cast<int>(e));
    }
  }
}

void DiscontinuityMesher::Internal::Check(
  int receiverId, const DiscontinuityMeshSettings& settings) const
{
  if (receiverId < 0 || receiverId >= static_cast<int>(this->Polygons.size()))
  {
    std::ostringstream os;
    os << "receiver id " << receiverId << " is out of range [0, " << this->Polygons.size() << ")";
    throw InputError(os.str());
  }
  if (!(settings.MinimumAngle >= 0.0 && settings.MinimumAngle <= kMaxMinimumAngle))
  {
    std::ostringstream os;
    os << "MinimumAngle " << settings.MinimumAngle << " is outside [0, " << kMaxMinimumAngle
       << "] degrees";
    throw InputError(os.str());
  }
  if (!(settings.JumpThreshold >= 0.0 && settings.JumpThreshold <= 1.0))
  {
    std::ostringstream os;
    os << "JumpThreshold " << settings.JumpThreshold << " is outside [0, 1]";
    throw InputError(os.str());
  }
  if (!(settings.ContactTolerance >= 0.0 && settings.ContactTolerance <= 1e-2))
  {
    std::ostringstream os;
    os << "ContactTolerance " << settings.ContactTolerance << " is outside [0, 0.01]";
    throw InputError(os.str());
  }
  if (!(settings.ShooterPowerFraction >= 0.0 && settings.ShooterPowerFraction <= 1.0))
  {
    std::ostringstream os;
    os << "ShooterPowerFraction " << settings.ShooterPowerFraction << " is outside [0, 1]";
    throw InputError(os.str());
  }
}

std::vector<int> DiscontinuityMesher::Internal::Select(
  const DiscontinuityMeshSettings& settings) const
{
  const int count = static_cast<int>(this->Polygons.size());
  std::vector<int> shooters;
  if (!settings.ShooterRadiance.empty() &&
    settings.ShooterRadiance.size() != settings.Shooters.size())
  {
    std::ostringstream os;
    os << "ShooterRadiance has " << settings.ShooterRadiance.size() << " entries but Shooters has "
       << settings.Shooters.size();
    throw InputError(os.str());
  }
  if (!settings.Shooters.empty())
  {
    for (int id : settings.Shooters)
    {
      if (id < 0 || id >= count)
      {
        std::ostringstream os;
        os << "shooter id " << id << " is out of range [0, " << count << ")";
        throw InputError(os.str());
      }
      shooters.push_back(id);
    }
  }
  else
  {
    for (const std::pair<int, double>& emitter : this->EmitterPower)
    {
      if (emitter.second >= settings.ShooterPowerFraction * this->TotalPower)
      {
        shooters.push_back(emitter.first);
      }
    }
  }
  std::sort(shooters.begin(), shooters.end());
  shooters.erase(std::unique(shooters.begin(), shooters.end()), shooters.end());
  return shooters;
}

DiscontinuityMesher::Internal::Frame DiscontinuityMesher::Internal::MakeFrame(int receiverId) const
{
  const PolygonData& r = this->Polygons[receiverId];
  Frame f;
  f.Origin = r.Centroid;
  f.N = r.N;
  f.D = r.D;
  // First axis along the longest edge (well conditioned), projected in-plane.
  std::size_t best = 0;
  double bestLength = -1.0;
  for (std::size_t i = 0; i < r.V.size(); ++i)
  {
    const double l = Length(r.V[(i + 1) % r.V.size()] - r.V[i]);
    if (l > bestLength)
    {
      bestLength = l;
      best = i;
    }
  }
  Vec3 u = r.V[(best + 1) % r.V.size()] - r.V[best];
  u = Normalized(u - Dot(u, r.N) * r.N);
  f.U = u;
  f.V = Cross(r.N, u);
  for (const Vec3& p : r.V)
  {
    f.Outline.push_back(f.To2D(p));
  }
  return f;
}

void DiscontinuityMesher::Internal::AddContacts(int receiverId,
  const DiscontinuityMeshSettings& settings, const Frame& frame, std::vector<Segment2>& out,
  DiscontinuityMeshStatistics& stats) const
{
  const PolygonData& r = this->Polygons[receiverId];
  const double tol = std::max(settings.ContactTolerance * this->Size, kLinear * this->Size);
  const double snap = kSnap * this->Size;
  // Polygons near the receiver's plane and bounds.
  CullingVolume slab;
  Vec3 lo = r.V[0], hi = r.V[0];
  for (const Vec3& p : r.V)
  {
    lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
    hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
  }
  slab.BoxMin = lo - Vec3(tol, tol, tol);
  slab.BoxMax = hi + Vec3(tol, tol, tol);
  slab.Planes.push_back({ r.N, r.D - tol });
  slab.Planes.push_back({ -r.N, -r.D - tol });
  std::vector<int> near;
  this->Occluders.VolumeCandidates(slab, receiverId, -1, near);
  std::sort(near.begin(), near.end());

  auto dist = [&](const Vec3& p) { return Dot(r.N, p) - r.D; };
  auto inPlane = [&](const PolygonData& p) {
    for (const Vec3& v : p.V)
    {
      if (std::abs(dist(v)) > tol)
      {
        return false;
      }
    }
    return true;
  };
  auto inFront = [&](const PolygonData& p) {
    for (const Vec3& v : p.V)
    {
      if (dist(v) > tol)
      {
        return true;
      }
    }
    return false;
  };
  std::vector<int> components;
  std::vector<Interval> pieces;
  for (int k : near)
  {
    const PolygonData& p = this->Polygons[k];
    if (inPlane(p) || !inFront(p))
    {
      continue;
    }
    const std::size_t n = p.V.size();
    bool touches = false;
    for (std::size_t i = 0; i < n; ++i)
    {
      const Vec3 a = p.V[i], b = p.V[(i + 1) % n];
      if (std::abs(dist(a)) > tol || std::abs(dist(b)) > tol)
      {
        continue;
      }
      touches = true;
      const P2 a2 = frame.To2D(a), b2 = frame.To2D(b);
      ClipSegmentToPolygon2(a2, b2, frame.Outline, snap, pieces);
      for (const Interval& iv : pieces)
      {
        Segment2 s;
        s.A = { a2[0] + iv.Lo * (b2[0] - a2[0]), a2[1] + iv.Lo * (b2[1] - a2[1]) };
        s.B = { a2[0] + iv.Hi * (b2[0] - a2[0]), a2[1] + iv.Hi * (b2[1] - a2[1]) };
        if (iv.Lo == 0.0)
        {
          s.A = a2;
        }
        if (iv.Hi == 1.0)
        {
          s.B = b2;
        }
        // Contacts along the receiver's own outline (a wall meeting the
        // floor) are that outline: not a separate line.
        bool onOutline = false;
        for (std::size_t e = 0; e < frame.Outline.size() && !onOutline; ++e)
        {
          const P2& oa = frame.Outline[e];
          const P2& ob = frame.Outline[(e + 1) % frame.Outline.size()];
          onOutline = DistancePointSegment2(s.A, oa, ob) <= tol &&
            DistancePointSegment2(s.B, oa, ob) <= tol;
        }
        if (onOutline)
        {
          continue;
        }
        s.Order = 0;
        s.SourceId = -1;
        out.push_back(s);
        ++stats.ContactSegments;
      }
    }
    if (touches)
    {
      components.push_back(p.Component);
    }
  }
  // Solids standing on the receiver: closed apart from edges in its plane.
  std::sort(components.begin(), components.end());
  components.erase(std::unique(components.begin(), components.end()), components.end());
  for (int c : components)
  {
    if (c == r.Component)
    {
      continue; // the receiver belongs to it: we are looking at its inside
    }
    bool closed = true;
    for (int e : this->ComponentOpenEdges[c])
    {
      const Vec3 a = this->ClusterPoint[this->EdgeClusters[e][0]];
      const Vec3 b = this->ClusterPoint[this->EdgeClusters[e][1]];
      if (std::abs(dist(a)) > tol || std::abs(dist(b)) > tol)
      {
        closed = false;
        break;
      }
    }
    for (int k : this->ComponentPolygons[c])
    {
      for (const Vec3& v : this->Polygons[k].V)
      {
        closed = closed && dist(v) >= -tol;
      }
    }
    if (!closed)
    {
      continue;
    }
    // Footprint outline: in-plane edges used by a polygon not in the plane.
    std::vector<int> edges;
    for (int k : this->ComponentPolygons[c])
    {
      const PolygonData& p = this->Polygons[k];
      if (inPlane(p))
      {
        continue;
      }
      for (std::size_t i = 0; i < p.V.size(); ++i)
      {
        if (std::abs(dist(p.V[i])) <= tol && std::abs(dist(p.V[(i + 1) % p.V.size()])) <= tol)
        {
          edges.push_back(p.Edge[i]);
        }
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (int e : edges)
    {
      const Use& u = this->EdgeUses[e][0];
      const PolygonData& p = this->Polygons[u.Polygon];
      Segment2 s;
      s.A = frame.To2D(p.V[u.Index]);
      s.B = frame.To2D(p.V[(u.Index + 1) % p.V.size()]);
      s.Order = 0;
      s.SourceId = -1;
      s.Removal = true;
      out.push_back(s);
    }
  }
}

namespace
{

// Everything the wedge tracer needs about one (shooter, receiver) pair.
struct PairContext
{
  const std::vector<PolygonData>* Polygons = nullptr;
  const PolygonData* Shooter = nullptr;
  const PolygonData* Receiver = nullptr;
  const OccluderSet* Occluders = nullptr;
  int ShooterId = -1;
  int ReceiverId = -1;
  std::vector<int>* Scratch = nullptr; ///< blocker candidates of the current wedge
  const std::vector<int>* Candidates = nullptr; ///< the pair's shaft candidates
  bool Cull = true;      ///< DiscontinuityMeshSettings::CullWedges
  double Tol = 0.0;      ///< linear tolerance
  Vec3 ReceiverCentre;   ///< for bounding the wedge's reach
  double ReceiverRadius = 0.0;
  double Margin = 0.0;   ///< lengthening of the receiver's chords (far above Tol)
};

enum class WedgeKind
{
  EV, ///< apex: shooter vertex; generator: occluder edge
  VE, ///< apex: occluder vertex; generator: shooter edge
  OO  ///< apex: occluder vertex; generator: another occluder's edge
};

struct Wedge
{
  WedgeKind Kind = WedgeKind::EV;
  Vec3 P;  ///< apex
  Vec3 G0; ///< generator edge
  Vec3 G1;
  Vec3 M;  ///< unit normal of the wedge plane
  std::vector<int> Exclude; ///< polygons sharing the features (sorted)
};

// Chords of polygon p with the plane (m, through point o): pairs of 3D points.
void PlaneChords(const PolygonData& p, const Vec3& m, const Vec3& o, double tol,
  std::vector<std::pair<Vec3, Vec3>>& chords)
{
  chords.clear();
  const std::size_t n = p.V.size();
  const Vec3 dir = Cross(m, p.N);
  if (!(Length(dir) > kAngle))
  {
    return; // polygon parallel to (or in) the plane
  }
  double d[64];
  std::vector<double> heap;
  double* dist = d;
  if (n > 64)
  {
    heap.resize(n);
    dist = heap.data();
  }
  bool pos = false, neg = false;
  for (std::size_t i = 0; i < n; ++i)
  {
    dist[i] = Dot(m, p.V[i] - o);
    // Symbolic perturbation: points within tol count as positive.
    if (dist[i] < -tol)
    {
      neg = true;
    }
    else
    {
      pos = true;
    }
  }
  if (!pos || !neg)
  {
    return;
  }
  // Crossing points, sorted along the line (scratch reused per thread).
  thread_local std::vector<std::pair<double, Vec3>> cuts;
  cuts.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t j = (i + 1) % n;
    const bool si = dist[i] >= -tol, sj = dist[j] >= -tol;
    if (si == sj)
    {
      continue;
    }
    double f = dist[i] / (dist[i] - dist[j]);
    f = std::max(0.0, std::min(1.0, f));
    const Vec3 x = p.V[i] + f * (p.V[j] - p.V[i]);
    cuts.push_back({ Dot(x, dir), x });
  }
  std::sort(cuts.begin(), cuts.end(),
    [](const std::pair<double, Vec3>& a, const std::pair<double, Vec3>& b) { return a.first < b.first; });
  for (std::size_t k = 0; k + 1 < cuts.size(); k += 2)
  {
    chords.push_back({ cuts[k].second, cuts[k + 1].second });
  }
}

// A half-space Dot(N, y) - D > 0 used to clip chords.
struct HalfSpace
{
  Vec3 N;
  double D;
};

bool ClipChord(Vec3& a, Vec3& b, const HalfSpace* h, int count)
{
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < count; ++k)
  {
    const double fa = Dot(h[k].N, a) - h[k].D, fb = Dot(h[k].N, b) - h[k].D;
    if (fa <= 0.0 && fb <= 0.0)
    {
      return false;
    }
    if (fa < 0.0)
    {
      lo = std::max(lo, fa / (fa - fb));
    }
    else if (fb < 0.0)
    {
      hi = std::min(hi, fa / (fa - fb));
    }
  }
  if (!(hi > lo))
  {
    return false;
  }
  const Vec3 d = b - a;
  const Vec3 na = a + lo * d, nb = a + hi * d;
  a = na;
  b = nb;
  return true;
}

/**
 * Trace one wedge: the visible t-intervals of the generator, mapped to 3D
 * segments on the receiver's plane. See the header for the geometry. All
 * conditions on t except blocking are linear in t; blocking chords map to
 * t-intervals by central projection from the apex.
 */
bool TraceWedge(const PairContext& ctx, const Wedge& w, std::vector<std::pair<Vec3, Vec3>>& out)
{
  out.clear();
  const double tol = ctx.Tol;
  const Vec3 gd = w.G1 - w.G0;
  const double len = Length(gd);
  if (!(len > tol))
  {
    return false;
  }
  const Vec3 u = gd / len;
  const Vec3 w0 = w.G0 - w.P;
  const double g0 = Dot(w0, u);
  const Vec3 wv = w0 - g0 * u;
  const double h = Length(wv);
  if (!(h > tol))
  {
    return false; // apex on the generator's line
  }
  const Vec3 wn = wv / h; // in-plane, from the apex towards the generator line
  const PolygonData& rec = *ctx.Receiver;
  const PolygonData& sh = *ctx.Shooter;
  const double hR = Dot(rec.N, w.P) - rec.D;
  const double hS = Dot(sh.N, w.P) - sh.D;
  // Plane distances along the generator: f(t) = a + b t.
  const double aR = Dot(rec.N, w.G0) - rec.D, bR = Dot(rec.N, gd);
  const double aS = Dot(sh.N, w.G0) - sh.D, bS = Dot(sh.N, gd);
  // |mu_r| <= muMax keeps receiver points within reach of the receiver (mu
  // is the line parameter: 0 at the apex, 1 on the generator).
  const double reach = Length(w.P - ctx.ReceiverCentre) + ctx.ReceiverRadius;
  const double muMax = reach / h + 1.0;

  std::vector<Interval> valid;
  std::vector<Interval> shooterHits;
  switch (w.Kind)
  {
    case WedgeKind::EV:
    {
      // mu_r = hR / (hR - fR) > 1  <=>  0 < fR < hR, and the generator in
      // front of the shooter.
      Interval iv{ 0.0, 1.0 };
      Restrict(iv, aR - tol, bR);
      Restrict(iv, hR - hR / muMax - aR, -bR);
      Restrict(iv, aS - tol, bS);
      valid.push_back(iv);
      break;
    }
    case WedgeKind::VE:
    {
      // mu_r < 0  <=>  fR > hR: the shooter point farther from the receiver.
      Interval iv{ 0.0, 1.0 };
      Restrict(iv, aR - hR - hR / muMax, bR);
      valid.push_back(iv);
      break;
    }
    case WedgeKind::OO:
    {
      // Case A: receiver, apex, generator, shooter (0 < fS < hS, fR > hR).
      Interval a{ 0.0, 1.0 };
      Restrict(a, aS - tol, bS);
      Restrict(a, hS - aS - tol, -bS);
      Restrict(a, aR - hR - hR / muMax, bR);
      // Case B: receiver, generator, apex, shooter (fS > hS, fR < hR).
      Interval b{ 0.0, 1.0 };
      Restrict(b, aS - hS - tol, bS);
      Restrict(b, aR - tol, bR);
      Restrict(b, hR - hR / muMax - aR, -bR);
      // Lines of case A must hit the shooter beyond the generator (b > h),
      // those of case B beyond the apex on the other side (b < 0).
      std::vector<std::pair<Vec3, Vec3>> chords;
      PlaneChords(sh, w.M, w.P, tol, chords);
      for (int c = 0; c < 2; ++c)
      {
        const Interval& iv = c == 0 ? a : b;
        if (!(iv.Hi > iv.Lo))
        {
          continue;
        }
        for (auto chord : chords)
        {
          HalfSpace hs = c == 0 ? HalfSpace{ wn, Dot(wn, w.P) + h + tol }
                                : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
          Vec3 c0 = chord.first, c1 = chord.second;
          if (!ClipChord(c0, c1, &hs, 1))
          {
            continue;
          }
          double t0 = (Dot(c0 - w.P, u) * h / Dot(c0 - w.P, wn) - g0) / len;
          double t1 = (Dot(c1 - w.P, u) * h / Dot(c1 - w.P, wn) - g0) / len;
          Interval hit{ std::max(iv.Lo, std::min(t0, t1)), std::min(iv.Hi, std::max(t0, t1)) };
          if (hit.Hi > hit.Lo)
          {
            shooterHits.push_back(hit);
          }
        }
      }
      Normalize(shooterHits);
      valid = shooterHits;
      break;
    }
  }
  Normalize(valid);
  if (valid.empty())
  {
    return false;
  }
  // Only the lines that meet the receiver polygon can leave a boundary on it
  // (the pieces are clipped to it afterwards), so before looking for
  // blockers: a receiver entirely on one side of the wedge plane (farther
  // than the snapping distance, so not even an outline piece could remain)
  // gets nothing, and otherwise t is restricted to the central projection of
  // the receiver's chords in the wedge plane. Most wedges miss a small
  // receiver entirely and stop here. Each chord is lengthened by ctx.Margin
  // so that the pieces still end where the 2D clip against R's outline puts
  // them, not at a rounded projection.
  {
    bool above = !ctx.Cull, below = !ctx.Cull;
    for (const Vec3& v : rec.V)
    {
      const double d = Dot(w.M, v - w.P);
      above = above || d >= -tol;
      below = below || d <= tol;
    }
    if (!above || !below)
    {
      return false;
    }
    thread_local std::vector<std::pair<Vec3, Vec3>> receiverChords;
    thread_local std::vector<Interval> reach, restricted;
    PlaneChords(rec, w.M, w.P, tol, receiverChords);
    reach.clear();
    for (const auto& chord : receiverChords)
    {
      const Vec3 along = chord.second - chord.first;
      const double chordLength = Length(along);
      const Vec3 pad = chordLength > 0.0 ? (ctx.Margin / chordLength) * along : Vec3();
      for (int side = 0; side < 2; ++side)
      {
        // EV lines reach R beyond the generator, VE lines behind the apex;
        // occluder EV lines may do either.
        if ((w.Kind == WedgeKind::EV && side == 1) || (w.Kind == WedgeKind::VE && side == 0))
        {
          continue;
        }
        const HalfSpace hs = side == 0 ? HalfSpace{ wn, Dot(wn, w.P) + tol }
                                       : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
        Vec3 c0 = chord.first - pad, c1 = chord.second + pad;
        if (!ClipChord(c0, c1, &hs, 1))
        {
          continue;
        }
        const double t0 = (Dot(c0 - w.P, u) * h / Dot(c0 - w.P, wn) - g0) / len;
        const double t1 = (Dot(c1 - w.P, u) * h / Dot(c1 - w.P, wn) - g0) / len;
        reach.push_back({ std::min(t0, t1), std::max(t0, t1) });
      }
    }
    // No chord although R meets the plane within tolerance (R nearly in the
    // wedge plane, or touching it): no restriction.
    if (ctx.Cull && !receiverChords.empty())
    {
      Normalize(reach);
      Intersect(valid, reach, restricted);
      valid.swap(restricted);
      if (valid.empty())
      {
        return false;
      }
    }
  }

  // Blocker candidates: the polygons crossing the wedge plane inside the box
  // of the wedge's region (the hull of the apex, the generator ends and the
  // receiver and shooter points of the valid intervals), found in the BVH.
  {
    Vec3 lo = w.P, hi = w.P;
    thread_local std::vector<Vec3> region3;
    region3.clear();
    region3.push_back(w.P);
    auto grow = [&](const Vec3& p) {
      lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
      hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
      region3.push_back(p);
    };
    for (const Interval& iv : valid)
    {
      for (double t : { iv.Lo, iv.Hi })
      {
        const Vec3 g = w.G0 + t * gd;
        grow(g);
        const double fR = Dot(rec.N, g) - rec.D;
        grow(w.P + (hR / (hR - fR)) * (g - w.P));
        if (w.Kind == WedgeKind::OO)
        {
          const double fS = Dot(sh.N, g) - sh.D;
          grow(w.P + (hS / (hS - fS)) * (g - w.P));
        }
      }
    }
    CullingVolume volume;
    volume.BoxMin = lo - Vec3(tol, tol, tol);
    volume.BoxMax = hi + Vec3(tol, tol, tol);
    volume.Planes.push_back({ w.M, Dot(w.M, w.P) - tol });
    volume.Planes.push_back({ -w.M, -Dot(w.M, w.P) - tol });
    // Within the wedge plane the region is the convex hull of those points
    // (a long thin triangle for a wedge from a light to a far shadow line):
    // its edges, as planes perpendicular to the wedge, keep away the many
    // polygons that cross the plane inside the box but far from the region.
    thread_local std::vector<std::array<double, 2>> flat, hull;
    flat.clear();
    for (const Vec3& p : region3)
    {
      flat.push_back({ Dot(p - w.P, u), Dot(p - w.P, wn) });
    }
    std::sort(flat.begin(), flat.end());
    hull.assign(2 * flat.size() + 1, { 0.0, 0.0 });
    std::size_t k = 0;
    auto turn = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                  const std::array<double, 2>& b) {
      return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    };
    for (std::size_t i = 0; i < flat.size(); ++i)
    {
      while (k >= 2 && turn(hull[k - 2], hull[k - 1], flat[i]) <= 0.0)
      {
        --k;
      }
      hull[k++] = flat[i];
    }
    for (std::size_t i = flat.size() - 1, t = k + 1; i-- > 0;)
    {
      while (k >= t && turn(hull[k - 2], hull[k - 1], flat[i]) <= 0.0)
      {
        --k;
      }
      hull[k++] = flat[i];
    }
    for (std::size_t i = 0; k >= 4 && i + 1 < k; ++i)
    {
      // Counter-clockwise hull: the inward normal of edge (a, b) is left of it.
      const double ex = hull[i + 1][0] - hull[i][0], ey = hull[i + 1][1] - hull[i][1];
      const double el = std::hypot(ex, ey);
      if (!(el > 0.0))
      {
        continue;
      }
      const Vec3 inward = (-ey / el) * u + (ex / el) * wn;
      const Vec3 at = w.P + hull[i][0] * u + hull[i][1] * wn;
      volume.Planes.push_back({ inward, Dot(inward, at) - tol });
    }
    // Blockers lie on event lines, inside the shaft: among few shaft
    // candidates a scan is cheaper than a BVH traversal.
    ctx.Scratch->clear();
    if (ctx.Cull && ctx.Candidates->size() <= kScanLimit)
    {
      ctx.Occluders->FilterCandidates(volume, ctx.Candidates->data(),
        static_cast<int>(ctx.Candidates->size()), ctx.ShooterId, ctx.ReceiverId, *ctx.Scratch);
    }
    else
    {
      ctx.Occluders->VolumeCandidates(volume, ctx.ShooterId, ctx.ReceiverId, *ctx.Scratch);
    }
  }

  // Blockers: each candidate's chords in the wedge plane, clipped to the part
  // of the lines between the receiver and the source point, projected to t.
  HalfSpace region[3];
  int regionCount = 0;
  region[regionCount++] = { rec.N, rec.D + tol }; // in front of the receiver
  if (w.Kind == WedgeKind::VE)
  {
    region[regionCount++] = { -wn, -Dot(wn, w.P) - h + tol }; // before the shooter edge
  }
  else if (w.Kind == WedgeKind::OO)
  {
    region[regionCount++] = { sh.N, sh.D + tol }; // in front of the shooter
  }
  std::vector<Interval> blocked;
  std::vector<std::pair<Vec3, Vec3>> chords;
  const std::vector<PolygonData>& polys = *ctx.Polygons;
  for (int k : *ctx.Scratch)
  {
    if (std::binary_search(w.Exclude.begin(), w.Exclude.end(), k))
    {
      continue;
    }
    PlaneChords(polys[k], w.M, w.P, tol, chords);
    for (const auto& chord : chords)
    {
      for (int side = 0; side < 2; ++side)
      {
        // EV lines only run on the generator's side of the apex.
        if (w.Kind == WedgeKind::EV && side == 1)
        {
          continue;
        }
        HalfSpace hs[4];
        std::copy(region, region + regionCount, hs);
        hs[regionCount] = side == 0 ? HalfSpace{ wn, Dot(wn, w.P) + tol }
                                    : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
        Vec3 c0 = chord.first, c1 = chord.second;
        if (!ClipChord(c0, c1, hs, regionCount + 1))
        {
          continue;
        }
        const double t0 = (Dot(c0 - w.P, u) * h / Dot(c0 - w.P, wn) - g0) / len;
        const double t1 = (Dot(c1 - w.P, u) * h / Dot(c1 - w.P, wn) - g0) / len;
        const double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(1.0, std::max(t0, t1));
        if (hi > lo)
        {
          blocked.push_back({ lo, hi });
        }
      }
    }
  }
  Normalize(blocked);
  std::vector<Interval> visible;
  Subtract(valid, blocked, visible);
  for (const Interval& iv : visible)
  {
    auto receiverPoint = [&](double t) {
      const Vec3 g = w.G0 + t * gd;
      const double fR = Dot(rec.N, g) - rec.D;
      const double mu = hR / (hR - fR);
      return w.P + mu * (g - w.P);
    };
    out.push_back({ receiverPoint(iv.Lo), receiverPoint(iv.Hi) });
  }
  return true;
}

} // namespace

double DiscontinuityMesher::Internal::JumpRadiance(
  const DiscontinuityMeshSettings& settings, int shooter) const
{
  if (!settings.ShooterRadiance.empty())
  {
    for (std::size_t k = 0; k < settings.Shooters.size(); ++k)
    {
      if (settings.Shooters[k] == shooter)
      {
        return settings.ShooterRadiance[k].Mean();
      }
    }
  }
  return this->SceneCopy.Surfaces[shooter].Emission.Mean();
}

void DiscontinuityMesher::Internal::AddShadows(int receiverId, int shooterId,
  const DiscontinuityMeshSettings& settings, double minimumJump, const Frame& frame,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats) const
{
  std::vector<int> candidates;
  CullingVolume shaft;
  if (!this->Occluders.ShaftCandidates(shooterId, receiverId, candidates, &shaft))
  {
    return;
  }
  ++stats.Pairs;
  stats.CandidateOccluders += candidates.size();
  const PolygonData& rec = this->Polygons[receiverId];
  const PolygonData& sh = this->Polygons[shooterId];
  const double tol = kLinear * this->Size;
  const double contactTol = std::max(settings.ContactTolerance * this->Size, tol);
  const double snap = kSnap * this->Size;
  const double minPiece = kMinPiece * this->Size;

  PairContext ctx;
  ctx.Polygons = &this->Polygons;
  ctx.Shooter = &sh;
  ctx.Receiver = &rec;
  ctx.Occluders = &this->Occluders;
  ctx.ShooterId = shooterId;
  ctx.ReceiverId = receiverId;
  std::vector<int> scratch;
  ctx.Scratch = &scratch;
  ctx.Candidates = &candidates;
  ctx.Cull = settings.CullWedges;
  ctx.Tol = tol;
  ctx.Margin = kChordMargin * this->Size;
  ctx.ReceiverCentre = rec.Centroid;
  for (const Vec3& v : rec.V)
  {
    ctx.ReceiverRadius = std::max(ctx.ReceiverRadius, Length(v - rec.Centroid));
  }

  auto distR = [&](const Vec3& p) { return Dot(rec.N, p) - rec.D; };
  auto distS = [&](const Vec3& p) { return Dot(sh.N, p) - sh.D; };

  // Features of the candidates: distinct edges and vertex clusters.
  std::vector<int> edges, vertices;
  for (int k : candidates)
  {
    const PolygonData& p = this->Polygons[k];
    for (std::size_t i = 0; i < p.V.size(); ++i)
    {
      edges.push_back(p.Edge[i]);
      vertices.push_back(p.Cluster[i]);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  // Keep only features usable as occluders of this pair: not lying in the
  // receiver's plane (contacts), partly in front of the shooter and receiver,
  // and meeting the shaft. Every event line runs from a receiving point to a
  // shooter point through its features, so a feature entirely outside the
  // convex hull of shooter and receiver (the shaft) is on no event line,
  // although its polygon may cross the shaft.
  auto outsideShaft = [&](const Vec3* points, int count) {
    if (!settings.CullWedges)
    {
      return false;
    }
    for (const Plane& plane : shaft.Planes)
    {
      bool outside = true;
      for (int k = 0; k < count && outside; ++k)
      {
        outside = Dot(plane.Normal, points[k]) < plane.Offset - tol;
      }
      if (outside)
      {
        return true;
      }
    }
    return false;
  };
  auto edgeEnds = [&](int e, Vec3& a, Vec3& b) {
    a = this->ClusterPoint[this->EdgeClusters[e][0]];
    b = this->ClusterPoint[this->EdgeClusters[e][1]];
  };
  std::vector<int> usableEdges;
  for (int e : edges)
  {
    Vec3 a, b;
    edgeEnds(e, a, b);
    if (std::abs(distR(a)) <= contactTol && std::abs(distR(b)) <= contactTol)
    {
      continue;
    }
    if ((distS(a) <= tol && distS(b) <= tol) || (distR(a) <= tol && distR(b) <= tol))
    {
      continue;
    }
    const Vec3 ends[2] = { a, b };
    if (outsideShaft(ends, 2))
    {
      continue;
    }
    usableEdges.push_back(e);
  }
  std::vector<int> usableVertices;
  for (int c : vertices)
  {
    const Vec3& p = this->ClusterPoint[c];
    if (distR(p) > contactTol && distS(p) > tol && !outsideShaft(&p, 1))
    {
      usableVertices.push_back(c);
    }
  }

  // Side of a shared edge / vertex with respect to a plane (2 = not on the
  // silhouette), and whether one of the polygons' edges at the feature lies
  // in the plane (coplanar edges: order 1).
  auto edgeFeatureSide = [&](int e, const Vec3& m) {
    int side = 0;
    for (const Use& use : this->EdgeUses[e])
    {
      side = CombineSides(side, EdgeSide(this->Polygons[use.Polygon], use.Index, m));
    }
    return side;
  };
  auto vertexFeatureSide = [&](int c, const Vec3& m, bool allowStraddle) {
    int side = 0;
    const auto& uses = this->ClusterUses[c];
    for (const Use& use : uses)
    {
      side = CombineSides(side, CornerSide(this->Polygons[use.Polygon], use.Index, m));
    }
    // Interior events: a corner straddling the plane is still an event where
    // the line through it only grazes the solid; lines that pierce a solid
    // leave it through another face, which blocks them (faces sharing the
    // vertex are never hit again by a line through it).
    return side == 2 && allowStraddle ? 1 : side;
  };
  auto vertexHasEdgeInPlane = [&](int c, const Vec3& m) {
    for (const Use& use : this->ClusterUses[c])
    {
      const PolygonData& p = this->Polygons[use.Polygon];
      const std::size_t n = p.V.size();
      const Vec3 v = p.V[use.Index];
      if (std::abs(Dot(m, Normalized(p.V[(use.Index + 1) % n] - v))) <= kAngle ||
        std::abs(Dot(m, Normalized(p.V[(use.Index + n - 1) % n] - v))) <= kAngle)
      {
        return true;
      }
    }
    return false;
  };
  auto excludeEdge = [&](int e, std::vector<int>& ex) {
    for (const Use& use : this->EdgeUses[e])
    {
      ex.push_back(use.Polygon);
    }
  };
  auto excludeVertex = [&](int c, std::vector<int>& ex) {
    for (const Use& use : this->ClusterUses[c])
    {
      ex.push_back(use.Polygon);
    }
  };
  auto finishExclude = [](std::vector<int>& ex) {
    std::sort(ex.begin(), ex.end());
    ex.erase(std::unique(ex.begin(), ex.end()), ex.end());
  };

  std::vector<std::pair<Vec3, Vec3>> traced;
  std::vector<Interval> pieces;
  // With a jump threshold, a wedge is not traced when even an upper bound of
  // the jump its pieces would get is below the minimum: the jump at a point
  // x of R is Ls min(F_occluders(x), F_S(x)) (see Boundaries), and a form
  // factor F(x) of a polygon of area A is at most A / (pi d^2), d the
  // distance between R and the polygon (bounded below by their centres'
  // distance minus their radii), and at most 1.
  const double shooterRadiance = this->JumpRadiance(settings, shooterId);
  auto formFactorBound = [&](int polygon) {
    const PolygonData& p = this->Polygons[polygon];
    double radius = 0.0;
    for (const Vec3& v : p.V)
    {
      radius = std::max(radius, Length(v - p.Centroid));
    }
    const double d = Length(p.Centroid - rec.Centroid) - radius - ctx.ReceiverRadius;
    return d > 0.0 ? std::min(1.0, p.Area / (M_PI * d * d)) : 1.0;
  };
  auto faint = [&](int occluderA, int occluderB) {
    if (!(minimumJump >= 0.0 && settings.CullWedges))
    {
      return false;
    }
    double bound = formFactorBound(shooterId);
    for (int k : { occluderA, occluderB })
    {
      if (k >= 0)
      {
        bound = std::min(bound, formFactorBound(k));
      }
    }
    // The margin keeps rounding from dropping a wedge at the threshold.
    return shooterRadiance * bound * (1.0 + 1e-9) < minimumJump;
  };
  auto emit = [&](const Wedge& w, int order, int occluderA, int occluderB) {
    if (faint(occluderA, occluderB))
    {
      return;
    }
    if (TraceWedge(ctx, w, traced))
    {
      ++stats.Wedges;
    }
    for (const auto& seg : traced)
    {
      const P2 a = frame.To2D(seg.first), b = frame.To2D(seg.second);
      ClipSegmentToPolygon2(a, b, frame.Outline, snap, pieces);
      for (const Interval& iv : pieces)
      {
        Segment2 s;
        s.A = { a[0] + iv.Lo * (b[0] - a[0]), a[1] + iv.Lo * (b[1] - a[1]) };
        s.B = { a[0] + iv.Hi * (b[0] - a[0]), a[1] + iv.Hi * (b[1] - a[1]) };
        if (iv.Lo == 0.0)
        {
          s.A = a;
        }
        if (iv.Hi == 1.0)
        {
          s.B = b;
        }
        if (std::hypot(s.B[0] - s.A[0], s.B[1] - s.A[1]) < minPiece)
        {
          continue;
        }
        s.Order = order;
        s.SourceId = shooterId;
        s.OccluderA = occluderA;
        s.OccluderB = occluderB;
        out.push_back(s);
        ++stats.SegmentsGenerated;
      }
    }
  };

  const std::size_t ns = sh.V.size();
  // EV: shooter vertex x occluder edge.
  for (std::size_t i = 0; i < ns; ++i)
  {
    const Vec3 v = sh.V[i];
    if (distR(v) <= tol)
    {
      continue;
    }
    for (int e : usableEdges)
    {
      Wedge w;
      w.Kind = WedgeKind::EV;
      w.P = v;
      edgeEnds(e, w.G0, w.G1);
      const Vec3 m = Cross(w.G1 - w.G0, v - w.G0);
      if (!(Length(m) > kAngle * Length(w.G1 - w.G0) * Length(v - w.G0)))
      {
        continue;
      }
      w.M = Normalized(m);
      const int occSide = edgeFeatureSide(e, w.M);
      if (occSide == 0 || occSide == 2)
      {
        continue; // not on the silhouette, or seen edge-on
      }
      const int shSide = CornerSide(sh, static_cast<int>(i), w.M);
      if (shSide == 2 && !settings.InteriorEvents)
      {
        continue;
      }
      const Vec3 dNext = Normalized(sh.V[(i + 1) % ns] - v);
      const Vec3 dPrev = Normalized(sh.V[(i + ns - 1) % ns] - v);
      const bool coplanar =
        std::abs(Dot(w.M, dNext)) <= kAngle || std::abs(Dot(w.M, dPrev)) <= kAngle;
      excludeEdge(e, w.Exclude);
      finishExclude(w.Exclude);
      emit(w, coplanar ? 1 : 2, this->EdgeUses[e][0].Polygon, -1);
    }
  }
  // VE: shooter edge x occluder vertex.
  for (std::size_t i = 0; i < ns; ++i)
  {
    const Vec3 p = sh.V[i], q = sh.V[(i + 1) % ns];
    for (int c : usableVertices)
    {
      Wedge w;
      w.Kind = WedgeKind::VE;
      w.P = this->ClusterPoint[c];
      w.G0 = p;
      w.G1 = q;
      const Vec3 m = Cross(q - p, w.P - p);
      if (!(Length(m) > kAngle * Length(q - p) * Length(w.P - p)))
      {
        continue;
      }
      w.M = Normalized(m);
      const int occSide = vertexFeatureSide(c, w.M, settings.InteriorEvents);
      if (occSide == 0 || occSide == 2)
      {
        continue;
      }
      excludeVertex(c, w.Exclude);
      finishExclude(w.Exclude);
      emit(w, vertexHasEdgeInPlane(c, w.M) ? 1 : 2, this->ClusterUses[c][0].Polygon, -1);
    }
  }
  // Occluder EV: vertex of one occluder x edge of another, wedge cutting the shooter.
  if (settings.OccluderOccluderEvents)
  {
    // Generators for an apex w lie on lines through w that hit both the
    // shooter and the receiver (their convex hulls): between w and the
    // shooter on lines continuing from w to the receiver (case A of
    // TraceWedge), or between w and the receiver on lines continuing from w
    // to the shooter (case B). Each case is the intersection of the cone from
    // w to one polygon with the reflected cone of the other, found in the BVH
    // with one query per case. Bounding by the receiver's cone too keeps the
    // cost per small receiver independent of how many polygons the shooter's
    // cone crosses.
    const PreparedPolygon& shp = this->Occluders.GetPolygon(shooterId);
    const PreparedPolygon& recp = this->Occluders.GetPolygon(receiverId);
    const Vec3* shHull = this->Occluders.GetHullVertices().data() + shp.FirstHullPoint;
    const Vec3* recHull = this->Occluders.GetHullVertices().data() + recp.FirstHullPoint;
    auto addCone = [&](const Vec3* hull, int count, const Vec3& centre, const Vec3& apex,
                     bool reflected, CullingVolume& cone) {
      for (int i = 0; i < count; ++i)
      {
        const Vec3 a = hull[i], b = hull[(i + 1) % count];
        Vec3 n = Normalized(Cross(b - a, apex - a));
        if ((Dot(n, centre - apex) < 0.0) != reflected)
        {
          n = -n;
        }
        cone.Planes.push_back({ n, Dot(n, apex) - tol });
      }
    };
    std::vector<int> found, generators;
    for (int c : usableVertices)
    {
      const Vec3 apex = this->ClusterPoint[c];
      generators.clear();
      for (int nappe = 0; nappe < 2; ++nappe)
      {
        // nappe 0: between the apex and the shooter; 1: between the apex and the receiver.
        CullingVolume cone;
        const PreparedPolygon& towards = nappe == 0 ? shp : recp;
        cone.BoxMin = Vec3(std::min(towards.BoundsMin.X, apex.X), std::min(towards.BoundsMin.Y, apex.Y),
                        std::min(towards.BoundsMin.Z, apex.Z)) - Vec3(tol, tol, tol);
        cone.BoxMax = Vec3(std::max(towards.BoundsMax.X, apex.X), std::max(towards.BoundsMax.Y, apex.Y),
                        std::max(towards.BoundsMax.Z, apex.Z)) + Vec3(tol, tol, tol);
        addCone(shHull, shp.NumberOfHullPoints, shp.Centroid, apex, nappe == 1, cone);
        if (settings.CullWedges)
        {
          addCone(recHull, recp.NumberOfHullPoints, recp.Centroid, apex, nappe == 0, cone);
        }
        cone.Planes.push_back(nappe == 0 ? Plane{ sh.N, sh.D - tol } : Plane{ rec.N, rec.D - tol });
        // Generators lie on event lines, inside the shaft: among few shaft
        // candidates a scan is cheaper than a BVH traversal.
        found.clear();
        if (settings.CullWedges && candidates.size() <= kScanLimit)
        {
          this->Occluders.FilterCandidates(cone, candidates.data(),
            static_cast<int>(candidates.size()), shooterId, receiverId, found);
        }
        else
        {
          this->Occluders.VolumeCandidates(cone, shooterId, receiverId, found);
        }
        for (int k : found)
        {
          for (int e : this->Polygons[k].Edge)
          {
            generators.push_back(e);
          }
        }
      }
      std::sort(generators.begin(), generators.end());
      generators.erase(std::unique(generators.begin(), generators.end()), generators.end());
      for (int e : generators)
      {
        if (!std::binary_search(usableEdges.begin(), usableEdges.end(), e) ||
          this->EdgeClusters[e][0] == c || this->EdgeClusters[e][1] == c)
        {
          continue;
        }
        Wedge w;
        w.Kind = WedgeKind::OO;
        w.P = apex;
        edgeEnds(e, w.G0, w.G1);
        const Vec3 m = Cross(w.G1 - w.G0, apex - w.G0);
        if (!(Length(m) > kAngle * Length(w.G1 - w.G0) * Length(apex - w.G0)))
        {
          continue;
        }
        w.M = Normalized(m);
        bool pos = false, neg = false;
        for (const Vec3& s : sh.V)
        {
          const double d = Dot(w.M, s - apex);
          pos = pos || d > tol;
          neg = neg || d < -tol;
        }
        if (!pos || !neg)
        {
          continue; // the wedge plane misses the shooter
        }
        const int sideE = edgeFeatureSide(e, w.M);
        if (sideE == 0 || sideE == 2)
        {
          continue;
        }
        const int sideV = vertexFeatureSide(c, w.M, false);
        if (sideV == 0 || sideV == 2)
        {
          continue;
        }
        excludeEdge(e, w.Exclude);
        excludeVertex(c, w.Exclude);
        finishExclude(w.Exclude);
        emit(w, vertexHasEdgeInPlane(c, w.M) ? 1 : 2, this->ClusterUses[c][0].Polygon,
          this->EdgeUses[e][0].Polygon);
      }
    }
  }
  if (!settings.PlaneEvents)
  {
    return;
  }
  // The shooter's own plane crossing the receiver: the form factor grows
  // linearly from 0 on its front side (the shooter is seen edge-on), a D1 line.
  {
    bool pos = false, neg = false;
    double reach = 0.0;
    for (const Vec3& v : rec.V)
    {
      const double d = distS(v);
      pos = pos || d > tol;
      neg = neg || d < -tol;
    }
    const double a = Dot(sh.N, frame.U), b = Dot(sh.N, frame.V);
    const double c = sh.D - Dot(sh.N, frame.Origin);
    const double norm = std::hypot(a, b);
    if (pos && neg && norm > kAngle)
    {
      const P2 foot = { a * c / (norm * norm), b * c / (norm * norm) };
      const P2 dir = { -b / norm, a / norm };
      for (const P2& q : frame.Outline)
      {
        reach = std::max(reach, std::hypot(q[0] - foot[0], q[1] - foot[1]));
      }
      const P2 p0 = { foot[0] - 2.0 * reach * dir[0], foot[1] - 2.0 * reach * dir[1] };
      const P2 p1 = { foot[0] + 2.0 * reach * dir[0], foot[1] + 2.0 * reach * dir[1] };
      ClipSegmentToPolygon2(p0, p1, frame.Outline, snap, pieces);
      for (const Interval& iv : pieces)
      {
        Segment2 seg;
        seg.A = { p0[0] + iv.Lo * (p1[0] - p0[0]), p0[1] + iv.Lo * (p1[1] - p0[1]) };
        seg.B = { p0[0] + iv.Hi * (p1[0] - p0[0]), p0[1] + iv.Hi * (p1[1] - p0[1]) };
        if (std::hypot(seg.B[0] - seg.A[0], seg.B[1] - seg.A[1]) < minPiece)
        {
          continue;
        }
        seg.Order = 1;
        seg.SourceId = shooterId;
        out.push_back(seg);
        ++stats.SegmentsGenerated;
      }
    }
  }
  // Face planes: from a receiving point in the plane of an occluder polygon F
  // whose plane cuts the shooter, F is seen edge-on; on either side a strip
  // of F's image, growing linearly, covers part of the shooter (the two
  // chains of F's outline recede at different rates): a D1 line (a
  // degenerate EEE event of F's coplanar edges). Its extent on the receiver
  // is where F's image overlaps the shooter's chord in that plane, bounded
  // by lines through a vertex of F and the chord (VE-like pencils) or
  // through a chord end and an edge of F (EV-like pencils).
  std::vector<std::pair<Vec3, Vec3>> shooterChords;
  for (int k : candidates)
  {
    const PolygonData& f = this->Polygons[k];
    if (!(Length(Cross(f.N, rec.N)) > kAngle))
    {
      continue;
    }
    bool pos = false, neg = false;
    for (const Vec3& v : sh.V)
    {
      const double d = Dot(f.N, v) - f.D;
      pos = pos || d > tol;
      neg = neg || d < -tol;
    }
    if (!pos || !neg)
    {
      continue;
    }
    PlaneChords(sh, f.N, f.V[0], tol, shooterChords);
    std::vector<int> exclude = { k };
    for (int c : f.Cluster)
    {
      excludeVertex(c, exclude);
    }
    finishExclude(exclude);
    const std::size_t nf = f.V.size();
    for (const auto& chord : shooterChords)
    {
      for (std::size_t i = 0; i < nf; ++i)
      {
        const Vec3& v = f.V[i];
        if (distR(v) > contactTol && distS(v) > tol)
        {
          Wedge w;
          w.Kind = WedgeKind::VE;
          w.P = v;
          w.G0 = chord.first;
          w.G1 = chord.second;
          w.M = f.N;
          w.Exclude = exclude;
          emit(w, 1, k, -1);
        }
        const Vec3& a = f.V[i];
        const Vec3& b = f.V[(i + 1) % nf];
        if ((std::abs(distR(a)) <= contactTol && std::abs(distR(b)) <= contactTol) ||
          (distS(a) <= tol && distS(b) <= tol))
        {
          continue;
        }
        for (const Vec3& end : { chord.first, chord.second })
        {
          if (distR(end) <= tol)
          {
            continue;
          }
          Wedge w;
          w.Kind = WedgeKind::EV;
          w.P = end;
          w.G0 = a;
          w.G1 = b;
          w.M = f.N;
          w.Exclude = exclude;
          emit(w, 1, k, -1);
        }
      }
    }
  }
}

std::vector<Segment2> DiscontinuityMesher::Internal::Boundaries(int receiverId,
  const DiscontinuityMeshSettings& settings, const Frame& frame,
  DiscontinuityMeshStatistics& stats) const
{
  std::vector<Segment2> segments;
  // The outline first (order -1).
  const std::size_t n = frame.Outline.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    Segment2 s;
    s.A = frame.Outline[i];
    s.B = frame.Outline[(i + 1) % n];
    s.Order = -1;
    s.Outline = true;
    segments.push_back(s);
  }
  if (settings.Contacts)
  {
    this->AddContacts(receiverId, settings, frame, segments, stats);
  }
  const std::vector<int> shooters = this->Select(settings);
  const std::size_t firstShadow = segments.size();
  const PolygonData& rec = this->Polygons[receiverId];
  auto formFactor = [&](const Vec3& x, int polygon, bool twoSided) {
    const std::vector<Vec3>& v = this->Polygons[polygon].V;
    double f = PointPolygonFormFactorClipped(x, rec.N, v);
    if (twoSided)
    {
      std::vector<Vec3> reversed(v.rbegin(), v.rend());
      f = std::max(f, PointPolygonFormFactorClipped(x, rec.N, reversed));
    }
    return f;
  };
  // The jump threshold's reference: the largest unoccluded direct radiance
  // over the receiver (sum over shooters). Shadows whose jump cannot reach
  // JumpThreshold times it are not even traced (see AddShadows).
  double minimumJump = -1.0;
  if (settings.JumpThreshold > 0.0)
  {
    std::vector<Vec3> samples = { rec.Centroid };
    for (const Vec3& v : rec.V)
    {
      samples.push_back(v + 0.05 * (rec.Centroid - v));
    }
    double reference = 0.0;
    for (const Vec3& x : samples)
    {
      double sum = 0.0;
      for (int s : shooters)
      {
        if (s != receiverId)
        {
          sum += this->JumpRadiance(settings, s) * formFactor(x, s, false);
        }
      }
      reference = std::max(reference, sum);
    }
    minimumJump = reference > 0.0 ? settings.JumpThreshold * reference
                                  : std::numeric_limits<double>::infinity();
  }
  for (int s : shooters)
  {
    if (s != receiverId)
    {
      this->AddShadows(receiverId, s, settings, minimumJump, frame, segments, stats);
    }
  }
  if (minimumJump >= 0.0 && segments.size() > firstShadow)
  {
    std::size_t write = firstShadow;
    for (std::size_t k = firstShadow; k < segments.size(); ++k)
    {
      const Segment2& s = segments[k];
      bool keep = true;
      if (s.SourceId >= 0 && s.Order > 0)
      {
        const Vec3 mid = frame.To3D({ 0.5 * (s.A[0] + s.B[0]), 0.5 * (s.A[1] + s.B[1]) });
        const double fs = formFactor(mid, s.SourceId, false);
        double fo = s.OccluderA >= 0 ? formFactor(mid, s.OccluderA, true) : fs;
        if (s.OccluderB >= 0)
        {
          fo = std::min(fo, formFactor(mid, s.OccluderB, true));
        }
        const double jump = this->JumpRadiance(settings, s.SourceId) * std::min(fo, fs);
        keep = jump >= minimumJump;
      }
      if (keep)
      {
        segments[write++] = s;
      }
    }
    segments.resize(write);
  }
  for (std::size_t k = firstShadow; k < segments.size(); ++k)
  {
    if (segments[k].SourceId >= 0)
    {
      ++stats.SegmentsKept;
    }
  }
  return segments;
}

std::vector<detail::Constraint2D> DiscontinuityMesher::Internal::Constraints(int receiverId,
  const DiscontinuityMeshSettings& settings, const Frame& frame,
  DiscontinuityMeshStatistics& stats) const
{
  std::vector<Segment2> segments = this->Boundaries(receiverId, settings, frame, stats);
  std::vector<detail::Constraint2D> constraints =
    MergeSegments(std::move(segments), kSnap * this->Size, kMinPiece * this->Size);
  stats.Constraints += constraints.size();
  return constraints;
}

//------------------------------------------------------------------------------
DiscontinuityMesher::DiscontinuityMesher(const Scene& scene)
  : Impl(new Internal(scene))
{
}

DiscontinuityMesher::~DiscontinuityMesher() = default;
DiscontinuityMesher::DiscontinuityMesher(DiscontinuityMesher&&) noexcept = default;
DiscontinuityMesher& DiscontinuityMesher::operator=(DiscontinuityMesher&&) noexcept = default;

int DiscontinuityMesher::GetNumberOfSurfaces() const
{
  return static_cast<int>(this->Impl->Polygons.size());
}

std::vector<int> DiscontinuityMesher::SelectShooters(
  const DiscontinuityMeshSettings& settings) const
{
  return this->Impl->Select(settings);
}

std::vector<DiscontinuitySegment> DiscontinuityMesher::ComputeBoundaries(int receiverId,
  const DiscontinuityMeshSettings& settings, DiscontinuityMeshStatistics* statistics) const
{
  const auto start = std::chrono::steady_clock::now();
  this->Impl->Check(receiverId, settings);
  DiscontinuityMeshStatistics stats;
  stats.Receivers = 1;
  const Internal::Frame frame = this->Impl->MakeFrame(receiverId);
  const std::vector<detail::Constraint2D> constraints =
    this->Impl->Constraints(receiverId, settings, frame, stats);
  std::vector<DiscontinuitySegment> out;
  out.reserve(constraints.size());
  for (const detail::Constraint2D& c : constraints)
  {
    DiscontinuitySegment s;
    s.A = frame.To3D({ c.A[0], c.A[1] });
    s.B = frame.To3D({ c.B[0], c.B[1] });
    s.Order = c.Order;
    s.SourceId = c.SourceId;
    s.ReceiverId = receiverId;
    out.push_back(s);
  }
  stats.BoundarySeconds = Seconds(start);
  if (statistics)
  {
    *statistics += stats;
  }
  return out;
}

ReceiverMesh DiscontinuityMesher::MeshReceiver(int receiverId,
  const DiscontinuityMeshSettings& settings, DiscontinuityMeshStatistics* statistics) const
{
  const auto start = std::chrono::steady_clock::now();
  this->Impl->Check(receiverId, settings);
  DiscontinuityMeshStatistics stats;
  stats.Receivers = 1;
  const Internal::Frame frame = this->Impl->MakeFrame(receiverId);
  detail::TriangulationInput input;
  input.ReceiverId = receiverId;
  input.Constraints = this->Impl->Constraints(receiverId, settings, frame, stats);
  input.Origin = frame.Origin;
  input.AxisU = frame.U;
  input.AxisV = frame.V;
  input.MinimumAngle = settings.MinimumAngle;
  const PolygonData& rec = this->Impl->Polygons[receiverId];
  for (std::size_t i = 0; i < rec.V.size(); ++i)
  {
    input.Known2D.push_back(frame.Outline[i]);
    input.Known3D.push_back(rec.V[i]);
  }
  stats.BoundarySeconds = Seconds(start);
  const auto triangulationStart = std::chrono::steady_clock::now();
  detail::TriangulationOutput result = detail::TriangulateReceiver(input);
  stats.TriangulationSeconds = Seconds(triangulationStart);
  stats.ConstraintFailures += result.Failures;
  stats.DroppedDegenerate += result.DroppedDegenerate;
  stats.RemovedArea += result.RemovedArea;
  stats.Points += result.Mesh.Points.size();
  stats.Triangles += result.Mesh.Triangles.size();
  if (statistics)
  {
    *statistics += stats;
  }
  return std::move(result.Mesh);
}

} // namespace penumbra
