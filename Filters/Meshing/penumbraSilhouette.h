// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSilhouette.h
 * @brief Silhouette tests of the mesher: on which side of a plane through a
 * feature (a polygon's edge or corner, or an edge or vertex shared by several
 * polygons of a solid) the polygons having it lie locally. A feature is on
 * the silhouette seen along the plane when they all lie on one side. Private.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraSilhouette_h
#define penumbraSilhouette_h

#include "penumbraSceneTopology.h"

namespace penumbra
{
namespace detail
{

/// Side of polygon p, locally at its edge i, with respect to a plane of unit
/// normal m through the edge: +1, -1, or 0 when the polygon lies in the plane.
int EdgeSide(const PolygonData& p, int i, const Vec3& m);

/// Side of polygon p, locally at its vertex i, with respect to a plane of unit
/// normal m through the vertex: +1, -1, 0 (polygon in the plane), or 2 when
/// the corner straddles the plane.
int CornerSide(const PolygonData& p, int i, const Vec3& m);

/// Side of shared edge `e` with respect to a plane of unit normal m through
/// it: the common side (+1/-1) of its polygons, 0 when they all lie in the
/// plane (seen edge-on), 2 when they straddle or disagree (not on the
/// silhouette).
int EdgeFeatureSide(const SceneTopology& topology, int e, const Vec3& m);

/// Likewise for vertex cluster `c`; with `allowStraddle`, a straddling
/// corner counts as one-sided (interior events).
int VertexFeatureSide(const SceneTopology& topology, int c, const Vec3& m, bool allowStraddle);

/// Whether one of the edges at vertex cluster `c` of its polygons lies in
/// the plane of unit normal m through it (coplanar edges: order 1).
bool VertexHasEdgeInPlane(const SceneTopology& topology, int c, const Vec3& m);

} // namespace detail
} // namespace penumbra

#endif
