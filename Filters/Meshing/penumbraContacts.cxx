// SPDX-License-Identifier: GPL-3.0-or-later
// Contact lines and footprints of standing solids on one receiver.
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

/// The contact search on one receiver.
class ContactFinder
{
public:
  ContactFinder(const SceneTopology& topology, int receiverId,
    const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame)
    : Topology(topology)
    , Receiver(topology.Polygons[receiverId])
    , Frame(frame)
    , Tol(std::max(settings.ContactTolerance * topology.Size, kLinear * topology.Size))
    , Snap(kSnap * topology.Size)
  {
  }

  /// Polygons near the receiver's plane and bounds (sorted).
  std::vector<int> NearPolygons(const OccluderSet& occluders, int receiverId) const;

  /// Contact lines of the near polygons' edges in the plane (clipped to the
  /// receiver, those along its outline left out); returns the components of
  /// the polygons that touch it (sorted, unique).
  std::vector<int> AddContactLines(const std::vector<int>& near, std::vector<Segment2>& out,
    DiscontinuityMeshStatistics& stats) const;

  /// Whether component c is a solid standing on the receiver: closed apart
  /// from edges in its plane, and entirely on its front side.
  bool Stands(int c) const;

  /// The outline of component c's footprint: its in-plane edges used by a
  /// polygon not in the plane.
  void AddFootprint(int c, std::vector<Segment2>& out) const;

private:
  double Distance(const Vec3& p) const { return Dot(this->Receiver.N, p) - this->Receiver.D; }
  bool InPlane(const PolygonData& p) const
  {
    for (const Vec3& v : p.V)
    {
      if (std::abs(this->Distance(v)) > this->Tol)
      {
        return false;
      }
    }
    return true;
  }
  bool InFront(const PolygonData& p) const
  {
    for (const Vec3& v : p.V)
    {
      if (this->Distance(v) > this->Tol)
      {
        return true;
      }
    }
    return false;
  }
  bool OnOutline(const P2& a, const P2& b) const;

  const SceneTopology& Topology;
  const PolygonData& Receiver;
  const ReceiverFrame& Frame;
  const double Tol;
  const double Snap;
};

std::vector<int> ContactFinder::NearPolygons(const OccluderSet& occluders, int receiverId) const
{
  return PolygonsNearPlane(
    this->Topology, occluders, receiverId, -this->Tol, this->Tol, this->Tol);
}

bool ContactFinder::OnOutline(const P2& a, const P2& b) const
{
  const std::vector<P2>& outline = this->Frame.Outline;
  bool onOutline = false;
  for (std::size_t e = 0; e < outline.size() && !onOutline; ++e)
  {
    const P2& oa = outline[e];
    const P2& ob = outline[(e + 1) % outline.size()];
    onOutline = DistancePointSegment2(a, oa, ob) <= this->Tol &&
      DistancePointSegment2(b, oa, ob) <= this->Tol;
  }
  return onOutline;
}

std::vector<int> ContactFinder::AddContactLines(const std::vector<int>& near,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats) const
{
  const double tol = this->Tol;
  std::vector<int> components;
  std::vector<Interval> scratch;
  std::vector<std::pair<P2, P2>> pieces;
  for (int k : near)
  {
    const PolygonData& p = this->Topology.Polygons[k];
    if (this->InPlane(p) || !this->InFront(p))
    {
      continue;
    }
    const std::size_t n = p.V.size();
    bool touches = false;
    for (std::size_t i = 0; i < n; ++i)
    {
      const Vec3 a = p.V[i], b = p.V[(i + 1) % n];
      if (std::abs(this->Distance(a)) > tol || std::abs(this->Distance(b)) > tol)
      {
        continue;
      }
      touches = true;
      ClipToOutline(this->Frame.To2D(a), this->Frame.To2D(b), this->Frame, this->Snap, scratch,
        pieces);
      for (const auto& piece : pieces)
      {
        // Contacts along the receiver's own outline (a wall meeting the
        // floor) are that outline: not a separate line.
        if (this->OnOutline(piece.first, piece.second))
        {
          continue;
        }
        Segment2 s;
        s.A = piece.first;
        s.B = piece.second;
        s.Order = 0;
        s.SourceId = -1;
        out.push_back(s);
        ++stats.ContactSegments;
      }
    }
    if (touches)
    {
      components.push_back(p.Component);
    }
  }
  std::sort(components.begin(), components.end());
  components.erase(std::unique(components.begin(), components.end()), components.end());
  return components;
}

bool ContactFinder::Stands(int c) const
{
  const SceneTopology& topo = this->Topology;
  const double tol = this->Tol;
  if (c == this->Receiver.Component)
  {
    return false; // the receiver belongs to it: we are looking at its inside
  }
  bool closed = true;
  for (int e : topo.ComponentOpenEdges[c])
  {
    Vec3 a, b;
    topo.EdgeEnds(e, a, b);
    if (std::abs(this->Distance(a)) > tol || std::abs(this->Distance(b)) > tol)
    {
      closed = false;
      break;
    }
  }
  for (int k : topo.ComponentPolygons[c])
  {
    for (const Vec3& v : topo.Polygons[k].V)
    {
      closed = closed && this->Distance(v) >= -tol;
    }
  }
  return closed;
}

void ContactFinder::AddFootprint(int c, std::vector<Segment2>& out) const
{
  const SceneTopology& topo = this->Topology;
  const double tol = this->Tol;
  std::vector<int> edges;
  for (int k : topo.ComponentPolygons[c])
  {
    const PolygonData& p = topo.Polygons[k];
    if (this->InPlane(p))
    {
      continue;
    }
    for (std::size_t i = 0; i < p.V.size(); ++i)
    {
      if (std::abs(this->Distance(p.V[i])) <= tol &&
        std::abs(this->Distance(p.V[(i + 1) % p.V.size()])) <= tol)
      {
        edges.push_back(p.Edge[i]);
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (int e : edges)
  {
    const Use& u = topo.EdgeUses[e][0];
    const PolygonData& p = topo.Polygons[u.Polygon];
    Segment2 s;
    s.A = this->Frame.To2D(p.V[u.Index]);
    s.B = this->Frame.To2D(p.V[(u.Index + 1) % p.V.size()]);
    s.Order = 0;
    s.SourceId = -1;
    s.Removal = true;
    out.push_back(s);
  }
}

} // namespace

std::vector<int> PolygonsNearPlane(const SceneTopology& topology, const OccluderSet& occluders,
  int receiverId, double nearDistance, double farDistance, double margin)
{
  const PolygonData& r = topology.Polygons[receiverId];
  CullingVolume slab;
  Vec3 lo = r.V[0], hi = r.V[0];
  for (const Vec3& p : r.V)
  {
    lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
    hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
  }
  slab.BoxMin = lo - Vec3(margin, margin, margin);
  slab.BoxMax = hi + Vec3(margin, margin, margin);
  slab.Planes.push_back({ r.N, r.D + nearDistance });
  slab.Planes.push_back({ -r.N, -r.D - farDistance });
  std::vector<int> polygons;
  occluders.VolumeCandidates(slab, receiverId, -1, polygons);
  std::sort(polygons.begin(), polygons.end());
  return polygons;
}

void AddContacts(const SceneTopology& topology, const OccluderSet& occluders, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame,
  std::vector<Segment2>& out, DiscontinuityMeshStatistics& stats)
{
  const ContactFinder finder(topology, receiverId, settings, frame);
  const std::vector<int> near = finder.NearPolygons(occluders, receiverId);
  // Solids standing on the receiver: closed apart from edges in its plane.
  for (int c : finder.AddContactLines(near, out, stats))
  {
    if (finder.Stands(c))
    {
      finder.AddFootprint(c, out);
    }
  }
}

} // namespace detail
} // namespace penumbra
