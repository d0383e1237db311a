// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCGAL.h
 * @brief Private CGAL typedefs of the Penumbra core: the kernels and the
 * constrained Delaunay triangulations used for receiver meshes. Include only
 * from .cxx files (never from a public header).
 *
 * The constraints are inserted with exact predicates and exact constructions
 * (Epeck) and Exact_intersections_tag: points where constraints cross are
 * constructed exactly, so crossing boundaries never produce inverted or flat
 * triangles; coordinates are rounded to double only on output. The optional
 * quality refinement runs on that arrangement rounded to doubles, with exact
 * predicates (Epick). Constrained_triangulation_plus_2 keeps, for every
 * constrained edge, the input constraints through it (their labels survive
 * splitting).
 */
#ifndef penumbraCGAL_h
#define penumbraCGAL_h

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

namespace penumbra
{
namespace cgal
{

/// The vertex id of the refinable triangulation's far bounding square's
/// corners: never part of the output.
constexpr int BoundingCornerId = -2;

/// Per-vertex data: index of the known 3D point it stands for, or -1, and
/// the refinable triangulation's vertex id.
struct VertexInfo
{
  int Known = -1;
  int Id = -1; ///< vertex id in a RefinableTriangulation, -1, or BoundingCornerId
};

/// Per-face data used by the receiver triangulation.
struct FaceInfo
{
  int State = -1;                ///< -1 unvisited; bit 0 inside outline, bit 1 under a footprint
  bool Kept = false;             ///< finite, inside the receiver, not under a footprint
  int Label[3] = { -1, -1, -1 }; ///< per edge: index of its label, -1 unconstrained
  int Point[3] = { -1, -1, -1 }; ///< per vertex: output point index
};

/// A constrained Delaunay triangulation "plus" (it remembers its input
/// constraints, whose labels survive splitting) over kernel K with the
/// vertex and face data above and Delaunay_mesher_2's bases.
template <class K, class Itag>
using ReceiverCDT = CGAL::Constrained_triangulation_plus_2<CGAL::Constrained_Delaunay_triangulation_2<K,
  CGAL::Triangulation_data_structure_2<
    CGAL::Delaunay_mesh_vertex_base_2<K, CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>>,
    CGAL::Delaunay_mesh_face_base_2<K,
      CGAL::Constrained_Delaunay_triangulation_face_base_2<K,
        CGAL::Constrained_triangulation_face_base_2<K,
          CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>>>>>,
  Itag>>;

/// Exact predicates and exact constructions: the arrangement of the
/// constraints, crossing points constructed exactly.
using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactCDT = ReceiverCDT<ExactKernel, CGAL::Exact_intersections_tag>;

/// Exact predicates on double coordinates: quality refinement of the rounded
/// arrangement (Steiner points stay doubles; with exact constructions the
/// circumcentres of circumcentres grow without bound).
using RefineKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using RefineCDT = ReceiverCDT<RefineKernel, CGAL::Exact_predicates_tag>;
using RefineCriteria = CGAL::Delaunay_mesh_size_criteria_2<RefineCDT>;
using RefineMesher = CGAL::Delaunay_mesher_2<RefineCDT, RefineCriteria>;

} // namespace cgal
} // namespace penumbra

#endif
