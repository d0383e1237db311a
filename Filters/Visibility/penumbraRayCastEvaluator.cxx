// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraRayCastEvaluator.h"

#include "penumbraFormFactor.h" // ClipPolygonToHalfSpace
#include "penumbraMath.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra
{

namespace
{


double Scalar(const RGB& c)
{
  return (std::abs(c.R) + std::abs(c.G) + std::abs(c.B)) / 3.0;
}

/// What one evaluation needs, shared down the recursion.
struct Query
{
  const RayCaster* Caster = nullptr;
  Vec3 X;
  Vec3 N;
  Vec3 M; // shooter front normal
  int Receiver = -1;
  int Shooter = -1;
  const ShooterRadiance* Radiance = nullptr;
  double Threshold = 0.0;
  int MinDepth = 0;
  int MaxDepth = 0;
  RayCastStatistics* Statistics = nullptr;
};

/// The shooter's radiance at a sample point (a grid lookup for a mesh).
RGB RadianceAt(const Query& q, const Vec3& y)
{
  return q.Radiance->IsConstant() ? q.Radiance->GetConstantValue() : q.Radiance->Evaluate(y);
}

/// cos(theta_x) cos(theta_y) pi A / (pi r^2 + A) for a piece of area A centred at c (0 if behind).
double Weight(const Query& q, const Vec3& c, double area)
{
  const Vec3 r = c - q.X;
  const double r2 = SquaredLength(r);
  const double cx = Dot(q.N, r);
  const double cy = -Dot(q.M, r);
  if (!(cx > 0.0 && cy > 0.0 && r2 > 0.0))
  {
    return 0.0;
  }
  return (cx * cy / r2) * (Pi * area / (Pi * r2 + area));
}

/// Whether a sample point needs a ray: in front of x's tangent plane and of the shooter.
bool NeedsRay(const Query& q, const Vec3& y)
{
  const Vec3 r = y - q.X;
  return Dot(q.N, r) > 0.0 && -Dot(q.M, r) > 0.0;
}

/**
 * Visibility of up to 8 sample points from x, traced as one packet:
 * 1 visible, 0 occluded, -1 no ray needed (behind x or the shooter).
 */
void Visibility(const Query& q, const Vec3* points, int count, int* visibility)
{
  Vec3 targets[8];
  int lane[8];
  int rays = 0;
  for (int i = 0; i < count; ++i)
  {
    if (NeedsRay(q, points[i]))
    {
      lane[i] = rays;
      targets[rays++] = points[i];
    }
    else
    {
      lane[i] = -1;
    }
  }
  unsigned char occluded[8] = { 0, 0, 0, 0, 0, 0, 0, 0 };
  if (rays > 0)
  {
    q.Caster->TraceFrom(q.X, targets, rays, occluded, q.Receiver, q.Shooter);
    if (q.Statistics)
    {
      q.Statistics->Rays += rays;
    }
  }
  for (int i = 0; i < count; ++i)
  {
    visibility[i] = lane[i] < 0 ? -1 : (occluded[lane[i]] ? 0 : 1);
  }
}

/// Estimate of a piece of area `area` centred at `centre` whose centre has visibility `visible`.
RGB Estimate(const Query& q, const Vec3& centre, double area, int visible)
{
  if (q.Statistics)
  {
    ++q.Statistics->Pieces;
  }
  const double weight = Weight(q, centre, area);
  return (visible == 1 && weight > 0.0) ? RadianceAt(q, centre) * weight : RGB();
}

/// Whether the known visibilities of a piece's samples disagree (a shadow edge may cross it).
bool Mixed(int a, int b, int c, int d)
{
  const int v[4] = { a, b, c, d };
  int seen = -1;
  for (const int x : v)
  {
    if (x >= 0)
    {
      if (seen >= 0 && x != seen)
      {
        return true;
      }
      seen = x;
    }
  }
  return false;
}

/// Piece of the recursion: corners, their visibility and radiance, centroid visibility and estimate.
struct Piece
{
  Vec3 P[3];
  int CornerVisibility[3];
  RGB CornerRadiance[3];
  int CentreVisibility;
  RGB Estimate;
};

/**
 * Sum over the subdivision of `piece` (area `area`, level `depth`). The
 * children are always computed (the error estimate needs them); the
 * recursion goes on into all of them when the estimates disagree by more
 * than the threshold (or above MinDepth), else only into those whose sample
 * visibilities disagree and whose unoccluded estimate exceeds the threshold
 * (a piece crossed by a shadow edge can err by its whole value even when its
 * samples happen to agree with its parent's), or whose centre radiance
 * departs from the mean of its corners' (zero for a linear radiance: a kink or
 * a step of a mesh radiance crosses it) by more than the threshold once
 * weighted.
 */
RGB Refine(const Query& q, const Piece& piece, double area, int depth)
{
  if (depth >= q.MaxDepth)
  {
    return piece.Estimate;
  }
  const Vec3* p = piece.P;
  const Vec3 m[3] = { (p[0] + p[1]) * 0.5, (p[1] + p[2]) * 0.5, (p[2] + p[0]) * 0.5 };
  // The 6 new samples (edge midpoints, centres of the 3 outer children) in one packet.
  const Vec3 samples[6] = { m[0], m[1], m[2], (p[0] + m[0] + m[2]) / 3.0,
    (m[0] + p[1] + m[1]) / 3.0, (m[2] + m[1] + p[2]) / 3.0 };
  int sampled[6];
  Visibility(q, samples, 6, sampled);
  const int* vm = sampled;
  const int* vp = piece.CornerVisibility;
  const RGB* lp = piece.CornerRadiance;
  const RGB lm[3] = { RadianceAt(q, m[0]), RadianceAt(q, m[1]), RadianceAt(q, m[2]) };
  Piece child[4] = {
    { { p[0], m[0], m[2] }, { vp[0], vm[0], vm[2] }, { lp[0], lm[0], lm[2] }, -1, RGB() },
    { { m[0], p[1], m[1] }, { vm[0], vp[1], vm[1] }, { lm[0], lp[1], lm[1] }, -1, RGB() },
    { { m[2], m[1], p[2] }, { vm[2], vm[1], vp[2] }, { lm[2], lm[1], lp[2] }, -1, RGB() },
    { { m[0], m[1], m[2] }, { vm[0], vm[1], vm[2] }, { lm[0], lm[1], lm[2] },
      piece.CentreVisibility, RGB() },
  };
  const double childArea = 0.25 * area;
  RGB sum;
  for (int k = 0; k < 4; ++k)
  {
    Piece& c = child[k];
    // The middle child has the parent's centroid: it reuses the parent's ray.
    const Vec3 centre = k < 3 ? samples[3 + k] : (p[0] + p[1] + p[2]) / 3.0;
    if (k < 3)
    {
      c.CentreVisibility = sampled[3 + k];
    }
    c.Estimate = Estimate(q, centre, childArea, c.CentreVisibility);
    sum += c.Estimate;
  }
  if (q.Statistics)
  {
    q.Statistics->DeepestLevel = std::max(q.Statistics->DeepestLevel, depth + 1);
  }
  const bool refineAll =
    depth + 1 < q.MinDepth || Scalar(sum + piece.Estimate * -1.0) > q.Threshold;
  RGB refined;
  for (int k = 0; k < 4; ++k)
  {
    const Piece& c = child[k];
    bool refine = refineAll;
    if (!refine)
    {
      const Vec3 centre = (c.P[0] + c.P[1] + c.P[2]) / 3.0;
      const RGB atCentre = RadianceAt(q, centre);
      const double weight = Weight(q, centre, childArea);
      if (Mixed(c.CornerVisibility[0], c.CornerVisibility[1], c.CornerVisibility[2],
            c.CentreVisibility))
      {
        refine = Scalar(atCentre) * weight > q.Threshold;
      }
      else if (!q.Radiance->IsConstant())
      {
        const RGB mean = (c.CornerRadiance[0] + c.CornerRadiance[1] + c.CornerRadiance[2]) * (1.0 / 3.0);
        refine = Scalar(atCentre + mean * -1.0) * weight > q.Threshold;
      }
    }
    refined += refine ? Refine(q, c, childArea, depth + 1) : c.Estimate;
  }
  return refined;
}

/// An initial piece of the shooter.
struct InitialPiece
{
  Vec3 P[3];
  double Area = 0.0;
};

/// Clip triangle p to x's front half-space and append the result as a fan.
void AddClipped(const Vec3 p[3], const Vec3& x, const Vec3& n, std::vector<InitialPiece>& pieces)
{
  Vec3 clipped[8];
  const int count = ClipPolygonToHalfSpace(p, 3, n, Dot(n, x), clipped);
  for (int k = 1; k + 1 < count; ++k)
  {
    InitialPiece piece;
    piece.P[0] = clipped[0];
    piece.P[1] = clipped[k];
    piece.P[2] = clipped[k + 1];
    piece.Area = 0.5 * Length(Cross(piece.P[1] - piece.P[0], piece.P[2] - piece.P[0]));
    if (piece.Area > 0.0)
    {
      pieces.push_back(piece);
    }
  }
}

} // namespace

//------------------------------------------------------------------------------
RayCastEvaluator::RayCastEvaluator(const Scene& scene)
  : Caster(new RayCaster(scene))
{
  for (const Surface& s : scene.Surfaces)
  {
    const PolygonGeometry geometry = ComputePolygonGeometry(s.Vertices);
    this->Normals.push_back(geometry.Normal);
    this->Reflectance.push_back(s.Reflectance);
    this->Emission.push_back(s.Emission);
  }
}

RayCastEvaluator::~RayCastEvaluator() = default;

void RayCastEvaluator::SetTolerance(double tolerance)
{
  if (!(tolerance > 0.0 && tolerance <= 1.0))
  {
    throw InputError("RayCastEvaluator: Tolerance " + std::to_string(tolerance) +
      " is outside the valid range (0, 1]");
  }
  this->Settings.Tolerance = tolerance;
}

void RayCastEvaluator::SetAbsoluteTolerance(double tolerance)
{
  if (!(tolerance >= 0.0 && tolerance < std::numeric_limits<double>::infinity()))
  {
    throw InputError("RayCastEvaluator: AbsoluteTolerance " + std::to_string(tolerance) +
      " is outside the valid range [0, inf)");
  }
  this->Settings.AbsoluteTolerance = tolerance;
}

void RayCastEvaluator::SetMinDepth(int depth)
{
  if (depth < 0 || depth > 16)
  {
    throw InputError(
      "RayCastEvaluator: MinDepth " + std::to_string(depth) + " is outside the valid range [0, 16]");
  }
  this->Settings.MinDepth = depth;
}

void RayCastEvaluator::SetMaxDepth(int depth)
{
  if (depth < 0 || depth > 16)
  {
    throw InputError(
      "RayCastEvaluator: MaxDepth " + std::to_string(depth) + " is outside the valid range [0, 16]");
  }
  this->Settings.MaxDepth = depth;
}

void RayCastEvaluator::SetRelativeRayOffset(double offset)
{
  this->Caster->SetRelativeOffset(offset);
}

double RayCastEvaluator::GetRelativeRayOffset() const
{
  return this->Caster->GetRelativeOffset();
}

void RayCastEvaluator::CheckQuery(int shooterId) const
{
  if (shooterId < 0 || shooterId >= static_cast<int>(this->Normals.size()))
  {
    throw InputError("RayCastEvaluator: shooter id " + std::to_string(shooterId) +
      " is not a surface of the scene (it has " + std::to_string(this->Normals.size()) +
      " surfaces)");
  }
  if (this->Settings.MinDepth > this->Settings.MaxDepth)
  {
    throw InputError("RayCastEvaluator: MinDepth " +
      std::to_string(this->Settings.MinDepth) + " exceeds MaxDepth " +
      std::to_string(this->Settings.MaxDepth));
  }
}

RGB RayCastEvaluator::Irradiance(const Vec3& x, const Vec3& n, int receiverId, int shooterId,
  const ShooterRadiance& radiance, RayCastStatistics* statistics) const
{
  this->CheckQuery(shooterId);
  const Vec3& m = this->Normals[shooterId];
  const RayCaster& caster = *this->Caster;
  const int firstTriangle = caster.GetFirstTriangle(shooterId);
  const int shooterTriangles = caster.GetNumberOfSurfaceTriangles(shooterId);
  if (shooterTriangles == 0)
  {
    return RGB();
  }
  // x must be strictly in front of the shooter's plane.
  {
    Vec3 corner[3];
    caster.GetTriangle(firstTriangle, corner);
    if (!(Dot(m, x - corner[0]) > 0.0))
    {
      return RGB();
    }
  }
  // Initial pieces: the shooter polygon's triangles clipped to x's front
  // half-space, whatever the radiance (a mesh radiance is looked up at the
  // samples, so the cost does not grow with the mesh and the domain is the
  // shooter, as for the exact evaluator). At most 2 pieces per triangle.
  std::vector<InitialPiece> pieces;
  pieces.reserve(2 * static_cast<std::size_t>(shooterTriangles));
  for (int t = 0; t < shooterTriangles; ++t)
  {
    Vec3 corner[3];
    caster.GetTriangle(firstTriangle + t, corner);
    AddClipped(corner, x, n, pieces);
  }

  Query q;
  q.Caster = &caster;
  q.X = x;
  q.N = n;
  q.M = m;
  q.Receiver = receiverId;
  q.Shooter = shooterId;
  q.Radiance = &radiance;
  q.MinDepth = this->Settings.MinDepth;
  q.MaxDepth = this->Settings.MaxDepth;
  q.Statistics = statistics;
  // The scale of the threshold: the unoccluded one-sample estimate (no rays).
  double unoccluded = 0.0;
  for (const InitialPiece& piece : pieces)
  {
    const Vec3 centre = (piece.P[0] + piece.P[1] + piece.P[2]) / 3.0;
    unoccluded += Scalar(RadianceAt(q, centre)) * Weight(q, centre, piece.Area);
  }
  q.Threshold =
    std::max(this->Settings.Tolerance * unoccluded, this->Settings.AbsoluteTolerance);
  RGB sum;
  for (const InitialPiece& initial : pieces)
  {
    Piece piece;
    const Vec3 centre = (initial.P[0] + initial.P[1] + initial.P[2]) / 3.0;
    const Vec3 samples[4] = { initial.P[0], initial.P[1], initial.P[2], centre };
    int sampled[4];
    Visibility(q, samples, 4, sampled);
    for (int k = 0; k < 3; ++k)
    {
      piece.P[k] = initial.P[k];
      piece.CornerVisibility[k] = sampled[k];
      piece.CornerRadiance[k] = RadianceAt(q, initial.P[k]);
    }
    piece.CentreVisibility = sampled[3];
    piece.Estimate = Estimate(q, centre, initial.Area, piece.CentreVisibility);
    sum += Refine(q, piece, initial.Area, 0);
  }
  return sum;
}

double RayCastEvaluator::FormFactor(
  const Vec3& x, const Vec3& n, int receiverId, int shooterId, RayCastStatistics* statistics) const
{
  const ShooterRadiance unit(RGB(1.0, 1.0, 1.0));
  return this->Irradiance(x, n, receiverId, shooterId, unit, statistics).R / Pi;
}

RGB RayCastEvaluator::ContributedRadiance(
  const Vec3& x, const Vec3& n, int receiverId, int shooterId, RayCastStatistics* statistics) const
{
  this->CheckQuery(shooterId);
  if (receiverId < 0 || receiverId >= static_cast<int>(this->Reflectance.size()))
  {
    return RGB();
  }
  const ShooterRadiance emission(this->Emission[shooterId]);
  const RGB e = this->Irradiance(x, n, receiverId, shooterId, emission, statistics);
  return this->Reflectance[receiverId] * e * (1.0 / Pi);
}

} // namespace penumbra
