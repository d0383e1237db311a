// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraExactShot.h
 * @brief The exact method of a shot (private): the part of the shooter a
 * point sees, found exactly, each visible piece clipped by the shooter's
 * triangles and integrated in closed form for their linear unshot radiance
 * (Documentation/design/transport.md, "The exact shot").
 */
#ifndef penumbraExactShot_h
#define penumbraExactShot_h

#include "penumbraShot.h"
#include "penumbraSurfaceSamples.h"
#include "penumbraVector.h"

#include <array>
#include <vector>

namespace penumbra
{

class ExactEvaluator;
struct LinearSourceWorkspace;

/**
 * The exact method's source: the linear unshot radiance of `s` over the
 * `kept` triangles of `points` (s's points projected onto its plane), or a
 * constant (Lambert's formula, about 25 times cheaper) when the unshot
 * radiance is the same at every point and every triangle is kept (an
 * emitter not shot yet).
 */
ShooterRadiance ExactShooterRadiance(
  const SurfaceSamples& s, std::vector<Vec3> points, std::vector<std::array<int, 3>> kept);

/**
 * Irradiance at x (unit normal n, on surface `receiver` or -1) from the
 * exact shot `shot`: the shooter's visible region from x (occluders from
 * `candidates`, the pair's shaft candidates, or all when null), each piece
 * intersected with each triangle that may meet it and integrated in closed
 * form. x must be in front of the shooter.
 */
RGB ExactIrradiance(const Shot& shot, const ExactEvaluator& exact, const Vec3& x, const Vec3& n,
  int receiver, const std::vector<int>* candidates, LinearSourceWorkspace& ws);

} // namespace penumbra

#endif
