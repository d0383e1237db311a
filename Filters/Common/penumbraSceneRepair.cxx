// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSceneRepair.h"

#include "penumbraPlaneFrame.h"
#include "penumbraMath.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace penumbra
{

namespace
{

std::string Plural(std::size_t n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string Number(double value)
{
  std::ostringstream os;
  os.precision(3);
  os << value;
  return os.str();
}

/// Welds vertices on a grid of cells one tolerance wide: a vertex joins the
/// first earlier vertex within the tolerance in its 27 neighbouring cells.
class VertexWelder
{
public:
  explicit VertexWelder(double tolerance)
    : Tolerance(tolerance)
  {
  }

  /// The cluster id of `p`, moving `p` onto its cluster's first vertex.
  int Weld(Vec3& p, RepairReport& report)
  {
    if (!IsFinite(p))
    {
      return -1 - static_cast<int>(this->NonFinite++); // never shared
    }
    const std::int64_t c[3] = { this->CellOf(p.X), this->CellOf(p.Y), this->CellOf(p.Z) };
    int best = -1;
    double bestDistance = this->Tolerance;
    for (int dx = -1; dx <= 1; ++dx)
    {
      for (int dy = -1; dy <= 1; ++dy)
      {
        for (int dz = -1; dz <= 1; ++dz)
        {
          const auto found = this->Cells.find(Key(c[0] + dx, c[1] + dy, c[2] + dz));
          if (found == this->Cells.end())
          {
            continue;
          }
          for (int id : found->second)
          {
            const double d = Length(this->Points[id] - p);
            if (d < bestDistance || (d == 0.0 && best < 0) || (d == bestDistance && id < best))
            {
              best = id;
              bestDistance = d;
            }
          }
        }
      }
    }
    if (best >= 0)
    {
      // Counted once per distinct position, however many polygons share it.
      if (bestDistance > 0.0 && this->Moved.insert({ p.X, p.Y, p.Z }).second)
      {
        ++report.WeldedVertices;
        report.LargestWeldDistance = std::max(report.LargestWeldDistance, bestDistance);
      }
      p = this->Points[best];
      return best;
    }
    const int id = static_cast<int>(this->Points.size());
    this->Points.push_back(p);
    this->Cells[Key(c[0], c[1], c[2])].push_back(id);
    return id;
  }

  /// The clusters' positions, by cluster id (moved by AxisPlaneSnapping).
  std::vector<Vec3> Points;

private:
  std::int64_t CellOf(double x) const
  {
    if (!(this->Tolerance > 0.0))
    {
      return 0; // exact duplicates only: one bucket per hash of the point below
    }
    return static_cast<std::int64_t>(std::floor(x / this->Tolerance));
  }

  static std::uint64_t Key(std::int64_t x, std::int64_t y, std::int64_t z)
  {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return h;
  }

  double Tolerance;
  std::size_t NonFinite = 0;
  std::set<std::array<double, 3>> Moved;
  std::unordered_map<std::uint64_t, std::vector<int>> Cells;
};

bool SameMaterial(const Surface& a, const Surface& b)
{
  return a.Reflectance.R == b.Reflectance.R && a.Reflectance.G == b.Reflectance.G &&
    a.Reflectance.B == b.Reflectance.B && a.Emission.R == b.Emission.R &&
    a.Emission.G == b.Emission.G && a.Emission.B == b.Emission.B;
}

/// The ids of a polygon rotated to start at its smallest id: equal for the
/// same outline in the same cyclic order.
std::vector<int> CanonicalOutline(const std::vector<int>& ids)
{
  const auto first = std::min_element(ids.begin(), ids.end());
  std::vector<int> out(first, ids.end());
  out.insert(out.end(), ids.begin(), first);
  return out;
}

/**
 * Snaps coordinates onto the axis-aligned planes the scene is built on.
 * Single-precision exports leave a floor's corners 1e-7 off its plane and a
 * box's base 1e-7 above or below the floor; the pipeline needs such contacts
 * exact. For each axis, a polygon whose vertices all lie within the tolerance
 * of its first vertex's value of that coordinate claims the vertices within
 * the tolerance of that value inside its bounding rectangle, its own
 * included; each claimed vertex takes the value of the earliest polygon
 * claiming it. Exact scenes are left as they are.
 */
void SnapToAxisPlanes(std::vector<Vec3>& points, const std::vector<std::vector<int>>& polygons,
  double tolerance, RepairReport& report)
{
  if (!(tolerance > 0.0) || points.empty())
  {
    return;
  }
  std::set<int> moved;
  for (int k = 0; k < 3; ++k)
  {
    const int a = (k + 1) % 3;
    const int b = (k + 2) % 3;
    struct Planar
    {
      double Value;
      std::size_t Polygon;
      double Lo[2], Hi[2];
    };
    std::vector<Planar> planar;
    for (std::size_t i = 0; i < polygons.size(); ++i)
    {
      const std::vector<int>& ids = polygons[i];
      if (ids.size() < 3 || *std::min_element(ids.begin(), ids.end()) < 0)
      {
        continue;
      }
      const double value = points[ids[0]][k];
      Planar entry{ value, i, { points[ids[0]][a], points[ids[0]][b] },
        { points[ids[0]][a], points[ids[0]][b] } };
      bool flat = true;
      for (int id : ids)
      {
        const Vec3& p = points[id];
        flat = flat && std::abs(p[k] - value) <= tolerance;
        entry.Lo[0] = std::min(entry.Lo[0], p[a]);
        entry.Hi[0] = std::max(entry.Hi[0], p[a]);
        entry.Lo[1] = std::min(entry.Lo[1], p[b]);
        entry.Hi[1] = std::max(entry.Hi[1], p[b]);
      }
      if (flat)
      {
        planar.push_back(entry);
      }
    }
    std::vector<int> order(points.size());
    for (std::size_t i = 0; i < order.size(); ++i)
    {
      order[i] = static_cast<int>(i);
    }
    std::sort(order.begin(), order.end(),
      [&points, k](int x, int y) { return points[x][k] < points[y][k]; });
    // Each vertex takes the value of the earliest (in input order) planar
    // polygon that claims it: within the tolerance of its value, inside its
    // bounding rectangle. Claims are local, so two distant boxes whose tops
    // differ by less than the tolerance keep their own heights.
    std::vector<std::pair<std::size_t, double>> claim(
      points.size(), { std::numeric_limits<std::size_t>::max(), 0.0 });
    for (const Planar& r : planar)
    {
      const auto begin = std::lower_bound(order.begin(), order.end(), r.Value - tolerance,
        [&points, k](int id, double v) { return points[id][k] < v; });
      for (auto it = begin; it != order.end() && points[*it][k] <= r.Value + tolerance; ++it)
      {
        const Vec3& p = points[*it];
        if (r.Polygon < claim[*it].first && p[a] >= r.Lo[0] - tolerance &&
          p[a] <= r.Hi[0] + tolerance && p[b] >= r.Lo[1] - tolerance &&
          p[b] <= r.Hi[1] + tolerance)
        {
          claim[*it] = { r.Polygon, r.Value };
        }
      }
    }
    for (std::size_t id = 0; id < points.size(); ++id)
    {
      if (claim[id].first != std::numeric_limits<std::size_t>::max() &&
        points[id][k] != claim[id].second)
      {
        report.LargestSnapDistance =
          std::max(report.LargestSnapDistance, std::abs(points[id][k] - claim[id].second));
        points[id][k] = claim[id].second;
        moved.insert(static_cast<int>(id));
      }
    }
  }
  report.SnappedVertices = moved.size();
}

/// Whether the point (u, v) lies inside the polygon `ring` (2D), or within
/// `margin` of its outline.
bool InsideOrNear(const std::vector<P2>& ring, double u, double v, double margin)
{
  bool inside = false;
  const std::size_t n = ring.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    const P2& a = ring[i];
    const P2& b = ring[j];
    if ((a[1] > v) != (b[1] > v) && u < (b[0] - a[0]) * (v - a[1]) / (b[1] - a[1]) + a[0])
    {
      inside = !inside;
    }
    // Distance to the edge, for points on or just outside the outline.
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double length2 = ex * ex + ey * ey;
    const double t = length2 > 0.0
      ? std::max(0.0, std::min(1.0, ((u - a[0]) * ex + (v - a[1]) * ey) / length2))
      : 0.0;
    const double dx = a[0] + t * ex - u, dy = a[1] + t * ey - v;
    if (dx * dx + dy * dy <= margin * margin)
    {
      return true;
    }
  }
  return inside;
}

/**
 * Vertices resting on a polygon they are not a vertex of (a box's base on a
 * floor, 1e-7 off after single-precision rounding, at any orientation): within
 * `tolerance` of its plane, their projection inside its outline, they are
 * moved onto the plane (of the earliest such polygon). Distances below
 * `exact` (rounding of an exact contact) are left alone, so exact scenes do
 * not change. Returns the surfaces whose vertices moved.
 */
std::vector<bool> SnapOntoPlanes(Scene& scene, double tolerance, double exact, RepairReport& report)
{
  const std::size_t n = scene.Surfaces.size();
  std::vector<bool> moved(n, false);
  if (!(tolerance > 0.0) || n == 0)
  {
    return moved;
  }
  // Distinct positions, with where each occurs.
  std::map<std::array<double, 3>, int> ids;
  std::vector<Vec3> points;
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> uses;
  std::vector<std::vector<int>> polygonIds(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (std::size_t k = 0; k < scene.Surfaces[i].Vertices.size(); ++k)
    {
      const Vec3& p = scene.Surfaces[i].Vertices[k];
      const auto found = ids.emplace(std::array<double, 3>{ p.X, p.Y, p.Z }, static_cast<int>(points.size()));
      if (found.second)
      {
        points.push_back(p);
        uses.emplace_back();
      }
      uses[found.first->second].emplace_back(i, k);
      polygonIds[i].push_back(found.first->second);
    }
  }
  // A grid of the positions, 64 cells along the scene's longest side.
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points)
  {
    for (int c = 0; c < 3; ++c)
    {
      lo[c] = std::min(lo[c], p[c]);
      hi[c] = std::max(hi[c], p[c]);
    }
  }
  const double cell = std::max({ hi.X - lo.X, hi.Y - lo.Y, hi.Z - lo.Z, 1e-300 }) / 64.0;
  const auto index = [&](double x, int c) {
    return std::max(0, std::min(64, static_cast<int>(std::floor((x - lo[c]) / cell))));
  };
  std::map<std::array<int, 3>, std::vector<int>> grid;
  for (std::size_t id = 0; id < points.size(); ++id)
  {
    grid[{ index(points[id].X, 0), index(points[id].Y, 1), index(points[id].Z, 2) }].push_back(
      static_cast<int>(id));
  }
  std::vector<std::size_t> claim(points.size(), n);
  std::vector<Vec3> target(points.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::vector<Vec3>& v = scene.Surfaces[i].Vertices;
    const PolygonGeometry g = ComputePolygonGeometry(v);
    if (!(g.Area > 0.0))
    {
      continue;
    }
    Vec3 u, w;
    InPlaneAxes(g.Normal, u, w);
    std::vector<P2> ring;
    Vec3 blo = v[0], bhi = v[0];
    for (const Vec3& p : v)
    {
      ring.push_back({ Dot(p, u), Dot(p, w) });
      for (int c = 0; c < 3; ++c)
      {
        blo[c] = std::min(blo[c], p[c] - tolerance);
        bhi[c] = std::max(bhi[c], p[c] + tolerance);
      }
    }
    const std::vector<int>& own = polygonIds[i];
    for (int x = index(blo.X, 0); x <= index(bhi.X, 0); ++x)
    {
      for (int y = index(blo.Y, 1); y <= index(bhi.Y, 1); ++y)
      {
        for (int z = index(blo.Z, 2); z <= index(bhi.Z, 2); ++z)
        {
          const auto found = grid.find({ x, y, z });
          if (found == grid.end())
          {
            continue;
          }
          for (int id : found->second)
          {
            const Vec3& p = points[id];
            const double distance = Dot(g.Normal, p) - g.Offset;
            if (claim[id] < i || std::abs(distance) > tolerance || std::abs(distance) <= exact ||
              std::find(own.begin(), own.end(), id) != own.end())
            {
              continue;
            }
            const Vec3 q = p - g.Normal * distance;
            if (InsideOrNear(ring, Dot(q, u), Dot(q, w), tolerance))
            {
              claim[id] = i;
              target[id] = q;
            }
          }
        }
      }
    }
  }
  std::size_t count = 0;
  for (std::size_t id = 0; id < points.size(); ++id)
  {
    if (claim[id] == n)
    {
      continue;
    }
    ++count;
    report.LargestPlaneSnapDistance =
      std::max(report.LargestPlaneSnapDistance, Length(target[id] - points[id]));
    for (const auto& use : uses[id])
    {
      scene.Surfaces[use.first].Vertices[use.second] = target[id];
      moved[use.first] = true;
    }
  }
  report.PlaneSnappedVertices = count;
  return moved;
}

} // namespace

bool RepairReport::Empty() const
{
  return this->WeldedVertices == 0 && this->SnappedVertices == 0 &&
    this->PlaneSnappedVertices == 0 &&
    this->RepeatedVertexPolygons == 0 &&
    this->NonPlanarPolygons == 0 && this->ZeroAreaPolygons == 0 && this->DuplicatePolygons == 0;
}

std::vector<std::string> RepairReport::Messages() const
{
  std::vector<std::string> lines;
  if (this->WeldedVertices > 0)
  {
    lines.push_back(Plural(this->WeldedVertices, "vertex", "vertices") +
      " welded onto a neighbour (moved at most " + Number(this->LargestWeldDistance) + ")");
  }
  if (this->SnappedVertices > 0)
  {
    lines.push_back(Plural(this->SnappedVertices, "vertex", "vertices") +
      " snapped onto the axis-aligned plane of a polygon (moved at most " +
      Number(this->LargestSnapDistance) + ")");
  }
  if (this->PlaneSnappedVertices > 0)
  {
    lines.push_back(Plural(this->PlaneSnappedVertices, "vertex", "vertices") +
      " resting on a polygon snapped onto its plane (moved at most " +
      Number(this->LargestPlaneSnapDistance) + ")");
  }
  if (this->RepeatedVertexPolygons > 0)
  {
    lines.push_back(Plural(this->RepeatedVertexPolygons, "polygon", "polygons") +
      " with repeated consecutive vertices cleaned");
  }
  if (this->ZeroAreaPolygons > 0)
  {
    lines.push_back(Plural(this->ZeroAreaPolygons, "zero-area polygon", "zero-area polygons") +
      " dropped");
  }
  if (this->DuplicatePolygons > 0)
  {
    std::string line = Plural(this->DuplicatePolygons, "duplicate polygon", "duplicate polygons") +
      " dropped";
    if (this->DuplicatesWithOtherMaterial > 0)
    {
      line += " (" + std::to_string(this->DuplicatesWithOtherMaterial) +
        " with a material other than the first copy's, which is kept)";
    }
    lines.push_back(line);
  }
  if (this->NonPlanarPolygons > 0)
  {
    lines.push_back(Plural(this->NonPlanarPolygons, "non-planar polygon", "non-planar polygons") +
      " triangulated into " + Plural(this->NonPlanarTriangles, "triangle", "triangles") +
      " (largest distance from the plane " + Number(this->LargestPlanarityDeviation) + ")");
  }
  return lines;
}

Scene RepairScene(const Scene& scene, const RepairOptions& options, RepairReport& report,
  std::vector<std::size_t>& sourceCell)
{
  report = RepairReport();
  sourceCell.clear();
  Scene out;
  VertexWelder welder(options.WeldTolerance * scene.Size());
  std::map<std::vector<int>, std::size_t> outlines; // canonical outline -> output surface
  ValidationTolerances anyPlane = options.Validation;
  anyPlane.Planarity = 1.0; // every other check of ValidateScene, planarity aside

  // Weld every vertex first, then snap the clusters onto axis planes, so that
  // a vertex shared by several polygons moves once, for all of them.
  std::vector<std::vector<int>> welded(scene.Surfaces.size());
  for (std::size_t cell = 0; cell < scene.Surfaces.size(); ++cell)
  {
    for (Vec3 p : scene.Surfaces[cell].Vertices)
    {
      welded[cell].push_back(welder.Weld(p, report));
    }
  }
  SnapToAxisPlanes(welder.Points, welded, options.WeldTolerance * scene.Size(), report);

  for (std::size_t cell = 0; cell < scene.Surfaces.size(); ++cell)
  {
    const Surface& input = scene.Surfaces[cell];
    Surface s{ {}, input.Reflectance, input.Emission };
    std::vector<int> ids;
    bool changed = false;
    bool repeated = false;
    const double diameter = ComputePolygonGeometry(input.Vertices).Diameter;
    const double coincident = options.Validation.Degeneracy * diameter;
    for (std::size_t v = 0; v < input.Vertices.size(); ++v)
    {
      const Vec3& original = input.Vertices[v];
      const int id = welded[cell][v];
      const Vec3 p = id >= 0 ? welder.Points[id] : original;
      changed = changed || !(p.X == original.X && p.Y == original.Y && p.Z == original.Z);
      const bool same = !ids.empty() &&
        (ids.back() == id || Length(p - s.Vertices.back()) <= coincident);
      if (!same)
      {
        ids.push_back(id);
        s.Vertices.push_back(p);
      }
      repeated = repeated || same;
    }
    while (ids.size() > 1 &&
      (ids.front() == ids.back() || Length(s.Vertices.front() - s.Vertices.back()) <= coincident))
    {
      ids.pop_back();
      s.Vertices.pop_back();
      repeated = true;
    }
    const PolygonGeometry g = ComputePolygonGeometry(s.Vertices);
    if (s.Vertices.size() < 3 || !(g.Diameter > 0.0) ||
      2.0 * g.Area / g.Diameter <= options.Validation.Degeneracy * g.Diameter)
    {
      if (IsFinite(g.Centroid))
      {
        ++report.ZeroAreaPolygons;
        if (report.ZeroAreaCells.size() < 8)
        {
          report.ZeroAreaCells.push_back(cell);
        }
        continue;
      }
    }
    if (repeated)
    {
      ++report.RepeatedVertexPolygons;
    }
    const std::vector<int> key = CanonicalOutline(ids);
    const auto copy = outlines.find(key);
    if (copy != outlines.end() && IsFinite(g.Centroid))
    {
      ++report.DuplicatePolygons;
      if (!SameMaterial(out.Surfaces[copy->second], s))
      {
        ++report.DuplicatesWithOtherMaterial;
      }
      continue;
    }
    double deviation = 0.0;
    for (const Vec3& p : s.Vertices)
    {
      deviation = std::max(deviation, std::abs(Dot(g.Normal, p) - g.Offset));
    }
    const double flatness = std::min(options.FlatnessTolerance, options.Validation.Planarity);
    bool triangulate = deviation > flatness * g.Diameter;
    if (triangulate)
    {
      // Only an outline that is otherwise valid is cut: a self-intersecting
      // one has no front side to keep, and ValidateScene names it.
      Scene single;
      single.Surfaces.push_back(s);
      try
      {
        ValidateScene(single, anyPlane);
      }
      catch (const InputError&)
      {
        triangulate = false;
      }
    }
    if (!triangulate)
    {
      outlines.emplace(key, out.Surfaces.size());
      out.Surfaces.push_back(changed || repeated ? s : input);
      sourceCell.push_back(cell);
      continue;
    }
    std::vector<std::array<int, 3>> triangles;
    TriangulatePolygon(s.Vertices, g.Normal, triangles);
    ++report.NonPlanarPolygons;
    report.LargestPlanarityDeviation = std::max(report.LargestPlanarityDeviation, deviation);
    outlines.emplace(key, out.Surfaces.size());
    for (const auto& t : triangles)
    {
      Surface piece{ { s.Vertices[t[0]], s.Vertices[t[1]], s.Vertices[t[2]] }, s.Reflectance,
        s.Emission };
      const PolygonGeometry pg = ComputePolygonGeometry(piece.Vertices);
      if (!(pg.Diameter > 0.0) ||
        2.0 * pg.Area / pg.Diameter <= options.Validation.Degeneracy * pg.Diameter)
      {
        continue; // a flat ear of a nearly collinear run: no area to light
      }
      ++report.NonPlanarTriangles;
      out.Surfaces.push_back(std::move(piece));
      sourceCell.push_back(cell);
    }
  }

  // Contacts made exact at any orientation; the polygons whose vertices moved
  // are flattened again.
  const double size = scene.Size();
  const std::vector<bool> moved =
    SnapOntoPlanes(out, options.WeldTolerance * size, 1e-12 * size, report);
  if (std::find(moved.begin(), moved.end(), true) == moved.end())
  {
    return out;
  }
  Scene flattened;
  std::vector<std::size_t> flattenedSource;
  const double flatness = std::min(options.FlatnessTolerance, options.Validation.Planarity);
  for (std::size_t i = 0; i < out.Surfaces.size(); ++i)
  {
    const Surface& surface = out.Surfaces[i];
    const PolygonGeometry g = ComputePolygonGeometry(surface.Vertices);
    double deviation = 0.0;
    for (const Vec3& p : surface.Vertices)
    {
      deviation = std::max(deviation, std::abs(Dot(g.Normal, p) - g.Offset));
    }
    if (!moved[i] || surface.Vertices.size() == 3 || !(deviation > flatness * g.Diameter))
    {
      flattened.Surfaces.push_back(surface);
      flattenedSource.push_back(sourceCell[i]);
      continue;
    }
    std::vector<std::array<int, 3>> triangles;
    TriangulatePolygon(surface.Vertices, g.Normal, triangles);
    ++report.NonPlanarPolygons;
    report.LargestPlanarityDeviation = std::max(report.LargestPlanarityDeviation, deviation);
    for (const auto& t : triangles)
    {
      flattened.Surfaces.push_back({ { surface.Vertices[t[0]], surface.Vertices[t[1]],
                                       surface.Vertices[t[2]] },
        surface.Reflectance, surface.Emission });
      flattenedSource.push_back(sourceCell[i]);
      ++report.NonPlanarTriangles;
    }
  }
  sourceCell = std::move(flattenedSource);
  return flattened;
}

} // namespace penumbra
