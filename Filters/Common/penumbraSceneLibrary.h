// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSceneLibrary.h
 * @brief Built-in test scenes: the Cornell box and 3D versions of the
 * configurations of Lischinski, Tampieri and Greenberg (1991).
 *
 * Every scene is in metres with +y up. Polygons are planar and counter-clockwise
 * seen from their front (right-hand-rule normal). Emitters have reflectance 0
 * (pure sources) except in "cornell"; the floor of the paper scenes has
 * reflectance 0.7 and occluders 0.5 (grey). Surfaces are listed in the order
 * below, which tests and examples may rely on.
 *
 * - "cornell" (17 surfaces): the measured Cornell box (design.md section 4),
 *   millimetres divided by 1000. Order: floor, ceiling, light, back wall, right
 *   (green, x = 0) wall, left (red) wall as two triangles, short block (top,
 *   then 4 sides), tall block (top, then 4 sides). The light is 0.5 mm below the
 *   ceiling (y = 0.5483) and faces down; walls, floor and ceiling face into the
 *   room; block faces face away from their block (no bottom faces; the sides
 *   stand on the floor). The measured left wall is not planar -- each of its
 *   vertices lies 3.2 mm off the plane of the other three -- so it is split
 *   along the diagonal (552.8,0,0)-(556,548.8,559.2) into two triangles that
 *   keep the measured vertices. Materials: white (0.725, 0.71, 0.68), red
 *   (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091); the light emits
 *   (17, 12, 4) and reflects 0.78 per channel, the flat luminaire reflectance
 *   common in Cornell box scene files (a documented choice: it only affects
 *   light bounced back off the luminaire).
 * - "strip" (2 surfaces; paper Fig. 2): floor 4 x 4 m at y = 0 centred on the
 *   origin, facing up; a strip light 3 m long (x) and 0.1 m wide (z) at
 *   y = 1 facing down, emission 30. No occluder: the radiance is smooth
 *   (floor centre about 0.96).
 * - "occluder" (3 surfaces; paper Fig. 3): floor 4 x 4 m; a square light
 *   0.5 x 0.5 m at y = 2 facing down, emission 50; one square occluder
 *   0.6 x 0.6 m at y = 1, centred and parallel, edges parallel to the light's.
 *   On the floor the umbra is |x|, |z| < 0.35 m and the penumbra reaches 0.85 m
 *   (similar triangles). The occluder faces UP, toward the light: it is lit
 *   and visible from above, and nothing it reflects can reach the floor (it
 *   faces away) while the floor cannot reach its front; with a black light the
 *   floor radiance is then exactly the direct term, which can be checked by
 *   brute-force integration as in the paper's Fig. 3.
 * - "seven" (9 surfaces; paper Fig. 4): floor 6 x 6 m; a light 0.6 m (x) by
 *   0.3 m (z) at y = 2.5 facing down, emission 100; then seven small
 *   rectangular occluders spread along x at x = -1.6, -1.1, -0.55, 0, 0.55,
 *   1.1, 1.6 and heights 0.4 to 1.5 m, some rotated about the vertical, some
 *   tilted (up to 40 degrees), all facing up toward the light. Their
 *   footprints are disjoint; the shadows of occluders 1-2 and 6-7 overlap and
 *   the penumbrae range from 0.1 m (low occluders) to about 1 m (high ones).
 * - "blind" (13 surfaces; the venetian blind of the paper's introduction):
 *   floor 4 x 4 m; a narrow window-like emitter 0.1 m (x) by 1.6 m (z) at
 *   y = 3 facing down, emission 200 (like a skylight slit: narrow across the
 *   slats so that their shadows stay sharp); 11 slats 1.6 m long (z) and
 *   0.08 m wide at y = 0.6, pitch 0.12 m in x (centres -0.6 ... 0.6), each
 *   tilted 30 degrees about its long axis and facing up. About 40 % of the
 *   floor under the blind is lit, in thin stripes parallel to z whose
 *   penumbrae (about 0.025 m) are narrower than the stripes.
 *
 * The emissions give an unoccluded floor radiance of order 1 W sr^-1 m^-2.
 */
#ifndef penumbraSceneLibrary_h
#define penumbraSceneLibrary_h

#include "penumbraCommonModule.h" // for export macro
#include "penumbraScene.h"

#include <string>
#include <vector>

namespace penumbra
{

/// Name and one-line description of a built-in scene.
struct BuiltinSceneInfo
{
  std::string Name;
  std::string Description;
};

/// The built-in scenes, in a fixed order ("cornell" first).
PENUMBRACOMMON_EXPORT std::vector<BuiltinSceneInfo> ListBuiltinScenes();

/// Build the built-in scene `name`; throws InputError listing the valid names
/// if there is no such scene.
PENUMBRACOMMON_EXPORT Scene MakeBuiltinScene(const std::string& name);

} // namespace penumbra

#endif
