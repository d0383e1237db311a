// SPDX-License-Identifier: GPL-3.0-or-later
// Polygon geometry against closed forms, and the tolerances of ValidateScene.
#include "penumbraScene.h"
#include "penumbraTesting.h"

#include <cmath>

using namespace penumbra;

PENUMBRA_TEST(TestGeometryAndTolerances)
{
  // A 2 x 3 rectangle in the plane z = 5, counter-clockwise seen from +z.
  const std::vector<Vec3> rectangle = { { 1, 1, 5 }, { 3, 1, 5 }, { 3, 4, 5 }, { 1, 4, 5 } };
  PolygonGeometry g = ComputePolygonGeometry(rectangle);
  PENUMBRA_EXPECT_REL(g.Area, 6.0, 1e-15);
  PENUMBRA_EXPECT_NEAR(g.Normal.Z, 1.0, 1e-15);
  PENUMBRA_EXPECT_NEAR(g.Offset, 5.0, 1e-14);
  PENUMBRA_EXPECT_NEAR(g.Centroid.X, 2.0, 1e-14);
  PENUMBRA_EXPECT_NEAR(g.Centroid.Y, 2.5, 1e-14);
  PENUMBRA_EXPECT_REL(g.Diameter, std::sqrt(13.0), 1e-15);

  // An L-shaped (concave) hexagon: area 3, centroid by decomposition into two
  // rectangles [0,2]x[0,1] (area 2, centroid (1, .5)) and [0,1]x[1,2] (area 1,
  // centroid (.5, 1.5)).
  const std::vector<Vec3> ell = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 },
    { 0, 2, 0 } };
  g = ComputePolygonGeometry(ell);
  PENUMBRA_EXPECT_REL(g.Area, 3.0, 1e-15);
  PENUMBRA_EXPECT_NEAR(g.Centroid.X, (2 * 1.0 + 1 * 0.5) / 3.0, 1e-14);
  PENUMBRA_EXPECT_NEAR(g.Centroid.Y, (2 * 0.5 + 1 * 1.5) / 3.0, 1e-14);

  // Clockwise order flips the normal: the front is the right-hand-rule side.
  std::vector<Vec3> reversed(rectangle.rbegin(), rectangle.rend());
  PENUMBRA_EXPECT_NEAR(ComputePolygonGeometry(reversed).Normal.Z, -1.0, 1e-15);

  // Far from the origin (offset 1e6) the area is still accurate.
  std::vector<Vec3> far = rectangle;
  for (Vec3& v : far)
  {
    v += Vec3(1e6, 1e6, 1e6);
  }
  PENUMBRA_EXPECT_REL(ComputePolygonGeometry(far).Area, 6.0, 1e-9);

  Scene scene;
  scene.Surfaces.push_back({ rectangle, RGB(0.5, 0.5, 0.5), RGB(1, 2, 3) });
  ValidateScene(scene);
  PENUMBRA_EXPECT_REL(scene.EmittedPower().G, M_PI * 2 * 6.0, 1e-15);
  PENUMBRA_EXPECT_REL(scene.Size(), 3.0, 1e-15);

  // Planarity tolerance is relative to the polygon's diameter.
  Scene bent = scene;
  bent.Surfaces[0].Vertices[2].Z += 1e-3;
  PENUMBRA_EXPECT_THROW(ValidateScene(bent), InputError, "non-planar");
  ValidationTolerances loose;
  loose.Planarity = 1e-3;
  ValidateScene(bent, loose); // 1e-3/4 off a plane fit, within 1e-3 * sqrt(13)

  // A sliver of aspect 1e6 is valid: thin is not degenerate.
  Scene sliver;
  sliver.Surfaces.push_back(
    { { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1e-6, 0 }, { 0, 1e-6, 0 } }, RGB(), RGB() });
  ValidateScene(sliver);
  // A triangle 1e-12 high over a unit base is a line, not a surface.
  sliver.Surfaces[0].Vertices = { { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, 1e-12, 0 } };
  PENUMBRA_EXPECT_THROW(ValidateScene(sliver), InputError, "zero area");
}
