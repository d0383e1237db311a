// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraFormFactor.h"

#include "penumbraMath.h"

#include <algorithm>

namespace penumbra
{

double PointPolygonFormFactorSigned(const Vec3& x, const Vec3& n, const Vec3* vertices, int count)
{
  if (count < 3)
  {
    return 0.0;
  }
  double sum = 0.0;
  Vec3 r0 = vertices[count - 1] - x;
  for (int k = 0; k < count; ++k)
  {
    const Vec3 r1 = vertices[k] - x;
    sum += LambertEdgeTerm(r0, r1, n);
    r0 = r1;
  }
  return sum * (0.5 / Pi);
}

double PointPolygonFormFactor(const Vec3& x, const Vec3& n, const Vec3* vertices, int count)
{
  // A back-facing polygon gives a negative sum: it emits nothing towards x.
  return std::max(0.0, PointPolygonFormFactorSigned(x, n, vertices, count));
}

int ClipPolygonToHalfSpace(
  const Vec3* vertices, int count, const Vec3& normal, double offset, Vec3* out)
{
  if (count <= 0)
  {
    return 0;
  }
  int m = 0;
  Vec3 prev = vertices[count - 1];
  double dPrev = Dot(normal, prev) - offset;
  for (int k = 0; k < count; ++k)
  {
    const Vec3& cur = vertices[k];
    const double dCur = Dot(normal, cur) - offset;
    // Only strict sign changes create a vertex, so a vertex lying on the plane
    // is never duplicated.
    if ((dPrev > 0.0 && dCur < 0.0) || (dPrev < 0.0 && dCur > 0.0))
    {
      const double t = dPrev / (dPrev - dCur);
      out[m++] = prev + (cur - prev) * t;
    }
    if (dCur >= 0.0)
    {
      out[m++] = cur;
    }
    prev = cur;
    dPrev = dCur;
  }
  return m >= 3 ? m : 0;
}

void ClipPolygonToHalfSpace(
  const std::vector<Vec3>& vertices, const Vec3& normal, double offset, std::vector<Vec3>& out)
{
  out.resize(2 * vertices.size());
  const int m = ClipPolygonToHalfSpace(
    vertices.data(), static_cast<int>(vertices.size()), normal, offset, out.data());
  out.resize(static_cast<std::size_t>(m));
}

double PointPolygonFormFactorClipped(const Vec3& x, const Vec3& n, const Vec3* vertices, int count)
{
  if (count < 3)
  {
    return 0.0;
  }
  // Fast path: nothing behind the tangent plane, no copy needed.
  const double offset = Dot(n, x);
  bool allFront = true;
  for (int k = 0; k < count && allFront; ++k)
  {
    allFront = Dot(n, vertices[k]) >= offset;
  }
  if (allFront)
  {
    return PointPolygonFormFactor(x, n, vertices, count);
  }
  constexpr int StackVertices = 64;
  Vec3 stackBuffer[StackVertices];
  std::vector<Vec3> heapBuffer;
  Vec3* clipped = stackBuffer;
  if (2 * count > StackVertices)
  {
    heapBuffer.resize(static_cast<std::size_t>(2 * count));
    clipped = heapBuffer.data();
  }
  const int m = ClipPolygonToHalfSpace(vertices, count, n, offset, clipped);
  return PointPolygonFormFactor(x, n, clipped, m);
}

} // namespace penumbra
