// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverTriangulation.h
 * @brief Private interface between the discontinuity mesher and its CGAL
 * translation unit: the constrained Delaunay triangulation of one receiver
 * in its plane. Not installed; carries no CGAL type.
 */
#ifndef penumbraReceiverTriangulation_h
#define penumbraReceiverTriangulation_h

#include "penumbraDiscontinuityMesher.h"

#include <cstddef>
#include <vector>

namespace penumbra
{
namespace detail
{

/// A constraint in the receiver's 2D frame, with its label.
struct Constraint2D
{
  double A[2];
  double B[2];
  int Order = 2;        ///< -1 outline, 0 contact, 1, 2
  int SourceId = -1;    ///< shooter, or -1
  bool Outline = false; ///< part of the receiver's outline (toggles "inside receiver")
  bool Removal = false; ///< part of a footprint outline (toggles "under a solid")
};

/// Input of TriangulateReceiver.
struct TriangulationInput
{
  int ReceiverId = -1;
  /// Constraints; collinear overlaps already merged, end points snapped.
  std::vector<Constraint2D> Constraints;
  /// The frame: a 2D point (x, y) is Origin + x AxisU + y AxisV in 3D.
  Vec3 Origin;
  Vec3 AxisU;
  Vec3 AxisV;
  /// 2D points that stand for known 3D points (the receiver's vertices):
  /// output exactly as given instead of being mapped back through the frame.
  std::vector<std::array<double, 2>> Known2D;
  std::vector<Vec3> Known3D;
  /// Minimum angle in degrees (0 = no refinement).
  double MinimumAngle = 0.0;
};

/// Output of TriangulateReceiver.
struct TriangulationOutput
{
  ReceiverMesh Mesh;
  std::size_t Failures = 0;          ///< constraint insertions that threw
  std::size_t DroppedDegenerate = 0; ///< zero-area triangles after rounding
  double RemovedArea = 0.0;          ///< area inside the outline and inside a footprint
};

/**
 * Triangulate: insert every constraint (exact intersections where they
 * cross), classify faces by flood fill (crossing an Outline edge toggles
 * "inside the receiver", crossing a Removal edge toggles "under a solid"),
 * refine when asked, then emit the kept triangles, their points (duplicated
 * across order-0 edges, see ReceiverMesh) and the constrained edges that
 * border them, labelled with the lowest order of the constraints through them.
 */
TriangulationOutput TriangulateReceiver(const TriangulationInput& input);

} // namespace detail
} // namespace penumbra

#endif
