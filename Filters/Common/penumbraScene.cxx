// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraScene.h"

#include "penumbraPlaneFrame.h"
#include "penumbraMath.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

namespace penumbra
{

void TriangulatePolygon(
  const std::vector<Vec3>& v, const Vec3& normal, std::vector<std::array<int, 3>>& out)
{
  const int count = static_cast<int>(v.size());
  if (count < 3)
  {
    return;
  }
  Vec3 axisU, axisV;
  InPlaneAxes(normal, axisU, axisV);
  std::vector<double> u(count);
  std::vector<double> w(count);
  for (int i = 0; i < count; ++i)
  {
    u[i] = Dot(v[i], axisU);
    w[i] = Dot(v[i], axisV);
  }
  // (axisU, axisV, normal) is right-handed: counter-clockwise about `normal` is positive.
  const auto cross = [&](int a, int b, int c) {
    return (u[b] - u[a]) * (w[c] - w[a]) - (w[b] - w[a]) * (u[c] - u[a]);
  };
  std::vector<int> ring(count);
  for (int i = 0; i < count; ++i)
  {
    ring[i] = i;
  }
  while (ring.size() > 3)
  {
    const int m = static_cast<int>(ring.size());
    int ear = -1;
    for (int k = 0; k < m && ear < 0; ++k)
    {
      const int a = ring[(k + m - 1) % m];
      const int b = ring[k];
      const int c = ring[(k + 1) % m];
      if (!(cross(a, b, c) > 0.0))
      {
        continue; // reflex or flat
      }
      bool empty = true;
      for (int j = 0; j < m && empty; ++j)
      {
        const int p = ring[j];
        if (p == a || p == b || p == c)
        {
          continue;
        }
        empty = !(cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0);
      }
      if (empty)
      {
        ear = k;
      }
    }
    if (ear < 0)
    {
      // No clean ear (flat or degenerate remainder): cut the flattest vertex.
      double best = std::numeric_limits<double>::infinity();
      for (int k = 0; k < m; ++k)
      {
        const double c = std::abs(cross(ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]));
        if (c < best)
        {
          best = c;
          ear = k;
        }
      }
    }
    const int a = ring[(ear + m - 1) % m];
    const int b = ring[ear];
    const int c = ring[(ear + 1) % m];
    if (cross(a, b, c) != 0.0)
    {
      out.push_back({ a, b, c });
    }
    ring.erase(ring.begin() + ear);
  }
  if (cross(ring[0], ring[1], ring[2]) != 0.0)
  {
    out.push_back({ ring[0], ring[1], ring[2] });
  }
}


PolygonGeometry ComputePolygonGeometry(const std::vector<Vec3>& vertices)
{
  PolygonGeometry g;
  const std::size_t n = vertices.size();
  if (n == 0)
  {
    return g;
  }
  // Newell's method is exact for planar polygons and robust for convex and
  // concave outlines alike; centring first keeps cancellation small when the
  // scene is far from the origin.
  Vec3 mean;
  for (const Vec3& v : vertices)
  {
    mean += v;
  }
  mean = mean / static_cast<double>(n);
  Vec3 areaVector;
  Vec3 weightedCentroid;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Vec3 a = vertices[i] - mean;
    const Vec3 b = vertices[(i + 1) % n] - mean;
    const Vec3 c = Cross(a, b);
    areaVector += c;
    for (std::size_t j = i + 1; j < n; ++j)
    {
      g.Diameter = std::max(g.Diameter, Length(vertices[j] - vertices[i]));
    }
  }
  const double twiceArea = Length(areaVector);
  g.Area = 0.5 * twiceArea;
  if (twiceArea <= 0.0)
  {
    g.Centroid = mean;
    return g;
  }
  g.Normal = areaVector / twiceArea;
  // Centroid as the signed-area weighted mean of the fan triangles.
  double weight = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    const Vec3 a = vertices[0] - mean;
    const Vec3 b = vertices[i] - mean;
    const Vec3 c = vertices[i + 1] - mean;
    const double w = Dot(Cross(b - a, c - a), g.Normal);
    weightedCentroid += (a + b + c) * (w / 3.0);
    weight += w;
  }
  g.Centroid = mean + (weight != 0.0 ? weightedCentroid / weight : Vec3());
  g.Offset = Dot(g.Normal, g.Centroid);
  return g;
}

double Scene::Size() const
{
  double lo[3] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  bool any = false;
  for (const Surface& s : this->Surfaces)
  {
    for (const Vec3& v : s.Vertices)
    {
      for (int k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], v[k]);
        hi[k] = std::max(hi[k], v[k]);
      }
      any = true;
    }
  }
  if (!any)
  {
    return 0.0;
  }
  return std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
}

bool Scene::IsIdentical(const Scene& other) const
{
  const auto same = [](const RGB& a, const RGB& b) {
    return a.R == b.R && a.G == b.G && a.B == b.B;
  };
  if (this->Surfaces.size() != other.Surfaces.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < this->Surfaces.size(); ++k)
  {
    const Surface& a = this->Surfaces[k];
    const Surface& b = other.Surfaces[k];
    if (a.Vertices.size() != b.Vertices.size() || !same(a.Reflectance, b.Reflectance) ||
      !same(a.Emission, b.Emission))
    {
      return false;
    }
    for (std::size_t v = 0; v < a.Vertices.size(); ++v)
    {
      const Vec3& p = a.Vertices[v];
      const Vec3& q = b.Vertices[v];
      if (!(p.X == q.X && p.Y == q.Y && p.Z == q.Z))
      {
        return false;
      }
    }
  }
  return true;
}

RGB Scene::EmittedPower() const
{
  RGB power;
  for (const Surface& s : this->Surfaces)
  {
    power += s.Emission * (Pi * ComputePolygonGeometry(s.Vertices).Area);
  }
  return power;
}

namespace
{

[[noreturn]] void Fail(std::size_t cell, const std::string& what)
{
  std::ostringstream os;
  os << "cell " << cell << ": " << what;
  throw InputError(os.str());
}

// Orientation of the 2D triangle (a, b, c): >0 counter-clockwise.
double Orient2D(const double a[2], const double b[2], const double c[2])
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Whether closed segments ab and cd share a point, with a tolerance eps on the
// orientation tests so that touching counts as intersecting.
bool SegmentsIntersect2D(
  const double a[2], const double b[2], const double c[2], const double d[2], double eps)
{
  const double d1 = Orient2D(c, d, a);
  const double d2 = Orient2D(c, d, b);
  const double d3 = Orient2D(a, b, c);
  const double d4 = Orient2D(a, b, d);
  auto sign = [eps](double v) { return v > eps ? 1 : (v < -eps ? -1 : 0); };
  const int s1 = sign(d1), s2 = sign(d2), s3 = sign(d3), s4 = sign(d4);
  if (s1 * s2 < 0 && s3 * s4 < 0)
  {
    return true;
  }
  auto onSegment = [](const double p[2], const double q[2], const double r[2]) {
    return std::min(p[0], q[0]) <= r[0] && r[0] <= std::max(p[0], q[0]) &&
      std::min(p[1], q[1]) <= r[1] && r[1] <= std::max(p[1], q[1]);
  };
  return (s1 == 0 && onSegment(c, d, a)) || (s2 == 0 && onSegment(c, d, b)) ||
    (s3 == 0 && onSegment(a, b, c)) || (s4 == 0 && onSegment(a, b, d));
}

void CheckColor(std::size_t cell, const char* name, const RGB& c, bool isReflectance)
{
  for (int k = 0; k < 3; ++k)
  {
    const char* channel = k == 0 ? "red" : (k == 1 ? "green" : "blue");
    if (!std::isfinite(c[k]))
    {
      Fail(cell, std::string(name) + " " + channel + " is not a finite number");
    }
    if (isReflectance && (c[k] < 0.0 || c[k] >= 1.0))
    {
      std::ostringstream os;
      os << "Reflectance " << channel << " is " << c[k] << ", outside [0, 1)";
      Fail(cell, os.str());
    }
    if (!isReflectance && c[k] < 0.0)
    {
      std::ostringstream os;
      os << "Emission " << channel << " is " << c[k] << ", negative";
      Fail(cell, os.str());
    }
  }
}

} // namespace

void ValidateScene(const Scene& scene, const ValidationTolerances& tolerances,
  const std::vector<std::size_t>* cellNumbers)
{
  for (std::size_t surface = 0; surface < scene.Surfaces.size(); ++surface)
  {
    const std::size_t cell = cellNumbers ? cellNumbers->at(surface) : surface;
    const Surface& s = scene.Surfaces[surface];
    const std::vector<Vec3>& v = s.Vertices;
    const std::size_t n = v.size();
    if (n < 3)
    {
      Fail(cell, "degenerate polygon with " + std::to_string(n) + " vertices (needs 3 or more)");
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!IsFinite(v[i]))
      {
        Fail(cell, "vertex " + std::to_string(i) + " has a non-finite coordinate");
      }
    }
    CheckColor(cell, "Reflectance", s.Reflectance, true);
    CheckColor(cell, "Emission", s.Emission, false);

    const PolygonGeometry g = ComputePolygonGeometry(v);
    const double size = g.Diameter;
    if (!(size > 0.0))
    {
      Fail(cell, "degenerate polygon: all vertices coincide");
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      if (Length(v[(i + 1) % n] - v[i]) <= tolerances.Degeneracy * size)
      {
        Fail(cell,
          "degenerate polygon: vertices " + std::to_string(i) + " and " +
            std::to_string((i + 1) % n) + " coincide");
      }
    }
    // Width = 2A / diameter; a zero-area (collinear) polygon has width 0.
    if (2.0 * g.Area / size <= tolerances.Degeneracy * size)
    {
      Fail(cell, "degenerate polygon: zero area (vertices are collinear)");
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      const double distance = std::abs(Dot(g.Normal, v[i]) - g.Offset);
      if (distance > tolerances.Planarity * size)
      {
        std::ostringstream os;
        os << "non-planar polygon: vertex " << i << " is " << distance
           << " from the polygon's plane (tolerance " << tolerances.Planarity * size << ")";
        Fail(cell, os.str());
      }
    }
    if (n > 3)
    {
      // Project on the plane and test every pair of non-adjacent edges.
      const Vec3 u = Normalized(std::abs(g.Normal.X) < 0.9 ? Cross(g.Normal, Vec3(1, 0, 0))
                                                           : Cross(g.Normal, Vec3(0, 1, 0)));
      const Vec3 w = Cross(g.Normal, u);
      std::vector<double> p(2 * n);
      for (std::size_t i = 0; i < n; ++i)
      {
        const Vec3 d = v[i] - g.Centroid;
        p[2 * i] = Dot(d, u);
        p[2 * i + 1] = Dot(d, w);
      }
      const double eps = 1e-12 * size * size;
      for (std::size_t i = 0; i < n; ++i)
      {
        for (std::size_t j = i + 2; j < n; ++j)
        {
          if (i == 0 && j == n - 1)
          {
            continue; // adjacent through the closing edge
          }
          if (SegmentsIntersect2D(&p[2 * i], &p[2 * ((i + 1) % n)], &p[2 * j],
                &p[2 * ((j + 1) % n)], eps))
          {
            Fail(cell,
              "self-intersecting polygon: edge " + std::to_string(i) + " crosses edge " +
                std::to_string(j));
          }
        }
      }
    }
  }
}

} // namespace penumbra
