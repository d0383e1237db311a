// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraAdaptiveSampler.h"

#include "penumbraReceiverTriangulation.h"
#include "penumbraScene.h" // InputError
#include "penumbraUnionFind.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace penumbra
{

namespace
{

using P2 = std::array<double, 2>;

double Seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline double Cross2(double ax, double ay, double bx, double by)
{
  return ax * by - ay * bx;
}

inline double Channel(const RGB& c, int k)
{
  return k == 0 ? c.R : (k == 1 ? c.G : c.B);
}

/// The receiver's plane frame.
struct Frame
{
  Vec3 Origin, U, V, N;
  double LargestCoordinate = 0.0; // largest |coordinate| of the mesh's points
  Vec3 To3D(double u, double v) const { return this->Origin + u * this->U + v * this->V; }
  P2 To2D(const Vec3& p) const
  {
    const Vec3 d = p - this->Origin;
    return { Dot(d, this->U), Dot(d, this->V) };
  }
};

void CheckSettings(const AdaptiveSamplingSettings& s)
{
  auto bad = [](const std::string& what) { throw InputError("adaptive sampling: " + what); };
  if (!(s.RelativeTolerance >= 0.0 && s.RelativeTolerance <= 1.0))
  {
    bad("RelativeTolerance must be in [0, 1]");
  }
  if (!(s.AbsoluteTolerance >= 0.0) || !std::isfinite(s.AbsoluteTolerance))
  {
    bad("AbsoluteTolerance must be finite and >= 0");
  }
  if (s.MaximumSamples < 1)
  {
    bad("MaximumSamples must be >= 1");
  }
  if (!(s.MinimumFeatureSize >= 0.0 && s.MinimumFeatureSize <= 1.0))
  {
    bad("MinimumFeatureSize must be in [0, 1]");
  }
  if (!(s.MaximumEdgeLength >= 0.0) || !std::isfinite(s.MaximumEdgeLength))
  {
    bad("MaximumEdgeLength must be finite and >= 0");
  }
  if (s.MaximumPasses < 0 || s.MaximumPasses > 10000)
  {
    bad("MaximumPasses must be in [0, 10000]");
  }
  if (!(s.SideOffset > 0.0 && s.SideOffset <= 1e-2))
  {
    bad("SideOffset must be in (0, 1e-2]");
  }
}

// Validate the mesh and compute its frame: normal from the triangles'
// summed cross products (their front), first axis along the longest outline
// piece (else the first triangle edge), origin at the bounding-box centre.
Frame MakeFrame(const ReceiverMesh& mesh)
{
  const int np = static_cast<int>(mesh.Points.size());
  if (mesh.Triangles.empty() || np < 3)
  {
    throw InputError("adaptive sampling: receiver mesh has no triangle");
  }
  if (mesh.PointVertex.size() != mesh.Points.size())
  {
    throw InputError("adaptive sampling: PointVertex size differs from Points size");
  }
  for (int p = 0; p < np; ++p)
  {
    if (!IsFinite(mesh.Points[p]))
    {
      throw InputError("adaptive sampling: point " + std::to_string(p) + " is not finite");
    }
    if (mesh.PointVertex[p] < 0)
    {
      throw InputError("adaptive sampling: point " + std::to_string(p) + " has a negative vertex");
    }
  }
  Vec3 n;
  for (std::size_t t = 0; t < mesh.Triangles.size(); ++t)
  {
    const auto& tri = mesh.Triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] < 0 || tri[k] >= np)
      {
        throw InputError("adaptive sampling: triangle " + std::to_string(t) +
          " has a point id out of range");
      }
    }
    n += Cross(mesh.Points[tri[1]] - mesh.Points[tri[0]], mesh.Points[tri[2]] - mesh.Points[tri[0]]);
  }
  for (std::size_t s = 0; s < mesh.Segments.size(); ++s)
  {
    const DiscontinuitySegment& seg = mesh.Segments[s];
    if (seg.PointA < 0 || seg.PointA >= np || seg.PointB < 0 || seg.PointB >= np)
    {
      throw InputError("adaptive sampling: segment " + std::to_string(s) +
        " has a point id out of range");
    }
    if (seg.Order < -1 || seg.Order > 2)
    {
      throw InputError("adaptive sampling: segment " + std::to_string(s) + " has order " +
        std::to_string(seg.Order) + " (valid: -1, 0, 1, 2)");
    }
  }
  Frame f;
  f.N = Normalized(n);
  if (!(Length(n) > 0.0) || !IsFinite(f.N))
  {
    throw InputError("adaptive sampling: receiver mesh has zero area");
  }
  Vec3 lo = mesh.Points[0], hi = mesh.Points[0];
  for (const Vec3& p : mesh.Points)
  {
    lo = Vec3(std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z));
    hi = Vec3(std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z));
  }
  f.LargestCoordinate = std::max({ std::abs(lo.X), std::abs(lo.Y), std::abs(lo.Z), std::abs(hi.X),
    std::abs(hi.Y), std::abs(hi.Z) });
  // The box centre is off the plane of a tilted receiver: project it, or
  // every point mapped back from the frame would lie beside the receiver.
  const Vec3 centre = 0.5 * (lo + hi);
  f.Origin = centre - Dot(centre - mesh.Points[mesh.Triangles[0][0]], f.N) * f.N;
  Vec3 axis = mesh.Points[mesh.Triangles[0][1]] - mesh.Points[mesh.Triangles[0][0]];
  double best = -1.0;
  for (const DiscontinuitySegment& s : mesh.Segments)
  {
    const Vec3 d = mesh.Points[s.PointB] - mesh.Points[s.PointA];
    if (s.Order == -1 && Length(d) > best)
    {
      best = Length(d);
      axis = d;
    }
  }
  f.U = Normalized(axis - Dot(axis, f.N) * f.N);
  f.V = Cross(f.N, f.U);
  return f;
}

/// A radiance sample of a vertex: on an order-0 line, one per side, with the
/// direction (unit, in the plane) toward which it was taken.
struct SideSample
{
  double Du = 0.0, Dv = 0.0;
  bool Sided = false;
  RGB Value;
};

/// Working state of one receiver.
struct Receiver
{
  Frame F;
  double Diameter = 0.0;
  double SideOffset = 1e-9;
  std::vector<Vec3> Vertex3; // per vertex id (input ones exact)
  std::vector<std::vector<SideSample>> Samples; // per vertex id
  std::vector<double> FeatureSize; // per vertex id: see DiscontinuityLineLengths
  std::unique_ptr<detail::RefinableTriangulation> Tri;
  detail::RefinableSnapshot Snap;
  std::vector<int> CornerStart, Corners; // per point: (triangle * 3 + corner) list
  std::vector<char> PointSided;
  std::vector<RGB> Values; // per point
  std::size_t Irregularities = 0;

  P2 Vertex(int id) const { return this->Snap.Vertices[id]; }
  P2 PointUV(int p) const { return this->Snap.Vertices[this->Snap.PointVertex[p]]; }

  Vec3 Position3(int vertex) const
  {
    if (vertex < static_cast<int>(this->Vertex3.size()))
    {
      return this->Vertex3[vertex];
    }
    const P2 uv = this->Snap.Vertices[vertex];
    return this->F.To3D(uv[0], uv[1]);
  }

  // Extract the current mesh and its per-point tables.
  void Refresh()
  {
    this->Tri->Extract(this->Snap);
    const int np = static_cast<int>(this->Snap.PointVertex.size());
    const int nt = static_cast<int>(this->Snap.Triangles.size());
    this->CornerStart.assign(np + 1, 0);
    for (const auto& t : this->Snap.Triangles)
    {
      for (int k = 0; k < 3; ++k)
      {
        ++this->CornerStart[t[k] + 1];
      }
    }
    for (int p = 0; p < np; ++p)
    {
      this->CornerStart[p + 1] += this->CornerStart[p];
    }
    this->Corners.assign(3 * nt, 0);
    std::vector<int> fill(this->CornerStart.begin(), this->CornerStart.end() - 1);
    for (int t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->Corners[fill[this->Snap.Triangles[t][k]]++] = 3 * t + k;
      }
    }
    // Sided points: vertices with several copies, on an order-0 line or on
    // the receiver's outline.
    const int nv = static_cast<int>(this->Snap.Vertices.size());
    std::vector<int> copies(nv, 0);
    std::vector<char> onCut(nv, 0);
    for (int p = 0; p < np; ++p)
    {
      ++copies[this->Snap.PointVertex[p]];
    }
    for (const auto& s : this->Snap.Segments)
    {
      if (s.Order <= 0)
      {
        onCut[s.VertexA] = onCut[s.VertexB] = 1;
      }
    }
    this->PointSided.assign(np, 0);
    for (int p = 0; p < np; ++p)
    {
      const int v = this->Snap.PointVertex[p];
      this->PointSided[p] = copies[v] > 1 || onCut[v];
    }
  }

  // Does direction d lie in the corner of one of point p's triangles?
  bool InSector(int p, double du, double dv) const
  {
    const P2 a = this->PointUV(p);
    for (int c = this->CornerStart[p]; c < this->CornerStart[p + 1]; ++c)
    {
      const auto& t = this->Snap.Triangles[this->Corners[c] / 3];
      const int k = this->Corners[c] % 3;
      const P2 next = this->PointUV(t[(k + 1) % 3]), prev = this->PointUV(t[(k + 2) % 3]);
      if (Cross2(next[0] - a[0], next[1] - a[1], du, dv) >= 0.0 &&
        Cross2(du, dv, prev[0] - a[0], prev[1] - a[1]) >= 0.0)
      {
        return true;
      }
    }
    return false;
  }

  // Offset of a point into triangle t (on its side): the unit direction
  // toward t's centroid and the distance to move.
  void SideDirection(int t, const P2& at, double& du, double& dv, double& distance) const
  {
    const auto& tri = this->Snap.Triangles[t];
    double c[2] = { 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      const P2 q = this->PointUV(tri[k]);
      c[0] += q[0] / 3.0;
      c[1] += q[1] / 3.0;
    }
    du = c[0] - at[0];
    dv = c[1] - at[1];
    const double l = std::sqrt(du * du + dv * dv);
    du /= l;
    dv /= l;
    distance = std::min(this->SideOffset * this->Diameter, 0.5 * l);
  }

  // Side sample direction of point p when its triangles form a fan with two
  // free edges (a point of the outline or of an order-0 line): the bisector
  // of the fan, so that a line crossing the boundary there at right angles
  // (e.g. where a shooter's plane crosses the receiver's outline) keeps the
  // point; returns false for a closed fan.
  bool FanBisector(int p, double& du, double& dv, double& distance) const
  {
    const P2 a = this->PointUV(p);
    int first = -1, last = -1;
    double shortest = HUGE_VAL;
    for (int c = this->CornerStart[p]; c < this->CornerStart[p + 1]; ++c)
    {
      const auto& tri = this->Snap.Triangles[this->Corners[c] / 3];
      const int k = this->Corners[c] % 3, next = tri[(k + 1) % 3], prev = tri[(k + 2) % 3];
      bool nextShared = false, prevShared = false;
      for (int o = this->CornerStart[p]; o < this->CornerStart[p + 1]; ++o)
      {
        const auto& other = this->Snap.Triangles[this->Corners[o] / 3];
        const int j = this->Corners[o] % 3;
        nextShared = nextShared || other[(j + 2) % 3] == next;
        prevShared = prevShared || other[(j + 1) % 3] == prev;
      }
      first = nextShared ? first : next;
      last = prevShared ? last : prev;
      for (const int q : { next, prev })
      {
        const P2 b = this->PointUV(q);
        shortest = std::min(shortest, std::hypot(b[0] - a[0], b[1] - a[1]));
      }
    }
    if (first < 0 || last < 0)
    {
      return false;
    }
    const P2 f = this->PointUV(first), l = this->PointUV(last);
    const double start = std::atan2(f[1] - a[1], f[0] - a[0]);
    double sweep = std::atan2(l[1] - a[1], l[0] - a[0]) - start;
    while (sweep <= 0.0)
    {
      sweep += 2.0 * M_PI;
    }
    du = std::cos(start + 0.5 * sweep);
    dv = std::sin(start + 0.5 * sweep);
    distance = std::min(this->SideOffset * this->Diameter, 0.25 * shortest);
    return true;
  }

  // Side sample direction of point p: toward the centroid of its triangle
  // with the largest angle at p (strictly inside the sector).
  int WidestTriangle(int p) const
  {
    const P2 a = this->PointUV(p);
    int best = -1;
    double bestAngle = -1.0;
    for (int c = this->CornerStart[p]; c < this->CornerStart[p + 1]; ++c)
    {
      const int t = this->Corners[c] / 3, k = this->Corners[c] % 3;
      const auto& tri = this->Snap.Triangles[t];
      const P2 next = this->PointUV(tri[(k + 1) % 3]), prev = this->PointUV(tri[(k + 2) % 3]);
      const double x0 = next[0] - a[0], y0 = next[1] - a[1], x1 = prev[0] - a[0],
                   y1 = prev[1] - a[1];
      const double angle = std::atan2(Cross2(x0, y0, x1, y1), x0 * x1 + y0 * y1);
      if (angle > bestAngle)
      {
        bestAngle = angle;
        best = t;
      }
    }
    return best;
  }
};

// Build the working state from vertices (2D and 3D), segments and seeds.
void Prepare(Receiver& rec, const std::vector<P2>& vertices, const std::vector<Vec3>& vertex3,
  const std::vector<detail::RefinableSegment>& segments, const std::vector<P2>& seeds)
{
  rec.Vertex3 = vertex3;
  double lo[2] = { vertices[0][0], vertices[0][1] }, hi[2] = { lo[0], lo[1] };
  for (const P2& v : vertices)
  {
    for (int c = 0; c < 2; ++c)
    {
      lo[c] = std::min(lo[c], v[c]);
      hi[c] = std::max(hi[c], v[c]);
    }
  }
  rec.Diameter = std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
  rec.Tri.reset(new detail::RefinableTriangulation(vertices, segments, seeds));
  rec.Irregularities = rec.Tri->GetIrregularities();
  rec.Samples.clear();
}

// The input mesh's vertices (compact ids in order of first use), segments
// and triangle centroids in the frame.
void Decompose(const ReceiverMesh& mesh, const Frame& f, std::vector<P2>& vertices,
  std::vector<Vec3>& vertex3, std::vector<int>& vertexOfPoint,
  std::vector<detail::RefinableSegment>& segments, std::vector<P2>& seeds)
{
  std::unordered_map<int, int> compact;
  vertexOfPoint.assign(mesh.Points.size(), -1);
  for (std::size_t p = 0; p < mesh.Points.size(); ++p)
  {
    auto inserted = compact.emplace(mesh.PointVertex[p], static_cast<int>(vertices.size()));
    if (inserted.second)
    {
      vertices.push_back(f.To2D(mesh.Points[p]));
      vertex3.push_back(mesh.Points[p]);
    }
    vertexOfPoint[p] = inserted.first->second;
  }
  for (const DiscontinuitySegment& s : mesh.Segments)
  {
    detail::RefinableSegment r;
    r.A = vertexOfPoint[s.PointA];
    r.B = vertexOfPoint[s.PointB];
    r.Order = s.Order;
    r.SourceId = s.SourceId;
    segments.push_back(r);
  }
  for (const auto& t : mesh.Triangles)
  {
    P2 c = { 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
    {
      const P2 q = f.To2D(mesh.Points[t[k]]);
      c[0] += q[0] / 3.0;
      c[1] += q[1] / 3.0;
    }
    seeds.push_back(c);
  }
}

// Give every point of the current snapshot its value, evaluating the points
// that have none (new vertices from irregular input, the initial mesh).
void AssignValues(Receiver& rec, const RadianceBatchFunction& evaluate,
  AdaptiveSamplingStatistics& stats)
{
  const int np = static_cast<int>(rec.Snap.PointVertex.size());
  const int nv = static_cast<int>(rec.Snap.Vertices.size());
  if (static_cast<int>(rec.Samples.size()) < nv)
  {
    rec.Samples.resize(nv);
  }
  rec.Values.assign(np, RGB());
  std::vector<int> missing;
  auto match = [&](int p) -> const SideSample* {
    const auto& samples = rec.Samples[rec.Snap.PointVertex[p]];
    for (const SideSample& s : samples)
    {
      if (!rec.PointSided[p] || (s.Sided && rec.InSector(p, s.Du, s.Dv)))
      {
        return &s;
      }
    }
    return nullptr;
  };
  for (int p = 0; p < np; ++p)
  {
    if (const SideSample* s = match(p))
    {
      rec.Values[p] = s->Value;
    }
    else
    {
      missing.push_back(p);
    }
  }
  if (missing.empty())
  {
    return;
  }
  std::vector<Vec3> points(missing.size());
  std::vector<SideSample> added(missing.size());
  for (std::size_t k = 0; k < missing.size(); ++k)
  {
    const int p = missing[k];
    const int v = rec.Snap.PointVertex[p];
    points[k] = rec.Position3(v);
    if (rec.PointSided[p])
    {
      double du, dv, distance;
      if (!rec.FanBisector(p, du, dv, distance))
      {
        rec.SideDirection(rec.WidestTriangle(p), rec.PointUV(p), du, dv, distance);
      }
      added[k].Du = du;
      added[k].Dv = dv;
      added[k].Sided = true;
      points[k] += distance * (du * rec.F.U + dv * rec.F.V);
    }
  }
  std::vector<RGB> values(missing.size());
  const auto start = std::chrono::steady_clock::now();
  evaluate(points.data(), static_cast<int>(points.size()), values.data());
  stats.EvaluationSeconds += Seconds(start);
  stats.Evaluations += static_cast<long long>(points.size());
  for (std::size_t k = 0; k < missing.size(); ++k)
  {
    added[k].Value = values[k];
    rec.Samples[rec.Snap.PointVertex[missing[k]]].push_back(added[k]);
    rec.Values[missing[k]] = values[k];
  }
}

// The current samples as a SampleMesh (same point and triangle ids).
SampleMesh MakeSampleMesh(const Receiver& rec)
{
  SampleMesh m;
  m.NumberOfChannels = 3;
  const int np = static_cast<int>(rec.Snap.PointVertex.size());
  m.Points.reserve(2 * np);
  m.Values.reserve(3 * np);
  for (int p = 0; p < np; ++p)
  {
    m.AddPoint(rec.PointUV(p)[0], rec.PointUV(p)[1], rec.Values[p]);
  }
  for (const auto& t : rec.Snap.Triangles)
  {
    m.AddTriangle(t[0], t[1], t[2]);
  }
  for (const auto& s : rec.Snap.Segments)
  {
    if (s.LeftA >= 0)
    {
      m.AddConstrainedEdge(s.LeftA, s.LeftB, s.Order);
    }
    if (s.RightA >= 0 && (s.RightA != s.LeftA || s.RightB != s.LeftB))
    {
      m.AddConstrainedEdge(s.RightA, s.RightB, s.Order);
    }
  }
  return m;
}

// Area-weighted mean of the linear interpolant of the current values.
RGB MeanRadiance(const Receiver& rec)
{
  double sum[3] = { 0.0, 0.0, 0.0 }, area = 0.0;
  for (const auto& t : rec.Snap.Triangles)
  {
    const P2 a = rec.PointUV(t[0]), b = rec.PointUV(t[1]), c = rec.PointUV(t[2]);
    const double w = 0.5 * Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]);
    area += w;
    for (int k = 0; k < 3; ++k)
    {
      sum[k] += w *
        (Channel(rec.Values[t[0]], k) + Channel(rec.Values[t[1]], k) + Channel(rec.Values[t[2]], k)) /
        3.0;
    }
  }
  return area > 0.0 ? RGB(sum[0] / area, sum[1] / area, sum[2] / area) : RGB();
}

// Fill the result from the final state.
void Finish(const Receiver& rec, int receiverId, AdaptiveSamplingResult& result)
{
  ReceiverMesh& mesh = result.Mesh;
  mesh = ReceiverMesh();
  mesh.ReceiverId = receiverId;
  const int np = static_cast<int>(rec.Snap.PointVertex.size());
  for (int p = 0; p < np; ++p)
  {
    mesh.Points.push_back(rec.Position3(rec.Snap.PointVertex[p]));
    mesh.PointVertex.push_back(rec.Snap.PointVertex[p]);
  }
  mesh.Triangles = rec.Snap.Triangles;
  for (const auto& s : rec.Snap.Segments)
  {
    DiscontinuitySegment d;
    d.Order = s.Order;
    d.SourceId = s.SourceId;
    d.ReceiverId = receiverId;
    d.PointA = s.LeftA >= 0 ? s.LeftA : s.RightA;
    d.PointB = s.LeftA >= 0 ? s.LeftB : s.RightB;
    d.A = mesh.Points[d.PointA];
    d.B = mesh.Points[d.PointB];
    mesh.Segments.push_back(d);
  }
  result.Values = rec.Values;
  result.Samples = MakeSampleMesh(rec);
  result.Origin = rec.F.Origin;
  result.AxisU = rec.F.U;
  result.AxisV = rec.F.V;
  result.Normal = rec.F.N;
  result.Statistics.Samples = np;
  result.Statistics.Irregularities = static_cast<int>(rec.Irregularities);
}

/// Key of a candidate point: a triangle's centroid (its three vertex ids,
/// sorted) or an edge midpoint (vertex ids sorted, C = -1 unsided, -2 on the
/// left of A->B, -3 on its right).
struct CandidateKey
{
  int A, B, C;
  bool operator==(const CandidateKey& o) const { return A == o.A && B == o.B && C == o.C; }
};
struct CandidateKeyHash
{
  std::size_t operator()(const CandidateKey& k) const
  {
    std::size_t h = static_cast<std::size_t>(k.A) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::size_t>(k.B) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= static_cast<std::size_t>(static_cast<long long>(k.C)) + 0x94D049BB133111EBull + (h << 6) +
      (h >> 2);
    return h;
  }
};
struct CandidateValue
{
  RGB Value;
  double Du = 0.0, Dv = 0.0; // side direction of a sided midpoint
  bool Sided = false;
  bool Evaluated = false;
  bool Used = false;
};

/// An insertion request of one pass.
struct Request
{
  double Score = 0.0;
  int Order = 0;          // creation order (tie break)
  bool Edge = false;
  int A = -1, B = -1;     // edge vertex ids, or the hint vertex of a centroid
  double U = 0.0, V = 0.0;
  bool Constrained = false;
  double FeatureSize = HUGE_VAL; // feature size the new vertex inherits
  std::vector<const CandidateValue*> Values; // the new point's samples
};

/// A feature whose discontinuity lines are shorter than the receiver's
/// diameter over this is refined down to MinimumFeatureSize times this times
/// their length (instead of times the diameter). Measured (direct light,
/// default settings, shortest line through each vertex): the adversarial
/// "features 1e-4 of the scene size" case passes (max error 0.26% of its
/// scale) from 1 to 10 and fails from 30 (2.5%, at the standing cube's
/// contact corners); the Cornell box's direct pass took 2% more evaluations
/// at 10, 7% at 3, 17% at 1.
constexpr double FeatureNeighbourhood = 10.0;
/// No triangle narrower, or edge shorter, than this fraction of the
/// receiver's diameter is refined, whatever MinimumFeatureSize (0 included)...
constexpr double NumericalWidth = 1e-9;
/// ... nor than this fraction of the largest coordinate of the receiver's
/// points (1e7 ulps): the output is written as 3D doubles and projected
/// again by the reconstructor, and a sliver within ~1e6 ulps of its
/// coordinates' rounding may come back flat or flipped.
constexpr double CoordinateRounding = 1e7 * std::numeric_limits<double>::epsilon();

/// Per vertex id: the length of the longest discontinuity line through it
/// (collinear chains of order 0-2 segments, joined across the points that
/// split them), HUGE_VAL on none. A line is as long as the shadow-casting
/// feature is large (a 1e-4 occluder casts lines of about 1e-4), so this is
/// the local size of what is to be resolved. The longest, not the shortest:
/// a short piece of a line cut off by another's visibility ends on that
/// line, which belongs to a large feature (the shortest lowered the floor at
/// such points of a 1,000-polygon room and refined slivers of 1e-9 there;
/// on the Cornell box it took 2% more evaluations, the longest 0.4%).
std::vector<double> DiscontinuityLineLengths(const Receiver& rec)
{
  const auto& segments = rec.Snap.Segments;
  const int ns = static_cast<int>(segments.size());
  const int nv = static_cast<int>(rec.Snap.Vertices.size());
  detail::UnionFind lines(ns);
  std::vector<std::vector<int>> incident(nv);
  std::vector<double> length(ns, 0.0);
  for (int i = 0; i < ns; ++i)
  {
    const auto& seg = segments[i];
    if (seg.Order < 0)
    {
      continue;
    }
    const P2 a = rec.Vertex(seg.VertexA), b = rec.Vertex(seg.VertexB);
    length[i] = std::hypot(b[0] - a[0], b[1] - a[1]);
    incident[seg.VertexA].push_back(i);
    incident[seg.VertexB].push_back(i);
  }
  // Join segments meeting at a vertex in a straight line (opposite directions).
  for (int v = 0; v < nv; ++v)
  {
    const auto& list = incident[v];
    const P2 o = rec.Vertex(v);
    for (std::size_t x = 0; x < list.size(); ++x)
    {
      for (std::size_t y = x + 1; y < list.size(); ++y)
      {
        const auto& s1 = segments[list[x]];
        const auto& s2 = segments[list[y]];
        const P2 p = rec.Vertex(s1.VertexA == v ? s1.VertexB : s1.VertexA);
        const P2 q = rec.Vertex(s2.VertexA == v ? s2.VertexB : s2.VertexA);
        const double ux = p[0] - o[0], uy = p[1] - o[1], wx = q[0] - o[0], wy = q[1] - o[1];
        const double scale = length[list[x]] * length[list[y]];
        if (ux * wx + uy * wy < 0.0 && std::abs(Cross2(ux, uy, wx, wy)) <= 1e-9 * scale)
        {
          lines.Union(list[x], list[y]);
        }
      }
    }
  }
  std::vector<double> chain(ns, 0.0);
  for (int i = 0; i < ns; ++i)
  {
    chain[lines.Find(i)] += length[i];
  }
  std::vector<double> out(nv, HUGE_VAL);
  for (int v = 0; v < nv; ++v)
  {
    if (!incident[v].empty())
    {
      out[v] = 0.0;
    }
    for (int i : incident[v])
    {
      out[v] = std::max(out[v], chain[lines.Find(i)]);
    }
  }
  return out;
}

/// Splits every segment longer than `spacing` into equal pieces no longer
/// than it (new points appended, on the segment; pieces keep its labels).
void SubdivideSegments(double spacing, std::vector<P2>& vertices, std::vector<Vec3>& vertex3,
  std::vector<detail::RefinableSegment>& segments)
{
  std::vector<detail::RefinableSegment> pieces;
  for (const detail::RefinableSegment& s : segments)
  {
    const P2 a = vertices[s.A], b = vertices[s.B];
    const Vec3 a3 = vertex3[s.A], b3 = vertex3[s.B];
    const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
    const int count = std::max(1, static_cast<int>(std::ceil(length / spacing - 1e-9)));
    int previous = s.A;
    for (int k = 1; k <= count; ++k)
    {
      int next = s.B;
      if (k < count)
      {
        const double t = static_cast<double>(k) / count;
        next = static_cast<int>(vertices.size());
        vertices.push_back({ a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]) });
        vertex3.push_back(a3 + t * (b3 - a3));
      }
      detail::RefinableSegment piece = s;
      piece.A = previous;
      piece.B = next;
      pieces.push_back(piece);
      previous = next;
    }
  }
  segments.swap(pieces);
}

} // namespace

//------------------------------------------------------------------------------
AdaptiveSamplingResult SampleReceiver(const ReceiverMesh& mesh,
  const RadianceBatchFunction& evaluate, const AdaptiveSamplingSettings& settings)
{
  const auto start = std::chrono::steady_clock::now();
  CheckSettings(settings);
  if (!evaluate)
  {
    throw InputError("adaptive sampling: no evaluation function");
  }
  AdaptiveSamplingResult result;
  AdaptiveSamplingStatistics& stats = result.Statistics;
  Receiver rec;
  rec.F = MakeFrame(mesh);
  rec.SideOffset = settings.SideOffset;
  {
    std::vector<P2> vertices, seeds;
    std::vector<Vec3> vertex3;
    std::vector<int> vertexOfPoint;
    std::vector<detail::RefinableSegment> segments;
    Decompose(mesh, rec.F, vertices, vertex3, vertexOfPoint, segments, seeds);
    Prepare(rec, vertices, vertex3, segments, seeds);
  }
  rec.Refresh();
  if (rec.Snap.Triangles.empty())
  {
    throw InputError("adaptive sampling: receiver mesh has no triangle after triangulation");
  }
  AssignValues(rec, evaluate, stats);
  stats.InitialSamples = static_cast<int>(rec.Snap.PointVertex.size());

  const double minimumSize = settings.MinimumFeatureSize * rec.Diameter;
  const double maximumLength = settings.MaximumEdgeLength;
  // Triangles narrower than this are not refined. The receiver's own width
  // (2 area / diameter) bounds it too: a strip 1e-6 wide (aspect 1e6) is all
  // "slivers" by the diameter rule and was never refined along its length.
  double area = 0.0;
  for (const auto& t : rec.Snap.Triangles)
  {
    const P2 a = rec.PointUV(t[0]), b = rec.PointUV(t[1]), c = rec.PointUV(t[2]);
    area += 0.5 * std::abs(Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]));
  }
  const double minimumWidth =
    settings.MinimumFeatureSize * std::min(rec.Diameter, 2.0 * area / rec.Diameter);
  // Near small features the floor is smaller: a feature whose discontinuity
  // lines are shorter than 1/FeatureNeighbourhood of the receiver is refined
  // as a receiver FeatureNeighbourhood times their length would be, i.e. to
  // the same fraction of its own size. Inserted vertices take the smallest
  // line length of the vertices they are inserted between.
  rec.FeatureSize = DiscontinuityLineLengths(rec);
  // No refinement below rounding.
  const double roundingWidth =
    std::max(NumericalWidth * rec.Diameter, CoordinateRounding * rec.F.LargestCoordinate);
  // Candidate 0 is the centroid, 1..3 the edge midpoints.
  const int firstCandidate = settings.ProbeCentroids ? 0 : 1;
  std::unordered_map<CandidateKey, CandidateValue, CandidateKeyHash> cache;
  Reconstruction interpolant;
  // The passes compare values with the interpolant only: no error model.
  ReconstructionOptions passInterpolant = settings.Interpolant;
  passInterpolant.ErrorModel = false;
  // Per triangle: its four candidates (centroid, edges 0..2).
  std::vector<std::array<CandidateValue*, 4>> candidates;
  std::vector<std::array<double, 4>> scores;
  std::vector<std::array<RGB, 4>> residuals;
  RGB tolerance;
  // The last pass's residuals become the result's probes.
  auto keepProbes = [&](int nt) {
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
  };
  // Localized passes. A pass changes the interpolant only near the points
  // it inserted: the triangles around a new vertex are new, the gradient
  // fits read at most two rings, line derivatives two points along a line.
  // So after a pass only triangles with a vertex within ScoredRings hops of
  // a new vertex are scored again, against an interpolant built on those
  // within BuiltRings hops (their fits and line derivatives then see all
  // they see in the whole mesh; one ring spare); the others keep their
  // residuals. TestAdaptiveSampler checks the final residuals against a
  // whole rebuild (equal to 1e-15). Late passes insert a few points
  // into a large mesh, and rebuilding it all made the sampler's cost about
  // passes x size (10 times the final size on a box-room floor).
  constexpr int ScoredRings = 2, BuiltRings = 5;
  struct TriangleState
  {
    std::array<CandidateValue*, 4> Candidates;
    std::array<RGB, 4> Residuals;
  };
  auto keyOf = [&](int t) {
    const auto& tri = rec.Snap.Triangles[t];
    int v[3] = { rec.Snap.PointVertex[tri[0]], rec.Snap.PointVertex[tri[1]],
      rec.Snap.PointVertex[tri[2]] };
    std::sort(v, v + 3);
    return CandidateKey{ v[0], v[1], v[2] }; // the key of its centroid
  };
  std::unordered_map<CandidateKey, TriangleState, CandidateKeyHash> previous;
  std::vector<int> newVertices;
  std::vector<int> hops;          // per vertex: rings from the nearest new vertex (capped)
  std::vector<int> subTriangle;   // per triangle: index in the built mesh, or -1
  std::vector<char> scored;       // per triangle: scored this pass
  for (int pass = 0;; ++pass)
  {
    if (pass > 0)
    {
      rec.Refresh();
      AssignValues(rec, evaluate, stats);
    }
    const int nt = static_cast<int>(rec.Snap.Triangles.size());
    scored.assign(nt, 1);
    subTriangle.resize(nt);
    bool localized = false;
    if (pass > 0 && !previous.empty())
    {
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
      localized = 2 * built < nt;
      if (localized)
      {
        // Triangles kept from the last pass must all be found.
        for (int t = 0; t < nt && localized; ++t)
        {
          localized = scored[t] || previous.count(keyOf(t)) > 0;
        }
      }
    }
    if (localized)
    {
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
      interpolant.Build(samples, passInterpolant);
      ++stats.LocalizedPasses;
    }
    else
    {
      for (int t = 0; t < nt; ++t)
      {
        subTriangle[t] = t;
      }
      scored.assign(nt, 1);
      interpolant.Build(MakeSampleMesh(rec), passInterpolant);
    }
    const RGB mean = MeanRadiance(rec);
    tolerance = RGB(std::max(settings.RelativeTolerance * mean.R, settings.AbsoluteTolerance),
      std::max(settings.RelativeTolerance * mean.G, settings.AbsoluteTolerance),
      std::max(settings.RelativeTolerance * mean.B, settings.AbsoluteTolerance));
    result.ReferenceRadiance = mean;

    // Candidates: cached values of unchanged elements, new ones evaluated in
    // one batch.
    for (auto& entry : cache)
    {
      entry.second.Used = false;
    }
    candidates.assign(nt, { nullptr, nullptr, nullptr, nullptr });
    residuals.assign(nt, {});
    std::vector<Vec3> newPoints;
    std::vector<CandidateValue*> newEntries;
    for (int t = 0; t < nt; ++t)
    {
      if (!scored[t])
      {
        const TriangleState& state = previous.find(keyOf(t))->second;
        candidates[t] = state.Candidates;
        residuals[t] = state.Residuals;
        for (int c = firstCandidate; c < 4; ++c)
        {
          candidates[t][c]->Used = true;
        }
        continue;
      }
      const auto& tri = rec.Snap.Triangles[t];
      const int v[3] = { rec.Snap.PointVertex[tri[0]], rec.Snap.PointVertex[tri[1]],
        rec.Snap.PointVertex[tri[2]] };
      for (int c = firstCandidate; c < 4; ++c)
      {
        CandidateKey key;
        P2 at;
        bool sided = false;
        if (c == 0)
        {
          int s[3] = { v[0], v[1], v[2] };
          std::sort(s, s + 3);
          key = { s[0], s[1], s[2] };
          const P2 a = rec.Vertex(v[0]), b = rec.Vertex(v[1]), d = rec.Vertex(v[2]);
          at = { (a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0 };
        }
        else
        {
          const int k = c - 1, a = v[k], b = v[(k + 1) % 3];
          const int segment = rec.Snap.TriangleSegments[t][k];
          sided = segment >= 0 && rec.Snap.Segments[segment].Order <= 0;
          // The triangle is on the left of a -> b (counter-clockwise).
          key = { std::min(a, b), std::max(a, b), sided ? (a < b ? -2 : -3) : -1 };
          const P2 pa = rec.Vertex(a), pb = rec.Vertex(b);
          at = { 0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]) };
        }
        CandidateValue& entry = cache[key];
        entry.Used = true;
        candidates[t][c] = &entry;
        if (!entry.Evaluated)
        {
          entry.Evaluated = true;
          Vec3 x = rec.F.To3D(at[0], at[1]);
          if (sided)
          {
            double du, dv, distance;
            rec.SideDirection(t, at, du, dv, distance);
            entry.Du = du;
            entry.Dv = dv;
            entry.Sided = true;
            x += distance * (du * rec.F.U + dv * rec.F.V);
          }
          newPoints.push_back(x);
          newEntries.push_back(&entry);
        }
      }
    }
    if (!newPoints.empty())
    {
      std::vector<RGB> values(newPoints.size());
      const auto evalStart = std::chrono::steady_clock::now();
      evaluate(newPoints.data(), static_cast<int>(newPoints.size()), values.data());
      stats.EvaluationSeconds += Seconds(evalStart);
      stats.Evaluations += static_cast<long long>(newPoints.size());
      for (std::size_t k = 0; k < newEntries.size(); ++k)
      {
        newEntries[k]->Value = values[k];
      }
    }

    // Residuals against the interpolant, scores = max over channels of
    // |residual| / tolerance.
    scores.assign(nt, { 0.0, 0.0, 0.0, 0.0 });
    const double tol[3] = { tolerance.R, tolerance.G, tolerance.B };
    static const double bary[4][3] = { { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 }, { 0.5, 0.5, 0.0 },
      { 0.0, 0.5, 0.5 }, { 0.5, 0.0, 0.5 } };
    for (int t = 0; t < nt; ++t)
    {
      for (int c = firstCandidate; c < 4; ++c)
      {
        if (scored[t])
        {
          double value[3];
          interpolant.Evaluate(subTriangle[t], bary[c], value);
          const RGB& exact = candidates[t][c]->Value;
          residuals[t][c] = RGB(exact.R - value[0], exact.G - value[1], exact.B - value[2]);
        }
        const RGB& r = residuals[t][c];
        double score = 0.0;
        for (int k = 0; k < 3; ++k)
        {
          const double a = std::abs(Channel(r, k));
          score = std::max(score, tol[k] > 0.0 ? a / tol[k] : (a > 0.0 ? HUGE_VAL : 0.0));
        }
        scores[t][c] = score;
      }
    }

    // Requests from failing refinable triangles.
    const int current = static_cast<int>(rec.Snap.PointVertex.size());
    const bool canInsert = pass < settings.MaximumPasses && current < settings.MaximumSamples;
    std::vector<Request> requests;
    std::unordered_map<long long, int> edgeRequest; // (min, max) vertex pair -> request
    int failing = 0;
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

    if (requests.empty())
    {
      // Final pass: its residuals are the probes.
      stats.UnrefinedFailures = 0;
      for (int t = 0; t < nt; ++t)
      {
        const auto& s = scores[t];
        stats.UnrefinedFailures += std::max({ s[0], s[1], s[2], s[3] }) > 1.0;
      }
      stats.Converged = stats.UnrefinedFailures == 0;
      if (!canInsert)
      {
        stats.BudgetReached = current >= settings.MaximumSamples;
      }
      keepProbes(nt);
      break;
    }

    // Insert by decreasing score within the budget.
    std::sort(requests.begin(), requests.end(), [](const Request& a, const Request& b) {
      return a.Score != b.Score ? a.Score > b.Score : a.Order < b.Order;
    });
    int budget = settings.MaximumSamples - current;
    int inserted = 0;
    previous.clear();
    previous.reserve(static_cast<std::size_t>(nt));
    for (int t = 0; t < nt; ++t)
    {
      previous.emplace(keyOf(t), TriangleState{ candidates[t], residuals[t] });
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
    // Forget candidates of elements that no longer exist.
    for (auto it = cache.begin(); it != cache.end();)
    {
      it = it->second.Used ? std::next(it) : cache.erase(it);
    }
    if (inserted == 0)
    {
      // Nothing could be inserted: the residuals of this pass stand.
      stats.Converged = false;
      stats.UnrefinedFailures = failing;
      keepProbes(nt);
      break;
    }
    ++stats.Passes;
  }
  result.Tolerance = tolerance;
  Finish(rec, mesh.ReceiverId, result);
  stats.Seconds = Seconds(start);
  return result;
}

//------------------------------------------------------------------------------
AdaptiveSamplingResult SampleReceiverUniform(const ReceiverMesh& mesh, int numberOfSamples,
  const RadianceBatchFunction& evaluate, const AdaptiveSamplingSettings& settings)
{
  const auto start = std::chrono::steady_clock::now();
  CheckSettings(settings);
  if (!evaluate)
  {
    throw InputError("adaptive sampling: no evaluation function");
  }
  if (numberOfSamples < 3)
  {
    throw InputError("uniform sampling: numberOfSamples must be >= 3");
  }
  AdaptiveSamplingResult result;
  AdaptiveSamplingStatistics& stats = result.Statistics;
  const Frame frame = MakeFrame(mesh);
  std::vector<P2> vertices, seeds;
  std::vector<Vec3> vertex3;
  std::vector<int> vertexOfPoint;
  std::vector<detail::RefinableSegment> segments;
  Decompose(mesh, frame, vertices, vertex3, vertexOfPoint, segments, seeds);

  // The full mesh once, for its boundary (edges with one kept side) and area.
  Receiver full;
  full.F = frame;
  Prepare(full, vertices, vertex3, segments, seeds);
  full.Refresh();
  std::vector<int> boundaryId(full.Snap.Vertices.size(), -1);
  std::vector<P2> boundaryVertices;
  std::vector<Vec3> boundary3;
  std::vector<detail::RefinableSegment> boundarySegments;
  auto idOf = [&](int v) {
    if (boundaryId[v] < 0)
    {
      boundaryId[v] = static_cast<int>(boundaryVertices.size());
      boundaryVertices.push_back(full.Snap.Vertices[v]);
      boundary3.push_back(full.Position3(v));
    }
    return boundaryId[v];
  };
  for (const auto& s : full.Snap.Segments)
  {
    if ((s.LeftA >= 0) != (s.RightA >= 0))
    {
      detail::RefinableSegment b;
      b.A = idOf(s.VertexA);
      b.B = idOf(s.VertexB);
      b.Order = s.Order;
      b.SourceId = s.SourceId;
      boundarySegments.push_back(b);
    }
  }
  double area = 0.0, lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
  for (const auto& t : full.Snap.Triangles)
  {
    const P2 a = full.PointUV(t[0]), b = full.PointUV(t[1]), c = full.PointUV(t[2]);
    area += 0.5 * Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]);
    for (const P2& q : { a, b, c })
    {
      for (int k = 0; k < 2; ++k)
      {
        lo[k] = std::min(lo[k], q[k]);
        hi[k] = std::max(hi[k], q[k]);
      }
    }
  }
  if (boundaryVertices.size() < 3)
  {
    throw InputError("uniform sampling: the receiver mesh has no boundary");
  }

  // Boundary points at about the grid's spacing: the outline usually comes
  // with its corners only, and long thin triangles joining them to the grid
  // would interpolate the radiance linearly along a whole edge (6% off along
  // a floor's edge in test_adversarial.py's light-plane case; a strip
  // narrower than the grid got no interior point and only its corners).
  double perimeter = 0.0;
  for (const auto& s : boundarySegments)
  {
    const P2 a = boundaryVertices[s.A], b = boundaryVertices[s.B];
    perimeter += std::hypot(b[0] - a[0], b[1] - a[1]);
  }
  SubdivideSegments(std::max(std::sqrt(area / numberOfSamples), 2.0 * perimeter / numberOfSamples),
    boundaryVertices, boundary3, boundarySegments);

  // Grid of cell centres, spacing adjusted to the requested count.
  Receiver rec;
  rec.F = frame;
  rec.SideOffset = settings.SideOffset;
  const int interior = std::max(1, numberOfSamples - static_cast<int>(boundaryVertices.size()));
  double h = std::sqrt(area / interior);
  for (int attempt = 0; attempt < 8; ++attempt)
  {
    Prepare(rec, boundaryVertices, boundary3, boundarySegments, seeds);
    int hint = 0;
    for (int j = 0; lo[1] + (j + 0.5) * h < hi[1]; ++j)
    {
      // Alternate the direction of the rows so consecutive points are close.
      const int columns = static_cast<int>(std::ceil((hi[0] - lo[0]) / h - 0.5));
      for (int i = 0; i < columns; ++i)
      {
        const int ii = j % 2 ? columns - 1 - i : i;
        const int id = rec.Tri->InsertInFace(lo[0] + (ii + 0.5) * h, lo[1] + (j + 0.5) * h, hint);
        hint = id >= 0 ? id : hint;
      }
    }
    rec.Refresh();
    const int count = static_cast<int>(rec.Snap.PointVertex.size());
    if (std::abs(count - numberOfSamples) <= std::max(1, numberOfSamples / 100) ||
      count - static_cast<int>(boundaryVertices.size()) <= 0)
    {
      break;
    }
    h *= std::sqrt(static_cast<double>(count - static_cast<int>(boundaryVertices.size())) / interior);
  }
  AssignValues(rec, evaluate, stats);
  stats.InitialSamples = static_cast<int>(rec.Snap.PointVertex.size());
  result.ReferenceRadiance = MeanRadiance(rec);
  Finish(rec, mesh.ReceiverId, result);
  stats.Seconds = Seconds(start);
  return result;
}

} // namespace penumbra
