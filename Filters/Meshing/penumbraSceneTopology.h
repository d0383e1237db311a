// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSceneTopology.h
 * @brief The mesher's view of the scene's adjacency: each polygon's plane and
 * measures, the features shared between polygons (vertices matched within
 * kVertexMatch of the scene size, edges by their pair of end vertices), and
 * the connected components through shared edges with their open edges (a
 * component closed apart from the edges it stands on is a solid). Private.
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraSceneTopology_h
#define penumbraSceneTopology_h

#include "penumbraScene.h"
#include "penumbraVector.h"

#include <array>
#include <vector>

namespace penumbra
{
namespace detail
{

/// One scene polygon with its plane, measures and shared-feature ids.
struct PolygonData
{
  std::vector<Vec3> V;
  Vec3 N;
  double D = 0.0; ///< plane: Dot(N, x) == D
  Vec3 Centroid;
  double Diameter = 0.0;
  double Area = 0.0;
  std::vector<int> Cluster; ///< vertex cluster of each vertex
  std::vector<int> Edge;    ///< edge id of edge i (from V[i] to V[i+1])
  int Component = -1;       ///< connected component through shared edges
};

/// A use of a shared feature: polygon `Polygon`, its vertex or edge `Index`.
struct Use
{
  int Polygon;
  int Index;
};

/// Polygons, shared features and components of a scene.
struct SceneTopology
{
  std::vector<PolygonData> Polygons;
  std::vector<std::vector<Use>> ClusterUses; ///< per vertex cluster
  std::vector<Vec3> ClusterPoint;
  std::vector<std::vector<Use>> EdgeUses; ///< per edge id
  std::vector<std::array<int, 2>> EdgeClusters;
  std::vector<std::vector<int>> ComponentPolygons;
  std::vector<std::vector<int>> ComponentOpenEdges; ///< edges not shared by exactly two polygons
  /// A sphere holding each component: the centre of its bounding box and the
  /// largest distance of its vertices from it.
  std::vector<Vec3> ComponentCentre;
  std::vector<double> ComponentRadius;
  double Size = 1.0; ///< the scene size (tolerances are relative to it)

  /// Fill every table from a validated scene.
  void Build(const Scene& scene);

  /// The end points of shared edge `e`.
  void EdgeEnds(int e, Vec3& a, Vec3& b) const;

private:
  void BuildVertexClusters(const Scene& scene);
  void BuildEdges();
  void BuildComponents();
};

} // namespace detail
} // namespace penumbra

#endif
