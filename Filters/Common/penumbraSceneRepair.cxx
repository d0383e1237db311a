// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSceneRepair.h"

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

} // namespace

bool RepairReport::Empty() const
{
  return this->WeldedVertices == 0 && this->SnappedVertices == 0 &&
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
  return out;
}

} // namespace penumbra
