// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraShooterCoarsening.h"

#include "penumbraDisplayDecimation.h"
#include "penumbraPlaneFrame.h"
#include "penumbraReconstruction.h" // ResampledMesh

#include <cstddef>

namespace penumbra
{

ShooterRadiance CoarsenShooterRadiance(
  const ShooterRadiance& fine, const std::vector<std::array<int, 2>>& creases, double tolerance)
{
  if (fine.IsConstant() || !(tolerance > 0.0))
  {
    return fine;
  }
  const std::vector<Vec3>& points = fine.GetPoints();
  const std::vector<std::array<int, 3>>& triangles = fine.GetTriangles();
  const std::vector<RGB>& values = fine.GetValues();
  Vec3 u, v;
  InPlaneAxes(fine.GetPlaneNormal(), u, v);
  // The decimation works on the used points only, counter-clockwise in (u, v).
  std::vector<int> local(points.size(), -1);
  ResampledMesh mesh;
  mesh.NumberOfChannels = 3;
  for (const std::array<int, 3>& tri : triangles)
  {
    for (const int p : tri)
    {
      if (local[static_cast<std::size_t>(p)] < 0)
      {
        local[static_cast<std::size_t>(p)] = mesh.GetNumberOfPoints();
        const Vec3& x = points[static_cast<std::size_t>(p)];
        const RGB& value = values[static_cast<std::size_t>(p)];
        mesh.Points.insert(mesh.Points.end(), { Dot(x, u), Dot(x, v) });
        mesh.Values.insert(mesh.Values.end(), { value.R, value.G, value.B });
        mesh.SourcePoint.push_back(p);
      }
    }
  }
  int positive = 0;
  for (const std::array<int, 3>& tri : triangles)
  {
    const double* a = &mesh.Points[2 * static_cast<std::size_t>(local[tri[0]])];
    const double* b = &mesh.Points[2 * static_cast<std::size_t>(local[tri[1]])];
    const double* c = &mesh.Points[2 * static_cast<std::size_t>(local[tri[2]])];
    const bool ccw = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0;
    positive += ccw ? 1 : 0;
    // Clockwise triangles are turned (their radiance does not care).
    mesh.Triangles.insert(mesh.Triangles.end(),
      { local[tri[0]], ccw ? local[tri[1]] : local[tri[2]], ccw ? local[tri[2]] : local[tri[1]] });
  }
  if (positive != 0 && positive != static_cast<int>(triangles.size()))
  {
    return fine; // a folded mesh: nothing to merge safely
  }
  // Each crease edge a line of two points: both ends stay.
  mesh.LineOffsets.push_back(0);
  for (const std::array<int, 2>& edge : creases)
  {
    const int a = local[static_cast<std::size_t>(edge[0])];
    const int b = local[static_cast<std::size_t>(edge[1])];
    if (a >= 0 && b >= 0)
    {
      mesh.LinePoints.insert(mesh.LinePoints.end(), { a, b });
      mesh.LineOffsets.push_back(static_cast<int>(mesh.LinePoints.size()));
    }
  }
  DecimateDisplay(mesh, tolerance);
  std::vector<std::array<int, 3>> coarse(static_cast<std::size_t>(mesh.GetNumberOfTriangles()));
  for (std::size_t t = 0; t < coarse.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      coarse[t][k] = mesh.SourcePoint[static_cast<std::size_t>(mesh.Triangles[3 * t + k])];
    }
  }
  return ShooterRadiance(points, std::move(coarse), values);
}

} // namespace penumbra
