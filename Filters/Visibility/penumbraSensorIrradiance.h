// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSensorIrradiance.h
 * @brief Irradiance at free points (sensors): a lighting simulator's
 * illuminance meters, anywhere in the scene and facing any way.
 *
 * A sensor at x with unit normal n receives
 *
 *   E(x) = sum over emitters j of pi L^e_j F_j(x)                (direct)
 *        + sum over surfaces j of the irradiance of L^r_j         (indirect)
 *
 * where F_j is the exact form factor to the part of emitter j visible from x
 * (the exact evaluator's visible region and closed form, as for samples) and
 * L^r_j is the reflected radiance of surface j in a solution, a
 * piecewise-linear function over its triangles, integrated exactly over its
 * visible part by the linear-source closed form. A sensor lying on a surface
 * sees nothing of that surface (its plane contains x) and is not shadowed by
 * it. Only the front sides of surfaces emit and reflect.
 */
#ifndef penumbraSensorIrradiance_h
#define penumbraSensorIrradiance_h

#include "penumbraVisibilityModule.h" // for export macro

#include "penumbraExactEvaluator.h"
#include "penumbraLinearSource.h"
#include "penumbraScene.h"
#include "penumbraShooterRadiance.h"
#include "penumbraVector.h"

#include <map>

namespace penumbra
{

/// The two parts of a sensor's irradiance, W m^-2 per channel.
struct SensorIrradiance
{
  RGB Direct;
  RGB Indirect;
};

/**
 * Irradiance at x (unit normal n, not on any particular surface) from the
 * scene's emitters and from the reflected radiance `reflected` (surface id to
 * its function; surfaces absent reflect nothing). `scene` is the evaluator's.
 * Thread-safe given one pair of workspaces per thread.
 */
PENUMBRAVISIBILITY_EXPORT SensorIrradiance EvaluateSensor(const ExactEvaluator& evaluator,
  const Scene& scene, const std::map<int, ShooterRadiance>& reflected, const Vec3& x,
  const Vec3& n, VisibilityWorkspace& visibility, LinearSourceWorkspace& linear);

} // namespace penumbra

#endif
