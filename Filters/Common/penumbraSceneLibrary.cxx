// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSceneLibrary.h"

#include "penumbraMath.h"

#include <cmath>

namespace penumbra
{

namespace
{

const RGB kBlack(0.0, 0.0, 0.0);
const RGB kFloorGrey(0.7, 0.7, 0.7);
const RGB kOccluderGrey(0.5, 0.5, 0.5);
const RGB kCornellWhite(0.725, 0.71, 0.68);
const RGB kCornellRed(0.63, 0.065, 0.05);
const RGB kCornellGreen(0.14, 0.45, 0.091);
const RGB kCornellLightReflectance(0.78, 0.78, 0.78);
const RGB kCornellLightEmission(17.0, 12.0, 4.0);

constexpr double kDegree = Pi / 180.0;

// Measured Cornell data are in millimetres; dividing (rather than multiplying
// by 1e-3) gives the correctly rounded metre value.
Vec3 Mm(double x, double y, double z)
{
  return { x / 1000.0, y / 1000.0, z / 1000.0 };
}

void Add(Scene& scene, std::vector<Vec3> vertices, const RGB& reflectance,
  const RGB& emission = RGB())
{
  scene.Surfaces.push_back(Surface{ std::move(vertices), reflectance, emission });
}

// Parallelogram centred at c with half-edge vectors u and v; its front normal
// is along Cross(u, v).
std::vector<Vec3> Quad(const Vec3& c, const Vec3& u, const Vec3& v)
{
  return { c - u - v, c + u - v, c + u + v, c - u + v };
}

// Horizontal rectangle of half-sizes hx, hz at height y facing up (+y) or down.
std::vector<Vec3> HorizontalRect(double cx, double y, double cz, double hx, double hz, bool up)
{
  const Vec3 u(hx, 0, 0), v(0, 0, hz);
  // Cross(x, z) = -y, so swap the half-edges to face up.
  return up ? Quad(Vec3(cx, y, cz), v, u) : Quad(Vec3(cx, y, cz), u, v);
}

// Rotate about +y by yaw, after tilting about +x by tilt (radians).
Vec3 Orient(const Vec3& p, double yaw, double tilt)
{
  const double ct = std::cos(tilt), st = std::sin(tilt);
  const Vec3 t(p.X, p.Y * ct - p.Z * st, p.Y * st + p.Z * ct);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  return { t.X * cy + t.Z * sy, t.Y, -t.X * sy + t.Z * cy };
}

// A block of height h standing on the floor, given its top outline
// (millimetres, counter-clockwise seen from above): the top plus one outward
// vertical side per top edge. No bottom: it would lie on the floor, unseen.
void AddCornellBlock(Scene& scene, const double top[4][2], double h)
{
  std::vector<Vec3> topFace;
  for (int i = 0; i < 4; ++i)
  {
    topFace.push_back(Mm(top[i][0], h, top[i][1]));
  }
  Add(scene, topFace, kCornellWhite);
  for (int i = 0; i < 4; ++i)
  {
    const double* p = top[i];
    const double* q = top[(i + 1) % 4];
    // (p_top, p_bottom, q_bottom, q_top) has normal (q - p) x up: outward for
    // a top outline that is counter-clockwise seen from above.
    Add(scene, { Mm(p[0], h, p[1]), Mm(p[0], 0, p[1]), Mm(q[0], 0, q[1]), Mm(q[0], h, q[1]) },
      kCornellWhite);
  }
}

Scene MakeCornell()
{
  Scene s;
  Add(s, { Mm(552.8, 0, 0), Mm(0, 0, 0), Mm(0, 0, 559.2), Mm(549.6, 0, 559.2) }, kCornellWhite);
  Add(s, { Mm(556, 548.8, 0), Mm(556, 548.8, 559.2), Mm(0, 548.8, 559.2), Mm(0, 548.8, 0) },
    kCornellWhite);
  // 0.5 mm below the ceiling so that the light and ceiling do not overlap.
  const double ly = 548.8 - 0.5;
  Add(s, { Mm(343, ly, 227), Mm(343, ly, 332), Mm(213, ly, 332), Mm(213, ly, 227) },
    kCornellLightReflectance, kCornellLightEmission);
  Add(s, { Mm(549.6, 0, 559.2), Mm(0, 0, 559.2), Mm(0, 548.8, 559.2), Mm(556, 548.8, 559.2) },
    kCornellWhite);
  Add(s, { Mm(0, 0, 559.2), Mm(0, 0, 0), Mm(0, 548.8, 0), Mm(0, 548.8, 559.2) }, kCornellGreen);
  // The measured left wall is not planar (3.2 mm twist): two triangles.
  const Vec3 l0 = Mm(552.8, 0, 0), l1 = Mm(549.6, 0, 559.2), l2 = Mm(556, 548.8, 559.2),
             l3 = Mm(556, 548.8, 0);
  Add(s, { l0, l1, l2 }, kCornellRed);
  Add(s, { l0, l2, l3 }, kCornellRed);
  const double shortTop[4][2] = { { 130, 65 }, { 82, 225 }, { 240, 272 }, { 290, 114 } };
  const double tallTop[4][2] = { { 423, 247 }, { 265, 296 }, { 314, 456 }, { 472, 406 } };
  AddCornellBlock(s, shortTop, 165);
  AddCornellBlock(s, tallTop, 330);
  return s;
}

Scene MakeStrip()
{
  Scene s;
  Add(s, HorizontalRect(0, 0, 0, 2, 2, true), kFloorGrey);
  Add(s, HorizontalRect(0, 1, 0, 1.5, 0.05, false), kBlack, RGB(30, 30, 30));
  return s;
}

Scene MakeOccluder()
{
  Scene s;
  Add(s, HorizontalRect(0, 0, 0, 2, 2, true), kFloorGrey);
  Add(s, HorizontalRect(0, 2, 0, 0.25, 0.25, false), kBlack, RGB(50, 50, 50));
  Add(s, HorizontalRect(0, 1, 0, 0.3, 0.3, true), kOccluderGrey);
  return s;
}

Scene MakeSeven()
{
  Scene s;
  Add(s, HorizontalRect(0, 0, 0, 3, 3, true), kFloorGrey);
  Add(s, HorizontalRect(0, 2.5, 0, 0.3, 0.15, false), kBlack, RGB(100, 100, 100));
  struct Occluder
  {
    double X, Y, Z, HalfX, HalfZ, YawDeg, TiltDeg;
  };
  // Footprint radii (<= 0.21 m) are below half the 0.55 m spacing in x, so
  // no two occluders intersect whatever their height and orientation.
  const Occluder occluders[7] = {
    { -1.6, 0.4, 0.3, 0.15, 0.12, 0, 0 },
    { -1.1, 0.9, -0.2, 0.12, 0.12, 30, 0 },
    { -0.55, 1.5, 0.2, 0.15, 0.10, 0, 35 },
    { 0.0, 1.1, -0.1, 0.12, 0.12, 45, 20 },
    { 0.55, 0.6, 0.25, 0.14, 0.14, 15, 0 },
    { 1.1, 1.3, -0.25, 0.12, 0.10, 60, 40 },
    { 1.6, 0.7, 0.1, 0.15, 0.12, 0, -25 },
  };
  for (const Occluder& o : occluders)
  {
    const double yaw = o.YawDeg * kDegree, tilt = o.TiltDeg * kDegree;
    // Half-edges ordered (z, x) so that the untransformed plate faces up;
    // rotations keep it facing up since |tilt| < 90 degrees.
    Add(s,
      Quad(Vec3(o.X, o.Y, o.Z), Orient(Vec3(0, 0, o.HalfZ), yaw, tilt),
        Orient(Vec3(o.HalfX, 0, 0), yaw, tilt)),
      kOccluderGrey);
  }
  return s;
}

Scene MakeBlind()
{
  Scene s;
  Add(s, HorizontalRect(0, 0, 0, 2, 2, true), kFloorGrey);
  Add(s, HorizontalRect(0, 3, 0, 0.05, 0.8, false), kBlack, RGB(200, 200, 200));
  const double tilt = 30.0 * kDegree, halfWidth = 0.04, halfLength = 0.8;
  // Tilt about the slat's long axis (z): the width vector leaves the
  // horizontal, the normal Cross(z, width) stays up-facing.
  const Vec3 across(halfWidth * std::cos(tilt), halfWidth * std::sin(tilt), 0);
  for (int i = 0; i < 11; ++i)
  {
    Add(s, Quad(Vec3(-0.6 + 0.12 * i, 0.6, 0), Vec3(0, 0, halfLength), across), kOccluderGrey);
  }
  return s;
}

struct Entry
{
  const char* Name;
  const char* Description;
  Scene (*Make)();
};

const Entry kScenes[] = {
  { "cornell", "the measured Cornell box with its two blocks (17 polygons)", MakeCornell },
  { "strip", "a long thin strip light above a floor, no occluder (paper Fig. 2)", MakeStrip },
  { "occluder", "a square light, one parallel square occluder and a floor (paper Fig. 3)",
    MakeOccluder },
  { "seven", "a light and seven small rotated and tilted occluders above a floor (paper Fig. 4)",
    MakeSeven },
  { "blind", "a narrow window light through 11 tilted venetian-blind slats onto a floor",
    MakeBlind },
};

} // namespace

std::vector<BuiltinSceneInfo> ListBuiltinScenes()
{
  std::vector<BuiltinSceneInfo> list;
  for (const Entry& e : kScenes)
  {
    list.push_back({ e.Name, e.Description });
  }
  return list;
}

Scene MakeBuiltinScene(const std::string& name)
{
  std::string names;
  for (const Entry& e : kScenes)
  {
    if (name == e.Name)
    {
      return e.Make();
    }
    names += std::string(names.empty() ? "" : ", ") + e.Name;
  }
  throw InputError("unknown built-in scene '" + name + "' (valid names: " + names + ")");
}

} // namespace penumbra
