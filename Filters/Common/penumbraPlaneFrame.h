// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraPlaneFrame.h
 * @brief A plane's frame: origin, two unit in-plane axes and the normal, with
 * the projection of 3D points to the frame's 2D coordinates and back.
 *
 * Each user builds its frames its own way (from a polygon's longest edge,
 * from a mesh's summed normals, ...); only the type and the two maps are shared.
 */
#ifndef penumbraPlaneFrame_h
#define penumbraPlaneFrame_h

#include "penumbraMath.h"
#include "penumbraVector.h"

namespace penumbra
{

/// The frame of a plane; U, V, N orthonormal, V = N x U.
struct PlaneFrame
{
  Vec3 Origin, U, V, N;

  /// Coordinates of p (projected onto the plane) in the frame.
  P2 To2D(const Vec3& p) const
  {
    const Vec3 d = p - this->Origin;
    return { Dot(d, this->U), Dot(d, this->V) };
  }
  /// The point of the plane at frame coordinates (u, v).
  Vec3 To3D(double u, double v) const { return this->Origin + u * this->U + v * this->V; }
  /// The point of the plane at frame coordinates p.
  Vec3 To3D(const P2& p) const { return this->To3D(p[0], p[1]); }
};

} // namespace penumbra

#endif
