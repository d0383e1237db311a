// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraFeatureSize.h
 * @brief Local feature size of the adaptive sampler: the length of the
 * discontinuity lines (collinear chains of segments) through each vertex,
 * and the constants of the refinement floors derived from it. Private to
 * Penumbra::Meshing.
 *
 * Design notes: Documentation/design/sampling.md
 */
#ifndef penumbraFeatureSize_h
#define penumbraFeatureSize_h

#include <limits>
#include <vector>

namespace penumbra
{
namespace detail
{

struct Receiver;

/// A feature whose discontinuity lines are shorter than the receiver's
/// diameter over this is refined down to MinimumFeatureSize times this times
/// their length (instead of times the diameter).
constexpr double FeatureNeighbourhood = 10.0;
/// No triangle narrower, or edge shorter, than this fraction of the
/// receiver's diameter is refined, whatever MinimumFeatureSize (0 included)...
constexpr double NumericalWidth = 1e-9;
/// ... nor than this fraction of the largest coordinate of the receiver's
/// points (1e7 ulps): the output is written as 3D doubles and projected
/// again by the reconstructor, and a sliver within ~1e6 ulps of its
/// coordinates' rounding may come back flat or flipped.
constexpr double CoordinateRounding = 1e7 * std::numeric_limits<double>::epsilon();

/// Per vertex id of `rec`'s snapshot: the length of the longest
/// discontinuity line through it (collinear chains of order 0-2 segments,
/// joined across the points that split them), HUGE_VAL on none.
std::vector<double> DiscontinuityLineLengths(const Receiver& rec);

} // namespace detail
} // namespace penumbra

#endif
