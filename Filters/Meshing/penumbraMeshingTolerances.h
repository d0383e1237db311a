// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraMeshingTolerances.h
 * @brief The discontinuity mesher's tolerances and search limits, shared by
 * its translation units. Private (not installed).
 */
#ifndef penumbraMeshingTolerances_h
#define penumbraMeshingTolerances_h

#include <cstddef>

namespace penumbra
{
namespace detail
{

// Tolerances, relative to the scene size unless said otherwise.
constexpr double kVertexMatch = 1e-9; // vertices closer than this are one feature
constexpr double kLinear = 1e-10;     // side tests of points against planes
constexpr double kSnap = 1e-10;       // 2D snapping of constraint end points
constexpr double kMinPiece = 1e-7;    // shorter boundary pieces are dropped
constexpr double kChordMargin = 1e-6; // receiver chords lengthened by this before culling wedges
// Up to this many shaft candidates, scan them instead of traversing the BVH.
constexpr std::size_t kScanLimit = 64;
constexpr double kAngle = 1e-9;       // |sin| below which directions count as in a plane

} // namespace detail
} // namespace penumbra

#endif
