// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSamplingReceiver.cxx
 * @brief Working state of one receiver in the adaptive sampler: frame,
 * per-point tables, side directions, samples in and out.
 */
#include "penumbraSamplingReceiver.h"

#include "penumbraMath.h"
#include "penumbraScene.h" // InputError
#include "penumbraTimer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace penumbra
{
namespace detail
{

double Channel(const RGB& c, int k)
{
  return k == 0 ? c.R : (k == 1 ? c.G : c.B);
}

//------------------------------------------------------------------------------
void CheckSettings(const AdaptiveSamplingSettings& s)
{
  auto bad = [](const std::string& what) { throw InputError("adaptive sampling: " + what); };
  if (!(s.SamplingTolerance >= 0.0 && s.SamplingTolerance <= 1.0))
  {
    bad("SamplingTolerance must be in [0, 1]");
  }
  if (!(s.AbsoluteTolerance >= 0.0) || !std::isfinite(s.AbsoluteTolerance))
  {
    bad("AbsoluteTolerance must be finite and >= 0");
  }
  if (s.MaximumSamplesPerSurface < 1)
  {
    bad("MaximumSamplesPerSurface must be >= 1");
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

//------------------------------------------------------------------------------
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
    n += Cross(
      mesh.Points[tri[1]] - mesh.Points[tri[0]], mesh.Points[tri[2]] - mesh.Points[tri[0]]);
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

//------------------------------------------------------------------------------
Vec3 Receiver::Position3(int vertex) const
{
  if (vertex < static_cast<int>(this->Vertex3.size()))
  {
    return this->Vertex3[vertex];
  }
  const P2 uv = this->Snap.Vertices[vertex];
  return this->F.To3D(uv[0], uv[1]);
}

//------------------------------------------------------------------------------
void Receiver::Refresh()
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

//------------------------------------------------------------------------------
bool Receiver::InSector(int p, double du, double dv) const
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

//------------------------------------------------------------------------------
void Receiver::SideDirection(
  int t, const P2& at, double& du, double& dv, double& distance) const
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

//------------------------------------------------------------------------------
bool Receiver::FanBisector(int p, double& du, double& dv, double& distance) const
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
    sweep += 2.0 * Pi;
  }
  du = std::cos(start + 0.5 * sweep);
  dv = std::sin(start + 0.5 * sweep);
  distance = std::min(this->SideOffset * this->Diameter, 0.25 * shortest);
  return true;
}

//------------------------------------------------------------------------------
int Receiver::WidestTriangle(int p) const
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

//------------------------------------------------------------------------------
void Prepare(Receiver& rec, const std::vector<P2>& vertices, const std::vector<Vec3>& vertex3,
  const std::vector<RefinableSegment>& segments, const std::vector<P2>& seeds)
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
  rec.Tri.reset(new RefinableTriangulation(vertices, segments, seeds));
  rec.Irregularities = rec.Tri->GetIrregularities();
  rec.Samples.clear();
}

//------------------------------------------------------------------------------
void Decompose(const ReceiverMesh& mesh, const Frame& f, std::vector<P2>& vertices,
  std::vector<Vec3>& vertex3, std::vector<int>& vertexOfPoint,
  std::vector<RefinableSegment>& segments, std::vector<P2>& seeds)
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
    RefinableSegment r;
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

//------------------------------------------------------------------------------
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

//------------------------------------------------------------------------------
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

//------------------------------------------------------------------------------
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
        (Channel(rec.Values[t[0]], k) + Channel(rec.Values[t[1]], k) +
          Channel(rec.Values[t[2]], k)) /
        3.0;
    }
  }
  return area > 0.0 ? RGB(sum[0] / area, sum[1] / area, sum[2] / area) : RGB();
}

//------------------------------------------------------------------------------
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

} // namespace detail
} // namespace penumbra
