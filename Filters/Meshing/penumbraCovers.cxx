// SPDX-License-Identifier: GPL-3.0-or-later
// Cover lines on one receiver.
#include "penumbraCovers.h"

#include "penumbraContacts.h"

#include "penumbraMeshingTolerances.h"
#include "penumbraOccluderSet.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

namespace
{

/// Twice the signed area of a 2D polygon (positive counter-clockwise).
double SignedArea2(const std::vector<P2>& p)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    const P2& a = p[i];
    const P2& b = p[(i + 1) % p.size()];
    sum += a[0] * b[1] - a[1] * b[0];
  }
  return sum;
}

/// Smallest extent of a convex polygon across one of its edges.
double Width(const std::vector<P2>& p)
{
  double width = HUGE_VAL;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    const P2& a = p[i];
    const P2& b = p[(i + 1) % p.size()];
    const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
    if (length <= 0.0)
    {
      continue;
    }
    double farthest = 0.0;
    for (const P2& q : p)
    {
      farthest = std::max(farthest,
        std::abs((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])) / length);
    }
    width = std::min(width, farthest);
  }
  return width;
}

/// Whether a counter-clockwise polygon is strictly convex (no reflex corner).
bool Convex(const std::vector<P2>& p)
{
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    const P2& a = p[i];
    const P2& b = p[(i + 1) % p.size()];
    const P2& c = p[(i + 2) % p.size()];
    if ((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) <= 0.0)
    {
      return false;
    }
  }
  return true;
}

/// The convex counter-clockwise polygon `p` with every edge moved inward by
/// `d`; empty when it vanishes.
std::vector<P2> Inset(const std::vector<P2>& p, double d)
{
  const std::size_t n = p.size();
  // Each edge as a line n . x = c with inward unit normal n.
  std::vector<std::array<double, 3>> lines(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const P2& a = p[i];
    const P2& b = p[(i + 1) % n];
    const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
    const double nx = -(b[1] - a[1]) / length, ny = (b[0] - a[0]) / length;
    lines[i] = { nx, ny, nx * a[0] + ny * a[1] + d };
  }
  std::vector<P2> out(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto& l0 = lines[(i + n - 1) % n];
    const auto& l1 = lines[i];
    const double det = l0[0] * l1[1] - l0[1] * l1[0];
    if (std::abs(det) < 1e-12)
    {
      return {};
    }
    out[i] = { (l0[2] * l1[1] - l0[1] * l1[2]) / det, (l0[0] * l1[2] - l0[2] * l1[0]) / det };
  }
  // Still the same polygon, shrunk: every edge keeps its direction (past
  // the collapse a rectangle turns inside out in both directions and would
  // look valid again) and the polygon stays convex.
  for (std::size_t i = 0; i < n; ++i)
  {
    const P2& a = p[i];
    const P2& b = p[(i + 1) % n];
    const P2& c = out[i];
    const P2& d = out[(i + 1) % n];
    if (!((b[0] - a[0]) * (d[0] - c[0]) + (b[1] - a[1]) * (d[1] - c[1]) > 0.0))
    {
      return {};
    }
  }
  if (!(SignedArea2(out) > 0.0) || !Convex(out))
  {
    return {};
  }
  return out;
}

/// Clip the counter-clockwise convex polygon `p` to the receiver's outline
/// when that is convex (else leave it); false when nothing is left.
bool ClipToConvexOutline(const std::vector<P2>& receiver, std::vector<P2>& p)
{
  std::vector<P2> ccw = receiver;
  if (SignedArea2(ccw) < 0.0)
  {
    std::reverse(ccw.begin(), ccw.end());
  }
  if (!Convex(ccw))
  {
    return true;
  }
  std::vector<double> in, out;
  for (const P2& q : p)
  {
    in.push_back(q[0]);
    in.push_back(q[1]);
  }
  int count = static_cast<int>(p.size());
  for (std::size_t i = 0; i < ccw.size() && count >= 3; ++i)
  {
    const P2& a = ccw[i];
    const P2& b = ccw[(i + 1) % ccw.size()];
    // Inside: to the left of a -> b.
    const double ea = -(b[1] - a[1]), eb = b[0] - a[0];
    out.assign(2 * (2 * count + 2), 0.0);
    count = ClipPolygon2D(in.data(), count, ea, eb, -(ea * a[0] + eb * a[1]), out.data());
    in.assign(out.begin(), out.begin() + 2 * count);
  }
  if (count < 3)
  {
    return false;
  }
  p.clear();
  for (int k = 0; k < count; ++k)
  {
    p.push_back({ in[2 * k], in[2 * k + 1] });
  }
  return SignedArea2(p) > 0.0;
}

} // namespace

void AddCovers(const SceneTopology& topology, const OccluderSet& occluders, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats)
{
  const PolygonData& r = topology.Polygons[receiverId];
  const double tol = std::max(settings.ContactTolerance * topology.Size, kLinear * topology.Size);
  const double snap = kSnap * topology.Size;
  // The candidates: polygons meeting the slab in front of the receiver as
  // thick as the largest gap a cover could have over it (the pocket lies on
  // the receiver, so its width is at most the receiver's diameter).
  const double thickness = kCoverGapRatio * r.Diameter;
  const std::vector<int> candidates =
    PolygonsNearPlane(topology, occluders, receiverId, tol, thickness, thickness);

  std::vector<Interval> scratch;
  std::vector<std::pair<P2, P2>> pieces;
  std::vector<P2> outline;
  for (int k : candidates)
  {
    const PolygonData& p = topology.Polygons[k];
    double nearest = HUGE_VAL, farthest = 0.0;
    for (const Vec3& v : p.V)
    {
      const double distance = Dot(r.N, v) - r.D;
      nearest = std::min(nearest, distance);
      farthest = std::max(farthest, distance);
    }
    if (!(nearest > tol))
    {
      continue; // touching or crossing the receiver's plane: contacts, not covers
    }
    outline.clear();
    for (const Vec3& v : p.V)
    {
      outline.push_back(frame.To2D(v));
    }
    if (SignedArea2(outline) < 0.0)
    {
      std::reverse(outline.begin(), outline.end());
    }
    if (!(farthest <= thickness) || !Convex(outline))
    {
      continue;
    }
    // The pocket: the part of the cover over the receiver (a cover larger
    // than the receiver, such as a floor under a plate, leaves the plate's
    // own outline as the pocket's). The gap must be small next to it.
    if (!ClipToConvexOutline(frame.Outline, outline) ||
      !(farthest <= kCoverGapRatio * Width(outline)))
    {
      continue;
    }
    // The outline, then loops inset by the gap, 4 times the gap, ... until
    // the polygon vanishes.
    const auto addLoop = [&](const std::vector<P2>& loop) {
      for (std::size_t i = 0; i < loop.size(); ++i)
      {
        ClipToOutline(loop[i], loop[(i + 1) % loop.size()], frame, snap, scratch, pieces);
        for (const auto& piece : pieces)
        {
          Segment2 s;
          s.A = piece.first;
          s.B = piece.second;
          s.Order = 1;
          s.SourceId = -1;
          out.push_back(s);
          ++stats.CoverSegments;
        }
      }
    };
    addLoop(outline);
    for (double inset = nearest;; inset *= 4.0)
    {
      const std::vector<P2> loop = Inset(outline, inset);
      if (loop.empty())
      {
        break;
      }
      addLoop(loop);
    }
  }
}

} // namespace detail
} // namespace penumbra
