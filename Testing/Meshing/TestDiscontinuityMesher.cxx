// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the discontinuity mesher against geometry derived here
// independently: central projections of occluder corners from light corners
// (parallel and rotated square occluders), the supporting-plane criterion
// evaluated on vertex sides, contact footprints, and area / inside checks on
// the built-in scenes.
#include "penumbraDiscontinuityMesher.h"
#include "penumbraExactEvaluator.h"
#include "penumbraSceneLibrary.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <string>

using namespace penumbra;

namespace
{

// Horizontal square of half-size h at height y, centred at (cx, cz), rotated
// by `yaw` radians about +y, facing up or down.
std::vector<Vec3> Square(double cx, double y, double cz, double hx, double hz, bool up,
  double yaw = 0.0)
{
  std::vector<Vec3> v;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double corners[4][2] = { { -hx, -hz }, { -hx, hz }, { hx, hz }, { hx, -hz } };
  // (-,-) (-,+) (+,+) (+,-) in (x, z) is counter-clockwise seen from +y.
  for (const auto& k : corners)
  {
    v.push_back(Vec3(cx + c * k[0] + s * k[1], y, cz - s * k[0] + c * k[1]));
  }
  if (!up)
  {
    std::reverse(v.begin(), v.end());
  }
  return v;
}

Surface Make(std::vector<Vec3> v, RGB reflectance, RGB emission = RGB())
{
  return Surface{ std::move(v), reflectance, emission };
}

// A 2D line a x + b z = c with (a, b) unit and a canonical sign.
struct Line2
{
  double A, B, C;
};

Line2 LineThrough(double x0, double z0, double x1, double z1)
{
  double a = -(z1 - z0), b = x1 - x0;
  const double n = std::hypot(a, b);
  a /= n;
  b /= n;
  if (a < -1e-12 || (std::abs(a) <= 1e-12 && b < 0))
  {
    a = -a;
    b = -b;
  }
  return { a, b, a * x0 + b * z0 };
}

bool SameLine(const Line2& p, const Line2& q, double tol)
{
  return std::abs(p.A - q.A) < 1e-9 && std::abs(p.B - q.B) < 1e-9 && std::abs(p.C - q.C) < tol;
}

void AddDistinct(std::vector<Line2>& lines, const Line2& l, double tol)
{
  for (const Line2& m : lines)
  {
    if (SameLine(m, l, tol))
    {
      return;
    }
  }
  lines.push_back(l);
}

double TriangleArea(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return 0.5 * Length(Cross(b - a, c - a));
}

// Side (+1/-1/0) of point p with respect to the plane through a, b, c.
int PlaneSide(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p)
{
  const Vec3 n = Normalized(Cross(b - a, c - a));
  const double d = Dot(n, p - a);
  return d > 1e-12 ? 1 : (d < -1e-12 ? -1 : 0);
}

bool AllOnOneSide(const Vec3& a, const Vec3& b, const Vec3& c, const std::vector<Vec3>& pts)
{
  bool pos = false, neg = false;
  for (const Vec3& p : pts)
  {
    const int s = PlaneSide(a, b, c, p);
    pos = pos || s > 0;
    neg = neg || s < 0;
  }
  return !(pos && neg);
}

// Point-in-polygon in the (x, z) plane (crossing number).
bool InsideXZ(double x, double z, const std::vector<Vec3>& poly)
{
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
  {
    const Vec3& a = poly[j];
    const Vec3& b = poly[i];
    if ((a.Z > z) != (b.Z > z))
    {
      const double xc = a.X + (z - a.Z) * (b.X - a.X) / (b.Z - a.Z);
      if (xc > x)
      {
        inside = !inside;
      }
    }
  }
  return inside;
}

double ShoelaceXZ(const std::vector<Vec3>& v)
{
  double twice = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    twice += a.X * b.Z - b.X * a.Z;
  }
  return 0.5 * std::abs(twice);
}

// Inside test of a point of a receiver's plane: project on the polygon's
// dominant axis plane and count crossings.
bool InsidePolygon3(const Vec3& p, const std::vector<Vec3>& poly, const Vec3& normal)
{
  int drop = 0;
  if (std::abs(normal.Y) >= std::abs(normal.X) && std::abs(normal.Y) >= std::abs(normal.Z))
    drop = 1;
  else if (std::abs(normal.Z) >= std::abs(normal.X))
    drop = 2;
  auto u = [&](const Vec3& v) { return drop == 0 ? v.Y : v.X; };
  auto w = [&](const Vec3& v) { return drop == 2 ? v.Y : v.Z; };
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
  {
    const Vec3& a = poly[j];
    const Vec3& b = poly[i];
    if ((w(a) > w(p)) != (w(b) > w(p)))
    {
      const double uc = u(a) + (w(p) - w(a)) * (u(b) - u(a)) / (w(b) - w(a));
      if (uc > u(p))
      {
        inside = !inside;
      }
    }
  }
  return inside;
}

struct MeshCheck
{
  double Area = 0.0;
  double MinArea = 1e300;
  int Outside = 0;
  int Clockwise = 0;
};

MeshCheck CheckMesh(const ReceiverMesh& mesh, const Surface& receiver)
{
  MeshCheck c;
  const PolygonGeometry g = ComputePolygonGeometry(receiver.Vertices);
  for (const auto& t : mesh.Triangles)
  {
    const Vec3 &a = mesh.Points[t[0]], &b = mesh.Points[t[1]], &d = mesh.Points[t[2]];
    const double area = TriangleArea(a, b, d);
    c.Area += area;
    c.MinArea = std::min(c.MinArea, area);
    if (Dot(Cross(b - a, d - a), g.Normal) <= 0.0)
    {
      ++c.Clockwise;
    }
    if (!InsidePolygon3((a + b + d) / 3.0, receiver.Vertices, g.Normal))
    {
      ++c.Outside;
    }
  }
  return c;
}

//------------------------------------------------------------------------------
// Square light [-0.5, 0.5]^2 at y = 2 facing down, parallel square occluder
// [-0.4, 0.4]^2 at y = 1, floor [-4, 4]^2 at y = 0. Every D1 line on the
// floor is the central projection of an occluder edge from a light vertex
// (equivalently of a light edge through an occluder vertex): the point
// 2 w - v for occluder corner w and light corner v. Lines x = 2 w_x - v_x and
// z = 2 w_z - v_z, i.e. x, z in {-1.3, -0.3, 0.3, 1.3}: the penumbra's outer
// square (+-1.3) and the umbra's square (+-0.3), the latter continued across
// the penumbra (those pieces are real slope discontinuities too: across
// them a strip of the light along one of its edges appears or disappears).
PENUMBRA_TEST(TestParallelOccluder)
{
  Scene scene;
  scene.Surfaces.push_back(Make(Square(0, 0, 0, 4, 4, true), RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make(Square(0, 2, 0, 0.5, 0.5, false), RGB(), RGB(10, 10, 10)));
  scene.Surfaces.push_back(Make(Square(0, 1, 0, 0.4, 0.4, true), RGB(0.5, 0.5, 0.5)));
  const double size = scene.Size();

  std::set<double> coords;
  std::vector<std::array<double, 2>> analytic;
  for (const Vec3& v : scene.Surfaces[1].Vertices)
  {
    for (const Vec3& w : scene.Surfaces[2].Vertices)
    {
      const Vec3 p = v + 2.0 * (w - v); // on y = 0
      PENUMBRA_EXPECT_NEAR(p.Y, 0.0, 1e-15);
      coords.insert(std::round(p.X * 1e9) / 1e9);
      analytic.push_back({ p.X, p.Z });
    }
  }
  PENUMBRA_EXPECT(coords.size() == 4); // -1.3, -0.3, 0.3, 1.3
  const double lo = *coords.begin(), hi = *coords.rbegin();
  // Both shadows exist: umbra half-width 0.3 > 0, penumbra half-width 1.3.
  PENUMBRA_EXPECT_NEAR(hi, 1.3, 1e-12);
  PENUMBRA_EXPECT_NEAR(*std::next(coords.begin(), 2), 0.3, 1e-12);

  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshSettings settings;
  DiscontinuityMeshStatistics stats;
  const ReceiverMesh mesh = mesher.MeshReceiver(0, settings, &stats);
  PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
  int shadow = 0, wrongOrder = 0, wrongSource = 0, offGrid = 0;
  double lengthX[4] = { 0, 0, 0, 0 }, lengthZ[4] = { 0, 0, 0, 0 };
  const std::vector<double> c(coords.begin(), coords.end());
  for (const DiscontinuitySegment& s : mesh.Segments)
  {
    if (s.Order == -1)
    {
      continue;
    }
    ++shadow;
    wrongOrder += s.Order != 1;
    wrongSource += s.SourceId != 1;
    for (const Vec3& p : { s.A, s.B })
    {
      double best = 1e300;
      for (const auto& q : analytic)
      {
        best = std::min(best, std::hypot(p.X - q[0], p.Z - q[1]));
      }
      offGrid += best > 1e-9 * size;
    }
    for (int k = 0; k < 4; ++k)
    {
      if (std::abs(s.A.X - c[k]) < 1e-9 && std::abs(s.B.X - c[k]) < 1e-9)
      {
        lengthX[k] += std::abs(s.B.Z - s.A.Z);
      }
      if (std::abs(s.A.Z - c[k]) < 1e-9 && std::abs(s.B.Z - c[k]) < 1e-9)
      {
        lengthZ[k] += std::abs(s.B.X - s.A.X);
      }
    }
  }
  // 8 lines, each cut in 3 by the 2 perpendicular lines crossing it inside.
  PENUMBRA_EXPECT(shadow == 24);
  PENUMBRA_EXPECT(wrongOrder == 0);
  PENUMBRA_EXPECT(wrongSource == 0);
  PENUMBRA_EXPECT(offGrid == 0);
  for (int k = 0; k < 4; ++k)
  {
    PENUMBRA_EXPECT_NEAR(lengthX[k], hi - lo, 1e-9 * size);
    PENUMBRA_EXPECT_NEAR(lengthZ[k], hi - lo, 1e-9 * size);
  }
  const MeshCheck check = CheckMesh(mesh, scene.Surfaces[0]);
  PENUMBRA_EXPECT_REL(check.Area, 64.0, 1e-9);
  PENUMBRA_EXPECT(check.Outside == 0);
  PENUMBRA_EXPECT(check.Clockwise == 0);
  PENUMBRA_EXPECT(check.MinArea > 0.0);
  std::printf("parallel occluder: %zu wedges, %zu pieces, %zu constraints, %zu triangles\n",
    stats.Wedges, stats.SegmentsGenerated, stats.Constraints, mesh.Triangles.size());

  // Before triangulation: the same lines as merged constraints (split only at
  // end points and T-junctions), all order 1, same total length.
  const std::vector<DiscontinuitySegment> boundaries = mesher.ComputeBoundaries(0, settings);
  double boundaryLength = 0.0, outlineLength = 0.0;
  int boundaryWrong = 0;
  for (const DiscontinuitySegment& s : boundaries)
  {
    (s.Order == -1 ? outlineLength : boundaryLength) += Length(s.B - s.A);
    boundaryWrong += s.Order != -1 && (s.Order != 1 || s.SourceId != 1 || s.PointA != -1);
  }
  PENUMBRA_EXPECT_NEAR(boundaryLength, 8 * (hi - lo), 1e-9 * size);
  PENUMBRA_EXPECT_NEAR(outlineLength, 32.0, 1e-12);
  PENUMBRA_EXPECT(boundaryWrong == 0);

  // The occluder and light receive nothing from each other here, but meshing
  // them must still work (outline only).
  const ReceiverMesh light = mesher.MeshReceiver(1, settings);
  PENUMBRA_EXPECT(light.Triangles.size() == 2);
  PENUMBRA_EXPECT_REL(CheckMesh(light, scene.Surfaces[1]).Area, 1.0, 1e-12);
}

//------------------------------------------------------------------------------
// The same with the occluder (half-size 0.45) rotated 30 degrees about the
// vertical: no edge is parallel, every line has order 2. Light and occluder
// lie in parallel planes, so from a floor point x the occluder's image on the
// light's plane is 2 w - x: the events are the edges of the translates
// "2 * occluder - light vertex" (EV: v with occluder edge ab -> segment
// [2a - v, 2b - v]) and "2 * occluder vertex - light" (VE: light edge pq with
// occluder vertex w -> [2w - p, 2w - q]), i.e. the arrangement of the
// Minkowski sum of the two polygons. A wedge is supporting when the plane
// through its three defining points has the whole light on one side and the
// whole occluder on one side; with InteriorEvents every wedge counts.
PENUMBRA_TEST(TestRotatedOccluder)
{
  const double yaw = 30.0 * M_PI / 180.0;
  Scene scene;
  scene.Surfaces.push_back(Make(Square(0, 0, 0, 4, 4, true), RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make(Square(0, 2, 0, 0.5, 0.5, false), RGB(), RGB(10, 10, 10)));
  scene.Surfaces.push_back(Make(Square(0, 1, 0, 0.45, 0.45, true, yaw), RGB(0.5, 0.5, 0.5)));
  const double size = scene.Size();
  const std::vector<Vec3>& light = scene.Surfaces[1].Vertices;
  const std::vector<Vec3>& occ = scene.Surfaces[2].Vertices;

  std::vector<Line2> supporting, all;
  for (std::size_t i = 0; i < 4; ++i)
  {
    for (std::size_t j = 0; j < 4; ++j)
    {
      // EV: light vertex i, occluder edge j.
      const Vec3 &v = light[i], &a = occ[j], &b = occ[(j + 1) % 4];
      const Vec3 pa = 2.0 * a - v, pb = 2.0 * b - v;
      const Line2 ev = LineThrough(pa.X, pa.Z, pb.X, pb.Z);
      AddDistinct(all, ev, 1e-9);
      if (AllOnOneSide(v, a, b, light) && AllOnOneSide(v, a, b, occ))
      {
        AddDistinct(supporting, ev, 1e-9);
      }
      // VE: light edge i, occluder vertex j.
      const Vec3 &p = light[i], &q = light[(i + 1) % 4], &w = occ[j];
      const Vec3 qa = 2.0 * w - p, qb = 2.0 * w - q;
      const Line2 ve = LineThrough(qa.X, qa.Z, qb.X, qb.Z);
      AddDistinct(all, ve, 1e-9);
      if (AllOnOneSide(p, q, w, light) && AllOnOneSide(p, q, w, occ))
      {
        AddDistinct(supporting, ve, 1e-9);
      }
    }
  }
  // For two convex quadrilaterals: per occluder edge 2 tangent light
  // vertices, per light edge 2 tangent occluder vertices: 8 + 8 distinct lines.
  PENUMBRA_EXPECT(supporting.size() == 16);
  PENUMBRA_EXPECT(all.size() == 32);

  DiscontinuityMesher mesher(scene);
  for (int interior = 0; interior < 2; ++interior)
  {
    DiscontinuityMeshSettings settings;
    settings.InteriorEvents = interior == 1;
    const std::vector<Line2>& expected = interior ? all : supporting;
    DiscontinuityMeshStatistics stats;
    const ReceiverMesh mesh = mesher.MeshReceiver(0, settings, &stats);
    PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
    std::vector<Line2> found;
    int unexpected = 0, wrongOrder = 0;
    for (const DiscontinuitySegment& s : mesh.Segments)
    {
      if (s.Order == -1)
      {
        continue;
      }
      wrongOrder += s.Order != 2;
      const Line2 l = LineThrough(s.A.X, s.A.Z, s.B.X, s.B.Z);
      AddDistinct(found, l, 1e-9 * size);
      bool match = false;
      for (const Line2& e : expected)
      {
        // Both end points on the analytic line.
        match = match ||
          (std::abs(e.A * s.A.X + e.B * s.A.Z - e.C) < 1e-9 * size &&
            std::abs(e.A * s.B.X + e.B * s.B.Z - e.C) < 1e-9 * size);
      }
      unexpected += !match;
    }
    PENUMBRA_EXPECT(found.size() == expected.size());
    PENUMBRA_EXPECT(unexpected == 0);
    PENUMBRA_EXPECT(wrongOrder == 0);
    const MeshCheck check = CheckMesh(mesh, scene.Surfaces[0]);
    PENUMBRA_EXPECT_REL(check.Area, 64.0, 1e-9);
    PENUMBRA_EXPECT(check.Outside == 0);
    PENUMBRA_EXPECT(check.MinArea > 0.0);
    std::printf("rotated occluder (%s): %zu distinct lines (expected %zu), %zu triangles\n",
      interior ? "all events" : "supporting", found.size(), expected.size(),
      mesh.Triangles.size());
  }
}

//------------------------------------------------------------------------------
// A closed box (top + 4 sides, no bottom) standing on the floor under a
// light, and a single wall standing on the floor (not closed).
PENUMBRA_TEST(TestContact)
{
  Scene scene;
  scene.Surfaces.push_back(Make(Square(0, 0, 0, 4, 4, true), RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make(Square(0, 2, 0, 0.5, 0.5, false), RGB(), RGB(10, 10, 10)));
  // Box x in [-0.3, 0.3], z in [-0.2, 0.4], height 0.5.
  const double x0 = -0.3, x1 = 0.3, z0 = -0.2, z1 = 0.4, h = 0.5;
  scene.Surfaces.push_back(Make(Square(0, h, 0.1, 0.3, 0.3, true), RGB(0.5, 0.5, 0.5)));
  const Vec3 b00(x0, 0, z0), b10(x1, 0, z0), b11(x1, 0, z1), b01(x0, 0, z1);
  const Vec3 t00(x0, h, z0), t10(x1, h, z0), t11(x1, h, z1), t01(x0, h, z1);
  // Outward normals: -z, +x, +z, -x.
  scene.Surfaces.push_back(Make({ b00, t00, t10, b10 }, RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make({ b10, t10, t11, b11 }, RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make({ b11, t11, t01, b01 }, RGB(0.5, 0.5, 0.5)));
  scene.Surfaces.push_back(Make({ b01, t01, t00, b00 }, RGB(0.5, 0.5, 0.5)));
  // A thin wall standing on the floor at x = 2, z in [-1, 1].
  scene.Surfaces.push_back(
    Make({ Vec3(2, 0, -1), Vec3(2, 0, 1), Vec3(2, 0.3, 1), Vec3(2, 0.3, -1) }, RGB(0.5, 0.5, 0.5)));
  for (std::size_t k = 3; k < 7; ++k)
  {
    const PolygonGeometry g = ComputePolygonGeometry(scene.Surfaces[k].Vertices);
    const Vec3 out = g.Centroid - Vec3(0, h / 2, 0.1);
    PENUMBRA_EXPECT(Dot(g.Normal, out) > 0.0); // sides face out
  }
  const std::vector<Vec3> footprint = { b00, b10, b11, b01 };
  const double footprintArea = ShoelaceXZ(footprint);
  PENUMBRA_EXPECT_NEAR(footprintArea, 0.36, 1e-15);

  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshSettings settings;
  DiscontinuityMeshStatistics stats;
  const ReceiverMesh mesh = mesher.MeshReceiver(0, settings, &stats);
  PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
  double footprintLength = 0.0, wallLength = 0.0;
  int contactOff = 0, shadows = 0;
  for (const DiscontinuitySegment& s : mesh.Segments)
  {
    if (s.Order == 0)
    {
      const bool onBox =
        (std::abs(s.A.X - s.B.X) < 1e-12 && (std::abs(s.A.X - x0) < 1e-12 || std::abs(s.A.X - x1) < 1e-12)) ||
        (std::abs(s.A.Z - s.B.Z) < 1e-12 && (std::abs(s.A.Z - z0) < 1e-12 || std::abs(s.A.Z - z1) < 1e-12));
      const bool onWall = std::abs(s.A.X - 2) < 1e-12 && std::abs(s.B.X - 2) < 1e-12;
      if (onBox)
      {
        footprintLength += Length(s.B - s.A);
      }
      else if (onWall)
      {
        wallLength += Length(s.B - s.A);
      }
      else
      {
        ++contactOff;
      }
      PENUMBRA_EXPECT(s.SourceId == -1);
    }
    else if (s.Order > 0)
    {
      ++shadows;
    }
  }
  PENUMBRA_EXPECT_NEAR(footprintLength, 2.4, 1e-12);
  PENUMBRA_EXPECT_NEAR(wallLength, 2.0, 1e-12);
  PENUMBRA_EXPECT(contactOff == 0);
  PENUMBRA_EXPECT(shadows > 0);
  int under = 0;
  for (const auto& t : mesh.Triangles)
  {
    const Vec3 c = (mesh.Points[t[0]] + mesh.Points[t[1]] + mesh.Points[t[2]]) / 3.0;
    under += InsideXZ(c.X, c.Z, footprint);
  }
  PENUMBRA_EXPECT(under == 0);
  const MeshCheck check = CheckMesh(mesh, scene.Surfaces[0]);
  PENUMBRA_EXPECT_REL(check.Area, 64.0 - footprintArea, 1e-9);
  PENUMBRA_EXPECT_REL(stats.RemovedArea, footprintArea, 1e-9);
  PENUMBRA_EXPECT(check.Outside == 0);
  PENUMBRA_EXPECT(check.MinArea > 0.0);

  // Points on the wall's contact line (strictly inside it) appear once per
  // side, and no triangle uses a point of the other side. Nothing crosses
  // that line, so refine (MinimumAngle) to put points inside it.
  DiscontinuityMeshSettings refine;
  refine.MinimumAngle = 20.0;
  DiscontinuityMeshStatistics refineStats;
  const ReceiverMesh fine = mesher.MeshReceiver(0, refine, &refineStats);
  PENUMBRA_EXPECT(refineStats.ConstraintFailures == 0);
  PENUMBRA_EXPECT_REL(CheckMesh(fine, scene.Surfaces[0]).Area, 64.0 - footprintArea, 1e-9);
  std::map<int, std::set<int>> copies;
  for (std::size_t p = 0; p < fine.Points.size(); ++p)
  {
    copies[fine.PointVertex[p]].insert(static_cast<int>(p));
  }
  int interiorWallVertices = 0, wellSplit = 0;
  for (const auto& entry : copies)
  {
    const Vec3 p = fine.Points[*entry.second.begin()];
    if (std::abs(p.X - 2) < 1e-12 && std::abs(p.Z) < 1 - 1e-9)
    {
      ++interiorWallVertices;
      wellSplit += entry.second.size() == 2;
    }
  }
  PENUMBRA_EXPECT(interiorWallVertices > 0);
  PENUMBRA_EXPECT(wellSplit == interiorWallVertices);
  // A triangle lies on one side of x = 2: its points on the line must be
  // that side's copies, so no point is shared by triangles of both sides.
  int crossing = 0;
  std::map<int, int> sideOfPoint; // point -> side (-1 / +1) of x = 2
  for (const auto& t : fine.Triangles)
  {
    const double cx = (fine.Points[t[0]].X + fine.Points[t[1]].X + fine.Points[t[2]].X) / 3.0;
    const int side = cx < 2 ? -1 : 1;
    for (int k = 0; k < 3; ++k)
    {
      const Vec3& p = fine.Points[t[k]];
      if (std::abs(p.X - 2) > 1e-12 || std::abs(p.Z) >= 1 - 1e-9)
      {
        continue;
      }
      auto it = sideOfPoint.find(t[k]);
      if (it == sideOfPoint.end())
      {
        sideOfPoint[t[k]] = side;
      }
      else
      {
        crossing += it->second != side;
      }
    }
  }
  PENUMBRA_EXPECT(crossing == 0);

  // Without contacts: no order-0 line and nothing removed.
  settings.Contacts = false;
  const ReceiverMesh plain = mesher.MeshReceiver(0, settings);
  int order0 = 0;
  for (const DiscontinuitySegment& s : plain.Segments)
  {
    order0 += s.Order == 0;
  }
  PENUMBRA_EXPECT(order0 == 0);
  PENUMBRA_EXPECT_REL(CheckMesh(plain, scene.Surfaces[0]).Area, 64.0, 1e-9);

  // An open box (no top) is not closed: the floor inside stays visible.
  Scene open = scene;
  open.Surfaces.erase(open.Surfaces.begin() + 2);
  const ReceiverMesh openMesh = DiscontinuityMesher(open).MeshReceiver(0, DiscontinuityMeshSettings());
  PENUMBRA_EXPECT_REL(CheckMesh(openMesh, open.Surfaces[0]).Area, 64.0, 1e-9);
}

//------------------------------------------------------------------------------
// Built-in scenes: every receiver meshed; no failed insertion, every triangle
// inside its receiver and counter-clockwise, area = receiver area minus the
// footprints of the blocks standing on it (Cornell floor), no zero area.
PENUMBRA_TEST(TestBuiltinScenes)
{
  struct Case
  {
    const char* Name;
    std::vector<int> Shooters;
  };
  const Case cases[] = { { "cornell", { 2 } }, { "seven", {} }, { "blind", {} },
    { "occluder", {} } };
  for (int variant = 0; variant < 3; ++variant)
  for (const Case& cs : cases)
  {
    const Scene scene = MakeBuiltinScene(cs.Name);
    DiscontinuityMesher mesher(scene);
    DiscontinuityMeshSettings settings;
    settings.Shooters = cs.Shooters;
    // Default settings, then all interior events, then quality refinement.
    settings.InteriorEvents = variant == 1;
    settings.MinimumAngle = variant == 2 ? 15.0 : 0.0;
    DiscontinuityMeshStatistics stats;
    const auto start = std::chrono::steady_clock::now();
    std::vector<ReceiverMesh> meshes;
    for (int r = 0; r < mesher.GetNumberOfSurfaces(); ++r)
    {
      meshes.push_back(mesher.MeshReceiver(r, settings, &stats));
    }
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
    PENUMBRA_EXPECT(stats.DroppedDegenerate == 0);
    int outside = 0, clockwise = 0, zero = 0, areaFailures = 0;
    std::size_t segments = 0;
    for (int r = 0; r < mesher.GetNumberOfSurfaces(); ++r)
    {
      const Surface& receiver = scene.Surfaces[r];
      const MeshCheck c = CheckMesh(meshes[r], receiver);
      outside += c.Outside;
      clockwise += c.Clockwise;
      zero += !(c.MinArea > 0.0);
      double expected = ComputePolygonGeometry(receiver.Vertices).Area;
      if (std::string(cs.Name) == "cornell" && r == 0)
      {
        // The two blocks stand on the floor: tops (surfaces 7 and 12)
        // projected on y = 0 are their footprints.
        expected -= ShoelaceXZ(scene.Surfaces[7].Vertices) + ShoelaceXZ(scene.Surfaces[12].Vertices);
      }
      if (testing::RelativeError(c.Area, expected) > 1e-9)
      {
        ++areaFailures;
        std::fprintf(stderr, "%s receiver %d: area %.17g expected %.17g\n", cs.Name, r, c.Area,
          expected);
      }
      for (const DiscontinuitySegment& s : meshes[r].Segments)
      {
        segments += s.Order >= 0;
      }
    }
    PENUMBRA_EXPECT(outside == 0);
    PENUMBRA_EXPECT(clockwise == 0);
    PENUMBRA_EXPECT(zero == 0);
    PENUMBRA_EXPECT(areaFailures == 0);
    PENUMBRA_EXPECT(segments > 0);
    std::printf("%-8s %-9s: %6.1f ms, %zu pairs, %zu wedges, %zu pieces generated, %zu kept, "
                "%zu contact, %zu constraints, %zu triangles, %zu points\n",
      cs.Name, variant == 0 ? "default" : (variant == 1 ? "interior" : "angle 15"), 1e3 * seconds, stats.Pairs, stats.Wedges, stats.SegmentsGenerated,
      stats.SegmentsKept, stats.ContactSegments, stats.Constraints, stats.Triangles, stats.Points);
  }

  // Cornell floor: the blocks' footprints are order-0 lines and nothing is
  // meshed under them.
  const Scene cornell = MakeBuiltinScene("cornell");
  DiscontinuityMesher mesher(cornell);
  DiscontinuityMeshSettings settings;
  settings.Shooters = { 2 };
  const ReceiverMesh floor = mesher.MeshReceiver(0, settings);
  double contactLength = 0.0;
  for (const DiscontinuitySegment& s : floor.Segments)
  {
    if (s.Order == 0)
    {
      contactLength += Length(s.B - s.A);
    }
  }
  double perimeter = 0.0;
  for (int top : { 7, 12 })
  {
    const auto& v = cornell.Surfaces[top].Vertices;
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      perimeter += Length(v[(i + 1) % v.size()] - v[i]);
    }
  }
  PENUMBRA_EXPECT_REL(contactLength, perimeter, 1e-9);
  int under = 0;
  for (const auto& t : floor.Triangles)
  {
    const Vec3 c = (floor.Points[t[0]] + floor.Points[t[1]] + floor.Points[t[2]]) / 3.0;
    under += InsideXZ(c.X, c.Z, cornell.Surfaces[7].Vertices) +
      InsideXZ(c.X, c.Z, cornell.Surfaces[12].Vertices);
  }
  PENUMBRA_EXPECT(under == 0);

  // Quality refinement keeps every constraint (same total boundary length)
  // and the area.
  auto boundaryLength = [](const ReceiverMesh& m) {
    double l = 0.0;
    for (const DiscontinuitySegment& s : m.Segments)
    {
      l += s.Order >= 0 ? Length(s.B - s.A) : 0.0;
    }
    return l;
  };
  settings.MinimumAngle = 20.0;
  DiscontinuityMeshStatistics refinedStats;
  const ReceiverMesh refined = mesher.MeshReceiver(0, settings, &refinedStats);
  PENUMBRA_EXPECT(refinedStats.ConstraintFailures == 0);
  PENUMBRA_EXPECT(refined.Triangles.size() > floor.Triangles.size());
  PENUMBRA_EXPECT_REL(boundaryLength(refined), boundaryLength(floor), 1e-9);
  PENUMBRA_EXPECT_REL(CheckMesh(refined, cornell.Surfaces[0]).Area,
    CheckMesh(floor, cornell.Surfaces[0]).Area, 1e-9);
  PENUMBRA_EXPECT(CheckMesh(refined, cornell.Surfaces[0]).Outside == 0);
  std::printf("cornell floor: %zu triangles, %zu with MinimumAngle 20\n", floor.Triangles.size(),
    refined.Triangles.size());

  // Same input, same output (no hidden state between calls).
  settings.MinimumAngle = 0.0;
  const ReceiverMesh again = mesher.MeshReceiver(0, settings);
  PENUMBRA_EXPECT(again.Triangles == floor.Triangles);
  PENUMBRA_EXPECT(again.Points.size() == floor.Points.size());
}

//------------------------------------------------------------------------------
// A concave (L-shaped) receiver with a shadow across its reflex corner: every
// triangle inside the L, area exact, shadow lines clipped to the L.
PENUMBRA_TEST(TestConcaveReceiver)
{
  Scene scene;
  const RGB grey(0.5, 0.5, 0.5);
  // Counter-clockwise seen from +y, like Square(): the quadrant x > 0, z < 0
  // is cut away.
  scene.Surfaces.push_back(Make({ Vec3(-2, 0, -2), Vec3(-2, 0, 2), Vec3(2, 0, 2), Vec3(2, 0, 0),
                                  Vec3(0, 0, 0), Vec3(0, 0, -2) },
    grey));
  scene.Surfaces.push_back(Make(Square(0.6, 2, -0.6, 0.3, 0.3, false), RGB(), RGB(10, 10, 10)));
  scene.Surfaces.push_back(Make(Square(0.3, 1, -0.3, 0.4, 0.25, true, 0.3), grey));
  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshStatistics stats;
  const ReceiverMesh mesh = mesher.MeshReceiver(0, DiscontinuityMeshSettings(), &stats);
  PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
  const MeshCheck check = CheckMesh(mesh, scene.Surfaces[0]);
  PENUMBRA_EXPECT_REL(check.Area, 12.0, 1e-9);
  PENUMBRA_EXPECT(check.Outside == 0);
  PENUMBRA_EXPECT(check.MinArea > 0.0);
  int shadow = 0, outside = 0;
  for (const DiscontinuitySegment& seg : mesh.Segments)
  {
    if (seg.Order < 0)
    {
      continue;
    }
    ++shadow;
    const Vec3 mid = 0.5 * (seg.A + seg.B);
    outside += mid.X > 1e-12 && mid.Z < -1e-12; // in the cut-away quadrant
  }
  PENUMBRA_EXPECT(shadow > 0);
  PENUMBRA_EXPECT(outside == 0);
}

//------------------------------------------------------------------------------
// A generated room: 64 boxes (top + 4 sides), randomly sized and rotated,
// standing on a floor on a jittered grid, and two lights. Many crossing
// shadows; the mesh must still cover exactly the floor minus the footprints.
// A 10 x 10 floor with 64 boxes (without bottom) of random size, height and
// yaw on a jittered grid, lit by two square lights at different heights. The
// boxes' footprints and their total area are returned too.
Scene RandomBoxes(std::vector<std::vector<Vec3>>& prints, double& footprints)
{
  Scene scene;
  const RGB grey(0.5, 0.5, 0.5);
  scene.Surfaces.push_back(Make(Square(0, 0, 0, 5, 5, true), grey));
  scene.Surfaces.push_back(Make(Square(-1, 3, 0.5, 0.6, 0.4, false), RGB(), RGB(10, 10, 10)));
  scene.Surfaces.push_back(Make(Square(1.5, 2.5, -1, 0.3, 0.3, false, 0.4), RGB(), RGB(20, 20, 20)));
  unsigned state = 12345u;
  auto random = [&state]() {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / 16777216.0;
  };
  footprints = 0.0;
  prints.clear();
  for (int i = 0; i < 8; ++i)
  {
    for (int j = 0; j < 8; ++j)
    {
      const double cx = -4.375 + 1.25 * i + 0.2 * (random() - 0.5);
      const double cz = -4.375 + 1.25 * j + 0.2 * (random() - 0.5);
      const double hx = 0.15 + 0.25 * random(), hz = 0.15 + 0.25 * random();
      const double h = 0.1 + 0.8 * random(), yaw = M_PI * random();
      const std::vector<Vec3> top = Square(cx, h, cz, hx, hz, true, yaw);
      std::vector<Vec3> bottom;
      for (const Vec3& t : top)
      {
        bottom.push_back(Vec3(t.X, 0.0, t.Z));
      }
      scene.Surfaces.push_back(Make(top, grey));
      // top is counter-clockwise seen from above: (b_k, t_k, t_k+1, b_k+1)
      // faces out.
      for (int k = 0; k < 4; ++k)
      {
        const int l = (k + 1) % 4;
        scene.Surfaces.push_back(Make({ bottom[k], top[k], top[l], bottom[l] }, grey));
      }
      footprints += ShoelaceXZ(bottom);
      prints.push_back(bottom);
    }
  }
  return scene;
}

PENUMBRA_TEST(TestRandomBoxes)
{
  std::vector<std::vector<Vec3>> prints;
  double footprints = 0.0;
  const Scene scene = RandomBoxes(prints, footprints);
  DiscontinuityMesher mesher(scene);
  for (int variant = 0; variant < 2; ++variant)
  {
    DiscontinuityMeshSettings settings;
    settings.InteriorEvents = variant == 1;
    DiscontinuityMeshStatistics stats;
    const auto start = std::chrono::steady_clock::now();
    const ReceiverMesh floor = mesher.MeshReceiver(0, settings, &stats);
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    PENUMBRA_EXPECT(stats.ConstraintFailures == 0);
    PENUMBRA_EXPECT(stats.DroppedDegenerate == 0);
    const MeshCheck check = CheckMesh(floor, scene.Surfaces[0]);
    PENUMBRA_EXPECT_REL(check.Area, 100.0 - footprints, 1e-9);
    // Shadow lines of several lights through a box's foot cross in clusters
    // of vertices a rounding error apart (clockwise once rounded, and a
    // gradient fitted over them divides by that distance): they are merged.
    double shortest = std::numeric_limits<double>::infinity();
    for (const auto& t : floor.Triangles)
    {
      for (int k = 0; k < 3; ++k)
      {
        shortest = std::min(shortest, Length(floor.Points[t[k]] - floor.Points[t[(k + 1) % 3]]));
      }
    }
    PENUMBRA_EXPECT(shortest >= 1e-7 * scene.Size());
    PENUMBRA_EXPECT(stats.MergedTriangles > 0);
    PENUMBRA_EXPECT_REL(stats.RemovedArea, footprints, 1e-9);
    PENUMBRA_EXPECT(check.Outside == 0);
    PENUMBRA_EXPECT(check.Clockwise == 0);
    PENUMBRA_EXPECT(check.MinArea > 0.0);
    int under = 0;
    for (const auto& t : floor.Triangles)
    {
      const Vec3 c = (floor.Points[t[0]] + floor.Points[t[1]] + floor.Points[t[2]]) / 3.0;
      for (const auto& p : prints)
      {
        under += InsideXZ(c.X, c.Z, p);
      }
    }
    PENUMBRA_EXPECT(under == 0);
    std::printf("random boxes (%s): %.1f ms, %zu wedges, %zu pieces, %zu constraints, %zu "
                "triangles\n",
      variant ? "interior" : "default", 1e3 * seconds, stats.Wedges, stats.SegmentsGenerated,
      stats.Constraints, stats.Triangles);
  }
}

//------------------------------------------------------------------------------
// Wedge culling (CullWedges) only skips wedges that leave nothing on the
// receiver, or only pieces the jump threshold drops: on every receiver of the
// built-in scenes and of the random boxes (box faces are small receivers,
// where most wedges are culled), with default settings, interior events, and
// a jump threshold, the boundaries are the same segments (same order and
// source, end points within 1e-9 of the scene size) with and without it, and
// no more wedges are traced with it (fewer than half on the boxes).
PENUMBRA_TEST(TestCullingKeepsBoundaries)
{
  std::vector<std::vector<Vec3>> prints;
  double footprints = 0.0;
  std::vector<std::pair<std::string, Scene>> scenes = { { "random boxes",
    RandomBoxes(prints, footprints) } };
  for (const char* name : { "cornell", "seven", "blind" })
  {
    scenes.emplace_back(name, MakeBuiltinScene(name));
  }
  for (const auto& named : scenes)
  {
    const Scene& scene = named.second;
    const double tol = 1e-9 * scene.Size();
    DiscontinuityMesher mesher(scene);
    for (int variant = 0; variant < 3; ++variant)
    {
      DiscontinuityMeshStatistics culled, traced;
      int unmatched = 0;
      std::size_t segments = 0;
      for (int r = 0; r < mesher.GetNumberOfSurfaces(); ++r)
      {
        DiscontinuityMeshSettings settings;
        settings.InteriorEvents = variant == 1;
        settings.JumpThreshold = variant == 2 ? 0.2 : 0.0;
        const std::vector<DiscontinuitySegment> with =
          mesher.ComputeBoundaries(r, settings, &culled);
        settings.CullWedges = false;
        const std::vector<DiscontinuitySegment> without =
          mesher.ComputeBoundaries(r, settings, &traced);
        segments += without.size();
        unmatched += static_cast<int>(with.size() > without.size() ? with.size() - without.size()
                                                                   : without.size() - with.size());
        std::vector<bool> used(without.size(), false);
        for (const DiscontinuitySegment& a : with)
        {
          bool found = false;
          for (std::size_t k = 0; k < without.size() && !found; ++k)
          {
            const DiscontinuitySegment& b = without[k];
            found = !used[k] && a.Order == b.Order && a.SourceId == b.SourceId &&
              ((Length(a.A - b.A) <= tol && Length(a.B - b.B) <= tol) ||
                (Length(a.A - b.B) <= tol && Length(a.B - b.A) <= tol));
            used[k] = found;
          }
          unmatched += found ? 0 : 1;
        }
      }
      std::printf("culling on %s (%s): %zu segments, %d unmatched; wedges traced %zu instead of "
                  "%zu\n",
        named.first.c_str(), variant == 0 ? "default" : (variant == 1 ? "interior" : "jump 0.2"),
        segments, unmatched, culled.Wedges, traced.Wedges);
      PENUMBRA_EXPECT(segments > 0);
      PENUMBRA_EXPECT(unmatched == 0);
      PENUMBRA_EXPECT(culled.SegmentsGenerated <= traced.SegmentsGenerated);
      PENUMBRA_EXPECT(culled.SegmentsKept == traced.SegmentsKept);
      PENUMBRA_EXPECT(culled.Wedges <= traced.Wedges);
      // Among many small receivers most wedges miss: culling must show.
      PENUMBRA_EXPECT(named.first != "random boxes" || 2 * culled.Wedges < traced.Wedges);
    }
  }
}

//------------------------------------------------------------------------------
// Completeness of the slope discontinuities, against an independent oracle:
// the exact visible form factor (penumbraExactEvaluator: visible part of the
// light by polygon clipping, Lambert's formula) sampled along transects of
// the Cornell floor. A slope jump J between samples makes the second
// difference spike (~ J h) above its smooth neighbours (~ F'' h^2); every such
// spike must lie on an order-0 or order-1 line of the mesh. Conversely the
// order-1 lines crossed are counted with and without a spike (face-plane and
// parallel-edge lines: D1 by construction).
PENUMBRA_TEST(TestSlopeJumpsOnCornellFloor)
{
  const Scene scene = MakeBuiltinScene("cornell");
  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshSettings settings;
  settings.Shooters = { 2 };
  const ReceiverMesh floor = mesher.MeshReceiver(0, settings);
  ExactEvaluator evaluator(scene);
  VisibilityWorkspace workspace;
  const Vec3 up(0, 1, 0);
  const int n = 4000;
  int spikes = 0, explained = 0, d1Crossed = 0, d1WithSpike = 0;
  for (int transect = 0; transect < 10; ++transect)
  {
    // Five transects along x (fixed z), five along z (fixed x), inside the
    // floor, avoiding its outline.
    const bool alongX = transect < 5;
    const double fixed = 0.06 + 0.1 * (transect % 5) + 0.013;
    const double lo = 0.002, hi = 0.548;
    const double h = (hi - lo) / n;
    auto at = [&](double t) { return alongX ? Vec3(t, 0, fixed) : Vec3(fixed, 0, t); };
    std::vector<double> f(n + 1);
    for (int i = 0; i <= n; ++i)
    {
      f[i] = evaluator.FormFactor(at(lo + i * h), up, 0, 2, workspace);
    }
    // Crossings of the transect with order-0/1 segments of the mesh.
    std::vector<std::pair<double, int>> crossings;
    for (const DiscontinuitySegment& seg : floor.Segments)
    {
      if (seg.Order < 0 || seg.Order > 1)
      {
        continue;
      }
      const double a0 = alongX ? seg.A.Z : seg.A.X, b0 = alongX ? seg.B.Z : seg.B.X;
      if ((a0 - fixed) * (b0 - fixed) > 0.0 || a0 == b0)
      {
        continue;
      }
      const double u = (fixed - a0) / (b0 - a0);
      const double a1 = alongX ? seg.A.X : seg.A.Z, b1 = alongX ? seg.B.X : seg.B.Z;
      crossings.push_back({ a1 + u * (b1 - a1), seg.Order });
    }
    std::vector<double> d2(n + 1, 0.0);
    for (int i = 1; i < n; ++i)
    {
      d2[i] = f[i + 1] - 2.0 * f[i] + f[i - 1];
    }
    std::vector<bool> spike(n + 1, false);
    for (int i = 4; i + 4 <= n; ++i)
    {
      const double around = std::max(std::abs(d2[i - 3]), std::abs(d2[i + 3]));
      if (std::abs(d2[i]) > 8.0 * around && std::abs(d2[i]) > 1e-12 &&
        std::abs(d2[i]) >= std::abs(d2[i - 1]) && std::abs(d2[i]) >= std::abs(d2[i + 1]))
      {
        spike[i] = true;
        ++spikes;
        const double t = lo + i * h;
        bool near = false;
        for (const auto& c : crossings)
        {
          near = near || std::abs(c.first - t) <= 1.5 * h;
        }
        explained += near;
        if (!near)
        {
          std::fprintf(stderr, "unexplained slope jump on the Cornell floor at (%g, %g)\n",
            at(t).X, at(t).Z);
        }
      }
    }
    for (const auto& c : crossings)
    {
      const int i = static_cast<int>(std::lround((c.first - lo) / h));
      if (c.second != 1 || i < 4 || i + 4 > n)
      {
        continue;
      }
      ++d1Crossed;
      d1WithSpike += spike[i - 1] || spike[i] || spike[i + 1];
    }
  }
  PENUMBRA_EXPECT(spikes > 10);
  PENUMBRA_EXPECT(explained == spikes);
  std::printf("cornell floor transects: %d slope jumps, %d on mesh lines; %d D1 lines crossed, "
              "%d with a detected jump\n",
    spikes, explained, d1Crossed, d1WithSpike);
}

//------------------------------------------------------------------------------
PENUMBRA_TEST(TestJumpThresholdAndErrors)
{
  const Scene scene = MakeBuiltinScene("seven");
  DiscontinuityMesher mesher(scene);
  DiscontinuityMeshSettings settings;
  DiscontinuityMeshStatistics all, some;
  mesher.MeshReceiver(0, settings, &all);
  PENUMBRA_EXPECT(all.SegmentsKept == all.SegmentsGenerated);
  // The seven boxes' shadows are all strong (each hides much of the light):
  // only a threshold near the floor's own light drops some.
  settings.JumpThreshold = 0.5;
  const ReceiverMesh thin = mesher.MeshReceiver(0, settings, &some);
  PENUMBRA_EXPECT(some.SegmentsGenerated <= all.SegmentsGenerated);
  PENUMBRA_EXPECT(some.SegmentsKept < some.SegmentsGenerated);
  PENUMBRA_EXPECT(some.SegmentsKept > 0);
  PENUMBRA_EXPECT(some.Triangles < all.Triangles);
  PENUMBRA_EXPECT_REL(CheckMesh(thin, scene.Surfaces[0]).Area, 36.0, 1e-9);
  std::printf("seven floor: jump threshold 0.5 keeps %zu of %zu pieces\n", some.SegmentsKept,
    some.SegmentsGenerated);
  settings.JumpThreshold = 1.0;
  DiscontinuityMeshStatistics fewer;
  mesher.MeshReceiver(0, settings, &fewer);
  PENUMBRA_EXPECT(fewer.SegmentsKept < some.SegmentsKept);

  DiscontinuityMeshSettings bad;
  PENUMBRA_EXPECT_THROW(mesher.MeshReceiver(99, bad), InputError, "receiver id 99");
  bad.MinimumAngle = 30.0;
  PENUMBRA_EXPECT_THROW(mesher.MeshReceiver(0, bad), InputError, "MinimumAngle");
  bad = DiscontinuityMeshSettings();
  bad.Shooters = { -1 };
  PENUMBRA_EXPECT_THROW(mesher.MeshReceiver(0, bad), InputError, "shooter id -1");
  bad = DiscontinuityMeshSettings();
  bad.Shooters = { 1 };
  bad.ShooterRadiance = { RGB(1, 1, 1), RGB(1, 1, 1) };
  PENUMBRA_EXPECT_THROW(mesher.MeshReceiver(0, bad), InputError, "ShooterRadiance");
  Scene broken = scene;
  broken.Surfaces[3].Vertices.resize(2);
  PENUMBRA_EXPECT_THROW(DiscontinuityMesher{ broken }, InputError, "cell 3");
}

} // namespace
