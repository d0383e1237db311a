// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSecondaryShooters.h
 * @brief Which surfaces besides the emitters should shoot for the
 * discontinuity mesher (paper section 5: secondary sources cast shadows
 * too): those whose reflected direct light is strong and is most of the
 * light of a receiver they cast shadows on.
 */
#ifndef penumbraSecondaryShooters_h
#define penumbraSecondaryShooters_h

#include "penumbraTransportModule.h" // for export macro
#include "penumbraPreparedScene.h"

#include <vector>

namespace penumbra
{

/// A secondary shooter and the receivers its boundaries are meshed on.
struct SecondaryShooter
{
  int Shooter = -1;
  std::vector<int> Receivers; ///< ascending surface ids
};

/**
 * The secondary shooters of `scene` (strongest first, at most `maximum`)
 * given each surface's reflected direct power `reflected` (watts, mean of
 * RGB, one per surface): a surface that does not emit and reflects at least
 * `fraction` of the emitted power, with the receivers it matters to: those
 * whose light it brings at least half of, and at least 1% of the emitted
 * power to their reflected light (by the form factor of two discs about the
 * centroids, against the receiver's own reflected direct power), and that
 * occluders shade from it (one of 64 rays between the two blocked). A
 * surface with no such receiver is not chosen: receivers it hardly lights,
 * or lights without shadows, gain nothing from its boundaries, and tracing
 * them everywhere (a floor's under every box of a room) would cost more
 * than all the direct light's.
 */
PENUMBRATRANSPORT_EXPORT std::vector<SecondaryShooter> SelectSecondaryShooters(
  const PreparedScene& scene, const std::vector<double>& reflected, double fraction,
  int maximum);

} // namespace penumbra

#endif
