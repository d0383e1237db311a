// SPDX-License-Identifier: GPL-3.0-or-later
// EV, VE and occluder EV events of one (shooter, receiver) pair: the usable
// features, the supporting-wedge tests, and the tracing of each wedge.
#include "penumbraVisualEvents.h"

#include "penumbraJumpThreshold.h"
#include "penumbraMeshingTolerances.h"
#include "penumbraOccluderSet.h"
#include "penumbraSilhouette.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

namespace
{

// The largest screens tried per pair: the big boards (shelves, desk tops,
// cabinet backs) come first by area, and each feature tries them all when
// none hides it.
constexpr int kMaxScreens = 12;

// Add to `cone` the planes through `apex` and the edges of a convex hull
// (centre `centre`), facing the hull, or away from it when `reflected`.
void AddCone(const Vec3* hull, int count, const Vec3& centre, const Vec3& apex, bool reflected,
  double tol, CullingVolume& cone)
{
  for (int i = 0; i < count; ++i)
  {
    const Vec3 a = hull[i], b = hull[(i + 1) % count];
    Vec3 n = Normalized(Cross(b - a, apex - a));
    if ((Dot(n, centre - apex) < 0.0) != reflected)
    {
      n = -n;
    }
    cone.Planes.push_back({ n, Dot(n, apex) - tol });
  }
}

} // namespace

ShadowEvents::ShadowEvents(const SceneTopology& topology, const OccluderSet& occluders,
  const Scene& scene, const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame,
  int receiverId, int shooterId, double minimumJump, std::vector<Segment2>& out,
  DiscontinuityMeshStatistics& stats)
  : Topology(topology)
  , Occluders(occluders)
  , SceneRef(scene)
  , Settings(settings)
  , Frame(frame)
  , ReceiverId(receiverId)
  , ShooterId(shooterId)
  , MinimumJump(minimumJump)
  , Out(out)
  , Stats(stats)
  , Rec(topology.Polygons[receiverId])
  , Sh(topology.Polygons[shooterId])
  , Tol(kLinear * topology.Size)
  , ContactTol(std::max(settings.ContactTolerance * topology.Size, kLinear * topology.Size))
  , Snap(kSnap * topology.Size)
  , MinPiece(kMinPiece * topology.Size)
{
}

void ShadowEvents::Run()
{
  CullingVolume shaft;
  if (!this->Occluders.ShaftCandidates(this->ShooterId, this->ReceiverId, this->Candidates, &shaft))
  {
    return;
  }
  ++this->Stats.Pairs;
  this->Stats.CandidateOccluders += this->Candidates.size();

  PairContext& ctx = this->Ctx;
  ctx.Polygons = &this->Topology.Polygons;
  ctx.Shooter = &this->Sh;
  ctx.Receiver = &this->Rec;
  ctx.Occluders = &this->Occluders;
  ctx.ShooterId = this->ShooterId;
  ctx.ReceiverId = this->ReceiverId;
  ctx.Scratch = &this->Scratch;
  ctx.Candidates = &this->Candidates;
  ctx.Cull = this->Settings.CullWedges;
  ctx.Tol = this->Tol;
  ctx.Margin = kChordMargin * this->Topology.Size;
  ctx.ReceiverCentre = this->Rec.Centroid;
  for (const Vec3& v : this->Rec.V)
  {
    ctx.ReceiverRadius = std::max(ctx.ReceiverRadius, Length(v - this->Rec.Centroid));
  }

  this->SelectFeatures(shaft);
  this->ShooterRadiance = JumpRadiance(this->SceneRef, this->Settings, this->ShooterId);
  this->AddEdgeVertexEvents();
  this->AddVertexEdgeEvents();
  if (this->Settings.OccluderOccluderEvents)
  {
    this->AddOccluderEvents();
  }
  if (!this->Settings.PlaneEvents)
  {
    return;
  }
  this->AddShooterPlaneEvent();
  this->AddFacePlaneEvents();
}

// Every event line runs from a receiving point to a shooter point through
// its features, so a feature entirely outside the convex hull of shooter and
// receiver (the shaft) is on no event line, although its polygon may cross
// the shaft.
bool ShadowEvents::OutsideShaft(const CullingVolume& shaft, const Vec3* points, int count) const
{
  if (!this->Settings.CullWedges)
  {
    return false;
  }
  for (const Plane& plane : shaft.Planes)
  {
    bool outside = true;
    for (int k = 0; k < count && outside; ++k)
    {
      outside = Dot(plane.Normal, points[k]) < plane.Offset - this->Tol;
    }
    if (outside)
    {
      return true;
    }
  }
  return false;
}

void ShadowEvents::SelectFeatures(const CullingVolume& shaft)
{
  const double tol = this->Tol, contactTol = this->ContactTol;
  // Features of the candidates: distinct edges and vertex clusters.
  std::vector<int> edges, vertices;
  for (int k : this->Candidates)
  {
    const PolygonData& p = this->Topology.Polygons[k];
    for (std::size_t i = 0; i < p.V.size(); ++i)
    {
      edges.push_back(p.Edge[i]);
      vertices.push_back(p.Cluster[i]);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  // Keep only features usable as occluders of this pair: not lying in the
  // receiver's plane (contacts), partly in front of the shooter and receiver,
  // meeting the shaft, and not hidden from the receiver by a screen.
  if (this->Settings.CullWedges)
  {
    this->Screens.Build(this->Topology, this->Candidates, this->Sh, this->Rec, tol, kMaxScreens);
  }
  for (int e : edges)
  {
    Vec3 a, b;
    this->Topology.EdgeEnds(e, a, b);
    if (std::abs(this->DistR(a)) <= contactTol && std::abs(this->DistR(b)) <= contactTol)
    {
      continue;
    }
    if ((this->DistS(a) <= tol && this->DistS(b) <= tol) ||
      (this->DistR(a) <= tol && this->DistR(b) <= tol))
    {
      continue;
    }
    const Vec3 ends[2] = { a, b };
    if (this->OutsideShaft(shaft, ends, 2) || this->Screens.Hides(ends, 2))
    {
      continue;
    }
    this->UsableEdges.push_back(e);
  }
  for (int c : vertices)
  {
    const Vec3& p = this->Topology.ClusterPoint[c];
    if (this->DistR(p) > contactTol && this->DistS(p) > tol &&
      !this->OutsideShaft(shaft, &p, 1) && !this->Screens.Hides(&p, 1))
    {
      this->UsableVertices.push_back(c);
    }
  }
}

void ShadowEvents::FinishExclude(std::vector<int>& exclude)
{
  std::sort(exclude.begin(), exclude.end());
  exclude.erase(std::unique(exclude.begin(), exclude.end()), exclude.end());
}

void ShadowEvents::ExcludeEdge(int e, std::vector<int>& exclude) const
{
  for (const Use& use : this->Topology.EdgeUses[e])
  {
    exclude.push_back(use.Polygon);
  }
}

void ShadowEvents::ExcludeVertex(int c, std::vector<int>& exclude) const
{
  for (const Use& use : this->Topology.ClusterUses[c])
  {
    exclude.push_back(use.Polygon);
  }
}

// With a jump threshold, a wedge is not traced when even an upper bound of
// the jump its pieces would get is below the minimum: the jump at a point
// x of R is Ls min(F_S(x), F_hidden(x)) (see DropFaintShadows), bounded
// over R by FormFactorBound and HiddenFormFactorBound.
bool ShadowEvents::Faint(int occluderA, int occluderB) const
{
  if (!(this->MinimumJump >= 0.0 && this->Settings.CullWedges))
  {
    return false;
  }
  const std::vector<PolygonData>& polygons = this->Topology.Polygons;
  const double receiverRadius = this->Ctx.ReceiverRadius;
  const PolygonData& shooter = polygons[this->ShooterId];
  double bound = FormFactorBound(shooter, this->Rec, receiverRadius, true);
  for (int k : { occluderA, occluderB })
  {
    if (k >= 0)
    {
      const int component = polygons[k].Component;
      bound = std::min(bound,
        HiddenFormFactorBound(shooter, this->Topology.ComponentCentre[component],
          this->Topology.ComponentRadius[component], this->Rec));
    }
  }
  // The margin keeps rounding from dropping a wedge at the threshold.
  return this->ShooterRadiance * bound * (1.0 + 1e-9) < this->MinimumJump;
}

void ShadowEvents::Emit(const Wedge& w, int order, int occluderA, int occluderB)
{
  if (this->Faint(occluderA, occluderB))
  {
    return;
  }
  if (TraceWedge(this->Ctx, w, this->Traced))
  {
    ++this->Stats.Wedges;
  }
  for (const auto& seg : this->Traced)
  {
    ClipToOutline(this->Frame.To2D(seg.first), this->Frame.To2D(seg.second), this->Frame,
      this->Snap, this->ClipScratch, this->Pieces);
    for (const auto& piece : this->Pieces)
    {
      if (std::hypot(piece.second[0] - piece.first[0], piece.second[1] - piece.first[1]) <
        this->MinPiece)
      {
        continue;
      }
      Segment2 s;
      s.A = piece.first;
      s.B = piece.second;
      s.Order = order;
      s.SourceId = this->ShooterId;
      s.OccluderA = occluderA;
      s.OccluderB = occluderB;
      this->Out.push_back(s);
      ++this->Stats.SegmentsGenerated;
    }
  }
}

void ShadowEvents::AddEdgeVertexEvents()
{
  const PolygonData& sh = this->Sh;
  const std::size_t ns = sh.V.size();
  for (std::size_t i = 0; i < ns; ++i)
  {
    const Vec3 v = sh.V[i];
    if (this->DistR(v) <= this->Tol)
    {
      continue;
    }
    for (int e : this->UsableEdges)
    {
      Wedge w;
      w.Kind = WedgeKind::EV;
      w.P = v;
      this->Topology.EdgeEnds(e, w.G0, w.G1);
      const Vec3 m = Cross(w.G1 - w.G0, v - w.G0);
      if (!(Length(m) > kAngle * Length(w.G1 - w.G0) * Length(v - w.G0)))
      {
        continue;
      }
      w.M = Normalized(m);
      const int occSide = EdgeFeatureSide(this->Topology, e, w.M);
      if (occSide == 0 || occSide == 2)
      {
        continue; // not on the silhouette, or seen edge-on
      }
      const int shSide = CornerSide(sh, static_cast<int>(i), w.M);
      if (shSide == 2 && !this->Settings.InteriorEvents)
      {
        continue;
      }
      const Vec3 dNext = Normalized(sh.V[(i + 1) % ns] - v);
      const Vec3 dPrev = Normalized(sh.V[(i + ns - 1) % ns] - v);
      const bool coplanar =
        std::abs(Dot(w.M, dNext)) <= kAngle || std::abs(Dot(w.M, dPrev)) <= kAngle;
      this->ExcludeEdge(e, w.Exclude);
      this->FinishExclude(w.Exclude);
      this->Emit(w, coplanar ? 1 : 2, this->Topology.EdgeUses[e][0].Polygon, -1);
    }
  }
}

void ShadowEvents::AddVertexEdgeEvents()
{
  const PolygonData& sh = this->Sh;
  const std::size_t ns = sh.V.size();
  for (std::size_t i = 0; i < ns; ++i)
  {
    const Vec3 p = sh.V[i], q = sh.V[(i + 1) % ns];
    for (int c : this->UsableVertices)
    {
      Wedge w;
      w.Kind = WedgeKind::VE;
      w.P = this->Topology.ClusterPoint[c];
      w.G0 = p;
      w.G1 = q;
      const Vec3 m = Cross(q - p, w.P - p);
      if (!(Length(m) > kAngle * Length(q - p) * Length(w.P - p)))
      {
        continue;
      }
      w.M = Normalized(m);
      const int occSide =
        VertexFeatureSide(this->Topology, c, w.M, this->Settings.InteriorEvents);
      if (occSide == 0 || occSide == 2)
      {
        continue;
      }
      this->ExcludeVertex(c, w.Exclude);
      this->FinishExclude(w.Exclude);
      this->Emit(w, VertexHasEdgeInPlane(this->Topology, c, w.M) ? 1 : 2,
        this->Topology.ClusterUses[c][0].Polygon, -1);
    }
  }
}

// Generators for an apex w lie on lines through w that hit both the
// shooter and the receiver (their convex hulls): between w and the
// shooter on lines continuing from w to the receiver (case A of
// TraceWedge), or between w and the receiver on lines continuing from w
// to the shooter (case B). Each case is the intersection of the cone from
// w to one polygon with the reflected cone of the other, found in the BVH
// with one query per case. Bounding by the receiver's cone too keeps the
// cost per small receiver independent of how many polygons the shooter's
// cone crosses.
void ShadowEvents::FindGenerators(
  int c, std::vector<int>& found, std::vector<int>& generators) const
{
  const double tol = this->Tol;
  const PolygonData& sh = this->Sh;
  const PolygonData& rec = this->Rec;
  const PreparedPolygon& shp = this->Occluders.GetPolygon(this->ShooterId);
  const PreparedPolygon& recp = this->Occluders.GetPolygon(this->ReceiverId);
  const Vec3* shHull = this->Occluders.GetHullVertices().data() + shp.FirstHullPoint;
  const Vec3* recHull = this->Occluders.GetHullVertices().data() + recp.FirstHullPoint;
  const Vec3 apex = this->Topology.ClusterPoint[c];
  generators.clear();
  for (int nappe = 0; nappe < 2; ++nappe)
  {
    // nappe 0: between the apex and the shooter; 1: between the apex and the receiver.
    CullingVolume cone;
    const PreparedPolygon& towards = nappe == 0 ? shp : recp;
    cone.BoxMin = Vec3(std::min(towards.BoundsMin.X, apex.X), std::min(towards.BoundsMin.Y, apex.Y),
                    std::min(towards.BoundsMin.Z, apex.Z)) - Vec3(tol, tol, tol);
    cone.BoxMax = Vec3(std::max(towards.BoundsMax.X, apex.X), std::max(towards.BoundsMax.Y, apex.Y),
                    std::max(towards.BoundsMax.Z, apex.Z)) + Vec3(tol, tol, tol);
    AddCone(shHull, shp.NumberOfHullPoints, shp.Centroid, apex, nappe == 1, tol, cone);
    if (this->Settings.CullWedges)
    {
      AddCone(recHull, recp.NumberOfHullPoints, recp.Centroid, apex, nappe == 0, tol, cone);
    }
    cone.Planes.push_back(nappe == 0 ? Plane{ sh.N, sh.D - tol } : Plane{ rec.N, rec.D - tol });
    // Generators lie on event lines, inside the shaft: among few shaft
    // candidates a scan is cheaper than a BVH traversal.
    found.clear();
    if (this->Settings.CullWedges && this->Candidates.size() <= kScanLimit)
    {
      this->Occluders.FilterCandidates(cone, this->Candidates.data(),
        static_cast<int>(this->Candidates.size()), this->ShooterId, this->ReceiverId, found);
    }
    else
    {
      this->Occluders.VolumeCandidates(cone, this->ShooterId, this->ReceiverId, found);
    }
    for (int k : found)
    {
      for (int e : this->Topology.Polygons[k].Edge)
      {
        generators.push_back(e);
      }
    }
  }
  std::sort(generators.begin(), generators.end());
  generators.erase(std::unique(generators.begin(), generators.end()), generators.end());
}

void ShadowEvents::AddOccluderEvents()
{
  const double tol = this->Tol;
  const SceneTopology& topo = this->Topology;
  std::vector<int> found, generators;
  for (int c : this->UsableVertices)
  {
    const Vec3 apex = topo.ClusterPoint[c];
    this->FindGenerators(c, found, generators);
    for (int e : generators)
    {
      if (!std::binary_search(this->UsableEdges.begin(), this->UsableEdges.end(), e) ||
        topo.EdgeClusters[e][0] == c || topo.EdgeClusters[e][1] == c)
      {
        continue;
      }
      Wedge w;
      w.Kind = WedgeKind::OO;
      w.P = apex;
      topo.EdgeEnds(e, w.G0, w.G1);
      const Vec3 m = Cross(w.G1 - w.G0, apex - w.G0);
      if (!(Length(m) > kAngle * Length(w.G1 - w.G0) * Length(apex - w.G0)))
      {
        continue;
      }
      w.M = Normalized(m);
      bool pos = false, neg = false;
      for (const Vec3& s : this->Sh.V)
      {
        const double d = Dot(w.M, s - apex);
        pos = pos || d > tol;
        neg = neg || d < -tol;
      }
      if (!pos || !neg)
      {
        continue; // the wedge plane misses the shooter
      }
      const int sideE = EdgeFeatureSide(topo, e, w.M);
      if (sideE == 0 || sideE == 2)
      {
        continue;
      }
      const int sideV = VertexFeatureSide(topo, c, w.M, false);
      if (sideV == 0 || sideV == 2)
      {
        continue;
      }
      this->ExcludeEdge(e, w.Exclude);
      this->ExcludeVertex(c, w.Exclude);
      this->FinishExclude(w.Exclude);
      this->Emit(w, VertexHasEdgeInPlane(topo, c, w.M) ? 1 : 2, topo.ClusterUses[c][0].Polygon,
        topo.EdgeUses[e][0].Polygon);
    }
  }
}

} // namespace detail
} // namespace penumbra
