// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraExactVisibility.h"

#include "penumbraFormFactor.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

// Pieces below this fraction of the shooter's area are dropped.
constexpr double PieceAreaFraction = 1e-14;
// Vertices closer than this fraction of the shooter's diameter to a shadow
// line count as on it, so that no sliver is created.
constexpr double LineEpsilonFraction = 1e-13;

double Area2D(const double* p, int count)
{
  double twice = 0.0;
  double px = p[2 * (count - 1)], py = p[2 * (count - 1) + 1];
  for (int k = 0; k < count; ++k)
  {
    twice += px * p[2 * k + 1] - py * p[2 * k];
    px = p[2 * k];
    py = p[2 * k + 1];
  }
  return 0.5 * twice;
}

// Everything one query needs about the shooter and the point, in the
// shooter's frame: x = centroid + xu*U + xv*V + hx*N, receiver normal nl.
struct QueryFrame
{
  const PreparedPolygon* Shooter;
  Vec3 X;
  double Xu, Xv, Hx;
  Vec3 Nl;
  double MinArea;
  double LineEps;
};

// Subtract the shadow {p : a*u + b*v + c >= 0 for every line} from the
// current pieces of the workspace. Returns the number of pieces left.
int SubtractShadow(VisibilityWorkspace& ws, const double* lines, int numberOfLines, double minArea,
  double eps)
{
  ws.NextPoints.clear();
  ws.NextStarts.clear();
  const int numberOfPieces = static_cast<int>(ws.Starts.size()) - 1;
  for (int piece = 0; piece < numberOfPieces; ++piece)
  {
    const int first = ws.Starts[piece];
    const int count = (ws.Starts[piece + 1] - first) / 2;
    const double* pts = ws.Points.data() + first;
    const std::size_t markPoints = ws.NextPoints.size();
    const std::size_t markStarts = ws.NextStarts.size();
    ws.Remainder.assign(pts, pts + 2 * count);
    bool untouched = false;
    for (int l = 0; l < numberOfLines && !untouched; ++l)
    {
      const double a = lines[3 * l], b = lines[3 * l + 1], c = lines[3 * l + 2];
      const int m = static_cast<int>(ws.Remainder.size()) / 2;
      const double* r = ws.Remainder.data();
      bool anyIn = false, anyOut = false;
      for (int k = 0; k < m; ++k)
      {
        const double s = a * r[2 * k] + b * r[2 * k + 1] + c;
        anyIn |= s > eps;
        anyOut |= s < -eps;
      }
      if (!anyIn)
      {
        // This line separates the remainder from the shadow, so the shadow
        // does not meet the piece at all: keep it whole.
        untouched = true;
        break;
      }
      if (!anyOut)
      {
        continue; // the remainder lies on the shadow's side of this line
      }
      // Split: the outer part is visible, the inner part goes on.
      const std::size_t outFirst = ws.NextPoints.size();
      ws.Split.clear();
      double ps = a * r[2 * (m - 1)] + b * r[2 * (m - 1) + 1] + c;
      int pc = ps > eps ? 1 : (ps < -eps ? -1 : 0);
      double px = r[2 * (m - 1)], py = r[2 * (m - 1) + 1];
      for (int k = 0; k < m; ++k)
      {
        const double cx = r[2 * k], cy = r[2 * k + 1];
        const double cs = a * cx + b * cy + c;
        const int cc = cs > eps ? 1 : (cs < -eps ? -1 : 0);
        if (pc * cc < 0)
        {
          const double t = ps / (ps - cs);
          const double ix = px + (cx - px) * t, iy = py + (cy - py) * t;
          ws.NextPoints.push_back(ix);
          ws.NextPoints.push_back(iy);
          ws.Split.push_back(ix);
          ws.Split.push_back(iy);
        }
        if (cc <= 0)
        {
          ws.NextPoints.push_back(cx);
          ws.NextPoints.push_back(cy);
        }
        if (cc >= 0)
        {
          ws.Split.push_back(cx);
          ws.Split.push_back(cy);
        }
        px = cx;
        py = cy;
        ps = cs;
        pc = cc;
      }
      const int outCount = static_cast<int>(ws.NextPoints.size() - outFirst) / 2;
      if (outCount >= 3 && Area2D(ws.NextPoints.data() + outFirst, outCount) > minArea)
      {
        ws.NextStarts.push_back(static_cast<int>(outFirst));
      }
      else
      {
        ws.NextPoints.resize(outFirst);
      }
      ws.Remainder.swap(ws.Split);
      const int inCount = static_cast<int>(ws.Remainder.size()) / 2;
      if (inCount < 3 || Area2D(ws.Remainder.data(), inCount) <= minArea)
      {
        untouched = true; // the shadow only grazes the piece
      }
    }
    if (untouched)
    {
      ws.NextPoints.resize(markPoints);
      ws.NextStarts.resize(markStarts);
      ws.NextStarts.push_back(static_cast<int>(markPoints));
      ws.NextPoints.insert(ws.NextPoints.end(), pts, pts + 2 * count);
    }
    // Otherwise the remainder is inside the shadow: it vanishes.
  }
  ws.NextStarts.push_back(static_cast<int>(ws.NextPoints.size()));
  ws.Points.swap(ws.NextPoints);
  ws.Starts.swap(ws.NextStarts);
  return static_cast<int>(ws.Starts.size()) - 1;
}

// Subtract the shadows of every convex piece of occluder `id`. Returns the
// number of visible pieces left.
int CastShadows(const OccluderSet& set, int id, const QueryFrame& q, VisibilityWorkspace& ws)
{
  const PreparedPolygon& o = set.GetPolygon(id);
  const PreparedPolygon& s = *q.Shooter;
  int left = static_cast<int>(ws.Starts.size()) - 1;
  // Signed distance of x from the occluder's plane: which side x sees.
  const double sigma = Dot(o.Normal, q.X - o.Centroid);
  if (std::abs(sigma) <= set.GetPlaneTolerance())
  {
    return left; // x lies in the occluder's plane: rays only graze it
  }
  const double side = sigma > 0.0 ? 1.0 : -1.0;

  // "Strictly beyond the occluder's plane, seen from x", as a half-plane of
  // the shooter's plane: -side * Dot(nO, y - cO) >= tolerance.
  double fa = -side * Dot(o.Normal, s.AxisU);
  double fb = -side * Dot(o.Normal, s.AxisV);
  double fc = -side * Dot(o.Normal, s.Centroid - o.Centroid) - set.GetTolerance();
  const double flen = std::sqrt(fa * fa + fb * fb);
  bool farLine = true;
  if (flen <= 1e-14)
  {
    // Occluder parallel to the shooter: all of it or none of it is beyond.
    if (fc <= 0.0)
    {
      return left;
    }
    farLine = false;
  }
  else
  {
    fa /= flen;
    fb /= flen;
    fc /= flen;
  }

  const std::vector<ConvexPiece>& pieces = set.GetPieces();
  const Vec3* vertices = set.GetPieceVertices().data();
  for (int pi = o.FirstPiece; pi < o.FirstPiece + o.NumberOfPieces && left > 0; ++pi)
  {
    const ConvexPiece& piece = pieces[pi];
    const Vec3* v = vertices + piece.First;
    if (o.NumberOfPieces > 1)
    {
      // Pieces of a concave occluder: cull each against the pyramid.
      bool outside = false;
      for (const Plane& plane : ws.Frustum.Planes)
      {
        outside = true;
        for (int k = 0; k < piece.Count && outside; ++k)
        {
          outside = Dot(plane.Normal, v[k]) < plane.Offset;
        }
        if (outside)
        {
          break;
        }
      }
      if (outside)
      {
        continue;
      }
    }
    ws.Local.resize(static_cast<std::size_t>(piece.Count));
    for (int k = 0; k < piece.Count; ++k)
    {
      const Vec3 d = v[k] - q.X;
      ws.Local[k] = Vec3(Dot(d, s.AxisU), Dot(d, s.AxisV), Dot(d, s.Normal));
    }
    ws.Lines.clear();
    bool empty = false;
    for (int k = 0; k < piece.Count && !empty; ++k)
    {
      const Vec3& r0 = ws.Local[k];
      const Vec3& r1 = ws.Local[(k + 1) % piece.Count];
      // Inward normal of the cone face through x and this edge.
      const Vec3 nk = side > 0.0 ? Cross(r1, r0) : Cross(r0, r1);
      // Restricted to the shooter's plane (local z = -hx relative to x).
      double a = nk.X, b = nk.Y;
      double c = -(nk.X * q.Xu + nk.Y * q.Xv + nk.Z * q.Hx);
      const double len = std::sqrt(a * a + b * b);
      if (!(len > 1e-14 * Length(nk)))
      {
        // Face parallel to the shooter's plane: everything or nothing.
        if (c < 0.0)
        {
          empty = true;
        }
        continue;
      }
      ws.Lines.push_back(a / len);
      ws.Lines.push_back(b / len);
      ws.Lines.push_back(c / len);
    }
    if (empty)
    {
      continue;
    }
    if (farLine)
    {
      ws.Lines.push_back(fa);
      ws.Lines.push_back(fb);
      ws.Lines.push_back(fc);
    }
    ++ws.ShadowCount;
    left = SubtractShadow(ws, ws.Lines.data(), static_cast<int>(ws.Lines.size()) / 3, q.MinArea,
      q.LineEps);
  }
  return left;
}

double Evaluate(const OccluderSet& set, const Vec3& x, const Vec3& n, int shooterId,
  int receiverId, const int* candidates, int numberOfCandidates, bool traverse,
  VisibilityWorkspace& ws, VisibleRegion* region)
{
  if (region)
  {
    region->Points.clear();
    region->Offsets.clear();
  }
  if (shooterId < 0 || shooterId >= set.GetNumberOfPolygons())
  {
    return 0.0;
  }
  const PreparedPolygon& s = set.GetPolygon(shooterId);
  if (!s.Valid)
  {
    return 0.0;
  }
  QueryFrame q;
  q.Shooter = &s;
  q.X = x;
  const Vec3 dx = x - s.Centroid;
  q.Hx = Dot(dx, s.Normal);
  if (!(q.Hx > 0.0) || !IsFinite(x) || !IsFinite(n))
  {
    return 0.0; // x is not in front of the shooter, which emits from its front only
  }
  q.Xu = Dot(dx, s.AxisU);
  q.Xv = Dot(dx, s.AxisV);
  q.Nl = Vec3(Dot(n, s.AxisU), Dot(n, s.AxisV), Dot(n, s.Normal));
  q.MinArea = PieceAreaFraction * s.Area;
  q.LineEps = LineEpsilonFraction * s.Diameter;

  // The shooter's convex pieces clipped to x's front half-space.
  const double hc = -(q.Nl.X * q.Xu + q.Nl.Y * q.Xv + q.Nl.Z * q.Hx);
  ws.Points.clear();
  ws.Starts.clear();
  const std::vector<ConvexPiece>& pieces = set.GetPieces();
  const double* p2 = set.GetPiecePoints2D().data();
  for (int pi = s.FirstPiece; pi < s.FirstPiece + s.NumberOfPieces; ++pi)
  {
    const ConvexPiece& piece = pieces[pi];
    const std::size_t first = ws.Points.size();
    ws.Points.resize(first + 2 * static_cast<std::size_t>(piece.Count + 1));
    const int m =
      ClipPolygon2D(p2 + 2 * piece.First, piece.Count, q.Nl.X, q.Nl.Y, hc, ws.Points.data() + first);
    if (m >= 3 && Area2D(ws.Points.data() + first, m) > q.MinArea)
    {
      ws.Points.resize(first + 2 * static_cast<std::size_t>(m));
      ws.Starts.push_back(static_cast<int>(first));
    }
    else
    {
      ws.Points.resize(first);
    }
  }
  ws.Starts.push_back(static_cast<int>(ws.Points.size()));
  int left = static_cast<int>(ws.Starts.size()) - 1;

  if (left > 0 && (traverse || numberOfCandidates > 0) &&
    set.BuildFrustum(x, n, shooterId, ws.Frustum))
  {
    if (traverse)
    {
      set.VolumeCandidates(ws.Frustum, shooterId, receiverId, ws.Candidates);
    }
    else
    {
      ws.Candidates.clear();
      set.FilterCandidates(
        ws.Frustum, candidates, numberOfCandidates, shooterId, receiverId, ws.Candidates);
    }
    for (std::size_t i = 0; i < ws.Candidates.size() && left > 0; ++i)
    {
      left = CastShadows(set, ws.Candidates[i], q, ws);
    }
  }

  // Lambert's formula over the visible pieces, in the shooter's frame.
  double sum = 0.0;
  for (int piece = 0; piece < left; ++piece)
  {
    const double* pts = ws.Points.data() + ws.Starts[piece];
    const int m = (ws.Starts[piece + 1] - ws.Starts[piece]) / 2;
    Vec3 r0(pts[2 * (m - 1)] - q.Xu, pts[2 * (m - 1) + 1] - q.Xv, -q.Hx);
    for (int k = 0; k < m; ++k)
    {
      const Vec3 r1(pts[2 * k] - q.Xu, pts[2 * k + 1] - q.Xv, -q.Hx);
      sum += LambertEdgeTerm(r0, r1, q.Nl);
      r0 = r1;
    }
  }
  double f = sum * (0.5 / M_PI);
  // Rounding can leave a hair below 0 (grazing pieces) or above 1.
  f = f > 0.0 ? std::min(f, 1.0) : 0.0;

  if (region)
  {
    for (int piece = 0; piece < left; ++piece)
    {
      region->Offsets.push_back(static_cast<int>(region->Points.size()));
      for (int k = ws.Starts[piece]; k < ws.Starts[piece + 1]; k += 2)
      {
        region->Points.push_back(s.Centroid + s.AxisU * ws.Points[k] + s.AxisV * ws.Points[k + 1]);
      }
    }
    if (left > 0)
    {
      region->Offsets.push_back(static_cast<int>(region->Points.size()));
    }
  }
  return f;
}

} // namespace

double VisibleRegion::GetArea() const
{
  double area = 0.0;
  for (int piece = 0; piece < this->GetNumberOfPieces(); ++piece)
  {
    Vec3 twice;
    const Vec3& o = this->Points[this->Offsets[piece]];
    for (int k = this->Offsets[piece] + 1; k + 1 < this->Offsets[piece + 1]; ++k)
    {
      twice += Cross(this->Points[k] - o, this->Points[k + 1] - o);
    }
    area += 0.5 * Length(twice);
  }
  return area;
}

double VisibleFormFactor(const OccluderSet& occluders, const Vec3& x, const Vec3& n,
  int shooterId, int receiverId, const int* candidates, int numberOfCandidates,
  VisibilityWorkspace& workspace, VisibleRegion* region)
{
  return Evaluate(occluders, x, n, shooterId, receiverId, candidates, numberOfCandidates, false,
    workspace, region);
}

ExactEvaluator::ExactEvaluator(const Scene& scene)
  : Occluders(scene)
{
  for (const Surface& s : scene.Surfaces)
  {
    this->Reflectance.push_back(s.Reflectance);
    this->Emission.push_back(s.Emission);
  }
}

double ExactEvaluator::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
  VisibilityWorkspace& workspace, VisibleRegion* region) const
{
  return Evaluate(
    this->Occluders, x, n, shooterId, receiverId, nullptr, 0, true, workspace, region);
}

double ExactEvaluator::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
  const std::vector<int>& shaftCandidates, VisibilityWorkspace& workspace,
  VisibleRegion* region) const
{
  return Evaluate(this->Occluders, x, n, shooterId, receiverId, shaftCandidates.data(),
    static_cast<int>(shaftCandidates.size()), false, workspace, region);
}

RGB ExactEvaluator::ContributedRadiance(const Vec3& x, const Vec3& n, int receiverId,
  int shooterId, VisibilityWorkspace& workspace) const
{
  if (receiverId < 0 || shooterId < 0 || shooterId >= this->Occluders.GetNumberOfPolygons() ||
    receiverId >= this->Occluders.GetNumberOfPolygons())
  {
    return RGB();
  }
  const double f = this->FormFactor(x, n, receiverId, shooterId, workspace);
  return this->Reflectance[receiverId] * this->Emission[shooterId] * f;
}

} // namespace penumbra
