// SPDX-License-Identifier: GPL-3.0-or-later
// Estimated radiance jumps of shadow boundaries, and their bounds.
#include "penumbraJumpThreshold.h"

#include "penumbraExactEvaluator.h"
#include "penumbraFormFactor.h"
#include "penumbraMath.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra
{
namespace detail
{

namespace
{

// The form factor from point x of the receiver to a polygon (either side of
// it with `twoSided`).
double FormFactor(const SceneTopology& topology, const PolygonData& rec, const Vec3& x,
  int polygon, bool twoSided)
{
  const std::vector<Vec3>& v = topology.Polygons[polygon].V;
  double f = PointPolygonFormFactorClipped(x, rec.N, v);
  if (twoSided)
  {
    std::vector<Vec3> reversed(v.rbegin(), v.rend());
    f = std::max(f, PointPolygonFormFactorClipped(x, rec.N, reversed));
  }
  return f;
}

} // namespace

double JumpRadiance(const Scene& scene, const DiscontinuityMeshSettings& settings, int shooter)
{
  if (!settings.ShooterRadiance.empty())
  {
    for (std::size_t k = 0; k < settings.Shooters.size(); ++k)
    {
      if (settings.Shooters[k] == shooter)
      {
        return settings.ShooterRadiance[k].Mean();
      }
    }
  }
  return scene.Surfaces[shooter].Emission.Mean();
}

double MinimumJump(const SceneTopology& topology, const Scene& scene,
  const ExactEvaluator& evaluator, int receiverId, const std::vector<int>& shooters,
  const DiscontinuityMeshSettings& settings)
{
  if (!(settings.JumpThreshold > 0.0))
  {
    return -1.0;
  }
  const PolygonData& rec = topology.Polygons[receiverId];
  std::vector<Vec3> samples = { rec.Centroid };
  for (const Vec3& v : rec.V)
  {
    samples.push_back(v + 0.05 * (rec.Centroid - v));
    samples.push_back(v + 0.5 * (rec.Centroid - v));
  }
  double unoccluded = 0.0;
  double visible = 0.0;
  VisibilityWorkspace workspace;
  for (const Vec3& x : samples)
  {
    double unoccludedSum = 0.0;
    double visibleSum = 0.0;
    for (int s : shooters)
    {
      if (s == receiverId)
      {
        continue;
      }
      const double radiance = JumpRadiance(scene, settings, s);
      const double f = FormFactor(topology, rec, x, s, false);
      if (f > 0.0)
      {
        unoccludedSum += radiance * f;
        visibleSum += radiance * evaluator.FormFactor(x, rec.N, receiverId, s, workspace);
      }
    }
    unoccluded = std::max(unoccluded, unoccludedSum);
    visible = std::max(visible, visibleSum);
  }
  if (!(unoccluded > 0.0))
  {
    return std::numeric_limits<double>::infinity(); // no direct light: no shadow
  }
  // The light the receiver really gets (an occluded light casts no jump
  // worth comparing with), sampled: a lit spot between the samples makes the
  // reference lower, which only keeps more boundaries.
  return settings.JumpThreshold * visible;
}

namespace
{

// The largest cosine between `normal` and a direction within `halfAngle` of
// unit direction `u`.
double LargestCosine(const Vec3& normal, const Vec3& u, double halfAngle)
{
  const double angle = std::acos(std::max(-1.0, std::min(1.0, Dot(normal, u))));
  return angle <= halfAngle ? 1.0 : std::max(0.0, std::cos(angle - halfAngle));
}

double BoundingRadius(const PolygonData& p)
{
  double radius = 0.0;
  for (const Vec3& v : p.V)
  {
    radius = std::max(radius, Length(v - p.Centroid));
  }
  return radius;
}

} // namespace

double HiddenFormFactor(const PolygonData& shooter, const Vec3& centre, double radius,
  const Vec3& receiverNormal, double reach)
{
  if (!(reach > radius))
  {
    return 1.0;
  }
  const double shooterRadius = BoundingRadius(shooter);
  const Vec3 between = shooter.Centroid - centre;
  const double distance = Length(between);
  const double gap = distance - radius - shooterRadius;
  double receiverCosine = 1.0;
  double shooterCosine = 1.0;
  if (gap > 0.0)
  {
    // Every hidden ray runs from the object's sphere to the shooter's.
    const Vec3 u = between * (1.0 / distance);
    const double halfAngle = std::asin(std::min(1.0, (radius + shooterRadius) / distance));
    receiverCosine = LargestCosine(receiverNormal, u, halfAngle);
    shooterCosine = LargestCosine(shooter.N, u * -1.0, halfAngle);
  }
  // The sphere seen from the point: a cap of half-angle a, sin a = radius /
  // reach, whose projected solid angle over pi is at most sin^2 a.
  const double sine = radius / reach;
  const double length = reach - radius + std::max(0.0, gap);
  const double hidden = receiverCosine * shooterCosine * shooter.Area / (Pi * length * length);
  return std::min({ 1.0, sine * sine, hidden });
}

double HiddenFormFactorBound(const PolygonData& shooter, const Vec3& centre, double radius,
  const PolygonData& receiver)
{
  // Every point of the receiver's plane is at least the centre's height
  // from it, and the estimate decreases with the distance.
  return HiddenFormFactor(shooter, centre, radius, receiver.N, Dot(receiver.N, centre) - receiver.D);
}

void DropFaintShadows(const SceneTopology& topology, const Scene& scene, int receiverId,
  const DiscontinuityMeshSettings& settings, const ReceiverFrame& frame, double minimumJump,
  std::size_t first, std::vector<Segment2>& segments)
{
  if (!(minimumJump >= 0.0 && segments.size() > first))
  {
    return;
  }
  const PolygonData& rec = topology.Polygons[receiverId];
  std::size_t write = first;
  for (std::size_t k = first; k < segments.size(); ++k)
  {
    const Segment2& s = segments[k];
    bool keep = true;
    // The line where the shooter's own plane crosses R (no occluder) is kept:
    // the shooter is seen edge-on there, so no jump estimate at the line
    // itself says how fast its light rises beside it.
    if (s.SourceId >= 0 && s.Order > 0 && s.OccluderA >= 0)
    {
      const Vec3 mid = frame.To3D({ 0.5 * (s.A[0] + s.B[0]), 0.5 * (s.A[1] + s.B[1]) });
      const double fs = FormFactor(topology, rec, mid, s.SourceId, false);
      double fo = fs;
      for (const int occluder : { s.OccluderA, s.OccluderB })
      {
        if (occluder >= 0)
        {
          // The whole object's, not the face's: a face seen edge-on may
          // bound a large object's shadow.
          const int c = topology.Polygons[occluder].Component;
          const Vec3& centre = topology.ComponentCentre[c];
          fo = std::min(fo,
            HiddenFormFactor(topology.Polygons[s.SourceId], centre, topology.ComponentRadius[c],
              rec.N, Length(mid - centre)));
        }
      }
      const double jump = JumpRadiance(scene, settings, s.SourceId) * std::min(fo, fs);
      keep = jump >= minimumJump;
    }
    if (keep)
    {
      segments[write++] = s;
    }
  }
  segments.resize(write);
}

double FormFactorBound(const PolygonData& p, const PolygonData& receiver, double receiverRadius,
  bool emitsFromFront)
{
  double radius = 0.0;
  for (const Vec3& v : p.V)
  {
    radius = std::max(radius, Length(v - p.Centroid));
  }
  const Vec3 between = p.Centroid - receiver.Centroid;
  const double distance = Length(between);
  const double d = distance - radius - receiverRadius;
  if (!(d > 0.0))
  {
    return 1.0;
  }
  // Every line from the receiver to p lies within this angle of the line
  // between their centres; the cosines at its ends are bounded accordingly.
  const Vec3 u = between * (1.0 / distance);
  const double halfAngle = std::asin(std::min(1.0, (radius + receiverRadius) / distance));
  double cosines = LargestCosine(receiver.N, u, halfAngle);
  if (emitsFromFront)
  {
    cosines *= LargestCosine(p.N, u * -1.0, halfAngle);
  }
  return std::min(1.0, cosines * p.Area / (Pi * d * d));
}

} // namespace detail
} // namespace penumbra
