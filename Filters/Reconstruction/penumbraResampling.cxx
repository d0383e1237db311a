// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraResampling.cxx
 * @brief Resampling of the reconstruction for display: every input triangle
 * subdivided (regularly, or a lattice inside and strips along its edges when
 * its edges get different counts), uniformly, to a target edge length, or as
 * finely as a display tolerance needs (the levels: penumbraDisplayLevels.cxx);
 * shared edges split identically on both sides, the error estimate spread to
 * the output points, and the input's constrained edges traced as polylines of
 * output points.
 */
#include "penumbraResampler.h"
#include "penumbraReconstructionInternals.h"
#include "penumbraDisplayDecimation.h"
#include "penumbraErrorModel.h"
#include "penumbraSampleMeshTopology.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace penumbra
{

using detail::CheckErrorOptions;
using detail::Next;
using detail::Prev;

namespace
{

/// The indirect part of the compact tolerance lets a point move by at most
/// this fraction of its own value: in furnished_room(1000) the ceiling inside
/// the lights' outlines and the gaps behind the bookcases, lit by 0.2-0.4% of
/// the surface around them, otherwise showed 10-25% more light.
constexpr double CompactLocalFraction = 0.25;

void CheckResampleOptions(const ResampleOptions& options, int channels)
{
  if (options.SubdivisionLevel < 1 || options.SubdivisionLevel > 1024)
  {
    throw InputError("Reconstruction: SubdivisionLevel is " +
      std::to_string(options.SubdivisionLevel) + ", must be in [1, 1024]");
  }
  if (!(options.TargetEdgeLength >= 0.0) || !std::isfinite(options.TargetEdgeLength))
  {
    throw InputError("Reconstruction: TargetEdgeLength must be finite and >= 0");
  }
  if (!(options.DisplayTolerance >= 0.0 && options.DisplayTolerance <= 1.0))
  {
    throw InputError("Reconstruction: DisplayTolerance is " +
      std::to_string(options.DisplayTolerance) + ", must be in [0, 1]");
  }
  if (options.MaximumSubdivisionLevel < 1 || options.MaximumSubdivisionLevel > 1024)
  {
    throw InputError("Reconstruction: MaximumSubdivisionLevel is " +
      std::to_string(options.MaximumSubdivisionLevel) + ", must be in [1, 1024]");
  }
  if (!(options.CompactTolerance >= 0.0 && options.CompactTolerance <= 1.0))
  {
    throw InputError("Reconstruction: CompactTolerance is " +
      std::to_string(options.CompactTolerance) + ", must be in [0, 1]");
  }
  if (!(options.CompactIndirectTolerance >= 0.0 && options.CompactIndirectTolerance <= 1.0))
  {
    throw InputError("Reconstruction: CompactIndirectTolerance is " +
      std::to_string(options.CompactIndirectTolerance) + ", must be in [0, 1]");
  }
  if (!options.IndirectRadiance.empty() &&
    options.IndirectRadiance.size() != static_cast<std::size_t>(channels))
  {
    throw InputError("Reconstruction: IndirectRadiance has " +
      std::to_string(options.IndirectRadiance.size()) + " entries for " +
      std::to_string(channels) + " channels");
  }
  for (const double value : options.IndirectRadiance)
  {
    if (!(value >= 0.0) || !std::isfinite(value))
    {
      throw InputError("Reconstruction: IndirectRadiance must be finite and >= 0");
    }
  }
}

/// The compact display's tolerance per channel (value units): the larger of
/// CompactTolerance times the receiver's area-mean |value| and
/// CompactIndirectTolerance times IndirectRadiance; empty when both are 0
/// (the dense display).
std::vector<double> CompactTolerances(const ResampleOptions& options, const SampleMesh& mesh)
{
  const int nc = mesh.NumberOfChannels;
  std::vector<double> mean(static_cast<std::size_t>(nc), 0.0);
  double area = 0.0;
  for (int t = 0; t < mesh.GetNumberOfTriangles(); ++t)
  {
    const int* tri = mesh.Triangles.data() + 3 * t;
    const double* a = mesh.Points.data() + 2 * tri[0];
    const double* b = mesh.Points.data() + 2 * tri[1];
    const double* d = mesh.Points.data() + 2 * tri[2];
    const double twice = std::abs((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
    area += twice;
    for (int c = 0; c < nc; ++c)
    {
      for (int k = 0; k < 3; ++k)
      {
        mean[static_cast<std::size_t>(c)] +=
          twice * std::abs(mesh.Values[static_cast<std::size_t>(tri[k]) * nc + c]) / 3.0;
      }
    }
  }
  std::vector<double> tolerances(static_cast<std::size_t>(nc), 0.0);
  bool any = false;
  for (int c = 0; c < nc; ++c)
  {
    double t = area > 0.0 ? options.CompactTolerance * mean[static_cast<std::size_t>(c)] / area : 0.0;
    if (!options.IndirectRadiance.empty())
    {
      t = std::max(t,
        options.CompactIndirectTolerance * options.IndirectRadiance[static_cast<std::size_t>(c)]);
    }
    // A channel that is zero throughout (a black one) stays exact.
    tolerances[static_cast<std::size_t>(c)] = std::max(t, 1e-300);
    any = any || t > 0.0;
  }
  return any ? tolerances : std::vector<double>();
}

/// A group per (order, label) pair of the constrained edges (the output's
/// lines), so that only lines of one kind are joined.
std::vector<int> LineGroups(const SampleMesh& mesh)
{
  std::vector<std::pair<int, int>> kinds;
  kinds.reserve(mesh.EdgeOrders.size());
  for (std::size_t e = 0; e < mesh.EdgeOrders.size(); ++e)
  {
    kinds.emplace_back(mesh.EdgeOrders[e], mesh.EdgeLabels.empty() ? 0 : mesh.EdgeLabels[e]);
  }
  std::vector<std::pair<int, int>> sorted = kinds;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  std::vector<int> groups;
  groups.reserve(kinds.size());
  for (const auto& kind : kinds)
  {
    groups.push_back(
      static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), kind) - sorted.begin()));
  }
  return groups;
}

} // namespace

//------------------------------------------------------------------------------
void Reconstruction::Internals::Resampler::Run()
{
  const Internals& in = this->In;
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int nc = this->NC;
  this->Nets.resize(nc);
  this->Value.resize(nc);
  this->Error.resize(nc);
  this->CountSegments();
  for (bool again = true; again;)
  {
    this->Output = ResampledMesh();
    this->Output.NumberOfChannels = nc;
    this->PointId.assign(in.Mesh.GetNumberOfPoints(), -1);
    this->EdgeFirst.assign(in.EdgeKinds.size(), -1);
    this->Reserve();
    for (int t = 0; t < nt; ++t)
    {
      this->SubdivideTriangle(t);
    }
    again = !this->InverseTolerance.empty() && this->RaiseFailingLevels();
    if (again)
    {
      this->CountEdgesFromLevels();
    }
  }
  this->TraceLines();
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::Resampler::CountSegments()
{
  const Internals& in = this->In;
  const int ne = static_cast<int>(in.EdgeKinds.size());
  this->Segments.assign(ne, this->Options.SubdivisionLevel);
  this->Needed.clear();
  this->InverseTolerance.clear();
  this->Green = false;
  if (this->Options.TargetEdgeLength <= 0.0 && this->Options.DisplayTolerance > 0.0)
  {
    this->ChooseAdaptiveLevels();
  }
  else if (this->Options.TargetEdgeLength <= 0.0 && this->Options.SubdivisionLevel == 2 &&
    this->Cubic && !this->CompactTolerances.empty())
  {
    this->ChooseCompactEdges();
  }
  else if (this->Options.TargetEdgeLength > 0.0)
  {
    for (int e = 0; e < ne; ++e)
    {
      const double* a = in.P(in.EdgePoints[2 * e]);
      const double* b = in.P(in.EdgePoints[2 * e + 1]);
      const double n =
        std::ceil(std::hypot(b[0] - a[0], b[1] - a[1]) / this->Options.TargetEdgeLength);
      this->Segments[e] = static_cast<int>(
        std::min(static_cast<double>(this->Options.MaximumSubdivisionLevel), std::max(1.0, n)));
    }
  }
}

//------------------------------------------------------------------------------
// The lattice level of triangle t whose edges get n[0..2] segments: the
// common count when they agree (regular subdivision); otherwise at least 3,
// so that the inner lattice has a point, and the level the triangle itself
// needs with DisplayTolerance (its strips take the finer edges), else the
// finest edge.
int Reconstruction::Internals::Resampler::InnerLevel(int t, const int n[3], bool& regular) const
{
  regular = n[0] == n[1] && n[1] == n[2];
  if (regular)
  {
    return n[0];
  }
  if (this->Green)
  {
    return 2; // SubdivideGreen
  }
  const int finest = std::max(n[0], std::max(n[1], n[2]));
  return std::max(3, this->Needed.empty() ? finest : this->Needed[t]);
}

//------------------------------------------------------------------------------
// Reserve the output (its size is known in advance).
void Reconstruction::Internals::Resampler::Reserve()
{
  const Internals& in = this->In;
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int ne = static_cast<int>(in.EdgeKinds.size());
  const int nc = this->NC;
  const std::vector<int>& segments = this->Segments;
  ResampledMesh& output = this->Output;
  std::size_t points = 0, triangles = 0;
  for (int e = 0; e < ne; ++e)
  {
    points += static_cast<std::size_t>(segments[e] - 1);
  }
  for (int t = 0; t < nt; ++t)
  {
    const int n[3] = { segments[in.TriangleEdge[3 * t]], segments[in.TriangleEdge[3 * t + 1]],
      segments[in.TriangleEdge[3 * t + 2]] };
    bool regular = false;
    const std::size_t s = static_cast<std::size_t>(this->InnerLevel(t, n, regular));
    if (regular)
    {
      points += (s - 1) * (s - 2) / 2 + 3;
      triangles += s * s;
    }
    else if (this->Green)
    {
      triangles += static_cast<std::size_t>(n[0] + n[1] + n[2] - 2);
    }
    else
    {
      const std::size_t m = s - 3;
      points += (m + 1) * (m + 2) / 2 + 3;
      triangles += m * m + static_cast<std::size_t>(n[0] + n[1] + n[2]) + 3 * m;
    }
  }
  output.Points.reserve(2 * points);
  output.Values.reserve(nc * points);
  output.SourcePoint.reserve(points);
  if (this->Estimate)
  {
    output.ErrorEstimate.reserve(nc * points);
  }
  output.Triangles.reserve(3 * triangles);
  output.SourceTriangle.reserve(triangles);
}

//------------------------------------------------------------------------------
// A new output point at barycentrics b of triangle t: input point `source`
// with its sample value, or (source < 0) the interpolant there.
int Reconstruction::Internals::Resampler::NewPoint(int t, const double b[3], int source)
{
  const Internals& in = this->In;
  const int nc = this->NC;
  ResampledMesh& output = this->Output;
  const int* tri = in.T(t);
  const int id = output.GetNumberOfPoints();
  if (source >= 0)
  {
    output.Points.push_back(in.P(source)[0]);
    output.Points.push_back(in.P(source)[1]);
    for (int c = 0; c < nc; ++c)
    {
      output.Values.push_back(in.Value(source, c));
    }
  }
  else
  {
    double u = 0.0, v = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      u += b[i] * in.P(tri[i])[0];
      v += b[i] * in.P(tri[i])[1];
    }
    output.Points.push_back(u);
    output.Points.push_back(v);
    in.EvaluateWithNets(
      t, this->Cubic ? this->Nets.data() : nullptr, b, this->Value.data(), nullptr);
    output.Values.insert(output.Values.end(), this->Value.begin(), this->Value.end());
  }
  output.SourcePoint.push_back(source);
  if (this->Estimate)
  {
    output.ErrorEstimate.insert(output.ErrorEstimate.end(), nc, 0.0);
  }
  return id;
}

//------------------------------------------------------------------------------
// Output id of the i-th of n points along edge k of triangle t, counted
// from corner k+1 (0 and n are the corners).
int Reconstruction::Internals::Resampler::EdgePoint(int t, int k, int i, int n)
{
  const Internals& in = this->In;
  const int* tri = in.T(t);
  double b[3];
  b[k] = 0.0;
  b[Next(k)] = static_cast<double>(n - i) / n;
  b[Prev(k)] = static_cast<double>(i) / n;
  int id;
  if (i == 0 || i == n)
  {
    const int p = tri[i == 0 ? Next(k) : Prev(k)];
    if (this->PointId[p] < 0)
    {
      this->PointId[p] = this->NewPoint(t, b, p);
    }
    id = this->PointId[p];
  }
  else
  {
    const int e = in.TriangleEdge[3 * t + k];
    const bool forward = in.EdgePoints[2 * e] == tri[Next(k)];
    if (this->EdgeFirst[e] < 0)
    {
      // Create all the edge's points, from its smaller end point.
      this->EdgeFirst[e] = this->Output.GetNumberOfPoints();
      for (int j = 1; j < n; ++j)
      {
        const double s = static_cast<double>(forward ? j : n - j) / n;
        double bj[3];
        bj[k] = 0.0;
        bj[Next(k)] = 1.0 - s;
        bj[Prev(k)] = s;
        this->NewPoint(t, bj, -1);
      }
    }
    id = this->EdgeFirst[e] + (forward ? i : n - i) - 1;
  }
  if (this->Estimate)
  {
    this->Contributions.push_back({ id, { b[0], b[1], b[2] } });
  }
  return id;
}

//------------------------------------------------------------------------------
// Lattice point (a, b) of the current triangle: barycentrics
// ((s-a-b)/s, a/s, b/s), created on first use.
int Reconstruction::Internals::Resampler::LatticePoint(int a, int b)
{
  const int s = this->S;
  int& id = this->Lattice[this->LatticeIndex(a, b)];
  if (id < 0)
  {
    const double bary[3] = { static_cast<double>(s - a - b) / s, static_cast<double>(a) / s,
      static_cast<double>(b) / s };
    id = this->NewPoint(this->T, bary, -1);
    if (this->Estimate)
    {
      this->Contributions.push_back({ id, { bary[0], bary[1], bary[2] } });
    }
  }
  return id;
}

void Reconstruction::Internals::Resampler::AddTriangle(int p0, int p1, int p2)
{
  this->Output.Triangles.push_back(p0);
  this->Output.Triangles.push_back(p1);
  this->Output.Triangles.push_back(p2);
  this->Output.SourceTriangle.push_back(this->T);
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::Resampler::SubdivideTriangle(int t)
{
  const Internals& in = this->In;
  if (this->Cubic)
  {
    for (int c = 0; c < this->NC; ++c)
    {
      in.ComputeNet(t, c, this->Nets[c]);
    }
  }
  this->Contributions.clear();
  int n[3];
  for (int k = 0; k < 3; ++k)
  {
    n[k] = this->Segments[in.TriangleEdge[3 * t + k]];
  }
  bool regular = false;
  const int s = this->InnerLevel(t, n, regular);
  this->T = t;
  this->S = s;
  this->Lattice.assign(static_cast<std::size_t>((s + 1) * (s + 2) / 2), -1);
  const int firstTriangle = this->Output.GetNumberOfTriangles();
  if (regular)
  {
    this->SubdivideRegular();
  }
  else if (this->Green)
  {
    this->SubdivideGreen(n);
  }
  else
  {
    this->SubdivideIrregular(n);
  }
  if (this->Green)
  {
    this->KeepLeftOut(firstTriangle);
  }
  if (this->Estimate)
  {
    this->SpreadErrors();
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::Resampler::SubdivideRegular()
{
  const int t = this->T;
  const int s = this->S;
  // Boundary lattice points come from the shared edges and corners.
  // Edge 0 (corner 1 -> 2): a + b = s, b counts from corner 1.
  // Edge 1 (corner 2 -> 0): a = 0, counted from corner 2 (b = s - i).
  // Edge 2 (corner 0 -> 1): b = 0, counted from corner 0 (a = i).
  for (int i = 0; i <= s; ++i)
  {
    this->Lattice[this->LatticeIndex(s - i, i)] = this->EdgePoint(t, 0, i, s);
    this->Lattice[this->LatticeIndex(0, s - i)] = this->EdgePoint(t, 1, i, s);
    this->Lattice[this->LatticeIndex(i, 0)] = this->EdgePoint(t, 2, i, s);
  }
  for (int a = 0; a < s; ++a)
  {
    for (int b = 0; a + b < s; ++b)
    {
      this->AddTriangle(
        this->LatticePoint(a, b), this->LatticePoint(a + 1, b), this->LatticePoint(a, b + 1));
      if (a + b + 1 < s)
      {
        this->AddTriangle(this->LatticePoint(a + 1, b), this->LatticePoint(a + 1, b + 1),
          this->LatticePoint(a, b + 1));
      }
    }
  }
}

//------------------------------------------------------------------------------
// A triangle of the compact base with one or two edges halved (n[k] 1 or
// 2): two triangles from the corner opposite a halved edge, or a corner
// triangle between two halved edges and the rest cut along its shorter
// diagonal. Corners and midpoints are those of the regular level 2, so the
// pieces match their neighbours.
void Reconstruction::Internals::Resampler::SubdivideGreen(const int n[3])
{
  const int t = this->T;
  int corner[3], middle[3];
  for (int j = 0; j < 3; ++j)
  {
    corner[j] = this->EdgePoint(t, Prev(j), 0, n[Prev(j)]); // edge Prev(j) starts at corner j
  }
  for (int k = 0; k < 3; ++k)
  {
    middle[k] = n[k] == 2 ? this->EdgePoint(t, k, 1, 2) : -1;
  }
  const int halved = (n[0] == 2 ? 1 : 0) + (n[1] == 2 ? 1 : 0) + (n[2] == 2 ? 1 : 0);
  if (halved == 1)
  {
    const int k = n[0] == 2 ? 0 : (n[1] == 2 ? 1 : 2);
    this->AddTriangle(corner[k], corner[Next(k)], middle[k]);
    this->AddTriangle(corner[k], middle[k], corner[Prev(k)]);
    return;
  }
  // Two halved edges, both at corner k (edge k stays whole).
  const int k = n[0] == 1 ? 0 : (n[1] == 1 ? 1 : 2);
  const int a = middle[Prev(k)]; // on edge (k, k+1)
  const int b = middle[Next(k)]; // on edge (k+2, k)
  this->AddTriangle(corner[k], a, b);
  const double* pa = &this->Output.Points[2 * static_cast<std::size_t>(a)];
  const double* pb = &this->Output.Points[2 * static_cast<std::size_t>(b)];
  const double* pn = &this->Output.Points[2 * static_cast<std::size_t>(corner[Next(k)])];
  const double* pp = &this->Output.Points[2 * static_cast<std::size_t>(corner[Prev(k)])];
  const double first = std::hypot(pp[0] - pa[0], pp[1] - pa[1]);
  const double second = std::hypot(pn[0] - pb[0], pn[1] - pb[1]);
  if (first <= second)
  {
    this->AddTriangle(a, corner[Next(k)], corner[Prev(k)]);
    this->AddTriangle(a, corner[Prev(k)], b);
  }
  else
  {
    this->AddTriangle(a, corner[Next(k)], b);
    this->AddTriangle(corner[Next(k)], corner[Prev(k)], b);
  }
}

//------------------------------------------------------------------------------
// The midpoints of the current triangle's edges left whole (each once),
// with the interpolant's value there and the output triangle holding them.
void Reconstruction::Internals::Resampler::KeepLeftOut(int firstTriangle)
{
  const Internals& in = this->In;
  const int t = this->T;
  const int* tri = in.T(t);
  const int nc = this->NC;
  const ResampledMesh& out = this->Output;
  for (int k = 0; k < 3; ++k)
  {
    const int e = in.TriangleEdge[3 * t + k];
    if (this->Segments[e] != 1 || this->LeftOutDone[e])
    {
      continue;
    }
    this->LeftOutDone[e] = 1;
    const int p = this->PointId[tri[Next(k)]], q = this->PointId[tri[Prev(k)]];
    int holder = -1;
    for (int o = firstTriangle; o < out.GetNumberOfTriangles() && holder < 0; ++o)
    {
      for (int i = 0; i < 3; ++i)
      {
        const int x = out.Triangles[3 * o + i], y = out.Triangles[3 * o + (i + 1) % 3];
        if ((x == p && y == q) || (x == q && y == p))
        {
          holder = o;
        }
      }
    }
    if (holder < 0)
    {
      continue;
    }
    this->LeftOutPoints.push_back(0.5 * (out.Points[2 * p] + out.Points[2 * q]));
    this->LeftOutPoints.push_back(0.5 * (out.Points[2 * p + 1] + out.Points[2 * q + 1]));
    this->LeftOutValues.insert(this->LeftOutValues.end(),
      this->MidValues.begin() + static_cast<std::ptrdiff_t>(e) * nc,
      this->MidValues.begin() + static_cast<std::ptrdiff_t>(e + 1) * nc);
    this->LeftOutTriangles.push_back(holder);
  }
}

//------------------------------------------------------------------------------
// The lattice points with all indices >= 1 (an inner triangle of level
// s - 3), and a strip along each edge zipping the edge's points to the inner
// triangle's side.
void Reconstruction::Internals::Resampler::SubdivideIrregular(const int n[3])
{
  const int s = this->S;
  for (int a = 1; a + 1 < s; ++a)
  {
    for (int b = 1; a + b + 1 <= s; ++b)
    {
      if (a + b <= s - 2)
      {
        this->AddTriangle(
          this->LatticePoint(a, b), this->LatticePoint(a + 1, b), this->LatticePoint(a, b + 1));
      }
      if (a + b <= s - 3)
      {
        this->AddTriangle(this->LatticePoint(a + 1, b), this->LatticePoint(a + 1, b + 1),
          this->LatticePoint(a, b + 1));
      }
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    this->Zip(k, n[k]);
  }
}

//------------------------------------------------------------------------------
// The strip between edge k (nk segments) and the inner side parallel to it.
void Reconstruction::Internals::Resampler::Zip(int k, int nk)
{
  const int t = this->T;
  const int s = this->S;
  const int m = s - 3; // segments of each inner side
  // Inner side parallel to edge k, from near corner k+1 to near corner k+2:
  // lattice index of corner k equal to 1.
  auto inner = [&](int q) {
    int idx[3];
    idx[k] = 1;
    idx[Next(k)] = s - 2 - q;
    idx[Prev(k)] = 1 + q;
    return this->LatticePoint(idx[1], idx[2]);
  };
  int p = 0;
  int q = 0;
  while (p < nk || q < m)
  {
    // Advance on the side whose next point comes first along the edge.
    const double nextOuter = static_cast<double>(p + 1) / nk;
    const double nextInner = (q + 1.5) / (s - 1);
    if (q == m || (p < nk && nextOuter <= nextInner))
    {
      this->AddTriangle(this->EdgePoint(t, k, p, nk), this->EdgePoint(t, k, p + 1, nk), inner(q));
      ++p;
    }
    else
    {
      this->AddTriangle(this->EdgePoint(t, k, p, nk), inner(q + 1), inner(q));
      ++q;
    }
  }
}

//------------------------------------------------------------------------------
// Each point of the current triangle gets the largest estimate of the
// triangles holding it.
void Reconstruction::Internals::Resampler::SpreadErrors()
{
  const int t = this->T;
  const int nc = this->NC;
  const std::size_t at = static_cast<std::size_t>(t) * nc;
  const double* probe = this->ProbeBounds.empty() ? nullptr : this->ProbeBounds.data() + at;
  const double* whole = this->TriangleBounds.empty() ? nullptr : this->TriangleBounds.data() + at;
  for (const Contribution& c : this->Contributions)
  {
    double* e = this->Output.ErrorEstimate.data() + static_cast<std::size_t>(c.Id) * nc;
    if (whole)
    {
      for (int j = 0; j < nc; ++j)
      {
        e[j] = std::max(e[j], whole[j]);
      }
      continue;
    }
    const double* interpolated = this->Output.Values.data() + static_cast<std::size_t>(c.Id) * nc;
    this->In.ModelError(t, c.B, interpolated, this->Error.data());
    for (int j = 0; j < nc; ++j)
    {
      const double scale = this->ModelScale.empty() ? 1.0 : this->ModelScale[at + j];
      e[j] = std::max(e[j], this->ErrorOptions.ModelSafetyFactor * scale * this->Error[j]);
      if (probe)
      {
        e[j] = std::max(e[j], probe[j]);
      }
    }
  }
}

//------------------------------------------------------------------------------
// The constrained edges of the input as polylines of output points.
void Reconstruction::Internals::Resampler::TraceLines()
{
  const Internals& in = this->In;
  ResampledMesh& output = this->Output;
  const int ne = static_cast<int>(in.EdgeKinds.size());
  const SampleMesh& m = in.Mesh;
  const std::uint64_t np = static_cast<std::uint64_t>(m.GetNumberOfPoints());
  output.LineOffsets.assign(1, 0);
  for (std::size_t i = 0; i < m.EdgeOrders.size(); ++i)
  {
    const int a = m.ConstrainedEdges[2 * i];
    const int b = m.ConstrainedEdges[2 * i + 1];
    const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) * np +
      static_cast<std::uint64_t>(std::max(a, b));
    // Unique edges are numbered in increasing key order.
    int lo = 0, hi = ne;
    while (lo < hi)
    {
      const int mid = (lo + hi) / 2;
      const std::uint64_t k = static_cast<std::uint64_t>(in.EdgePoints[2 * mid]) * np +
        static_cast<std::uint64_t>(in.EdgePoints[2 * mid + 1]);
      if (k < key)
      {
        lo = mid + 1;
      }
      else
      {
        hi = mid;
      }
    }
    if (a != b && lo < ne && in.EdgePoints[2 * lo] == std::min(a, b) &&
      in.EdgePoints[2 * lo + 1] == std::max(a, b))
    {
      const int n = this->Segments[lo];
      output.LinePoints.push_back(this->PointId[a]);
      for (int j = 1; j < n; ++j)
      {
        output.LinePoints.push_back(this->EdgeFirst[lo] + (a < b ? j : n - j) - 1);
      }
      output.LinePoints.push_back(this->PointId[b]);
    }
    output.LineOffsets.push_back(static_cast<int>(output.LinePoints.size()));
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Resample(const ResampleOptions& options, ResampledMesh& output,
  const ErrorProbes* probes, const ErrorEstimateOptions& errorOptions) const
{
  CheckResampleOptions(options, this->Internal->NC);
  Internals::Resampler resampler(*this->Internal, options, errorOptions, output);
  if (options.ComputeErrorEstimate)
  {
    CheckErrorOptions(errorOptions);
    if (errorOptions.PerTriangle)
    {
      this->ComputeTriangleErrorBounds(probes, errorOptions, resampler.TriangleBounds);
    }
    else
    {
      this->Internal->CalibrateWithProbes(
        probes, errorOptions, resampler.ProbeBounds, resampler.ModelScale);
    }
  }
  resampler.CompactTolerances = CompactTolerances(options, this->Internal->Mesh);
  resampler.Run();
  if (resampler.CompactTolerances.empty())
  {
    return; // the dense display
  }
  DecimationOptions compact;
  compact.AbsoluteTolerance = resampler.CompactTolerances;
  compact.TestEdgeMidpoints = true;
  compact.LocalFraction = CompactLocalFraction;
  compact.LineGroups = LineGroups(this->Internal->Mesh);
  compact.TestPoints = std::move(resampler.LeftOutPoints);
  compact.TestValues = std::move(resampler.LeftOutValues);
  compact.TestTriangles = std::move(resampler.LeftOutTriangles);
  DecimateDisplay(output, compact);
}

} // namespace penumbra
