// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSceneRepair.h"

#include "penumbraMath.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

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
  std::vector<Vec3> Points;
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

} // namespace

bool RepairReport::Empty() const
{
  return this->WeldedVertices == 0 && this->RepeatedVertexPolygons == 0 &&
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

  for (std::size_t cell = 0; cell < scene.Surfaces.size(); ++cell)
  {
    const Surface& input = scene.Surfaces[cell];
    Surface s{ {}, input.Reflectance, input.Emission };
    std::vector<int> ids;
    bool changed = false;
    bool repeated = false;
    const double diameter = ComputePolygonGeometry(input.Vertices).Diameter;
    const double coincident = options.Validation.Degeneracy * diameter;
    for (Vec3 p : input.Vertices)
    {
      const Vec3 original = p;
      const int id = welder.Weld(p, report);
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
