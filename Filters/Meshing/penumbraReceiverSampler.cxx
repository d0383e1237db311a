// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReceiverSampler.cxx
 * @brief The refinement passes of the adaptive sampler on one receiver:
 * floors, localized interpolant, insertion requests and their insertion.
 */
#include "penumbraReceiverSampler.h"

#include "penumbraFeatureSize.h"
#include "penumbraMath.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <cstddef>
#include <unordered_set>
#include <utility>

namespace penumbra
{
namespace detail
{

namespace
{

// Localized passes: after a pass only triangles with a vertex within
// ScoredRings hops of a new vertex are scored again, against an interpolant
// built on those within BuiltRings hops (the gradient fits read at most two
// rings, line derivatives two points along a line; one ring spare).
constexpr int ScoredRings = 2, BuiltRings = 5;

} // namespace

//------------------------------------------------------------------------------
ReceiverSampler::ReceiverSampler(const ReceiverMesh& mesh, const RadianceBatchFunction& evaluate,
  const AdaptiveSamplingSettings& settings, AdaptiveSamplingResult& result)
  : Mesh(mesh)
  , Evaluate(evaluate)
  , Settings(settings)
  , Result(result)
  , Stats(result.Statistics)
  , PassInterpolant(settings.Interpolant)
{
  // The passes compare values with the interpolant only: no error model, and
  // no overshoot limit (an overshoot marks where the samples are too sparse).
  this->PassInterpolant.ErrorModel = false;
  this->PassInterpolant.LimitOvershoot = false;
}

//------------------------------------------------------------------------------
void ReceiverSampler::Run()
{
  this->Initialize();
  for (int pass = 0; this->Pass(pass); ++pass)
  {
    ++this->Stats.Passes;
  }
  this->Result.Tolerance = this->Tolerance;
  Finish(this->Rec, this->Mesh.ReceiverId, this->Result);
}

//------------------------------------------------------------------------------
// The initial mesh, triangulated and evaluated.
void ReceiverSampler::Initialize()
{
  const ReceiverMesh& mesh = this->Mesh;
  AdaptiveSamplingStatistics& stats = this->Stats;
  Receiver& rec = this->Rec;
  rec.F = MakeFrame(mesh);
  rec.SideOffset = this->Settings.SideOffset;
  {
    std::vector<P2> vertices, seeds;
    std::vector<Vec3> vertex3;
    std::vector<int> vertexOfPoint;
    std::vector<RefinableSegment> segments;
    Decompose(mesh, rec.F, vertices, vertex3, vertexOfPoint, segments, seeds);
    Prepare(rec, vertices, vertex3, segments, seeds);
  }
  rec.Refresh();
  if (rec.Snap.Triangles.empty())
  {
    throw InputError("adaptive sampling: receiver mesh has no triangle after triangulation");
  }
  AssignValues(rec, this->Evaluate, stats);
  stats.InitialSamples = static_cast<int>(rec.Snap.PointVertex.size());
  this->ComputeFloors();
}

//------------------------------------------------------------------------------
// The sizes below which nothing is refined.
void ReceiverSampler::ComputeFloors()
{
  const AdaptiveSamplingSettings& settings = this->Settings;
  Receiver& rec = this->Rec;
  this->MinimumSize = settings.MinimumFeatureSize * rec.Diameter;
  this->MaximumLength = settings.MaximumEdgeLength;
  // Triangles narrower than this are not refined. The receiver's own width
  // (2 area / diameter) bounds it too: a strip 1e-6 wide (aspect 1e6) is all
  // "slivers" by the diameter rule and would never be refined along its
  // length.
  double area = 0.0;
  for (const auto& t : rec.Snap.Triangles)
  {
    const P2 a = rec.PointUV(t[0]), b = rec.PointUV(t[1]), c = rec.PointUV(t[2]);
    area += 0.5 * std::abs(Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]));
  }
  this->MinimumWidth =
    settings.MinimumFeatureSize * std::min(rec.Diameter, 2.0 * area / rec.Diameter);
  // Near small features the floor is smaller: a feature whose discontinuity
  // lines are shorter than 1/FeatureNeighbourhood of the receiver is refined
  // as a receiver FeatureNeighbourhood times their length would be, i.e. to
  // the same fraction of its own size. Inserted vertices take the smallest
  // line length of the vertices they are inserted between.
  rec.FeatureSize = DiscontinuityLineLengths(rec);
  // No refinement below rounding.
  this->RoundingWidth =
    std::max(NumericalWidth * rec.Diameter, CoordinateRounding * rec.F.LargestCoordinate);
  this->FirstCandidate = settings.ProbeCentroids ? 0 : 1;
}

//------------------------------------------------------------------------------
// One refinement pass; false when sampling stops after it.
bool ReceiverSampler::Pass(int pass)
{
  Receiver& rec = this->Rec;
  AdaptiveSamplingStatistics& stats = this->Stats;
  const AdaptiveSamplingSettings& settings = this->Settings;
  if (pass > 0)
  {
    rec.Refresh();
    AssignValues(rec, this->Evaluate, stats);
  }
  const int nt = static_cast<int>(rec.Snap.Triangles.size());
  this->Scored.assign(nt, 1);
  this->SubTriangle.resize(nt);
  bool localized = false;
  if (pass > 0 && !this->Previous.empty())
  {
    localized = this->MarkRescoredTriangles(nt);
  }
  if (localized)
  {
    this->BuildLocalInterpolant(nt);
  }
  else
  {
    for (int t = 0; t < nt; ++t)
    {
      this->SubTriangle[t] = t;
    }
    this->Scored.assign(nt, 1);
    this->Interpolant.Build(MakeSampleMesh(rec), this->PassInterpolant);
  }
  this->UpdateTolerance();
  this->ProbeCandidates(nt);
  this->ScoreCandidates(nt);

  // Requests from failing refinable triangles.
  const int current = static_cast<int>(rec.Snap.PointVertex.size());
  const bool canInsert =
    pass < settings.MaximumPasses && current < settings.MaximumSamplesPerSurface;
  int failing = 0;
  std::vector<Request> requests = this->CollectRequests(nt, canInsert, failing);
  this->AddOtherSides(requests);
  if (requests.empty())
  {
    this->StopConverged(nt, canInsert, current);
    return false;
  }
  const int inserted = this->InsertRequests(requests, nt, current);
  this->ForgetStaleCandidates();
  if (inserted == 0)
  {
    // Nothing could be inserted: the residuals of this pass stand.
    stats.Converged = false;
    stats.UnrefinedFailures = failing;
    this->KeepProbes(nt);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
// Marks the triangles to score again (near the last insertions) and tells
// whether rebuilding the interpolant around them only is worth it.
bool ReceiverSampler::MarkRescoredTriangles(int nt)
{
  const Receiver& rec = this->Rec;
  std::vector<int>& hops = this->Hops;
  std::vector<int>& newVertices = this->NewVertices;
  std::vector<char>& scored = this->Scored;
  auto& previous = this->Previous;
  // Hops from the new vertices, breadth first over the triangles' edges.
  const int nv = static_cast<int>(rec.Snap.Vertices.size());
  std::vector<int> vertexTriangleStart(nv + 1, 0), vertexTriangles;
  for (const auto& tri : rec.Snap.Triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      ++vertexTriangleStart[rec.Snap.PointVertex[tri[k]] + 1];
    }
  }
  for (int v = 0; v < nv; ++v)
  {
    vertexTriangleStart[v + 1] += vertexTriangleStart[v];
  }
  vertexTriangles.resize(vertexTriangleStart[nv]);
  {
    std::vector<int> fill(vertexTriangleStart.begin(), vertexTriangleStart.end() - 1);
    for (int t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        vertexTriangles[fill[rec.Snap.PointVertex[rec.Snap.Triangles[t][k]]]++] = t;
      }
    }
  }
  hops.assign(nv, BuiltRings + 1);
  std::vector<int> front;
  for (int v : newVertices)
  {
    if (v >= 0 && v < nv && hops[v] != 0)
    {
      hops[v] = 0;
      front.push_back(v);
    }
  }
  for (int ring = 1; ring <= BuiltRings && !front.empty(); ++ring)
  {
    std::vector<int> next;
    for (int v : front)
    {
      for (int i = vertexTriangleStart[v]; i < vertexTriangleStart[v + 1]; ++i)
      {
        for (int p : rec.Snap.Triangles[vertexTriangles[i]])
        {
          const int w = rec.Snap.PointVertex[p];
          if (hops[w] > ring)
          {
            hops[w] = ring;
            next.push_back(w);
          }
        }
      }
    }
    front.swap(next);
  }
  int built = 0;
  for (int t = 0; t < nt; ++t)
  {
    const auto& tri = rec.Snap.Triangles[t];
    const int h = std::min({ hops[rec.Snap.PointVertex[tri[0]]],
      hops[rec.Snap.PointVertex[tri[1]]], hops[rec.Snap.PointVertex[tri[2]]] });
    scored[t] = h <= ScoredRings;
    built += h <= BuiltRings;
  }
  // Worth it only when most of the mesh is left alone.
  bool localized = 2 * built < nt;
  if (localized)
  {
    // Triangles kept from the last pass must all be found.
    for (int t = 0; t < nt && localized; ++t)
    {
      localized = scored[t] || previous.count(this->KeyOf(t)) > 0;
    }
  }
  return localized;
}

//------------------------------------------------------------------------------
// The interpolant of the triangles within BuiltRings of the last insertions.
void ReceiverSampler::BuildLocalInterpolant(int nt)
{
  const Receiver& rec = this->Rec;
  AdaptiveSamplingStatistics& stats = this->Stats;
  std::vector<int>& hops = this->Hops;
  std::vector<int>& subTriangle = this->SubTriangle;
  SampleMesh samples;
  samples.NumberOfChannels = 3;
  std::vector<int> subPoint(rec.Snap.PointVertex.size(), -1);
  auto pointOf = [&](int p) {
    if (subPoint[p] < 0)
    {
      subPoint[p] = samples.AddPoint(rec.PointUV(p)[0], rec.PointUV(p)[1], rec.Values[p]);
    }
    return subPoint[p];
  };
  std::unordered_set<long long> subEdges;
  auto edgeKey = [](int a, int b) {
    return static_cast<long long>(std::min(a, b)) * (1ll << 32) + std::max(a, b);
  };
  for (int t = 0; t < nt; ++t)
  {
    const auto& tri = rec.Snap.Triangles[t];
    const int h = std::min({ hops[rec.Snap.PointVertex[tri[0]]],
      hops[rec.Snap.PointVertex[tri[1]]], hops[rec.Snap.PointVertex[tri[2]]] });
    subTriangle[t] = -1;
    if (h <= BuiltRings)
    {
      subTriangle[t] = samples.AddTriangle(pointOf(tri[0]), pointOf(tri[1]), pointOf(tri[2]));
      for (int k = 0; k < 3; ++k)
      {
        subEdges.insert(edgeKey(tri[k], tri[(k + 1) % 3]));
      }
    }
  }
  for (const auto& seg : rec.Snap.Segments)
  {
    for (int side = 0; side < 2; ++side)
    {
      const int a = side ? seg.RightA : seg.LeftA, b = side ? seg.RightB : seg.LeftB;
      if (a < 0 || (side && a == seg.LeftA && b == seg.LeftB) ||
        !subEdges.count(edgeKey(a, b)))
      {
        continue;
      }
      samples.AddConstrainedEdge(subPoint[a], subPoint[b], seg.Order);
    }
  }
  this->Interpolant.Build(samples, this->PassInterpolant);
  ++stats.LocalizedPasses;
}

//------------------------------------------------------------------------------
// Tolerance of this pass from the receiver's mean radiance.
void ReceiverSampler::UpdateTolerance()
{
  const Receiver& rec = this->Rec;
  const AdaptiveSamplingSettings& settings = this->Settings;
  const RGB mean = MeanRadiance(rec);
  this->Tolerance = RGB(std::max(settings.SamplingTolerance * mean.R, settings.AbsoluteTolerance),
    std::max(settings.SamplingTolerance * mean.G, settings.AbsoluteTolerance),
    std::max(settings.SamplingTolerance * mean.B, settings.AbsoluteTolerance));
  this->Result.ReferenceRadiance = mean;
}

//------------------------------------------------------------------------------
// Insertion requests of the failing triangles that are wide enough.
std::vector<Request> ReceiverSampler::CollectRequests(int nt, bool canInsert, int& failing)
{
  const Receiver& rec = this->Rec;
  const AdaptiveSamplingSettings& settings = this->Settings;
  std::vector<std::array<double, 4>>& scores = this->Scores;
  std::vector<std::array<CandidateValue*, 4>>& candidates = this->Candidates;
  const double maximumLength = this->MaximumLength;
  const double roundingWidth = this->RoundingWidth;
  const double minimumWidth = this->MinimumWidth;
  const double minimumSize = this->MinimumSize;
  std::vector<Request> requests;
  std::unordered_map<long long, int> edgeRequest; // (min, max) vertex pair -> request
  failing = 0;
  for (int t = 0; t < nt && canInsert; ++t)
  {
    const auto& tri = rec.Snap.Triangles[t];
    const int v[3] = { rec.Snap.PointVertex[tri[0]], rec.Snap.PointVertex[tri[1]],
      rec.Snap.PointVertex[tri[2]] };
    double length[3], longest = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const P2 a = rec.Vertex(v[k]), b = rec.Vertex(v[(k + 1) % 3]);
      length[k] = std::hypot(b[0] - a[0], b[1] - a[1]);
      longest = std::max(longest, length[k]);
    }
    // An edge longer than MaximumEdgeLength fails like a residual above
    // tolerance, scored by how much too long it is.
    auto s = scores[t];
    for (int k = 0; k < 3 && maximumLength > 0.0; ++k)
    {
      s[k + 1] = std::max(s[k + 1], length[k] / maximumLength);
    }
    if (!(std::max({ s[0], s[1], s[2], s[3] }) > 1.0))
    {
      continue;
    }
    ++failing;
    // Width = smallest altitude: a sliver (e.g. between two nearly
    // parallel lines) is as unresolvable as a tiny triangle, and splitting
    // it along its length would only make more slivers.
    const P2 p0 = rec.Vertex(v[0]), p1 = rec.Vertex(v[1]), p2 = rec.Vertex(v[2]);
    const double width =
      std::abs(Cross2(p1[0] - p0[0], p1[1] - p0[1], p2[0] - p0[0], p2[1] - p0[1])) / longest;
    const double triangleFeature =
      std::min({ rec.FeatureSize[v[0]], rec.FeatureSize[v[1]], rec.FeatureSize[v[2]] });
    const double local = settings.MinimumFeatureSize * FeatureNeighbourhood * triangleFeature;
    const double widthFloor = std::max(roundingWidth, std::min(minimumWidth, local));
    const double lengthFloor = std::max(roundingWidth, std::min(minimumSize, local));
    if (width < widthFloor)
    {
      continue;
    }
    bool edgeInserted = false;
    for (int k = 0; k < 3; ++k)
    {
      if (!(s[k + 1] > 1.0) || length[k] < lengthFloor)
      {
        continue;
      }
      edgeInserted = true;
      const int a = std::min(v[k], v[(k + 1) % 3]), b = std::max(v[k], v[(k + 1) % 3]);
      const long long pair = static_cast<long long>(a) * (1ll << 32) + b;
      auto found = edgeRequest.find(pair);
      if (found != edgeRequest.end())
      {
        Request& r = requests[found->second];
        r.Score = std::max(r.Score, s[k + 1]);
        if (candidates[t][k + 1]->Sided &&
          std::find(r.Values.begin(), r.Values.end(), candidates[t][k + 1]) == r.Values.end())
        {
          r.Values.push_back(candidates[t][k + 1]);
        }
        continue;
      }
      Request r;
      r.Score = s[k + 1];
      r.Order = static_cast<int>(requests.size());
      r.Edge = true;
      r.A = a;
      r.B = b;
      const P2 pa = rec.Vertex(a), pb = rec.Vertex(b);
      r.U = 0.5 * (pa[0] + pb[0]);
      r.V = 0.5 * (pa[1] + pb[1]);
      r.Constrained = rec.Snap.TriangleSegments[t][k] >= 0;
      r.FeatureSize = std::min(rec.FeatureSize[a], rec.FeatureSize[b]);
      r.Values.push_back(candidates[t][k + 1]);
      edgeRequest.emplace(pair, static_cast<int>(requests.size()));
      requests.push_back(std::move(r));
    }
    if (!edgeInserted && s[0] > 1.0)
    {
      Request r;
      r.Score = s[0];
      r.Order = static_cast<int>(requests.size());
      r.A = v[0];
      const P2 a = rec.Vertex(v[0]), b = rec.Vertex(v[1]), d = rec.Vertex(v[2]);
      r.U = (a[0] + b[0] + d[0]) / 3.0;
      r.V = (a[1] + b[1] + d[1]) / 3.0;
      r.FeatureSize = triangleFeature;
      r.Values.push_back(candidates[t][0]);
      requests.push_back(std::move(r));
    }
  }
  return requests;
}

//------------------------------------------------------------------------------
void ReceiverSampler::AddOtherSides(std::vector<Request>& requests)
{
  CandidateMap& cache = this->Cache;
  // A sided edge needs the candidates of both kept sides: add the other
  // side's (evaluated this pass by its own triangle).
  for (Request& r : requests)
  {
    if (!r.Edge || !r.Values[0]->Sided || r.Values.size() > 1)
    {
      continue;
    }
    for (int c : { -2, -3 })
    {
      auto found = cache.find(CandidateKey{ r.A, r.B, c });
      if (found != cache.end() && found->second.Used && &found->second != r.Values[0])
      {
        r.Values.push_back(&found->second);
      }
    }
  }
}

//------------------------------------------------------------------------------
// No request: the last pass's residuals are the probes.
void ReceiverSampler::StopConverged(int nt, bool canInsert, int current)
{
  AdaptiveSamplingStatistics& stats = this->Stats;
  const AdaptiveSamplingSettings& settings = this->Settings;
  std::vector<std::array<double, 4>>& scores = this->Scores;
  stats.UnrefinedFailures = 0;
  for (int t = 0; t < nt; ++t)
  {
    const auto& s = scores[t];
    stats.UnrefinedFailures += std::max({ s[0], s[1], s[2], s[3] }) > 1.0;
  }
  stats.Converged = stats.UnrefinedFailures == 0;
  if (!canInsert)
  {
    stats.BudgetReached = current >= settings.MaximumSamplesPerSurface;
  }
  this->KeepProbes(nt);
}

//------------------------------------------------------------------------------
// Inserts the requests by decreasing score within the budget; returns the
// number inserted.
int ReceiverSampler::InsertRequests(std::vector<Request>& requests, int nt, int current)
{
  Receiver& rec = this->Rec;
  AdaptiveSamplingStatistics& stats = this->Stats;
  const AdaptiveSamplingSettings& settings = this->Settings;
  std::vector<std::array<CandidateValue*, 4>>& candidates = this->Candidates;
  std::vector<std::array<RGB, 4>>& residuals = this->Residuals;
  std::vector<int>& newVertices = this->NewVertices;
  auto& previous = this->Previous;
  std::sort(requests.begin(), requests.end(), [](const Request& a, const Request& b) {
    return a.Score != b.Score ? a.Score > b.Score : a.Order < b.Order;
  });
  int budget = settings.MaximumSamplesPerSurface - current;
  int inserted = 0;
  previous.clear();
  previous.reserve(static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t)
  {
    previous.emplace(this->KeyOf(t), TriangleState{ candidates[t], residuals[t] });
  }
  newVertices.clear();
  for (const Request& r : requests)
  {
    const int cost = static_cast<int>(r.Values.size());
    if (cost > budget)
    {
      stats.BudgetReached = true;
      break;
    }
    int id = r.Edge ? rec.Tri->InsertOnEdge(r.A, r.B, r.U, r.V)
                    : rec.Tri->InsertInFace(r.U, r.V, r.A);
    if (id < 0 && r.Edge && !r.Constrained)
    {
      // An earlier insertion of this pass flipped the edge away; its
      // midpoint is still inside the same region.
      id = rec.Tri->InsertInFace(r.U, r.V, r.A);
    }
    if (id < 0)
    {
      ++stats.RejectedInsertions;
      continue;
    }
    ++inserted;
    newVertices.push_back(id);
    budget -= cost;
    if (static_cast<int>(rec.Samples.size()) <= id)
    {
      rec.Samples.resize(id + 1);
    }
    if (static_cast<int>(rec.FeatureSize.size()) <= id)
    {
      rec.FeatureSize.resize(id + 1, HUGE_VAL);
    }
    rec.FeatureSize[id] = r.FeatureSize;
    for (const CandidateValue* value : r.Values)
    {
      SideSample s;
      s.Value = value->Value;
      s.Sided = value->Sided;
      s.Du = value->Du;
      s.Dv = value->Dv;
      rec.Samples[id].push_back(s);
    }
    if (r.Edge)
    {
      ++stats.EdgeInsertions;
      stats.ConstrainedSplits += r.Constrained;
    }
    else
    {
      ++stats.FaceInsertions;
    }
  }
  return inserted;
}

//------------------------------------------------------------------------------
// The last pass's residuals become the result's probes.
void ReceiverSampler::KeepProbes(int nt)
{
  AdaptiveSamplingResult& result = this->Result;
  AdaptiveSamplingStatistics& stats = this->Stats;
  const int firstCandidate = this->FirstCandidate;
  std::vector<std::array<double, 4>>& scores = this->Scores;
  std::vector<std::array<RGB, 4>>& residuals = this->Residuals;
  result.Probes = ErrorProbes();
  for (int t = 0; t < nt; ++t)
  {
    for (int c = firstCandidate; c < 4; ++c)
    {
      const double r[3] = { residuals[t][c].R, residuals[t][c].G, residuals[t][c].B };
      result.Probes.Add(t, r, 3);
      stats.MaximumResidual = std::max(stats.MaximumResidual, scores[t][c]);
    }
  }
}

} // namespace detail
} // namespace penumbra
