// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraConvexHull.h
 * @brief The convex hull of 2D points (Andrew's monotone chain), used for
 * occluders' outlines and by the mesher's wedge regions.
 */
#ifndef penumbraConvexHull_h
#define penumbraConvexHull_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraMath.h"

#include <vector>

namespace penumbra
{

/**
 * The indices of the convex hull of p (not empty) into `hull`:
 * counter-clockwise from the lexicographically smallest point, no collinear
 * points, the first point not repeated at the end.
 */
PENUMBRAVISIBILITY_EXPORT void ConvexHull2(const std::vector<P2>& p, std::vector<int>& hull);

} // namespace penumbra

#endif
