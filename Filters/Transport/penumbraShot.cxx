// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraShot.h"

#include "penumbraExactShot.h"
#include "penumbraFastShot.h"
#include "penumbraOccluderSet.h"
#include "penumbraSampleSet.h"

#include <algorithm>
#include <array>
#include <utility>

namespace penumbra
{

void PrepareShot(const SampleSet& samples, int j, ShotMethod method, double openingAngle,
  double leafSize, Shot& shot)
{
  shot.OpeningAngle = openingAngle;
  const PreparedPolygon& poly = samples.Polygon(j);
  const SurfaceSamples& s = samples.Surfaces[j];
  shot.Shooter = j;
  shot.Members.assign(1, j);
  shot.Method = method;
  shot.Normal = poly.Normal;
  shot.Offset = poly.Offset;
  shot.Hierarchy.Origin = poly.Centroid;
  shot.Empty = true;
  shot.Mixed = false;
  shot.Hierarchy.Nodes.clear();
  shot.Hierarchy.Moments.clear();
  // Triangles that carry unshot radiance and have an area (the others add nothing).
  Vec3 lo = s.Points.empty() ? Vec3() : s.Points[0];
  Vec3 hi = lo;
  for (const Vec3& p : s.Points)
  {
    lo = { std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z) };
    hi = { std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z) };
  }
  const double diagonal = Length(hi - lo);
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < s.Triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = s.Triangles[t];
    if (s.Unshot[tri[0]].IsZero() && s.Unshot[tri[1]].IsZero() && s.Unshot[tri[2]].IsZero())
    {
      continue;
    }
    if (!(samples.Areas[j][t] > 2e-12 * diagonal * diagonal))
    {
      continue;
    }
    kept.push_back(tri);
  }
  if (kept.empty())
  {
    return;
  }
  shot.Empty = false;
  // Points projected onto the shooter's plane exactly (input points may be
  // off it by rounding), so that the integrals are over the shooter itself.
  std::vector<Vec3> points(s.Points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    points[k] = s.Points[k] - poly.Normal * (Dot(poly.Normal, s.Points[k]) - poly.Offset);
  }
  if (method == ShotMethod::Exact)
  {
    shot.Radiance = ExactShooterRadiance(s, std::move(points), std::move(kept));
    return;
  }
  PrepareFastShooter(s, points, kept, leafSize * poly.Diameter, j, poly.Normal, shot.Hierarchy);
}

} // namespace penumbra
