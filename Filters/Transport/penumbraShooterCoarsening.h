// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShooterCoarsening.h
 * @brief A secondary shooter's radiance on fewer triangles (private): the
 * exact evaluation of its shadows costs its triangles times the receiving
 * points, and its mesh is as fine as its own direct light needed.
 */
#ifndef penumbraShooterCoarsening_h
#define penumbraShooterCoarsening_h

#include "penumbraShooterRadiance.h"
#include "penumbraTransportModule.h" // for export macro

#include <array>
#include <vector>

namespace penumbra
{

/**
 * `fine` (a piecewise-linear radiance) with triangles merged by half-edge
 * collapses while the linear radiance stays within `tolerance` times its
 * area-mean value of every point it drops, per channel (the display
 * decimation of penumbraDisplayDecimation.h). The points of `creases` (edges
 * of the discontinuity lines, as point pairs of `fine`) stay, as do the
 * outline and every hole's shape, so jumps and kinks are where they were.
 * The result's points are `fine`'s (unused ones included). A constant
 * radiance, a tolerance of 0 or triangles of mixed orientation return
 * `fine` as it is.
 */
PENUMBRATRANSPORT_EXPORT ShooterRadiance CoarsenShooterRadiance(
  const ShooterRadiance& fine, const std::vector<std::array<int, 2>>& creases, double tolerance);

} // namespace penumbra

#endif
