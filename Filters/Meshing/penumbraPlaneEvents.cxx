// SPDX-License-Identifier: GPL-3.0-or-later
// The D1 lines of planes seen edge-on: the shooter's own plane crossing the
// receiver, and the planes of occluder polygons that cut the shooter (the
// degenerate EEE events of their coplanar edges).
#include "penumbraVisualEvents.h"

#include "penumbraMeshingTolerances.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

// The shooter's own plane crossing the receiver: the form factor grows
// linearly from 0 on its front side (the shooter is seen edge-on), a D1 line.
// It is kept whole, without a visibility test.
void ShadowEvents::AddShooterPlaneEvent()
{
  const double tol = this->Tol;
  const PolygonData& sh = this->Sh;
  const ReceiverFrame& frame = this->Frame;
  bool pos = false, neg = false;
  double reach = 0.0;
  for (const Vec3& v : this->Rec.V)
  {
    const double d = this->DistS(v);
    pos = pos || d > tol;
    neg = neg || d < -tol;
  }
  const double a = Dot(sh.N, frame.U), b = Dot(sh.N, frame.V);
  const double c = sh.D - Dot(sh.N, frame.Origin);
  const double norm = std::hypot(a, b);
  if (!(pos && neg && norm > kAngle))
  {
    return;
  }
  const P2 foot = { a * c / (norm * norm), b * c / (norm * norm) };
  const P2 dir = { -b / norm, a / norm };
  for (const P2& q : frame.Outline)
  {
    reach = std::max(reach, std::hypot(q[0] - foot[0], q[1] - foot[1]));
  }
  const P2 p0 = { foot[0] - 2.0 * reach * dir[0], foot[1] - 2.0 * reach * dir[1] };
  const P2 p1 = { foot[0] + 2.0 * reach * dir[0], foot[1] + 2.0 * reach * dir[1] };
  ClipSegmentToPolygon2(p0, p1, frame.Outline, this->Snap, this->ClipScratch);
  for (const Interval& iv : this->ClipScratch)
  {
    Segment2 seg;
    seg.A = { p0[0] + iv.Lo * (p1[0] - p0[0]), p0[1] + iv.Lo * (p1[1] - p0[1]) };
    seg.B = { p0[0] + iv.Hi * (p1[0] - p0[0]), p0[1] + iv.Hi * (p1[1] - p0[1]) };
    if (std::hypot(seg.B[0] - seg.A[0], seg.B[1] - seg.A[1]) < this->MinPiece)
    {
      continue;
    }
    seg.Order = 1;
    seg.SourceId = this->ShooterId;
    this->Out.push_back(seg);
    ++this->Stats.SegmentsGenerated;
  }
}

// Face planes: from a receiving point in the plane of an occluder polygon F
// whose plane cuts the shooter, F is seen edge-on; on either side a strip
// of F's image, growing linearly, covers part of the shooter (the two
// chains of F's outline recede at different rates): a D1 line (a
// degenerate EEE event of F's coplanar edges). Its extent on the receiver
// is where F's image overlaps the shooter's chord in that plane, bounded
// by lines through a vertex of F and the chord (VE-like pencils) or
// through a chord end and an edge of F (EV-like pencils).
void ShadowEvents::AddFacePlaneEvents()
{
  const double tol = this->Tol, contactTol = this->ContactTol;
  const PolygonData& sh = this->Sh;
  std::vector<std::pair<Vec3, Vec3>> shooterChords;
  for (int k : this->Candidates)
  {
    const PolygonData& f = this->Topology.Polygons[k];
    if (!(Length(Cross(f.N, this->Rec.N)) > kAngle))
    {
      continue;
    }
    bool pos = false, neg = false;
    for (const Vec3& v : sh.V)
    {
      const double d = Dot(f.N, v) - f.D;
      pos = pos || d > tol;
      neg = neg || d < -tol;
    }
    if (!pos || !neg)
    {
      continue;
    }
    PlaneChords(sh, f.N, f.V[0], tol, shooterChords);
    std::vector<int> exclude = { k };
    for (int c : f.Cluster)
    {
      this->ExcludeVertex(c, exclude);
    }
    this->FinishExclude(exclude);
    const std::size_t nf = f.V.size();
    for (const auto& chord : shooterChords)
    {
      for (std::size_t i = 0; i < nf; ++i)
      {
        const Vec3& v = f.V[i];
        if (this->DistR(v) > contactTol && this->DistS(v) > tol)
        {
          Wedge w;
          w.Kind = WedgeKind::VE;
          w.P = v;
          w.G0 = chord.first;
          w.G1 = chord.second;
          w.M = f.N;
          w.Exclude = exclude;
          this->Emit(w, 1, k, -1);
        }
        const Vec3& a = f.V[i];
        const Vec3& b = f.V[(i + 1) % nf];
        if ((std::abs(this->DistR(a)) <= contactTol && std::abs(this->DistR(b)) <= contactTol) ||
          (this->DistS(a) <= tol && this->DistS(b) <= tol))
        {
          continue;
        }
        for (const Vec3& end : { chord.first, chord.second })
        {
          if (this->DistR(end) <= tol)
          {
            continue;
          }
          Wedge w;
          w.Kind = WedgeKind::EV;
          w.P = end;
          w.G0 = a;
          w.G1 = b;
          w.M = f.N;
          w.Exclude = exclude;
          this->Emit(w, 1, k, -1);
        }
      }
    }
  }
}

} // namespace detail
} // namespace penumbra
