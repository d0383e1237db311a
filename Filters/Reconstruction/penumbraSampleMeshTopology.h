// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSampleMeshTopology.h
 * @brief Topology of a SampleMesh for the reconstruction: the kinds of its
 * unique edges and the corner index helpers shared by the reconstruction's
 * files. Private to Penumbra::Reconstruction.
 *
 * The edge, incidence and sector arrays themselves live in
 * Reconstruction::Internals (penumbraReconstructionInternals.h) and are
 * built by penumbraSampleMeshTopology.cxx.
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraSampleMeshTopology_h
#define penumbraSampleMeshTopology_h

namespace penumbra
{
namespace detail
{

/// Kinds of unique edges.
enum EdgeKind : signed char
{
  SmoothEdge = 0,      ///< two triangles, C1 across
  ConstrainedEdge = 1, ///< two triangles, C0 across (order 1, or 0/-1 not cut)
  BoundaryEdge = 2     ///< one triangle (mesh boundary or order-0 cut), or non-manifold
};

/// Next corner of a triangle (0 -> 1 -> 2 -> 0).
inline int Next(int i)
{
  return i == 2 ? 0 : i + 1;
}

/// Previous corner of a triangle (0 -> 2 -> 1 -> 0).
inline int Prev(int i)
{
  return i == 0 ? 2 : i - 1;
}

} // namespace detail
} // namespace penumbra

#endif
