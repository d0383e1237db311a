// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSceneRepair.h
 * @brief Safe repairs of imported scenes: what a modeller's export gets
 * slightly wrong is fixed, counted and reported, so that it solves.
 *
 * Real exports weld badly, leave quads a little out of plane, repeat faces
 * and keep zero-area slivers. None of that changes the light a careful user
 * meant, so RepairScene fixes it instead of rejecting the scene; anything it
 * cannot fix without guessing (non-finite numbers, reflectance >= 1,
 * self-intersecting outlines) is left for ValidateScene to report.
 */
#ifndef penumbraSceneRepair_h
#define penumbraSceneRepair_h

#include "penumbraCommonModule.h" // for export macro
#include "penumbraScene.h"

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra
{

/// Tolerances of RepairScene.
struct RepairOptions
{
  /// Vertices closer than this times the scene's size are welded into one
  /// (single-precision exports differ by ~1e-7 of the size; 1e-6 leaves a
  /// margin and stays far below any feature a lighting model resolves).
  /// [1e-6], in [0, 1e-3]; 0 welds exact duplicates only.
  double WeldTolerance = 1e-6;
  /// Polygons with a vertex further than this from their plane, relative to
  /// their diameter, are triangulated. Far below ValidateScene's planarity
  /// tolerance on purpose: the pipeline takes a polygon as exactly planar, and
  /// the faces of a box exported in single precision (bent by ~1e-7, their
  /// shared corners welded) leave slivers of gaps along every edge that the
  /// sampler refines to its limit (Documentation/design.md, "Import").
  /// [1e-9], in [0, 1]
  double FlatnessTolerance = 1e-9;
  /// The degeneracy tolerance (polygons ValidateScene would reject as
  /// degenerate are dropped) and the planarity tolerance, which bounds
  /// FlatnessTolerance from above.
  ValidationTolerances Validation;
};

/// What RepairScene changed, per kind.
struct RepairReport
{
  /// Vertices moved onto a neighbour within the weld tolerance.
  std::size_t WeldedVertices = 0;
  /// Largest distance a welded vertex moved (scene units).
  double LargestWeldDistance = 0.0;
  /// Vertices snapped onto the axis-aligned plane of a polygon they lie
  /// within the weld tolerance of, and the largest distance one moved.
  std::size_t SnappedVertices = 0;
  double LargestSnapDistance = 0.0;
  /// Vertices within the weld tolerance of a polygon's plane (any
  /// orientation) whose projection lies inside it, moved onto the plane.
  std::size_t PlaneSnappedVertices = 0;
  double LargestPlaneSnapDistance = 0.0;
  /// Polygons that lost repeated consecutive vertices.
  std::size_t RepeatedVertexPolygons = 0;
  /// Non-planar polygons replaced by triangles, and the triangles made.
  std::size_t NonPlanarPolygons = 0;
  std::size_t NonPlanarTriangles = 0;
  /// Largest distance of a vertex from its polygon's plane among those.
  double LargestPlanarityDeviation = 0.0;
  /// Polygons dropped for zero area (collinear, coincident or sliver
  /// narrower than the degeneracy tolerance), and the power they emitted.
  std::size_t ZeroAreaPolygons = 0;
  /// The first (at most 8) input cells dropped for zero area, to name them.
  std::vector<std::size_t> ZeroAreaCells;
  /// Later copies of a polygon (same vertices in the same cyclic order)
  /// dropped, and how many of them had a different material.
  std::size_t DuplicatePolygons = 0;
  std::size_t DuplicatesWithOtherMaterial = 0;

  /// Whether anything was changed.
  PENUMBRACOMMON_EXPORT bool Empty() const;
  /// One line per kind of repair, e.g. "12 non-planar polygons triangulated
  /// into 24 triangles (largest deviation 0.0017)"; empty when nothing changed.
  PENUMBRACOMMON_EXPORT std::vector<std::string> Messages() const;
};

/**
 * The scene with its safe repairs applied, in this order: vertices within
 * WeldTolerance of each other welded (each to the first of its cluster in
 * input order), vertices within WeldTolerance of the axis-aligned plane of a
 * polygon (one whose vertices all lie within WeldTolerance of one x, y or z)
 * and inside its bounding rectangle snapped onto it (single-precision
 * exports leave floors and the boxes standing on them 1e-7 off, and the
 * pipeline needs contacts exact), repeated consecutive vertices removed, polygons of zero area
 * dropped, later duplicates of a polygon dropped, polygons bent beyond
 * FlatnessTolerance triangulated by ear clipping in their mean plane (each
 * triangle keeps the polygon's front side and material), then vertices
 * resting on a polygon (within WeldTolerance of its plane, inside its
 * outline, at any orientation) moved onto its plane, and the polygons this
 * bends triangulated in turn. `sourceCell[i]` receives the input
 * polygon of output surface i. Polygons needing no repair are copied
 * unchanged, so a clean scene comes out identical (Scene::IsIdentical).
 * Never throws for geometry; non-finite vertices are passed through for
 * ValidateScene to name.
 */
PENUMBRACOMMON_EXPORT Scene RepairScene(const Scene& scene, const RepairOptions& options,
  RepairReport& report, std::vector<std::size_t>& sourceCell);

} // namespace penumbra

#endif
