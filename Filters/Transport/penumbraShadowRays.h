// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShadowRays.h
 * @brief Whether occluders shade one surface's samples from another's, and
 * a first guess of the light between them (private): the tests that decide
 * which receivers of a shot need their secondary shadows evaluated exactly
 * and which surfaces shoot for the mesher (Documentation/design/transport.md,
 * "Secondary shadows").
 */
#ifndef penumbraShadowRays_h
#define penumbraShadowRays_h

namespace penumbra
{

class RayCaster;
struct PreparedPolygon;
struct SampleSet;

/**
 * The fraction of `from`'s power that reaches `to`, unoccluded, by the form
 * factor of two discs about their centroids (areas, normals, the distance
 * between centroids): a first guess, exact for small coaxial discs.
 */
double DiscTransferFraction(const PreparedPolygon& from, const PreparedPolygon& to);

/**
 * Whether any of 64 segments from the centroids of `shooter`'s triangles to
 * `receiver`'s evaluation points in front of it (both taken at even steps
 * through their lists) is blocked by a third surface. False when either has
 * no samples.
 */
bool AnyRayBlocked(const SampleSet& samples, const RayCaster& caster, int shooter, int receiver);

} // namespace penumbra

#endif
