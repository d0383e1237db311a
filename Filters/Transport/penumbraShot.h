// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShot.h
 * @brief One shot as the progressive shooter prepares it (private):
 * everything the evaluation at a receiving point needs about the shooting
 * surfaces, built once per shot, for the exact method (the shooter's
 * radiance function) or the fast one (a hierarchy of its pieces).
 */
#ifndef penumbraShot_h
#define penumbraShot_h

#include "penumbraShooterHierarchy.h"
#include "penumbraShooterRadiance.h"
#include "penumbraShootingEnergy.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

struct SampleSet;

/// Everything one shot needs about its shooter, built once per shot.
struct Shot
{
  int Shooter = -1;  ///< the shooter, or -1 for a group shot
  std::vector<int> Members; ///< the shooting surfaces (one, or a parallel group)
  ShotMethod Method = ShotMethod::Exact;
  Vec3 Normal;   ///< shooter's front normal
  double Offset = 0.0; ///< shooter's plane: Dot(Normal, p) == Offset (a group: the lowest)
  bool Empty = true;   ///< no triangle carries unshot radiance
  ShooterRadiance Radiance; ///< exact method: the triangles with unshot radiance
  ShooterHierarchy Hierarchy; ///< fast method: the pieces of the shooter(s)
  bool Mixed = false; ///< a group shot of surfaces facing different ways
  double OpeningAngle = 0.3; ///< fast method: this shot's opening angle

  /// x is behind the shooter, which emits from its front only (a group
  /// facing several ways: decided node by node instead).
  bool Behind(const Vec3& x) const { return !Mixed && !(Dot(Normal, x) - Offset > 0.0); }
};

/**
 * The shot of surface `j` alone by `method`: its triangles that carry
 * unshot radiance and have an area, projected onto its plane, as the exact
 * method's radiance function (penumbraExactShot.h) or the fast method's
 * hierarchy (penumbraFastShot.h), leaves split to `leafSize` times its
 * diameter. Group shots: penumbraGroupShot.h.
 */
void PrepareShot(const SampleSet& samples, int j, ShotMethod method, double openingAngle,
  double leafSize, Shot& shot);

} // namespace penumbra

#endif
