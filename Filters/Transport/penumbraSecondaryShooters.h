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

/**
 * The secondary shooters of `scene` (surface ids, strongest first, at most
 * `maximum`) given each surface's reflected direct power `reflected` (watts,
 * mean of RGB, one per surface): a surface that does not emit, reflects at
 * least `fraction` of the emitted power, and brings at least half the light
 * of some receiver, and at least 1% of the emitted power to its reflected
 * light (by the form factor of two discs about the centroids, against the
 * receiver's own reflected direct power), that occluders shade from it (one
 * of 64 rays between the two blocked). Receivers it hardly
 * lights, or lights without shadows, gain nothing from its boundaries.
 */
PENUMBRATRANSPORT_EXPORT std::vector<int> SelectSecondaryShooters(const PreparedScene& scene,
  const std::vector<double>& reflected, double fraction, int maximum);

} // namespace penumbra

#endif
