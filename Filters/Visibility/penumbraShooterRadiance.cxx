// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraShooterRadiance.h"

#include "penumbraPlaneFrame.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra
{

LinearRadiance LinearRadiance::FromTriangle(const Vec3 points[3], const RGB values[3])
{
  LinearRadiance f;
  f.Origin = points[0];
  f.Value = values[0];
  const Vec3 e1 = points[1] - points[0];
  const Vec3 e2 = points[2] - points[0];
  const Vec3 normal = Cross(e1, e2);
  const double n2 = SquaredLength(normal);
  if (!(n2 > 0.0))
  {
    return f;
  }
  // g = (dv1 (e2 x N) + dv2 (N x e1)) / |N|^2 satisfies g.e1 = dv1, g.e2 = dv2
  // and g.N = 0: the in-plane gradient.
  const Vec3 a = Cross(e2, normal) / n2;
  const Vec3 b = Cross(normal, e1) / n2;
  for (int c = 0; c < 3; ++c)
  {
    f.Gradient[c] = a * (values[1][c] - values[0][c]) + b * (values[2][c] - values[0][c]);
  }
  return f;
}

ShooterRadiance::ShooterRadiance(const RGB& value)
  : Constant(value)
{
  if (!std::isfinite(value.R) || !std::isfinite(value.G) || !std::isfinite(value.B))
  {
    throw InputError("shooter radiance: the constant value is not finite");
  }
}

ShooterRadiance::ShooterRadiance(
  std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles, std::vector<RGB> values)
  : Points(std::move(points))
  , Triangles(std::move(triangles))
  , Values(std::move(values))
{
  const std::string where = "shooter radiance mesh: ";
  if (this->Triangles.empty())
  {
    throw InputError(where + "no triangle (use the constant constructor for a constant radiance)");
  }
  if (this->Values.size() != this->Points.size())
  {
    throw InputError(where + "got " + std::to_string(this->Values.size()) + " values for " +
      std::to_string(this->Points.size()) + " points");
  }
  for (std::size_t i = 0; i < this->Points.size(); ++i)
  {
    const RGB& v = this->Values[i];
    if (!IsFinite(this->Points[i]))
    {
      throw InputError(where + "point " + std::to_string(i) + " has non-finite coordinates");
    }
    if (!std::isfinite(v.R) || !std::isfinite(v.G) || !std::isfinite(v.B))
    {
      throw InputError(where + "point " + std::to_string(i) + " has a non-finite value");
    }
  }
  const int numberOfPoints = static_cast<int>(this->Points.size());
  Vec3 lo = this->Points.empty() ? Vec3() : this->Points[0];
  Vec3 hi = lo;
  for (const Vec3& p : this->Points)
  {
    lo = { std::min(lo.X, p.X), std::min(lo.Y, p.Y), std::min(lo.Z, p.Z) };
    hi = { std::max(hi.X, p.X), std::max(hi.Y, p.Y), std::max(hi.Z, p.Z) };
  }
  const double diameter = Length(hi - lo);
  // Orientation-independent plane normal: the largest triangle's normal, then
  // every triangle's normal summed with the sign that agrees with it.
  // Triangles of (nearly) zero area carry no radiance into any integral and
  // have no well-defined plane or gradient: they are dropped. Compact
  // displays and decimated meshes produce such slivers legitimately.
  std::vector<Vec3> normals;
  normals.reserve(this->Triangles.size());
  std::size_t kept = 0;
  std::size_t largest = 0;
  for (std::size_t t = 0; t < this->Triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int id = this->Triangles[t][k];
      if (id < 0 || id >= numberOfPoints)
      {
        throw InputError(where + "triangle " + std::to_string(t) + " refers to point " +
          std::to_string(id) + ", out of range [0, " + std::to_string(numberOfPoints) + ")");
      }
    }
    const Vec3& a = this->Points[this->Triangles[t][0]];
    const Vec3 normal =
      Cross(this->Points[this->Triangles[t][1]] - a, this->Points[this->Triangles[t][2]] - a);
    if (!(Length(normal) * 0.5 > 1e-12 * diameter * diameter))
    {
      continue;
    }
    if (normals.empty() || SquaredLength(normal) > SquaredLength(normals[largest]))
    {
      largest = kept;
    }
    this->Triangles[kept++] = this->Triangles[t];
    normals.push_back(normal);
  }
  this->DroppedTriangles = static_cast<int>(this->Triangles.size() - kept);
  this->Triangles.resize(kept);
  if (this->Triangles.empty())
  {
    throw InputError(where + "every triangle is degenerate (zero area)");
  }
  Vec3 sum;
  for (const Vec3& c : normals)
  {
    sum += Dot(c, normals[largest]) >= 0.0 ? c : -c;
  }
  this->Normal = Normalized(sum);
  // The plane through the area-weighted mean point.
  double offset = 0.0;
  double totalWeight = 0.0;
  for (std::size_t t = 0; t < this->Triangles.size(); ++t)
  {
    const double w = Length(normals[t]);
    for (int k = 0; k < 3; ++k)
    {
      offset += w * Dot(this->Normal, this->Points[this->Triangles[t][k]]) / 3.0;
    }
    totalWeight += w;
  }
  offset /= totalWeight;
  for (std::size_t t = 0; t < this->Triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int id = this->Triangles[t][k];
      if (std::abs(Dot(this->Normal, this->Points[id]) - offset) > 1e-6 * diameter)
      {
        throw InputError(where + "point " + std::to_string(id) + " of triangle " +
          std::to_string(t) + " lies off the plane of the mesh");
      }
    }
  }
  this->Functions.resize(this->Triangles.size());
  this->Areas.resize(this->Triangles.size());
  for (std::size_t t = 0; t < this->Triangles.size(); ++t)
  {
    const RadianceTriangle tri = this->GetTriangle(static_cast<int>(t));
    this->Functions[t] = LinearRadiance::FromTriangle(tri.Points, tri.Values);
    this->Areas[t] = 0.5 * Length(normals[t]);
  }
  this->Tolerance = 1e-9 * diameter;
  this->BuildGrid();
}

RadianceTriangle ShooterRadiance::GetTriangle(int i) const
{
  RadianceTriangle tri;
  for (int k = 0; k < 3; ++k)
  {
    tri.Points[k] = this->Points[this->Triangles[i][k]];
    tri.Values[k] = this->Values[this->Triangles[i][k]];
  }
  return tri;
}

void ShooterRadiance::BuildGrid()
{
  // In-plane frame: any unit vector orthogonal to the normal.
  const Vec3& n = this->Normal;
  InPlaneAxes(n, this->AxisU, this->AxisV);
  const int count = static_cast<int>(this->Triangles.size());
  this->Boxes.resize(static_cast<std::size_t>(count));
  this->FirstCells.resize(static_cast<std::size_t>(count));
  double lo[2] = { 1e300, 1e300 };
  double hi[2] = { -1e300, -1e300 };
  for (int t = 0; t < count; ++t)
  {
    double* b = this->Boxes[static_cast<std::size_t>(t)].data();
    b[0] = b[1] = 1e300;
    b[2] = b[3] = -1e300;
    for (int k = 0; k < 3; ++k)
    {
      const Vec3& p = this->Points[this->Triangles[t][k]];
      const double u = Dot(p, this->AxisU);
      const double v = Dot(p, this->AxisV);
      b[0] = std::min(b[0], u);
      b[1] = std::min(b[1], v);
      b[2] = std::max(b[2], u);
      b[3] = std::max(b[3], v);
    }
    lo[0] = std::min(lo[0], b[0]);
    lo[1] = std::min(lo[1], b[1]);
    hi[0] = std::max(hi[0], b[2]);
    hi[1] = std::max(hi[1], b[3]);
  }
  // About one triangle per cell, cells roughly square.
  const double w = std::max(hi[0] - lo[0], 1e-300);
  const double h = std::max(hi[1] - lo[1], 1e-300);
  const double cells = std::max(1.0, static_cast<double>(count));
  int nu = static_cast<int>(std::ceil(std::sqrt(cells * w / h)));
  int nv = static_cast<int>(std::ceil(cells / nu));
  nu = std::max(1, std::min(nu, 4096));
  nv = std::max(1, std::min(nv, 4096));
  this->GridMin[0] = lo[0];
  this->GridMin[1] = lo[1];
  this->GridMax[0] = hi[0];
  this->GridMax[1] = hi[1];
  this->GridSize[0] = nu;
  this->GridSize[1] = nv;
  this->CellSize[0] = w / nu;
  this->CellSize[1] = h / nv;
  // Two passes (count, then fill) give a compact CSR layout.
  this->CellStarts.assign(static_cast<std::size_t>(nu) * nv + 1, 0);
  for (int pass = 0; pass < 2; ++pass)
  {
    std::vector<int> fill;
    if (pass == 1)
    {
      for (std::size_t c = 1; c < this->CellStarts.size(); ++c)
      {
        this->CellStarts[c] += this->CellStarts[c - 1];
      }
      this->CellItems.resize(static_cast<std::size_t>(this->CellStarts.back()));
      fill.assign(this->CellStarts.begin(), this->CellStarts.end() - 1);
    }
    for (int t = 0; t < count; ++t)
    {
      const double* b = this->Boxes[static_cast<std::size_t>(t)].data();
      int range[4];
      this->CellRange(b[0], b[1], b[2], b[3], range);
      this->FirstCells[static_cast<std::size_t>(t)] = { range[0], range[1] };
      for (int j = range[1]; j <= range[3]; ++j)
      {
        for (int i = range[0]; i <= range[2]; ++i)
        {
          const std::size_t cell = static_cast<std::size_t>(j) * nu + i;
          if (pass == 0)
          {
            ++this->CellStarts[cell + 1];
          }
          else
          {
            this->CellItems[static_cast<std::size_t>(fill[cell]++)] = t;
          }
        }
      }
    }
  }
}

void ShooterRadiance::CellRange(double u0, double v0, double u1, double v1, int range[4]) const
{
  // Widened by the tolerance so that points on a cell border find both sides.
  const double lo[2] = { u0 - this->Tolerance, v0 - this->Tolerance };
  const double hi[2] = { u1 + this->Tolerance, v1 + this->Tolerance };
  for (int a = 0; a < 2; ++a)
  {
    const double first = std::floor((lo[a] - this->GridMin[a]) / this->CellSize[a]);
    const double last = std::floor((hi[a] - this->GridMin[a]) / this->CellSize[a]);
    range[a] = static_cast<int>(std::max(0.0, std::min(first, this->GridSize[a] - 1.0)));
    range[a + 2] = static_cast<int>(std::max(0.0, std::min(last, this->GridSize[a] - 1.0)));
    if (last < 0.0 || first > this->GridSize[a] - 1.0)
    {
      range[a + 2] = range[a] - 1; // empty
    }
  }
}

int ShooterRadiance::FindTriangle(const Vec3& p) const
{
  if (this->Triangles.empty())
  {
    return -1;
  }
  const double u = Dot(p, this->AxisU);
  const double v = Dot(p, this->AxisV);
  int range[4];
  this->CellRange(u, v, u, v, range);
  int best = -1;
  double bestMargin = -1e300;
  for (int j = range[1]; j <= range[3]; ++j)
  {
    for (int i = range[0]; i <= range[2]; ++i)
    {
      const std::size_t cell = static_cast<std::size_t>(j) * this->GridSize[0] + i;
      for (int k = this->CellStarts[cell]; k < this->CellStarts[cell + 1]; ++k)
      {
        const int t = this->CellItems[static_cast<std::size_t>(k)];
        // Signed distance of (u, v) inside each edge line; the smallest is the margin.
        double q[3][2];
        for (int c = 0; c < 3; ++c)
        {
          const Vec3& pc = this->Points[this->Triangles[t][c]];
          q[c][0] = Dot(pc, this->AxisU);
          q[c][1] = Dot(pc, this->AxisV);
        }
        const double orientation =
          (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
        double margin = 1e300;
        for (int c = 0; c < 3; ++c)
        {
          const double* a = q[c];
          const double* b = q[(c + 1) % 3];
          const double ex = b[0] - a[0];
          const double ey = b[1] - a[1];
          const double len = std::sqrt(ex * ex + ey * ey);
          const double side = (ex * (v - a[1]) - ey * (u - a[0])) / len;
          margin = std::min(margin, orientation > 0.0 ? side : -side);
        }
        if (margin > bestMargin)
        {
          bestMargin = margin;
          best = t;
        }
      }
    }
  }
  return bestMargin >= -this->Tolerance ? best : -1;
}

RGB ShooterRadiance::Evaluate(const Vec3& p) const
{
  if (this->Triangles.empty())
  {
    return this->Constant;
  }
  const int t = this->FindTriangle(p);
  return t < 0 ? RGB() : this->Functions[t].Evaluate(p);
}

RGB ShooterRadiance::Integrate(double shooterArea) const
{
  if (this->Triangles.empty())
  {
    return this->Constant * shooterArea;
  }
  RGB sum;
  for (std::size_t t = 0; t < this->Triangles.size(); ++t)
  {
    const auto& tri = this->Triangles[t];
    sum += (this->Values[tri[0]] + this->Values[tri[1]] + this->Values[tri[2]]) *
      (this->Areas[t] / 3.0);
  }
  return sum;
}

void ShooterRadiance::FindTriangles(const Vec3* vertices, int count, std::vector<int>& ids) const
{
  ids.clear();
  if (this->Triangles.empty() || count <= 0)
  {
    return;
  }
  double lo[2] = { 1e300, 1e300 };
  double hi[2] = { -1e300, -1e300 };
  for (int k = 0; k < count; ++k)
  {
    const double u = Dot(vertices[k], this->AxisU);
    const double v = Dot(vertices[k], this->AxisV);
    lo[0] = std::min(lo[0], u);
    lo[1] = std::min(lo[1], v);
    hi[0] = std::max(hi[0], u);
    hi[1] = std::max(hi[1], v);
  }
  if (lo[0] <= this->GridMin[0] && lo[1] <= this->GridMin[1] && hi[0] >= this->GridMax[0] &&
    hi[1] >= this->GridMax[1])
  {
    // The polygon's box holds the whole mesh (an unoccluded shooter, the
    // common case): every triangle, without visiting the grid.
    ids.resize(this->Triangles.size());
    for (std::size_t t = 0; t < ids.size(); ++t)
    {
      ids[t] = static_cast<int>(t);
    }
    return;
  }
  int range[4];
  this->CellRange(lo[0], lo[1], hi[0], hi[1], range);
  for (int j = range[1]; j <= range[3]; ++j)
  {
    for (int i = range[0]; i <= range[2]; ++i)
    {
      const std::size_t cell = static_cast<std::size_t>(j) * this->GridSize[0] + i;
      for (int k = this->CellStarts[cell]; k < this->CellStarts[cell + 1]; ++k)
      {
        const int t = this->CellItems[static_cast<std::size_t>(k)];
        // A triangle listed in several cells of the range is reported from
        // the first of them only.
        const std::array<int, 2>& first = this->FirstCells[static_cast<std::size_t>(t)];
        if (i != std::max(range[0], first[0]) || j != std::max(range[1], first[1]))
        {
          continue;
        }
        // Exact rectangle test, so that a large polygon's cell range does not
        // return triangles far from it.
        const double* b = this->Boxes[static_cast<std::size_t>(t)].data();
        if (b[0] <= hi[0] + this->Tolerance && b[2] >= lo[0] - this->Tolerance &&
          b[1] <= hi[1] + this->Tolerance && b[3] >= lo[1] - this->Tolerance)
        {
          ids.push_back(t);
        }
      }
    }
  }
}

} // namespace penumbra
