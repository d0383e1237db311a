// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraPlaneFrame.h
 * @brief A plane's frame: origin, two unit in-plane axes and the normal, with
 * the projection of 3D points to the frame's 2D coordinates and back.
 *
 * Each user builds its frames its own way (from a polygon's longest edge,
 * from a mesh's summed normals, ...); only the type, the two maps and
 * InPlaneAxes (for planes without a preferred direction) are shared.
 */
#ifndef penumbraPlaneFrame_h
#define penumbraPlaneFrame_h

#include "penumbraMath.h"
#include "penumbraVector.h"

#include <cmath>

namespace penumbra
{

/// Unit in-plane axes u, v of the plane with unit normal n (u, v, n right-handed):
/// any pair will do where no edge gives a preferred direction.
inline void InPlaneAxes(const Vec3& n, Vec3& u, Vec3& v)
{
  const Vec3 helper = std::abs(n.X) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  u = Normalized(Cross(helper, n));
  v = Cross(n, u);
}

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
