// SPDX-License-Identifier: GPL-3.0-or-later
// A receiver's frame, and clipping to its outline in that frame.
#include "penumbraReceiverFrame.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

namespace
{

// 1 inside, 0 on the boundary (within tol), -1 outside; concave polygons too.
int PointInPolygon2(const P2& p, const std::vector<P2>& poly, double tol)
{
  const std::size_t n = poly.size();
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    if (DistancePointSegment2(p, poly[j], poly[i]) <= tol)
    {
      return 0;
    }
    const P2& a = poly[j];
    const P2& b = poly[i];
    if ((a[1] > p[1]) != (b[1] > p[1]))
    {
      const double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x > p[0])
      {
        inside = !inside;
      }
    }
  }
  return inside ? 1 : -1;
}

} // namespace

ReceiverFrame MakeFrame(const PolygonData& r)
{
  ReceiverFrame f;
  f.Origin = r.Centroid;
  f.N = r.N;
  f.D = r.D;
  // First axis along the longest edge (well conditioned), projected in-plane.
  std::size_t best = 0;
  double bestLength = -1.0;
  for (std::size_t i = 0; i < r.V.size(); ++i)
  {
    const double l = Length(r.V[(i + 1) % r.V.size()] - r.V[i]);
    if (l > bestLength)
    {
      bestLength = l;
      best = i;
    }
  }
  Vec3 u = r.V[(best + 1) % r.V.size()] - r.V[best];
  u = Normalized(u - Dot(u, r.N) * r.N);
  f.U = u;
  f.V = Cross(r.N, u);
  for (const Vec3& p : r.V)
  {
    f.Outline.push_back(f.To2D(p));
  }
  return f;
}

double DistancePointSegment2(const P2& p, const P2& a, const P2& b)
{
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  double s = len2 > 0.0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
  s = std::max(0.0, std::min(1.0, s));
  const double ex = a[0] + s * dx - p[0], ey = a[1] + s * dy - p[1];
  return std::sqrt(ex * ex + ey * ey);
}

void ClipSegmentToPolygon2(const P2& a, const P2& b, const std::vector<P2>& poly, double tol,
  std::vector<Interval>& pieces)
{
  pieces.clear();
  std::vector<double> cuts = { 0.0, 1.0 };
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len = std::sqrt(dx * dx + dy * dy);
  if (!(len > 0.0))
  {
    return;
  }
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const P2& p = poly[i];
    const P2& q = poly[(i + 1) % n];
    const double ex = q[0] - p[0], ey = q[1] - p[1];
    const double den = dx * ey - dy * ex;
    const double elen = std::sqrt(ex * ex + ey * ey);
    if (std::abs(den) > 1e-14 * len * elen)
    {
      const double s = ((p[0] - a[0]) * ey - (p[1] - a[1]) * ex) / den;
      const double u = ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx) / den;
      if (s > 0.0 && s < 1.0 && u >= -1e-12 && u <= 1.0 + 1e-12)
      {
        cuts.push_back(s);
      }
    }
    // Polygon vertices on (or near) the segment also cut it: collinear
    // overlaps and grazing corners.
    if (DistancePointSegment2(p, a, b) <= tol)
    {
      const double s = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (len * len);
      if (s > 0.0 && s < 1.0)
      {
        cuts.push_back(s);
      }
    }
  }
  std::sort(cuts.begin(), cuts.end());
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
  {
    const double s0 = cuts[k], s1 = cuts[k + 1];
    if (!(s1 > s0))
    {
      continue;
    }
    const double sm = 0.5 * (s0 + s1);
    const P2 m = { a[0] + sm * dx, a[1] + sm * dy };
    if (PointInPolygon2(m, poly, tol) >= 0)
    {
      if (!pieces.empty() && pieces.back().Hi == s0)
      {
        pieces.back().Hi = s1;
      }
      else
      {
        pieces.push_back({ s0, s1 });
      }
    }
  }
}

void ClipToOutline(const P2& a, const P2& b, const ReceiverFrame& frame, double snap,
  std::vector<Interval>& scratch, std::vector<std::pair<P2, P2>>& pieces)
{
  pieces.clear();
  ClipSegmentToPolygon2(a, b, frame.Outline, snap, scratch);
  for (const Interval& iv : scratch)
  {
    P2 pa = { a[0] + iv.Lo * (b[0] - a[0]), a[1] + iv.Lo * (b[1] - a[1]) };
    P2 pb = { a[0] + iv.Hi * (b[0] - a[0]), a[1] + iv.Hi * (b[1] - a[1]) };
    if (iv.Lo == 0.0)
    {
      pa = a;
    }
    if (iv.Hi == 1.0)
    {
      pb = b;
    }
    pieces.emplace_back(pa, pb);
  }
}

} // namespace detail
} // namespace penumbra
