// SPDX-License-Identifier: GPL-3.0-or-later
// Snapping, collinear grouping and splitting of a receiver's boundary segments.
#include "penumbraConstraintMerging.h"

#include "penumbraMath.h"
#include "penumbraUnionFind.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace penumbra
{
namespace detail
{

namespace
{

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

struct Breakpoint
{
  double S;
  int Rep;
};

/// The state of one MergeSegments call, step by step.
class ConstraintMerger
{
public:
  ConstraintMerger(std::vector<Segment2> segments, double tol, double minLength)
    : Segments(std::move(segments))
    , Tol(tol)
    , MinLength(minLength)
  {
  }

  std::vector<Constraint2D> Run()
  {
    this->SnapEndPoints();
    this->IndexEndPoints();
    this->GroupCollinear();
    std::vector<Constraint2D> out;
    for (int root : this->GroupRoots)
    {
      this->SplitLine(this->Groups[root], out);
    }
    return out;
  }

private:
  /// Step 1: end points closer than Tol become their cluster's best point;
  /// degenerate and (non-outline, non-footprint) too short segments go.
  void SnapEndPoints();
  /// The distinct end points, their best priority and a grid of them.
  void IndexEndPoints();
  /// Step 2: groups of collinear segments (GroupRoots in output order).
  void GroupCollinear();
  /// End points of any segment near the members of one line (NearReps).
  void FindNearEndPoints(const std::vector<int>& members);
  /// The constraints of one line: its pieces between breakpoints.
  void SplitLine(const std::vector<int>& members, std::vector<Constraint2D>& out);

  std::array<long long, 2> CellOf(double x, double y) const
  {
    const long long i = std::max(0LL,
      std::min(this->GridX - 1, static_cast<long long>((x - this->MinX) / this->RepCell)));
    const long long j = std::max(0LL,
      std::min(this->GridY - 1, static_cast<long long>((y - this->MinY) / this->RepCell)));
    return std::array<long long, 2>{ i, j };
  }

  std::vector<Segment2> Segments;
  const double Tol;
  const double MinLength;
  std::vector<P2> Points;                   ///< end points, two per input segment
  std::vector<std::array<int, 2>> KeptRep;  ///< snapped end points of each kept segment
  std::vector<int> UniqueReps;              ///< distinct snapped end points
  std::unordered_map<int, int> PriorityOfRep;
  std::vector<double> Length;
  std::unordered_map<int, std::vector<int>> Groups;
  std::vector<int> GroupRoots;
  // Dense grid of the distinct end points (about one per cell), stored as
  // cell starts + items, for the T-junction search.
  double MinX = 0.0, MinY = 0.0, RepCell = 0.0;
  long long GridX = 1, GridY = 1;
  std::vector<int> CellStart, CellItems;
  std::vector<int> NearReps;
  std::vector<Breakpoint> Breaks;
};

void ConstraintMerger::SnapEndPoints()
{
  std::vector<Segment2>& segments = this->Segments;
  const double tol = this->Tol, minLength = this->MinLength;
  // 1. End point clustering on a grid of cell size tol.
  const std::size_t n = segments.size();
  std::vector<P2>& points = this->Points;
  points.resize(2 * n);
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
  std::vector<std::array<int, 2>>& keptRep = this->KeptRep;
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
}

void ConstraintMerger::IndexEndPoints()
{
  const std::vector<P2>& points = this->Points;
  const std::vector<std::array<int, 2>>& keptRep = this->KeptRep;
  const double tol = this->Tol;
  // Distinct end points (for T-junctions), with their best priority.
  std::vector<int>& uniqueReps = this->UniqueReps;
  for (const auto& r : keptRep)
  {
    uniqueReps.push_back(r[0]);
    uniqueReps.push_back(r[1]);
  }
  std::sort(uniqueReps.begin(), uniqueReps.end());
  uniqueReps.erase(std::unique(uniqueReps.begin(), uniqueReps.end()), uniqueReps.end());
  // Priority of each distinct end point (for choosing breakpoint coordinates).
  std::unordered_map<int, int>& priorityOfRep = this->PriorityOfRep;
  for (std::size_t i = 0; i < keptRep.size(); ++i)
  {
    for (int r : keptRep[i])
    {
      auto found = priorityOfRep.find(r);
      const int p = this->Segments[i].Priority();
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
  this->MinX = minX;
  this->MinY = minY;
  const double count = static_cast<double>(std::max<std::size_t>(uniqueReps.size(), 1));
  this->RepCell = std::max(extent / std::sqrt(count), 4.0 * tol);
  const double repCell = this->RepCell;
  this->GridX = uniqueReps.empty() ? 1 : 1 + static_cast<long long>((maxX - minX) / repCell);
  this->GridY = uniqueReps.empty() ? 1 : 1 + static_cast<long long>((maxY - minY) / repCell);
  const long long gridX = this->GridX, gridY = this->GridY;
  std::vector<int>& cellStart = this->CellStart;
  std::vector<int>& cellItems = this->CellItems;
  cellStart.assign(static_cast<std::size_t>(gridX * gridY + 1), 0);
  cellItems.resize(uniqueReps.size());
  for (int r : uniqueReps)
  {
    const auto c = this->CellOf(points[r][0], points[r][1]);
    ++cellStart[static_cast<std::size_t>(c[1] * gridX + c[0] + 1)];
  }
  for (std::size_t c = 1; c < cellStart.size(); ++c)
  {
    cellStart[c] += cellStart[c - 1];
  }
  std::vector<int> fill(cellStart.begin(), cellStart.end() - 1);
  for (int r : uniqueReps)
  {
    const auto c = this->CellOf(points[r][0], points[r][1]);
    cellItems[static_cast<std::size_t>(fill[static_cast<std::size_t>(c[1] * gridX + c[0])]++)] = r;
  }
}

void ConstraintMerger::GroupCollinear()
{
  const std::vector<Segment2>& segments = this->Segments;
  const double tol = this->Tol;
  const std::size_t m = segments.size();

  // 2. Line grouping on a grid over (direction angle, offset): collinear
  // segments (within tol) fall in the same or neighbouring cells.
  std::vector<double> angle(m), offset(m);
  std::vector<double>& length = this->Length;
  length.resize(m);
  double shortest = std::numeric_limits<double>::max(), radius = 0.0;
  for (std::size_t i = 0; i < m; ++i)
  {
    const double dx = segments[i].B[0] - segments[i].A[0];
    const double dy = segments[i].B[1] - segments[i].A[1];
    double a = std::atan2(dy, dx);
    if (a < 0.0)
    {
      a += Pi;
    }
    if (a >= Pi)
    {
      a -= Pi;
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
  const double window = m > 0 ? std::min(Pi, 4.0 * tol / shortest + 1e-12) : Pi;
  const long long angleBins = std::max(1LL, static_cast<long long>(std::floor(Pi / window)));
  const double binWidth = Pi / static_cast<double>(angleBins);
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
  std::unordered_map<int, std::vector<int>>& groups = this->Groups;
  for (std::size_t i = 0; i < m; ++i)
  {
    groups[lines.Find(static_cast<int>(i))].push_back(static_cast<int>(i));
  }
  std::vector<int>& groupRoots = this->GroupRoots;
  for (const auto& g : groups)
  {
    groupRoots.push_back(g.first);
  }
  std::sort(groupRoots.begin(), groupRoots.end()); // deterministic output order
}

void ConstraintMerger::FindNearEndPoints(const std::vector<int>& members)
{
  const std::vector<Segment2>& segments = this->Segments;
  const std::vector<double>& length = this->Length;
  const std::vector<int>& cellStart = this->CellStart;
  const std::vector<int>& cellItems = this->CellItems;
  const double repCell = this->RepCell;
  const long long gridX = this->GridX, gridY = this->GridY;
  // T-junctions: end points of other lines lying inside this one (found
  // through the grid cells along each member).
  std::vector<int>& nearReps = this->NearReps;
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
      const auto c = this->CellOf(a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]));
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
}

void ConstraintMerger::SplitLine(const std::vector<int>& members, std::vector<Constraint2D>& out)
{
  const std::vector<Segment2>& segments = this->Segments;
  const std::vector<P2>& points = this->Points;
  const std::vector<std::array<int, 2>>& keptRep = this->KeptRep;
  const std::vector<double>& length = this->Length;
  std::unordered_map<int, int>& priorityOfRep = this->PriorityOfRep;
  std::vector<Breakpoint>& breaks = this->Breaks;
  const double tol = this->Tol;
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
  this->FindNearEndPoints(members);
  for (int r : this->NearReps)
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
    Constraint2D c;
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

} // namespace

std::vector<Constraint2D> MergeSegments(
  std::vector<Segment2> segments, double tol, double minLength)
{
  return ConstraintMerger(std::move(segments), tol, minLength).Run();
}

} // namespace detail
} // namespace penumbra
