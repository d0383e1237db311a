// SPDX-License-Identifier: GPL-3.0-or-later
// RepairScene: each repair on a scene made to need exactly it, checked
// against what the repair must leave (areas, front sides, vertex positions,
// counts) and against ValidateScene accepting the result.
#include "penumbraSceneRepair.h"
#include "penumbraTesting.h"

#include "penumbraSceneLibrary.h"

#include <cmath>

using namespace penumbra;

namespace
{

Surface Quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double rho = 0.5)
{
  return { { a, b, c, d }, RGB(rho, rho, rho), RGB() };
}

double TotalArea(const Scene& s)
{
  double area = 0.0;
  for (const Surface& surface : s.Surfaces)
  {
    area += ComputePolygonGeometry(surface.Vertices).Area;
  }
  return area;
}

Scene Repair(const Scene& in, RepairReport& report, std::vector<std::size_t>& source)
{
  const Scene out = RepairScene(in, RepairOptions(), report, source);
  PENUMBRA_EXPECT(source.size() == out.Surfaces.size());
  ValidateScene(out, ValidationTolerances(), &source); // must not throw
  return out;
}

} // namespace

// A clean scene comes out identical, with nothing reported.
PENUMBRA_TEST(TestCleanScenesUnchanged)
{
  for (const char* name : { "cornell", "strip", "occluder", "seven", "blind" })
  {
    const Scene in = MakeBuiltinScene(name);
    RepairReport report;
    std::vector<std::size_t> source;
    const Scene out = Repair(in, report, source);
    PENUMBRA_EXPECT(out.IsIdentical(in));
    PENUMBRA_EXPECT(report.Empty() && report.Messages().empty());
    for (std::size_t i = 0; i < source.size(); ++i)
    {
      PENUMBRA_EXPECT(source[i] == i);
    }
  }
}

// A quad 1.7 mm out of plane becomes two triangles with the same front side,
// the same corners and (to the bend's second order) the same area.
PENUMBRA_TEST(TestNonPlanarTriangulated)
{
  Scene in;
  in.Surfaces.push_back(Quad({ 0, 0, 0 }, { 2, 0, 0 }, { 2, 0.0017, 2 }, { 0, 0, 2 }));
  in.Surfaces[0].Vertices = { { 0, 0, 0 }, { 0, 0, 2 }, { 2, 0.0017, 2 }, { 2, 0, 0 } }; // faces +y
  in.Surfaces.push_back(Quad({ 0, 1, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 0, 1, 1 }));
  RepairReport report;
  std::vector<std::size_t> source;
  const Scene out = Repair(in, report, source);
  PENUMBRA_EXPECT(out.Surfaces.size() == 3);
  PENUMBRA_EXPECT(report.NonPlanarPolygons == 1 && report.NonPlanarTriangles == 2);
  PENUMBRA_EXPECT(source[0] == 0 && source[1] == 0 && source[2] == 1);
  // No plane is closer than 0.0017 / 4 to all four corners of this bend; the
  // polygon's own plane passes within half the bend of each.
  PENUMBRA_EXPECT(report.LargestPlanarityDeviation >= 0.0017 / 4.0 &&
    report.LargestPlanarityDeviation <= 0.0017 / 2.0);
  double area = 0.0;
  for (int i = 0; i < 2; ++i)
  {
    const PolygonGeometry g = ComputePolygonGeometry(out.Surfaces[i].Vertices);
    PENUMBRA_EXPECT(g.Normal.Y > 0.99);
    area += g.Area;
    PENUMBRA_EXPECT(out.Surfaces[i].Reflectance.R == 0.5);
  }
  PENUMBRA_EXPECT_REL(area, 4.0, 1e-6);
  PENUMBRA_EXPECT(report.Messages().size() == 1 &&
    report.Messages()[0].find("1 non-planar polygon triangulated into 2 triangles") == 0);
}

// Near-duplicate vertices weld, repeated vertices go, zero-area faces and
// duplicate faces are dropped; a reversed copy (a two-sided sheet) stays.
PENUMBRA_TEST(TestWeldAndDrop)
{
  Scene in;
  const double e = 1e-8; // far below the weld tolerance of a 3-unit scene
  in.Surfaces.push_back(Quad({ 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }));
  in.Surfaces.push_back(Quad({ 1 + e, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1 - e, 0 }));
  in.Surfaces.push_back({ { { 0, 0, 3 }, { 1, 0, 3 }, { 1, 0, 3 }, { 1, 1, 3 } }, RGB(0.2, 0.2, 0.2),
    RGB() });                                                                   // repeated vertex
  in.Surfaces.push_back({ { { 0, 2, 0 }, { 1, 2, 0 }, { 2, 2, 0 } }, RGB(), RGB() }); // collinear
  in.Surfaces.push_back(Quad({ 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 0 }, 0.3)); // copy
  in.Surfaces.push_back(Quad({ 0, 1, 0 }, { 1, 1, 0 }, { 1, 0, 0 }, { 0, 0, 0 })); // reversed
  RepairReport report;
  std::vector<std::size_t> source;
  const Scene out = Repair(in, report, source);
  PENUMBRA_EXPECT(report.WeldedVertices == 2);
  PENUMBRA_EXPECT_REL(report.LargestWeldDistance, e, 1e-6);
  PENUMBRA_EXPECT(report.RepeatedVertexPolygons == 1);
  PENUMBRA_EXPECT(report.ZeroAreaPolygons == 1);
  PENUMBRA_EXPECT(report.DuplicatePolygons == 1 && report.DuplicatesWithOtherMaterial == 1);
  PENUMBRA_EXPECT(out.Surfaces.size() == 4);
  const std::vector<std::size_t> expected = { 0, 1, 2, 5 };
  PENUMBRA_EXPECT(source == expected);
  // The welded quad shares its corners with the first one, exactly.
  PENUMBRA_EXPECT(out.Surfaces[1].Vertices[0].X == 1.0 && out.Surfaces[1].Vertices[3].Y == 1.0);
  PENUMBRA_EXPECT(out.Surfaces[2].Vertices.size() == 3);
  PENUMBRA_EXPECT_REL(TotalArea(out), 1.0 + 1.0 + 0.5 + 1.0, 1e-7);
  PENUMBRA_EXPECT(report.Messages().size() == 4);
}

// What cannot be repaired safely is left for ValidateScene, naming the cell
// of the input.
PENUMBRA_TEST(TestUnrepairableLeftToValidation)
{
  Scene in;
  in.Surfaces.push_back({ { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } }, RGB(), RGB() }); // dropped
  in.Surfaces.push_back(Quad({ 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, 1.0));
  // A bow tie, bent: no front side to keep.
  in.Surfaces.push_back({ { { 0, 0, 1 }, { 2, 2, 1.5 }, { 2, 0, 1 }, { 0, 1, 1 } }, RGB(), RGB() });
  RepairReport report;
  std::vector<std::size_t> source;
  const Scene out = RepairScene(in, RepairOptions(), report, source);
  PENUMBRA_EXPECT(report.ZeroAreaPolygons == 1 && report.NonPlanarPolygons == 0);
  PENUMBRA_EXPECT_THROW(ValidateScene(out, ValidationTolerances(), &source), InputError,
    "cell 1: Reflectance red is 1, outside [0, 1)");
  PENUMBRA_EXPECT(out.Surfaces.size() == 2);
  Scene bowtie;
  bowtie.Surfaces.push_back(in.Surfaces[2]);
  const Scene kept = RepairScene(bowtie, RepairOptions(), report, source);
  PENUMBRA_EXPECT(kept.Surfaces.size() == 1 && kept.Surfaces[0].Vertices.size() == 4);
  PENUMBRA_EXPECT_THROW(ValidateScene(kept, ValidationTolerances(), &source), InputError, "cell 0: ");
}

// Single-precision noise on axis-aligned geometry: a floor whose corners are
// 1e-8 off y = 0 and a box side whose base is 3e-8 above it snap onto the
// floor's plane (the first floor corner's y); a vertex beyond the floor's
// rectangle, or further than the tolerance, stays where it is.
PENUMBRA_TEST(TestSnapToAxisPlanes)
{
  Scene in;
  in.Surfaces.push_back({ { { 0, 0, 0 }, { 0, 2e-8, 4 }, { 4, -1e-8, 4 }, { 4, 1e-8, 0 } },
    RGB(0.5, 0.5, 0.5), RGB() });
  in.Surfaces.push_back(Quad({ 1, 3e-8, 1 }, { 1, 3e-8, 2 }, { 1, 1, 2 }, { 1, 1, 1 }));
  in.Surfaces.push_back(Quad({ 5, 3e-8, 1 }, { 5, 3e-8, 2 }, { 5, 1, 2 }, { 5, 1, 1 }));
  in.Surfaces.push_back(Quad({ 2, 1e-3, 1 }, { 2, 1e-3, 2 }, { 2, 1, 2 }, { 2, 1, 1 }));
  RepairReport report;
  std::vector<std::size_t> source;
  const Scene out = Repair(in, report, source);
  PENUMBRA_EXPECT(out.Surfaces.size() == 4);
  PENUMBRA_EXPECT(report.SnappedVertices == 5 && report.NonPlanarPolygons == 0);
  PENUMBRA_EXPECT_REL(report.LargestSnapDistance, 3e-8, 1e-6);
  for (const Vec3& p : out.Surfaces[0].Vertices)
  {
    PENUMBRA_EXPECT(p.Y == 0.0);
  }
  PENUMBRA_EXPECT(out.Surfaces[1].Vertices[0].Y == 0.0 && out.Surfaces[1].Vertices[1].Y == 0.0);
  PENUMBRA_EXPECT(out.Surfaces[2].Vertices[0].Y == 3e-8); // outside the floor
  PENUMBRA_EXPECT(out.Surfaces[3].Vertices[0].Y == 1e-3); // a real gap
  PENUMBRA_EXPECT(report.Messages().size() == 1 &&
    report.Messages()[0].find("5 vertices snapped onto the axis-aligned plane") == 0);
}

// At any orientation: a vertex 3e-8 off a tilted polygon's plane, inside its
// outline, is moved onto the plane; one outside the outline, or off by less
// than rounding, stays.
PENUMBRA_TEST(TestSnapOntoTiltedPlanes)
{
  const Vec3 n = Normalized(Vec3(0.3, 1.0, 0.2));
  const Vec3 u = Normalized(Cross(Vec3(0, 0, 1), n));
  const Vec3 w = Cross(n, u);
  Scene in;
  in.Surfaces.push_back({ { u * -2 + w * -2, u * 2 + w * -2, u * 2 + w * 2, u * -2 + w * 2 },
    RGB(0.5, 0.5, 0.5), RGB() });
  const Vec3 inside = u * 0.5 + w * 0.5 + n * 3e-8;
  const Vec3 outside = u * 3 + w * 0.5 + n * 3e-8;
  const Vec3 rounding = u * -0.5 + w * 0.5 + n * 1e-14;
  for (const Vec3& base : { inside, outside, rounding })
  {
    // A thin upright triangle standing on the floor at `base`.
    in.Surfaces.push_back({ { base, base + u * 0.3, base + n * 0.5 }, RGB(0.5, 0.5, 0.5), RGB() });
  }
  RepairReport report;
  std::vector<std::size_t> source;
  const Scene out = Repair(in, report, source);
  // The inside triangle's two vertices on the floor.
  PENUMBRA_EXPECT(report.PlaneSnappedVertices == 2 && report.SnappedVertices == 0);
  PENUMBRA_EXPECT_REL(report.LargestPlaneSnapDistance, 3e-8, 1e-6);
  const PolygonGeometry floor = ComputePolygonGeometry(out.Surfaces[0].Vertices);
  for (int k = 0; k < 2; ++k)
  {
    PENUMBRA_EXPECT(std::abs(Dot(floor.Normal, out.Surfaces[1].Vertices[k]) - floor.Offset) < 1e-15);
  }
  PENUMBRA_EXPECT(Length(out.Surfaces[2].Vertices[0] - outside) == 0.0);
  PENUMBRA_EXPECT(Length(out.Surfaces[3].Vertices[0] - rounding) == 0.0);
}
