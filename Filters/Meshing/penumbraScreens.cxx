// SPDX-License-Identifier: GPL-3.0-or-later
// Screens between a shooter and a receiver, and the features they hide.
#include "penumbraScreens.h"

#include "penumbraMath.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace penumbra
{
namespace detail
{

namespace
{

// Whether polygon p turns the same way at every vertex (collinear vertices
// allowed), counter-clockwise about its normal.
bool IsConvex(const PolygonData& p)
{
  const std::size_t n = p.V.size();
  for (std::size_t k = 0; k < n; ++k)
  {
    const Vec3 a = p.V[(k + 1) % n] - p.V[k];
    const Vec3 b = p.V[(k + 2) % n] - p.V[(k + 1) % n];
    if (Dot(Cross(a, b), p.N) < -1e-12 * Length(a) * Length(b))
    {
      return false;
    }
  }
  return true;
}

// The lowest and highest signed heights of `points` over the plane of p.
void HeightRange(const PolygonData& p, const std::vector<Vec3>& points, double& low, double& high)
{
  low = std::numeric_limits<double>::max();
  high = -low;
  for (const Vec3& v : points)
  {
    const double h = Dot(p.N, v) - p.D;
    low = std::min(low, h);
    high = std::max(high, h);
  }
}

} // namespace

void ScreenSet::Build(const SceneTopology& topology, const std::vector<int>& candidates,
  const PolygonData& shooter, const PolygonData& receiver, double tolerance, int maximum)
{
  this->Screens.clear();
  this->Last = 0;
  this->Tolerance = tolerance;
  this->ShooterVertices = shooter.V;
  // (area, polygon id, or -1 - id when the shooter is behind the polygon)
  std::vector<std::pair<double, int>> separating;
  for (const int k : candidates)
  {
    const PolygonData& p = topology.Polygons[k];
    double shooterLow, shooterHigh, receiverLow, receiverHigh;
    HeightRange(p, shooter.V, shooterLow, shooterHigh);
    HeightRange(p, receiver.V, receiverLow, receiverHigh);
    const bool shooterInFront = shooterLow > tolerance && receiverHigh < -tolerance;
    const bool shooterBehind = shooterHigh < -tolerance && receiverLow > tolerance;
    if ((shooterInFront || shooterBehind) && IsConvex(p))
    {
      separating.emplace_back(p.Area, shooterInFront ? k : -1 - k);
    }
  }
  const std::size_t kept = std::min(separating.size(), static_cast<std::size_t>(maximum));
  std::partial_sort(separating.begin(), separating.begin() + static_cast<std::ptrdiff_t>(kept),
    separating.end(), [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first;
    });
  for (std::size_t s = 0; s < kept; ++s)
  {
    const int code = separating[s].second;
    const PolygonData& p = topology.Polygons[code >= 0 ? code : -1 - code];
    const double sign = code >= 0 ? 1.0 : -1.0;
    Screen screen;
    screen.Normal = p.N * sign;
    screen.Offset = p.D * sign;
    screen.NearestShooter = std::numeric_limits<double>::max();
    for (const Vec3& v : shooter.V)
    {
      const double h = Dot(screen.Normal, v) - screen.Offset;
      screen.ShooterHeights.push_back(h);
      screen.NearestShooter = std::min(screen.NearestShooter, h);
    }
    const std::size_t n = p.V.size();
    for (std::size_t k = 0; k < n; ++k)
    {
      // Counter-clockwise about N: N x edge points inside.
      const Vec3 inward = Normalized(Cross(p.N, p.V[(k + 1) % n] - p.V[k]));
      screen.EdgeNormals.push_back(inward);
      screen.EdgeOffsets.push_back(Dot(inward, p.V[k]) + tolerance);
    }
    this->Screens.push_back(std::move(screen));
  }
}

bool ScreenSet::Inside(const Screen& screen, const Vec3& x) const
{
  for (std::size_t k = 0; k < screen.EdgeNormals.size(); ++k)
  {
    if (Dot(screen.EdgeNormals[k], x) < screen.EdgeOffsets[k])
    {
      return false;
    }
  }
  return true;
}

bool ScreenSet::HidesBehind(const Screen& screen, const Vec3* points, int count) const
{
  double heights[2];
  for (int i = 0; i < count; ++i)
  {
    // Strictly between the screen and the nearest shooter vertex: every
    // line from the shooter through the point descends to the plane.
    heights[i] = Dot(screen.Normal, points[i]) - screen.Offset;
    if (!(heights[i] > this->Tolerance && heights[i] < screen.NearestShooter - this->Tolerance))
    {
      return false;
    }
  }
  for (std::size_t j = 0; j < this->ShooterVertices.size(); ++j)
  {
    const Vec3& s = this->ShooterVertices[j];
    const double hs = screen.ShooterHeights[j];
    for (int i = 0; i < count; ++i)
    {
      const Vec3 crossing = s + (points[i] - s) * (hs / (hs - heights[i]));
      if (!this->Inside(screen, crossing))
      {
        return false;
      }
    }
  }
  return true;
}

bool ScreenSet::Hides(const Vec3* points, int count)
{
  const int size = static_cast<int>(this->Screens.size());
  for (int n = 0; n < size; ++n)
  {
    const int i = (this->Last + n) % size;
    if (this->HidesBehind(this->Screens[static_cast<std::size_t>(i)], points, count))
    {
      this->Last = i;
      return true;
    }
  }
  return false;
}

} // namespace detail
} // namespace penumbra
