// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReconstruction.cxx
 * @brief The Reconstruction class: validation of its input, the steps of Build,
 * and the public queries (the steps live in the files named in
 * penumbraReconstructionInternals.h).
 */
#include "penumbraReconstructionInternals.h"
#include "penumbraPointLocation.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace penumbra
{

using detail::CheckTriangle;
using detail::InsideTolerance;

//------------------------------------------------------------------------------
void Reconstruction::Internals::Validate() const
{
  const SampleMesh& m = this->Mesh;
  const ReconstructionOptions& o = this->Options;
  auto fail = [](const std::string& what) { throw InputError("Reconstruction: " + what); };
  if (m.NumberOfChannels < 1)
  {
    fail("NumberOfChannels is " + std::to_string(m.NumberOfChannels) + ", must be >= 1");
  }
  if (o.MinimumFitPoints < 5 || o.MinimumFitPoints > 1000)
  {
    fail("MinimumFitPoints is " + std::to_string(o.MinimumFitPoints) + ", must be in [5, 1000]");
  }
  if (o.Mode != ReconstructionMode::Linear && o.Mode != ReconstructionMode::CloughTocher)
  {
    fail("unknown Mode");
  }
  if (m.Points.size() % 2 != 0)
  {
    fail("Points has " + std::to_string(m.Points.size()) + " entries, not 2 per point");
  }
  const std::size_t np = m.Points.size() / 2;
  if (m.Values.size() != np * static_cast<std::size_t>(m.NumberOfChannels))
  {
    fail("Values has " + std::to_string(m.Values.size()) + " entries, expected " +
      std::to_string(np * m.NumberOfChannels) + " (" + std::to_string(np) + " points x " +
      std::to_string(m.NumberOfChannels) + " channels)");
  }
  if (np > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4))
  {
    fail("too many points");
  }
  for (std::size_t i = 0; i < m.Points.size(); ++i)
  {
    if (!std::isfinite(m.Points[i]))
    {
      fail("point " + std::to_string(i / 2) + " has a non-finite coordinate");
    }
  }
  for (std::size_t i = 0; i < m.Values.size(); ++i)
  {
    if (!std::isfinite(m.Values[i]))
    {
      fail("point " + std::to_string(i / m.NumberOfChannels) + " has a non-finite value");
    }
  }
  if (m.Triangles.size() % 3 != 0)
  {
    fail("Triangles has " + std::to_string(m.Triangles.size()) + " entries, not 3 per triangle");
  }
  if (m.Triangles.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4))
  {
    fail("too many triangles");
  }
  const int nt = m.GetNumberOfTriangles();
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = m.Triangles.data() + 3 * t;
    for (int c = 0; c < 3; ++c)
    {
      if (tri[c] < 0 || static_cast<std::size_t>(tri[c]) >= np)
      {
        fail("triangle " + std::to_string(t) + " has point id " + std::to_string(tri[c]) +
          " out of range [0, " + std::to_string(np) + ")");
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
    {
      fail("triangle " + std::to_string(t) + " repeats a point");
    }
    const double* a = m.Points.data() + 2 * tri[0];
    const double* b = m.Points.data() + 2 * tri[1];
    const double* c = m.Points.data() + 2 * tri[2];
    const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (!(area2 > 0.0))
    {
      fail("triangle " + std::to_string(t) + " is not counter-clockwise or has zero area");
    }
  }
  if (m.ConstrainedEdges.size() % 2 != 0)
  {
    fail("ConstrainedEdges has an odd number of entries");
  }
  if (m.EdgeOrders.size() != m.ConstrainedEdges.size() / 2)
  {
    fail("EdgeOrders has " + std::to_string(m.EdgeOrders.size()) + " entries for " +
      std::to_string(m.ConstrainedEdges.size() / 2) + " constrained edges");
  }
  for (std::size_t e = 0; e < m.EdgeOrders.size(); ++e)
  {
    const int a = m.ConstrainedEdges[2 * e];
    const int b = m.ConstrainedEdges[2 * e + 1];
    if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= np || static_cast<std::size_t>(b) >= np)
    {
      fail("constrained edge " + std::to_string(e) + " has a point id out of range");
    }
    const int order = m.EdgeOrders[e];
    if (order < -1 || order > 2)
    {
      fail("constrained edge " + std::to_string(e) + " has order " + std::to_string(order) +
        ", must be -1, 0, 1 or 2");
    }
  }
  if (!m.EdgeLabels.empty() && m.EdgeLabels.size() != m.EdgeOrders.size())
  {
    fail("EdgeLabels has " + std::to_string(m.EdgeLabels.size()) + " entries for " +
      std::to_string(m.EdgeOrders.size()) + " constrained edges");
  }
}

//------------------------------------------------------------------------------
void detail::CheckTriangle(int t, int nt)
{
  if (t < 0 || t >= nt)
  {
    throw InputError("Reconstruction: triangle id " + std::to_string(t) + " out of range [0, " +
      std::to_string(nt) + ")");
  }
}

//------------------------------------------------------------------------------
Reconstruction::Reconstruction()
  : Internal(new Internals)
{
}

Reconstruction::~Reconstruction() = default;

Reconstruction::Reconstruction(const Reconstruction& other)
  : Internal(new Internals(*other.Internal))
{
}

Reconstruction& Reconstruction::operator=(const Reconstruction& other)
{
  if (this != &other)
  {
    this->Internal.reset(new Internals(*other.Internal));
  }
  return *this;
}

Reconstruction::Reconstruction(Reconstruction&& other) noexcept
  : Internal(std::move(other.Internal))
{
  other.Internal.reset(new Internals);
}

Reconstruction& Reconstruction::operator=(Reconstruction&& other) noexcept
{
  if (this != &other)
  {
    this->Internal = std::move(other.Internal);
    other.Internal.reset(new Internals);
  }
  return *this;
}

//------------------------------------------------------------------------------
void Reconstruction::Build(const SampleMesh& mesh, const ReconstructionOptions& options)
{
  std::unique_ptr<Internals> in(new Internals);
  in->Mesh = mesh;
  in->Options = options;
  in->Validate();
  in->NC = mesh.NumberOfChannels;
  in->ComputeGeometry();
  in->BuildEdges();
  in->BuildPointIncidences();
  in->BuildSectors();
  in->FitGradients();
  in->EnforceLineContinuity();
  if (options.LimitOvershoot)
  {
    in->LimitOvershoot();
  }
  if (options.EnforceNonNegativity && options.Mode == ReconstructionMode::CloughTocher)
  {
    in->EnforceNonNegativity();
  }
  in->BuildGrid();
  this->Internal = std::move(in);
}

const SampleMesh& Reconstruction::GetMesh() const
{
  return this->Internal->Mesh;
}

const ReconstructionOptions& Reconstruction::GetOptions() const
{
  return this->Internal->Options;
}

const ReconstructionStatistics& Reconstruction::GetStatistics() const
{
  return this->Internal->Statistics;
}

int Reconstruction::GetNumberOfChannels() const
{
  return this->Internal->NC;
}

void Reconstruction::Evaluate(
  int triangle, const double barycentric[3], double* value, double* gradient) const
{
  CheckTriangle(triangle, this->Internal->Mesh.GetNumberOfTriangles());
  this->Internal->Evaluate(triangle, barycentric, value, gradient);
}

bool Reconstruction::EvaluateAt(
  int triangle, double u, double v, double* value, double* gradient) const
{
  CheckTriangle(triangle, this->Internal->Mesh.GetNumberOfTriangles());
  double b[3];
  this->Internal->Barycentric(triangle, u, v, b);
  this->Internal->Evaluate(triangle, b, value, gradient);
  return std::min(b[0], std::min(b[1], b[2])) >= -InsideTolerance;
}

void Reconstruction::GetBarycentric(int triangle, double u, double v, double barycentric[3]) const
{
  CheckTriangle(triangle, this->Internal->Mesh.GetNumberOfTriangles());
  this->Internal->Barycentric(triangle, u, v, barycentric);
}

int Reconstruction::FindTriangle(double u, double v, double barycentric[3]) const
{
  return this->Internal->FindTriangle(u, v, barycentric);
}

void Reconstruction::GetCornerGradient(int triangle, int corner, double* gradient) const
{
  const Internals& in = *this->Internal;
  CheckTriangle(triangle, in.Mesh.GetNumberOfTriangles());
  if (corner < 0 || corner > 2)
  {
    throw InputError("Reconstruction: corner must be 0, 1 or 2");
  }
  const std::size_t s = in.CornerSector[3 * triangle + corner];
  for (int c = 0; c < in.NC; ++c)
  {
    gradient[2 * c] = in.SectorGradient[(s * in.NC + c) * 2];
    gradient[2 * c + 1] = in.SectorGradient[(s * in.NC + c) * 2 + 1];
  }
}

} // namespace penumbra
