// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraLightingDiagnostics.h"

#include "penumbraPlaneFrame.h"
#include "penumbraMath.h"
#include "penumbraRayCaster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace penumbra
{

namespace
{

bool Emits(const Surface& s)
{
  return s.Emission.R > 0.0 || s.Emission.G > 0.0 || s.Emission.B > 0.0;
}

/// Whether some vertex of `vertices` lies strictly in front of the plane.
bool AnyInFront(const std::vector<Vec3>& vertices, const PolygonGeometry& plane, double margin)
{
  for (const Vec3& v : vertices)
  {
    if (Dot(plane.Normal, v) - plane.Offset > margin)
    {
      return true;
    }
  }
  return false;
}

std::string CellList(const std::vector<std::size_t>& cells)
{
  std::ostringstream os;
  const std::size_t shown = std::min<std::size_t>(cells.size(), 8);
  for (std::size_t i = 0; i < shown; ++i)
  {
    os << (i ? ", " : "") << cells[i];
  }
  if (shown < cells.size())
  {
    os << ", ... (" << cells.size() << " in all)";
  }
  return os.str();
}

/// The fraction of cosine-distributed rays from `e` that meet a surface's back.
double BackHitFraction(const Scene& scene, int e, const PolygonGeometry& g,
  const std::vector<PolygonGeometry>& planes, const RayCaster& caster, int rays)
{
  const Surface& s = scene.Surfaces[e];
  std::vector<std::array<int, 3>> triangles;
  TriangulatePolygon(s.Vertices, g.Normal, triangles);
  if (triangles.empty())
  {
    return 0.0;
  }
  std::vector<double> cumulative;
  double total = 0.0;
  for (const auto& t : triangles)
  {
    total += Length(Cross(s.Vertices[t[1]] - s.Vertices[t[0]], s.Vertices[t[2]] - s.Vertices[t[0]]));
    cumulative.push_back(total);
  }
  Vec3 u, v;
  InPlaneAxes(g.Normal, u, v);
  std::vector<Vec3> origins(rays), directions(rays);
  for (int r = 0; r < rays; ++r)
  {
    const unsigned index = static_cast<unsigned>(r) + 1;
    const double pick = RadicalInverse(index, 2) * total;
    const std::size_t k = std::min<std::size_t>(
      std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
      triangles.size() - 1);
    double a = RadicalInverse(index, 3);
    double b = RadicalInverse(index, 11);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const auto& t = triangles[k];
    origins[r] = s.Vertices[t[0]] + a * (s.Vertices[t[1]] - s.Vertices[t[0]]) +
      b * (s.Vertices[t[2]] - s.Vertices[t[0]]);
    const double radius = std::sqrt(RadicalInverse(index, 5));
    const double phi = 2.0 * Pi * RadicalInverse(index, 7);
    const double z = std::sqrt(std::max(0.0, 1.0 - radius * radius));
    directions[r] = u * (radius * std::cos(phi)) + v * (radius * std::sin(phi)) + g.Normal * z;
  }
  std::vector<int> hits(rays);
  caster.FindNearest(origins.data(), directions.data(), rays, hits.data(), e);
  int backs = 0;
  for (int r = 0; r < rays; ++r)
  {
    backs += hits[r] >= 0 && Dot(directions[r], planes[hits[r]].Normal) > 0.0;
  }
  return static_cast<double>(backs) / rays;
}

} // namespace

std::vector<std::string> DiagnoseLighting(const Scene& scene,
  const LightingDiagnosticsOptions& options, const std::vector<std::size_t>* cellNumbers)
{
  std::vector<std::string> warnings;
  const std::size_t n = scene.Surfaces.size();
  const auto cellOf = [&](std::size_t i) { return cellNumbers ? cellNumbers->at(i) : i; };
  std::vector<int> emitters;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (Emits(scene.Surfaces[i]))
    {
      emitters.push_back(static_cast<int>(i));
    }
  }
  if (n == 0)
  {
    return warnings;
  }
  if (emitters.empty())
  {
    warnings.push_back("no surface emits light (Emission is zero on every cell): the result "
                       "will be black");
    return warnings;
  }
  std::vector<PolygonGeometry> planes(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    planes[i] = ComputePolygonGeometry(scene.Surfaces[i].Vertices);
  }
  // An emitter lights surface s only where each lies in front of the other.
  const double margin = 1e-9 * scene.Size();
  std::vector<std::size_t> facingNothing;
  std::vector<int> lighting;
  for (int e : emitters)
  {
    bool any = false;
    for (std::size_t s = 0; s < n && !any; ++s)
    {
      any = static_cast<int>(s) != e &&
        AnyInFront(scene.Surfaces[s].Vertices, planes[e], margin) &&
        AnyInFront(scene.Surfaces[e].Vertices, planes[s], margin);
    }
    if (any)
    {
      lighting.push_back(e);
    }
    else
    {
      facingNothing.push_back(cellOf(e));
    }
  }
  if (lighting.empty())
  {
    warnings.push_back("every emitter faces away from every surface (cells " +
      CellList(facingNothing) +
      "): their light leaves the scene; a polygon's front is the side its vertices are "
      "counter-clockwise from");
    return warnings;
  }
  if (!facingNothing.empty())
  {
    warnings.push_back(std::to_string(facingNothing.size()) + " of " +
      std::to_string(emitters.size()) + " emitters face no surface (cells " +
      CellList(facingNothing) + "): their light leaves the scene");
  }
  const RayCaster caster(scene);
  const int rays = std::max(1, std::min(options.RaysPerEmitter, 65536));
  std::vector<std::size_t> enclosed;
  double worst = 0.0;
  for (int e : lighting)
  {
    const double fraction = BackHitFraction(scene, e, planes[e], planes, caster, rays);
    if (fraction > options.BackFraction)
    {
      enclosed.push_back(cellOf(e));
      worst = std::max(worst, fraction);
    }
  }
  if (!enclosed.empty())
  {
    std::ostringstream os;
    os << enclosed.size() << " of " << emitters.size() << " emitters (cells "
       << CellList(enclosed) << ") send up to " << std::lround(100.0 * worst)
       << "% of their light onto the backs of surfaces, which absorb it: is an emitter inside "
          "a closed solid, or do those surfaces face the wrong way?";
    warnings.push_back(os.str());
  }
  return warnings;
}

} // namespace penumbra
