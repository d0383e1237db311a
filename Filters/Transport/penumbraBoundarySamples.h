// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraBoundarySamples.h
 * @brief Where the progressive shooter evaluates a surface's samples
 * (private): boundary samples moved inside their surface, the limit from
 * inside, and the fast method's ray origins moved likewise
 * (Documentation/design/transport.md, "Boundary samples").
 */
#ifndef penumbraBoundarySamples_h
#define penumbraBoundarySamples_h

#include "penumbraSurfaceSamples.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

/**
 * The evaluation points `eval` and ray origins `origins` of the samples of
 * one surface (triangle areas `areas`): each point itself, except that a
 * boundary sample (an incident edge used by one triangle) moves toward the
 * centroid of its incident triangle with the largest angle there (the mean
 * of the tied centroids on a tie) by `offset`, respectively `rayOffset`
 * (scene units; at most half the way). A Uniform surface with triangles has
 * one point for all: the area centroid of its triangles, or the centroid
 * of the largest if that lies in none.
 */
void ComputeEvaluationPoints(const SurfaceSamples& samples, const std::vector<double>& areas,
  double offset, double rayOffset, std::vector<Vec3>& eval, std::vector<Vec3>& origins);

} // namespace penumbra

#endif
