// SPDX-License-Identifier: GPL-3.0-or-later
// Exact visibility of one wedge on a receiver: the valid range of the wedge
// parameter, its culling against the receiver, the blockers and the visible rest.
#include "penumbraWedgeTracer.h"

#include "penumbraConvexHull.h"
#include "penumbraMath.h"
#include "penumbraMeshingTolerances.h"
#include "penumbraOccluderSet.h"
#include "penumbraParameterIntervals.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra
{
namespace detail
{

namespace
{

// A half-space Dot(N, y) - D > 0, for clipping chords.
struct HalfSpace
{
  Vec3 N;
  double D;
};

bool ClipChord(Vec3& a, Vec3& b, const HalfSpace* h, int count)
{
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < count; ++k)
  {
    const double fa = Dot(h[k].N, a) - h[k].D, fb = Dot(h[k].N, b) - h[k].D;
    if (fa <= 0.0 && fb <= 0.0)
    {
      return false;
    }
    if (fa < 0.0)
    {
      lo = std::max(lo, fa / (fa - fb));
    }
    else if (fb < 0.0)
    {
      hi = std::min(hi, fa / (fa - fb));
    }
  }
  if (!(hi > lo))
  {
    return false;
  }
  const Vec3 d = b - a;
  const Vec3 na = a + lo * d, nb = a + hi * d;
  a = na;
  b = nb;
  return true;
}

/// The wedge's frame: the generator's direction u and length, the in-plane
/// direction wn from the apex towards the generator line at distance h, and
/// the plane distances of the apex and of the generator's points.
struct WedgeFrame
{
  Vec3 Gd;     ///< G1 - G0
  double Len;  ///< |Gd|
  Vec3 U;      ///< Gd / Len
  double G0;   ///< parameter of G0 along U from the apex
  double H;    ///< distance from the apex to the generator's line
  Vec3 Wn;     ///< in-plane, from the apex towards the generator line
  double HR;   ///< receiver plane distance of the apex
  double HS;   ///< shooter plane distance of the apex
  double AR, BR; ///< receiver plane distance along the generator: AR + BR t
  double AS, BS; ///< shooter plane distance along the generator: AS + BS t
  double MuMax;  ///< bound of |mu| for receiver points within reach
};

// The frame of wedge w, or false when it is degenerate.
bool MakeWedgeFrame(const PairContext& ctx, const Wedge& w, WedgeFrame& f)
{
  const double tol = ctx.Tol;
  const Vec3 gd = w.G1 - w.G0;
  const double len = Length(gd);
  if (!(len > tol))
  {
    return false;
  }
  const Vec3 u = gd / len;
  const Vec3 w0 = w.G0 - w.P;
  const double g0 = Dot(w0, u);
  const Vec3 wv = w0 - g0 * u;
  const double h = Length(wv);
  if (!(h > tol))
  {
    return false; // apex on the generator's line
  }
  f.Gd = gd;
  f.Len = len;
  f.U = u;
  f.G0 = g0;
  f.H = h;
  f.Wn = wv / h;
  const PolygonData& rec = *ctx.Receiver;
  const PolygonData& sh = *ctx.Shooter;
  f.HR = Dot(rec.N, w.P) - rec.D;
  f.HS = Dot(sh.N, w.P) - sh.D;
  f.AR = Dot(rec.N, w.G0) - rec.D;
  f.BR = Dot(rec.N, gd);
  f.AS = Dot(sh.N, w.G0) - sh.D;
  f.BS = Dot(sh.N, gd);
  // |mu_r| <= muMax keeps receiver points within reach of the receiver (mu
  // is the line parameter: 0 at the apex, 1 on the generator).
  const double reach = Length(w.P - ctx.ReceiverCentre) + ctx.ReceiverRadius;
  f.MuMax = reach / h + 1.0;
  return true;
}

// The wedge parameter t of the line from the apex through point c.
double CentralParameter(const Wedge& w, const WedgeFrame& f, const Vec3& c)
{
  return (Dot(c - w.P, f.U) * f.H / Dot(c - w.P, f.Wn) - f.G0) / f.Len;
}

// Occluder EV wedges: the t-intervals of the lines of case A or B (see
// ValidIntervals) that also hit the shooter beyond the right feature.
void OccluderShooterHits(const PairContext& ctx, const Wedge& w, const WedgeFrame& f,
  const Interval& a, const Interval& b, std::vector<Interval>& shooterHits)
{
  const double tol = ctx.Tol;
  const Vec3& wn = f.Wn;
  const double h = f.H;
  // Lines of case A must hit the shooter beyond the generator (b > h),
  // those of case B beyond the apex on the other side (b < 0).
  std::vector<std::pair<Vec3, Vec3>> chords;
  PlaneChords(*ctx.Shooter, w.M, w.P, tol, chords);
  for (int c = 0; c < 2; ++c)
  {
    const Interval& iv = c == 0 ? a : b;
    if (!(iv.Hi > iv.Lo))
    {
      continue;
    }
    for (auto chord : chords)
    {
      HalfSpace hs = c == 0 ? HalfSpace{ wn, Dot(wn, w.P) + h + tol }
                            : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
      Vec3 c0 = chord.first, c1 = chord.second;
      if (!ClipChord(c0, c1, &hs, 1))
      {
        continue;
      }
      double t0 = CentralParameter(w, f, c0);
      double t1 = CentralParameter(w, f, c1);
      Interval hit{ std::max(iv.Lo, std::min(t0, t1)), std::min(iv.Hi, std::max(t0, t1)) };
      if (hit.Hi > hit.Lo)
      {
        shooterHits.push_back(hit);
      }
    }
  }
  Normalize(shooterHits);
}

// The t-intervals whose lines run from the receiver's side through the
// features to the source point in the right order (normalized).
void ValidIntervals(
  const PairContext& ctx, const Wedge& w, const WedgeFrame& f, std::vector<Interval>& valid)
{
  const double tol = ctx.Tol;
  const double hR = f.HR, hS = f.HS, aR = f.AR, bR = f.BR, aS = f.AS, bS = f.BS;
  const double muMax = f.MuMax;
  std::vector<Interval> shooterHits;
  switch (w.Kind)
  {
    case WedgeKind::EV:
    {
      // mu_r = hR / (hR - fR) > 1  <=>  0 < fR < hR, and the generator in
      // front of the shooter.
      Interval iv{ 0.0, 1.0 };
      Restrict(iv, aR - tol, bR);
      Restrict(iv, hR - hR / muMax - aR, -bR);
      Restrict(iv, aS - tol, bS);
      valid.push_back(iv);
      break;
    }
    case WedgeKind::VE:
    {
      // mu_r < 0  <=>  fR > hR: the shooter point farther from the receiver.
      Interval iv{ 0.0, 1.0 };
      Restrict(iv, aR - hR - hR / muMax, bR);
      valid.push_back(iv);
      break;
    }
    case WedgeKind::OO:
    {
      // Case A: receiver, apex, generator, shooter (0 < fS < hS, fR > hR).
      Interval a{ 0.0, 1.0 };
      Restrict(a, aS - tol, bS);
      Restrict(a, hS - aS - tol, -bS);
      Restrict(a, aR - hR - hR / muMax, bR);
      // Case B: receiver, generator, apex, shooter (fS > hS, fR < hR).
      Interval b{ 0.0, 1.0 };
      Restrict(b, aS - hS - tol, bS);
      Restrict(b, aR - tol, bR);
      Restrict(b, hR - hR / muMax - aR, -bR);
      OccluderShooterHits(ctx, w, f, a, b, shooterHits);
      valid = shooterHits;
      break;
    }
  }
  Normalize(valid);
}

// Only the lines that meet the receiver polygon can leave a boundary on it
// (the pieces are clipped to it afterwards), so before looking for
// blockers: a receiver entirely on one side of the wedge plane (farther
// than the snapping distance, so not even an outline piece could remain)
// gets nothing, and otherwise t is restricted to the central projection of
// the receiver's chords in the wedge plane. Most wedges miss a small
// receiver entirely and stop here. Each chord is lengthened by ctx.Margin
// so that the pieces still end where the 2D clip against R's outline puts
// them, not at a rounded projection. Returns false when nothing is left.
bool RestrictToReceiver(
  const PairContext& ctx, const Wedge& w, const WedgeFrame& f, std::vector<Interval>& valid)
{
  const double tol = ctx.Tol;
  const Vec3& wn = f.Wn;
  const PolygonData& rec = *ctx.Receiver;
  bool above = !ctx.Cull, below = !ctx.Cull;
  for (const Vec3& v : rec.V)
  {
    const double d = Dot(w.M, v - w.P);
    above = above || d >= -tol;
    below = below || d <= tol;
  }
  if (!above || !below)
  {
    return false;
  }
  thread_local std::vector<std::pair<Vec3, Vec3>> receiverChords;
  thread_local std::vector<Interval> reach, restricted;
  PlaneChords(rec, w.M, w.P, tol, receiverChords);
  reach.clear();
  for (const auto& chord : receiverChords)
  {
    const Vec3 along = chord.second - chord.first;
    const double chordLength = Length(along);
    const Vec3 pad = chordLength > 0.0 ? (ctx.Margin / chordLength) * along : Vec3();
    for (int side = 0; side < 2; ++side)
    {
      // EV lines reach R beyond the generator, VE lines behind the apex;
      // occluder EV lines may do either.
      if ((w.Kind == WedgeKind::EV && side == 1) || (w.Kind == WedgeKind::VE && side == 0))
      {
        continue;
      }
      const HalfSpace hs = side == 0 ? HalfSpace{ wn, Dot(wn, w.P) + tol }
                                     : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
      Vec3 c0 = chord.first - pad, c1 = chord.second + pad;
      if (!ClipChord(c0, c1, &hs, 1))
      {
        continue;
      }
      const double t0 = CentralParameter(w, f, c0);
      const double t1 = CentralParameter(w, f, c1);
      reach.push_back({ std::min(t0, t1), std::max(t0, t1) });
    }
  }
  // No chord although R meets the plane within tolerance (R nearly in the
  // wedge plane, or touching it): no restriction.
  if (ctx.Cull && !receiverChords.empty())
  {
    Normalize(reach);
    Intersect(valid, reach, restricted);
    valid.swap(restricted);
    if (valid.empty())
    {
      return false;
    }
  }
  return true;
}

// Blocker candidates (into ctx.Scratch): the polygons crossing the wedge
// plane inside the box of the wedge's region (the hull of the apex, the
// generator ends and the receiver and shooter points of the valid
// intervals), found in the BVH.
void FindBlockerCandidates(const PairContext& ctx, const Wedge& w, const WedgeFrame& f,
  const std::vector<Interval>& valid)
{
  const double tol = ctx.Tol;
  const Vec3& u = f.U;
  const Vec3& wn = f.Wn;
  const PolygonData& rec = *ctx.Receiver;
  const PolygonData& sh = *ctx.Shooter;
  const double hR = f.HR, hS = f.HS;
  Vec3 lo = w.P, hi = w.P;
  thread_local std::vector<Vec3> region3;
  region3.clear();
  region3.push_back(w.P);
  auto grow = [&](const Vec3& p) {
    lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
    hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
    region3.push_back(p);
  };
  for (const Interval& iv : valid)
  {
    for (double t : { iv.Lo, iv.Hi })
    {
      const Vec3 g = w.G0 + t * f.Gd;
      grow(g);
      const double fR = Dot(rec.N, g) - rec.D;
      grow(w.P + (hR / (hR - fR)) * (g - w.P));
      if (w.Kind == WedgeKind::OO)
      {
        const double fS = Dot(sh.N, g) - sh.D;
        grow(w.P + (hS / (hS - fS)) * (g - w.P));
      }
    }
  }
  CullingVolume volume;
  volume.BoxMin = lo - Vec3(tol, tol, tol);
  volume.BoxMax = hi + Vec3(tol, tol, tol);
  volume.Planes.push_back({ w.M, Dot(w.M, w.P) - tol });
  volume.Planes.push_back({ -w.M, -Dot(w.M, w.P) - tol });
  // Within the wedge plane the region is the convex hull of those points
  // (a long thin triangle for a wedge from a light to a far shadow line):
  // its edges, as planes perpendicular to the wedge, keep away the many
  // polygons that cross the plane inside the box but far from the region.
  thread_local std::vector<P2> flat;
  thread_local std::vector<int> hull;
  flat.clear();
  for (const Vec3& p : region3)
  {
    flat.push_back({ Dot(p - w.P, u), Dot(p - w.P, wn) });
  }
  ConvexHull2(flat, hull);
  const std::size_t k = hull.size();
  for (std::size_t i = 0; k >= 3 && i < k; ++i)
  {
    // Counter-clockwise hull: the inward normal of edge (a, b) is left of it.
    const P2& a = flat[hull[i]];
    const P2& b = flat[hull[(i + 1) % k]];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double el = std::hypot(ex, ey);
    if (!(el > 0.0))
    {
      continue;
    }
    const Vec3 inward = (-ey / el) * u + (ex / el) * wn;
    const Vec3 at = w.P + a[0] * u + a[1] * wn;
    volume.Planes.push_back({ inward, Dot(inward, at) - tol });
  }
  // Blockers lie on event lines, inside the shaft: among few shaft
  // candidates a scan is cheaper than a BVH traversal.
  ctx.Scratch->clear();
  if (ctx.Cull && ctx.Candidates->size() <= kScanLimit)
  {
    ctx.Occluders->FilterCandidates(volume, ctx.Candidates->data(),
      static_cast<int>(ctx.Candidates->size()), ctx.ShooterId, ctx.ReceiverId, *ctx.Scratch);
  }
  else
  {
    ctx.Occluders->VolumeCandidates(volume, ctx.ShooterId, ctx.ReceiverId, *ctx.Scratch);
  }
}

// Blocked t-intervals (normalized): each candidate's chords in the wedge
// plane, clipped to the part of the lines between the receiver and the
// source point, projected to t.
void BlockedIntervals(
  const PairContext& ctx, const Wedge& w, const WedgeFrame& f, std::vector<Interval>& blocked)
{
  const double tol = ctx.Tol;
  const Vec3& wn = f.Wn;
  const PolygonData& rec = *ctx.Receiver;
  const PolygonData& sh = *ctx.Shooter;
  HalfSpace region[3];
  int regionCount = 0;
  region[regionCount++] = { rec.N, rec.D + tol }; // in front of the receiver
  if (w.Kind == WedgeKind::VE)
  {
    region[regionCount++] = { -wn, -Dot(wn, w.P) - f.H + tol }; // before the shooter edge
  }
  else if (w.Kind == WedgeKind::OO)
  {
    region[regionCount++] = { sh.N, sh.D + tol }; // in front of the shooter
  }
  std::vector<std::pair<Vec3, Vec3>> chords;
  const std::vector<PolygonData>& polys = *ctx.Polygons;
  for (int k : *ctx.Scratch)
  {
    if (std::binary_search(w.Exclude.begin(), w.Exclude.end(), k))
    {
      continue;
    }
    PlaneChords(polys[k], w.M, w.P, tol, chords);
    for (const auto& chord : chords)
    {
      for (int side = 0; side < 2; ++side)
      {
        // EV lines only run on the generator's side of the apex.
        if (w.Kind == WedgeKind::EV && side == 1)
        {
          continue;
        }
        HalfSpace hs[4];
        std::copy(region, region + regionCount, hs);
        hs[regionCount] = side == 0 ? HalfSpace{ wn, Dot(wn, w.P) + tol }
                                    : HalfSpace{ -wn, -Dot(wn, w.P) + tol };
        Vec3 c0 = chord.first, c1 = chord.second;
        if (!ClipChord(c0, c1, hs, regionCount + 1))
        {
          continue;
        }
        const double t0 = CentralParameter(w, f, c0);
        const double t1 = CentralParameter(w, f, c1);
        const double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(1.0, std::max(t0, t1));
        if (hi > lo)
        {
          blocked.push_back({ lo, hi });
        }
      }
    }
  }
  Normalize(blocked);
}

} // namespace

// Chords of polygon p with the plane (m, through point o): pairs of 3D points.
void PlaneChords(const PolygonData& p, const Vec3& m, const Vec3& o, double tol,
  std::vector<std::pair<Vec3, Vec3>>& chords)
{
  chords.clear();
  const std::size_t n = p.V.size();
  const Vec3 dir = Cross(m, p.N);
  if (!(Length(dir) > kAngle))
  {
    return; // polygon parallel to (or in) the plane
  }
  double d[64];
  std::vector<double> heap;
  double* dist = d;
  if (n > 64)
  {
    heap.resize(n);
    dist = heap.data();
  }
  bool pos = false, neg = false;
  for (std::size_t i = 0; i < n; ++i)
  {
    dist[i] = Dot(m, p.V[i] - o);
    // Symbolic perturbation: points within tol count as positive.
    if (dist[i] < -tol)
    {
      neg = true;
    }
    else
    {
      pos = true;
    }
  }
  if (!pos || !neg)
  {
    return;
  }
  // Crossing points, sorted along the line (scratch reused per thread).
  thread_local std::vector<std::pair<double, Vec3>> cuts;
  cuts.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t j = (i + 1) % n;
    const bool si = dist[i] >= -tol, sj = dist[j] >= -tol;
    if (si == sj)
    {
      continue;
    }
    double f = dist[i] / (dist[i] - dist[j]);
    f = std::max(0.0, std::min(1.0, f));
    const Vec3 x = p.V[i] + f * (p.V[j] - p.V[i]);
    cuts.push_back({ Dot(x, dir), x });
  }
  std::sort(cuts.begin(), cuts.end(),
    [](const std::pair<double, Vec3>& a, const std::pair<double, Vec3>& b)
    { return a.first < b.first; });
  for (std::size_t k = 0; k + 1 < cuts.size(); k += 2)
  {
    chords.push_back({ cuts[k].second, cuts[k + 1].second });
  }
}

bool TraceWedge(const PairContext& ctx, const Wedge& w, std::vector<std::pair<Vec3, Vec3>>& out)
{
  out.clear();
  WedgeFrame f;
  if (!MakeWedgeFrame(ctx, w, f))
  {
    return false;
  }
  std::vector<Interval> valid;
  ValidIntervals(ctx, w, f, valid);
  if (valid.empty())
  {
    return false;
  }
  if (!RestrictToReceiver(ctx, w, f, valid))
  {
    return false;
  }
  FindBlockerCandidates(ctx, w, f, valid);
  std::vector<Interval> blocked;
  BlockedIntervals(ctx, w, f, blocked);
  std::vector<Interval> visible;
  Subtract(valid, blocked, visible);
  const PolygonData& rec = *ctx.Receiver;
  for (const Interval& iv : visible)
  {
    auto receiverPoint = [&](double t) {
      const Vec3 g = w.G0 + t * f.Gd;
      const double fR = Dot(rec.N, g) - rec.D;
      const double mu = f.HR / (f.HR - fR);
      return w.P + mu * (g - w.P);
    };
    out.push_back({ receiverPoint(iv.Lo), receiverPoint(iv.Hi) });
  }
  return true;
}

} // namespace detail
} // namespace penumbra
