// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverFrame.h
 * @brief A receiver's 2D frame (origin at its centroid, first axis along its
 * longest edge) and the 2D geometry the mesher does in it: distances to
 * segments and the clipping of segments to the receiver's (possibly
 * concave) outline. Private (not installed).
 */
#ifndef penumbraReceiverFrame_h
#define penumbraReceiverFrame_h

#include "penumbraMath.h"
#include "penumbraParameterIntervals.h"
#include "penumbraPlaneFrame.h"
#include "penumbraSceneTopology.h"

#include <utility>
#include <vector>

namespace penumbra
{
namespace detail
{

/// The plane frame of one receiver (plane offset D = Dot(N, x)) and its outline in it.
struct ReceiverFrame : PlaneFrame
{
  double D = 0.0;
  std::vector<P2> Outline;
};

/// The frame of `receiver`.
ReceiverFrame MakeFrame(const PolygonData& receiver);

/// Distance from p to segment a-b.
double DistancePointSegment2(const P2& p, const P2& a, const P2& b);

/// The parameter ranges of segment a-b inside the polygon (boundary
/// included, within tol).
void ClipSegmentToPolygon2(const P2& a, const P2& b, const std::vector<P2>& poly, double tol,
  std::vector<Interval>& pieces);

/// The pieces of segment a-b inside the frame's outline, as end points;
/// pieces reaching an end of a-b end exactly there. `scratch` holds the
/// parameter ranges.
void ClipToOutline(const P2& a, const P2& b, const ReceiverFrame& frame, double snap,
  std::vector<Interval>& scratch, std::vector<std::pair<P2, P2>>& pieces);

} // namespace detail
} // namespace penumbra

#endif
