// SPDX-License-Identifier: GPL-3.0-or-later
// Checks the built-in scenes against facts computed here independently: the
// measured Cornell data (shoelace, Heron, edge x height), planarity, facing,
// and for the paper scenes their documented sizes, an O(1) unoccluded floor
// radiance (Lambert's formula) and the shadows they are meant to cast.
#include "penumbraSceneLibrary.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <set>

using namespace penumbra;

namespace
{

// Largest distance of a vertex from the plane through the three vertices
// spanning the largest triangle (so the plane is well conditioned).
double PlanarityError(const std::vector<Vec3>& v)
{
  const std::size_t n = v.size();
  Vec3 best;
  std::size_t ia = 0;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      for (std::size_t c = b + 1; c < n; ++c)
      {
        const Vec3 cr = Cross(v[b] - v[a], v[c] - v[a]);
        if (Length(cr) > Length(best))
        {
          best = cr;
          ia = a;
        }
      }
  const Vec3 normal = Normalized(best);
  double worst = 0.0;
  for (const Vec3& p : v)
  {
    worst = std::max(worst, std::abs(Dot(normal, p - v[ia])));
  }
  return worst;
}

// Shoelace area of a polygon projected on the coordinate plane (i, j).
double Shoelace(const std::vector<Vec3>& v, int i, int j)
{
  double twice = 0.0;
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    const Vec3& a = v[k];
    const Vec3& b = v[(k + 1) % v.size()];
    twice += a[i] * b[j] - b[i] * a[j];
  }
  return 0.5 * std::abs(twice);
}

double Heron(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const double x = Length(b - a), y = Length(c - b), z = Length(a - c);
  const double s = 0.5 * (x + y + z);
  return std::sqrt(s * (s - x) * (s - y) * (s - z));
}

double Distance2D(double x0, double z0, double x1, double z1)
{
  return std::hypot(x1 - x0, z1 - z0);
}

// Point-to-polygon form factor (design.md section 4) for a polygon wholly in
// front of the receiving point.
double FormFactor(const Vec3& x, const Vec3& n, const std::vector<Vec3>& poly)
{
  double sum = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k)
  {
    const Vec3 r0 = poly[k] - x, r1 = poly[(k + 1) % poly.size()] - x;
    const Vec3 c = Cross(r0, r1);
    const double gamma = std::acos(std::clamp(Dot(r0, r1) / (Length(r0) * Length(r1)), -1.0, 1.0));
    sum += gamma * Dot(n, c) / Length(c);
  }
  return std::abs(sum) / (2.0 * M_PI);
}

// Whether the open segment p-q crosses the convex polygon.
bool SegmentHits(const Vec3& p, const Vec3& q, const std::vector<Vec3>& poly)
{
  const PolygonGeometry g = ComputePolygonGeometry(poly);
  const double dp = Dot(g.Normal, p) - g.Offset, dq = Dot(g.Normal, q) - g.Offset;
  if ((dp > 0) == (dq > 0) || dp == dq)
  {
    return false;
  }
  const Vec3 x = p + (q - p) * (dp / (dp - dq));
  for (std::size_t k = 0; k < poly.size(); ++k)
  {
    const Vec3& a = poly[k];
    const Vec3& b = poly[(k + 1) % poly.size()];
    if (Dot(g.Normal, Cross(b - a, x - a)) < 0)
    {
      return false;
    }
  }
  return true;
}

bool Equal(const RGB& a, double r, double g, double b)
{
  return a.R == r && a.G == g && a.B == b;
}

bool Same(const Vec3& a, const Vec3& b)
{
  return Length(a - b) < 1e-12;
}

// Index of the surface with exactly the vertex set `v` (any order), or -1.
int FindSurface(const Scene& scene, const std::vector<Vec3>& v)
{
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    const std::vector<Vec3>& s = scene.Surfaces[i].Vertices;
    bool all = s.size() == v.size();
    for (std::size_t k = 0; all && k < v.size(); ++k)
    {
      all = std::any_of(s.begin(), s.end(), [&](const Vec3& p) { return Same(p, v[k]); });
    }
    if (all)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

Vec3 Mm(double x, double y, double z)
{
  return { x / 1000.0, y / 1000.0, z / 1000.0 };
}

void CheckCommon(const std::string& name, const Scene& scene)
{
  bool valid = true;
  try
  {
    ValidateScene(scene);
  }
  catch (const InputError& e)
  {
    valid = false;
    std::cerr << name << ": " << e.what() << std::endl;
  }
  PENUMBRA_EXPECT(valid);
  PENUMBRA_EXPECT(!scene.Surfaces.empty());
  for (const Surface& s : scene.Surfaces)
  {
    const double diameter = ComputePolygonGeometry(s.Vertices).Diameter;
    PENUMBRA_EXPECT(PlanarityError(s.Vertices) <= 1e-12 * std::max(1.0, diameter));
  }
}

PENUMBRA_TEST(TestCornell)
{
  const Scene scene = MakeBuiltinScene("cornell");
  CheckCommon("cornell", scene);
  PENUMBRA_EXPECT(scene.Surfaces.size() == 17);

  struct Expected
  {
    std::vector<Vec3> Vertices;
    double Area;
    int Kind; // 0 room, 1 short block, 2 tall block
  };
  std::vector<Expected> expected;
  const std::vector<Vec3> floor = { Mm(552.8, 0, 0), Mm(0, 0, 0), Mm(0, 0, 559.2),
    Mm(549.6, 0, 559.2) };
  const std::vector<Vec3> ceiling = { Mm(556, 548.8, 0), Mm(556, 548.8, 559.2),
    Mm(0, 548.8, 559.2), Mm(0, 548.8, 0) };
  const std::vector<Vec3> light = { Mm(343, 548.3, 227), Mm(343, 548.3, 332),
    Mm(213, 548.3, 332), Mm(213, 548.3, 227) };
  const std::vector<Vec3> back = { Mm(549.6, 0, 559.2), Mm(0, 0, 559.2), Mm(0, 548.8, 559.2),
    Mm(556, 548.8, 559.2) };
  const std::vector<Vec3> right = { Mm(0, 0, 559.2), Mm(0, 0, 0), Mm(0, 548.8, 0),
    Mm(0, 548.8, 559.2) };
  const Vec3 l0 = Mm(552.8, 0, 0), l1 = Mm(549.6, 0, 559.2), l2 = Mm(556, 548.8, 559.2),
             l3 = Mm(556, 548.8, 0);
  expected.push_back({ floor, Shoelace(floor, 0, 2), 0 });
  expected.push_back({ ceiling, Shoelace(ceiling, 0, 2), 0 });
  expected.push_back({ light, 0.13 * 0.105, 0 });
  expected.push_back({ back, Shoelace(back, 0, 1), 0 });
  expected.push_back({ right, 0.5592 * 0.5488, 0 });
  expected.push_back({ { l0, l1, l2 }, Heron(l0, l1, l2), 0 });
  expected.push_back({ { l0, l2, l3 }, Heron(l0, l2, l3), 0 });
  // The left wall really is twisted: the split is needed.
  PENUMBRA_EXPECT(PlanarityError({ l0, l1, l2, l3 }) > 0.003);

  const double blocks[2][4][2] = { { { 130, 65 }, { 82, 225 }, { 240, 272 }, { 290, 114 } },
    { { 423, 247 }, { 265, 296 }, { 314, 456 }, { 472, 406 } } };
  const double heights[2] = { 165, 330 };
  Vec3 blockCentre[2];
  for (int b = 0; b < 2; ++b)
  {
    const double h = heights[b];
    std::vector<Vec3> top;
    for (int i = 0; i < 4; ++i)
    {
      top.push_back(Mm(blocks[b][i][0], h, blocks[b][i][1]));
      blockCentre[b] += Mm(blocks[b][i][0], h / 2, blocks[b][i][1]) * 0.25;
    }
    expected.push_back({ top, Shoelace(top, 0, 2), b + 1 });
    for (int i = 0; i < 4; ++i)
    {
      const double* p = blocks[b][i];
      const double* q = blocks[b][(i + 1) % 4];
      expected.push_back({ { Mm(p[0], h, p[1]), Mm(p[0], 0, p[1]), Mm(q[0], 0, q[1]),
                             Mm(q[0], h, q[1]) },
        Distance2D(p[0], p[1], q[0], q[1]) * h / 1e6, b + 1 });
    }
  }

  const Vec3 roomCentre = Mm(278, 274.4, 279.6);
  std::set<int> matched;
  for (const Expected& e : expected)
  {
    const int i = FindSurface(scene, e.Vertices);
    PENUMBRA_EXPECT(i >= 0);
    if (i < 0)
    {
      continue;
    }
    matched.insert(i);
    const PolygonGeometry g = ComputePolygonGeometry(scene.Surfaces[i].Vertices);
    PENUMBRA_EXPECT_REL(g.Area, e.Area, 1e-12);
    if (e.Kind == 0)
    {
      PENUMBRA_EXPECT(Dot(g.Normal, roomCentre - g.Centroid) > 0.2);
    }
    else
    {
      PENUMBRA_EXPECT(Dot(g.Normal, g.Centroid - blockCentre[e.Kind - 1]) > 0.02);
    }
  }
  PENUMBRA_EXPECT(matched.size() == 17);

  // Exactly one emitter: the light, facing down, with the documented materials.
  int emitters = 0;
  for (const Surface& s : scene.Surfaces)
  {
    if (!s.Emission.IsZero())
    {
      ++emitters;
      PENUMBRA_EXPECT(FindSurface(scene, light) >= 0 &&
        &s == &scene.Surfaces[FindSurface(scene, light)]);
      PENUMBRA_EXPECT(Equal(s.Emission, 17, 12, 4));
      PENUMBRA_EXPECT(Equal(s.Reflectance, 0.78, 0.78, 0.78));
      PENUMBRA_EXPECT_NEAR(ComputePolygonGeometry(s.Vertices).Normal.Y, -1.0, 1e-15);
    }
  }
  PENUMBRA_EXPECT(emitters == 1);
  const Surface& floorSurface = scene.Surfaces[FindSurface(scene, floor)];
  PENUMBRA_EXPECT(Equal(floorSurface.Reflectance, 0.725, 0.71, 0.68));
  const Surface& red = scene.Surfaces[FindSurface(scene, { l0, l1, l2 })];
  PENUMBRA_EXPECT(Equal(red.Reflectance, 0.63, 0.065, 0.05));
  const Surface& green = scene.Surfaces[FindSurface(scene, right)];
  PENUMBRA_EXPECT(Equal(green.Reflectance, 0.14, 0.45, 0.091));
}

// Rectangle check: right angles and area = product of edge lengths.
void CheckRectangle(const std::vector<Vec3>& v, double expectedArea)
{
  PENUMBRA_EXPECT(v.size() == 4);
  if (v.size() != 4)
  {
    return;
  }
  for (int k = 0; k < 4; ++k)
  {
    const Vec3 e0 = v[(k + 1) % 4] - v[k], e1 = v[(k + 3) % 4] - v[k];
    PENUMBRA_EXPECT(std::abs(Dot(e0, e1)) <= 1e-12 * Length(e0) * Length(e1));
  }
  const double area = Length(v[1] - v[0]) * Length(v[3] - v[0]);
  PENUMBRA_EXPECT_REL(area, expectedArea, 1e-12);
  PENUMBRA_EXPECT_REL(ComputePolygonGeometry(v).Area, expectedArea, 1e-12);
}

// Shared layout of the paper scenes: surface 0 the floor at y = 0 facing up,
// surface 1 the only emitter facing down, the rest occluders between them
// (facing up, toward the light). Returns the unoccluded floor radiance
// rho * Le * F below the emitter's centre.
double CheckPaperScene(const std::string& name, const std::vector<double>& areas)
{
  const Scene scene = MakeBuiltinScene(name);
  CheckCommon(name, scene);
  PENUMBRA_EXPECT(scene.Surfaces.size() == areas.size());
  if (scene.Surfaces.size() != areas.size())
  {
    return 0.0;
  }
  for (std::size_t i = 0; i < areas.size(); ++i)
  {
    CheckRectangle(scene.Surfaces[i].Vertices, areas[i]);
    PENUMBRA_EXPECT(scene.Surfaces[i].Emission.IsZero() == (i != 1));
  }
  const PolygonGeometry floor = ComputePolygonGeometry(scene.Surfaces[0].Vertices);
  const PolygonGeometry light = ComputePolygonGeometry(scene.Surfaces[1].Vertices);
  PENUMBRA_EXPECT_NEAR(floor.Normal.Y, 1.0, 1e-15);
  PENUMBRA_EXPECT_NEAR(light.Normal.Y, -1.0, 1e-15);
  for (const Vec3& p : scene.Surfaces[0].Vertices)
  {
    PENUMBRA_EXPECT(p.Y == 0.0);
  }
  for (std::size_t i = 2; i < scene.Surfaces.size(); ++i)
  {
    PENUMBRA_EXPECT(ComputePolygonGeometry(scene.Surfaces[i].Vertices).Normal.Y > 0.1);
    for (const Vec3& p : scene.Surfaces[i].Vertices)
    {
      PENUMBRA_EXPECT(p.Y > 0.05 && p.Y < light.Centroid.Y - 0.05);
    }
  }
  const Vec3 below(light.Centroid.X, 0, light.Centroid.Z);
  const double radiance = scene.Surfaces[0].Reflectance.Mean() *
    scene.Surfaces[1].Emission.Mean() * FormFactor(below, floor.Normal, scene.Surfaces[1].Vertices);
  PENUMBRA_EXPECT(radiance > 0.3 && radiance < 3.0);
  return radiance;
}

// Per floor point on the segment z = 0, x in [x0, x1], whether any sample
// point of the light is blocked, and which occluders block.
std::vector<std::set<std::size_t>> Blockers(
  const Scene& scene, const Vec3& floorPoint, const std::vector<Vec3>& lightSamples)
{
  std::vector<std::set<std::size_t>> result(lightSamples.size());
  for (std::size_t s = 0; s < lightSamples.size(); ++s)
  {
    for (std::size_t i = 2; i < scene.Surfaces.size(); ++i)
    {
      if (SegmentHits(floorPoint, lightSamples[s], scene.Surfaces[i].Vertices))
      {
        result[s].insert(i);
      }
    }
  }
  return result;
}

// Light sample points: a 5 x 5 grid over the (parallelogram) light.
std::vector<Vec3> LightSamples(const std::vector<Vec3>& light)
{
  std::vector<Vec3> samples;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
    {
      samples.push_back(light[0] + (light[1] - light[0]) * (i / 4.0) +
        (light[3] - light[0]) * (j / 4.0));
    }
  return samples;
}

PENUMBRA_TEST(TestPaperScenes)
{
  // strip: floor 4 x 4, strip 3 x 0.1 at height 1.
  const double strip = CheckPaperScene("strip", { 16.0, 0.3 });
  // Closed form of F for a thin strip: (2b/pi) * integral of h^2/(x^2+h^2)^2
  // over |x| < a, here with a = 1.5, h = 1 (b = 0.05 makes it accurate to 0.3 %).
  const double a = 1.5;
  const double integral = 2.0 * (a / (2.0 * (a * a + 1.0)) + 0.5 * std::atan(a));
  PENUMBRA_EXPECT_REL(strip, 0.7 * 30.0 * (0.1 / M_PI) * integral, 3e-3);

  // occluder: floor, light 0.5 x 0.5 at 2, occluder 0.6 x 0.6 at 1.
  CheckPaperScene("occluder", { 16.0, 0.25, 0.36 });
  {
    const Scene scene = MakeBuiltinScene("occluder");
    PENUMBRA_EXPECT_NEAR(ComputePolygonGeometry(scene.Surfaces[2].Vertices).Normal.Y, 1.0, 1e-15);
    // Umbra |x| < 0.35, penumbra to 0.85 (corners of the light as samples).
    const std::vector<Vec3>& corners = scene.Surfaces[1].Vertices;
    for (double x : { 0.0, 0.34, 0.36, 0.84, 0.86 })
    {
      const auto blocked = Blockers(scene, Vec3(x, 0, 0), corners);
      const auto count = std::count_if(
        blocked.begin(), blocked.end(), [](const std::set<std::size_t>& b) { return !b.empty(); });
      PENUMBRA_EXPECT(count == (x < 0.35 ? 4 : (x < 0.85 ? 2 : 0)));
    }
  }

  // seven: floor 6 x 6, light 0.6 x 0.3, occluders 2hx x 2hz.
  const double halves[7][2] = { { 0.15, 0.12 }, { 0.12, 0.12 }, { 0.15, 0.10 }, { 0.12, 0.12 },
    { 0.14, 0.14 }, { 0.12, 0.10 }, { 0.15, 0.12 } };
  std::vector<double> areas = { 36.0, 0.18 };
  for (const auto& h : halves)
  {
    areas.push_back(4.0 * h[0] * h[1]);
  }
  CheckPaperScene("seven", areas);
  {
    const Scene scene = MakeBuiltinScene("seven");
    std::set<double> heights;
    int rotated = 0, tilted = 0;
    for (std::size_t i = 2; i < scene.Surfaces.size(); ++i)
    {
      const std::vector<Vec3>& v = scene.Surfaces[i].Vertices;
      const PolygonGeometry g = ComputePolygonGeometry(v);
      heights.insert(std::round(g.Centroid.Y * 100.0));
      tilted += g.Normal.Y < std::cos(10.0 * M_PI / 180.0);
      const Vec3 e = Normalized(Vec3(v[1].X - v[0].X, 0, v[1].Z - v[0].Z));
      rotated += std::abs(e.X) > 0.05 && std::abs(e.Z) > 0.05;
      // Footprints (xz boxes) pairwise disjoint: no intersections.
      for (std::size_t j = 2; j < i; ++j)
      {
        double loI = 1e9, hiI = -1e9, loJ = 1e9, hiJ = -1e9;
        for (const Vec3& p : v)
        {
          loI = std::min(loI, p.X);
          hiI = std::max(hiI, p.X);
        }
        for (const Vec3& p : scene.Surfaces[j].Vertices)
        {
          loJ = std::min(loJ, p.X);
          hiJ = std::max(hiJ, p.X);
        }
        PENUMBRA_EXPECT(hiI < loJ || hiJ < loI);
      }
    }
    PENUMBRA_EXPECT(heights.size() >= 5);
    PENUMBRA_EXPECT(rotated >= 2);
    PENUMBRA_EXPECT(tilted >= 2);
    // Overlapping shadows: floor points where two different occluders each
    // hide part of the light; and every occluder casts a shadow on the floor.
    const std::vector<Vec3> samples = LightSamples(scene.Surfaces[1].Vertices);
    int overlapPoints = 0;
    std::set<std::size_t> casting;
    for (double x = -2.9; x <= 2.9; x += 0.05)
      for (double z = -1.0; z <= 1.0; z += 0.05)
      {
        std::set<std::size_t> all;
        for (const auto& b : Blockers(scene, Vec3(x, 0, z), samples))
        {
          all.insert(b.begin(), b.end());
        }
        casting.insert(all.begin(), all.end());
        overlapPoints += all.size() >= 2;
      }
    PENUMBRA_EXPECT(casting.size() == 7);
    PENUMBRA_EXPECT(overlapPoints > 20);
  }

  // blind: floor 4 x 4, light 0.1 x 1.6, 11 slats 0.08 x 1.6.
  areas = { 16.0, 0.16 };
  areas.insert(areas.end(), 11, 0.08 * 1.6);
  CheckPaperScene("blind", areas);
  {
    const Scene scene = MakeBuiltinScene("blind");
    const Vec3 n0 = ComputePolygonGeometry(scene.Surfaces[2].Vertices).Normal;
    PENUMBRA_EXPECT_NEAR(std::acos(n0.Y) * 180.0 / M_PI, 30.0, 1e-9);
    for (std::size_t i = 2; i < scene.Surfaces.size(); ++i)
    {
      const PolygonGeometry g = ComputePolygonGeometry(scene.Surfaces[i].Vertices);
      PENUMBRA_EXPECT(Length(g.Normal - n0) < 1e-12); // parallel slats
      PENUMBRA_EXPECT_NEAR(g.Centroid.X, -0.6 + 0.12 * (i - 2), 1e-12);
    }
    // Thin stripes: along z = 0 under the blind, count runs of floor points
    // that see the whole light (every sample unblocked), separated by slat
    // shadows that hide all of it: each of the 10 gaps between slats gives
    // one stripe (their images on the floor are 1.25 times wider apart).
    const std::vector<Vec3> samples = LightSamples(scene.Surfaces[1].Vertices);
    int stripes = 0, dark = 0;
    bool inStripe = false;
    for (double x = -0.7; x <= 0.7; x += 0.0005)
    {
      int blocked = 0;
      for (const auto& b : Blockers(scene, Vec3(x, 0, 0), samples))
      {
        blocked += !b.empty();
      }
      const bool lit = blocked == 0;
      stripes += lit && !inStripe;
      inStripe = lit;
      dark += blocked == static_cast<int>(samples.size());
    }
    PENUMBRA_EXPECT(stripes == 10);
    PENUMBRA_EXPECT(dark > 0);
  }
}

} // namespace

// The list of built-in scenes, the checks common to all, unknown names.
PENUMBRA_TEST(TestBuiltinList)
{
  const std::vector<BuiltinSceneInfo> list = ListBuiltinScenes();
  PENUMBRA_EXPECT(list.size() == 5);
  std::set<std::string> names;
  for (const BuiltinSceneInfo& info : list)
  {
    names.insert(info.Name);
    PENUMBRA_EXPECT(!info.Description.empty());
    CheckCommon(info.Name, MakeBuiltinScene(info.Name));
  }
  PENUMBRA_EXPECT(
    names == std::set<std::string>({ "cornell", "strip", "occluder", "seven", "blind" }));
  for (const std::string& name : names)
  {
    PENUMBRA_EXPECT_THROW(MakeBuiltinScene("nope"), InputError, name);
  }
  PENUMBRA_EXPECT_THROW(MakeBuiltinScene("nope"), InputError, "unknown built-in scene 'nope'");
}
