// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraReconstruction.h"

#include "penumbraScene.h" // InputError
#include "penumbraUnionFind.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace penumbra
{

namespace
{

// Two constrained edges at a point count as one straight line when the sine
// of the angle between them is below this (about 5.7 degrees): solving for
// both directional derivatives separately would then be ill-conditioned.
constexpr double CollinearSine = 0.1;
// A fit column keeping less than this fraction of its norm after
// orthogonalisation against the previous ones is taken as undetermined by
// the stencil (offsets are scaled to O(1)).
constexpr double FitRankThreshold = 1e-6;
// Below this many repairs of one triangle, gradients are scaled by the exact
// factor; beyond, they are set to zero (guarantees termination).
constexpr int MaximumScalingsPerTriangle = 8;
// The scale factor is shrunk by this relative amount so that the repaired
// net stays non-negative after rounding.
constexpr double ScaleMargin = 1e-9;
// Net values this far below the samples' minimum, relative to the values
// and gradients entering the net, are rounding, not negativity to repair.
constexpr double NetRoundingSlack = 1e-12;
// The cubic error model needs at least this many neighbours (9 unknowns).
constexpr int CubicModelPoints = 12;
// Barycentric tolerance of point location.
constexpr double InsideTolerance = 1e-9;

// Kinds of unique edges.
enum EdgeKind : signed char
{
  SmoothEdge = 0,      // two triangles, C1 across
  ConstrainedEdge = 1, // two triangles, C0 across (order 1, or 0/-1 not cut)
  BoundaryEdge = 2     // one triangle (mesh boundary or order-0 cut), or non-manifold
};

// Rank of an order for "lowest order wins" (-1 lowest).
inline int OrderRank(int order)
{
  return order == -1 ? 0 : order + 1;
}

inline int Next(int i)
{
  return i == 2 ? 0 : i + 1;
}
inline int Prev(int i)
{
  return i == 0 ? 2 : i - 1;
}

// Per-triangle geometry of the Clough-Tocher element.
struct TriangleGeometry
{
  double Sigma[3];    // incentre barycentrics
  double Tau[3];      // edge k (corner k+1 -> k+2): foot of the incentre, parameter from k+1
  double Split[2];    // incentre position
  double GradB[3][2]; // gradients of the barycentric coordinates
  double Area2;       // twice the signed area
  double Diameter;    // longest edge
};

// Control net of one triangle for one channel: 19 distinct control points.
struct Net
{
  double F[3];    // corner values
  double E[3][3]; // E[i][j]: edge point next to corner i on edge i-j
  double A[3];    // inner point next to corner i toward the split point
  double M[3];    // middle point of micro-triangle k (edge opposite corner k)
  double C[3];    // point next to the split point toward corner i
  double Z;       // split point
};

} // namespace

struct Reconstruction::Internals
{
  SampleMesh Mesh;
  ReconstructionOptions Options;
  ReconstructionStatistics Statistics;
  int NC = 0;

  std::vector<TriangleGeometry> Geometry;
  // Unique edges: end points (smaller id first), triangles (3*t + k, edge k
  // of t is opposite corner k), kind.
  std::vector<int> TriangleEdge; // 3 per triangle
  std::vector<int> EdgePoints;   // 2 per edge
  std::vector<int> EdgeSides;    // 2 per edge (3*t + k, or -1)
  std::vector<signed char> EdgeKinds;
  // Constrained (C0) edges per point, CSR.
  std::vector<int> PointEdgeStart;
  std::vector<int> PointEdges;
  // Triangles per point, CSR.
  std::vector<int> PointTriangleStart;
  std::vector<int> PointTriangles;
  // Sectors.
  std::vector<int> CornerSector; // 3 per triangle
  std::vector<int> SectorPoint;
  std::vector<int> SectorCornerStart;
  std::vector<int> SectorCorners;
  std::vector<double> SectorFit;      // 5 * NC per sector: gu, gv, huu, huv, hvv
  std::vector<double> SectorModel;    // 9 * NC per sector: cubic error model
  std::vector<double> SectorGradient; // 2 * NC per sector, as used by the interpolant
  // NC per triangle: rounding slack of the non-negativity repair (empty: no repair).
  std::vector<double> NetSlack;
  // Point location grid.
  double GridOrigin[2] = { 0.0, 0.0 };
  double GridInverseCell[2] = { 0.0, 0.0 };
  int GridDims[2] = { 0, 0 };
  std::vector<int> GridStart;
  std::vector<int> GridTriangles;

  const double* P(int i) const { return this->Mesh.Points.data() + 2 * i; }
  const int* T(int t) const { return this->Mesh.Triangles.data() + 3 * t; }
  double Value(int point, int channel) const
  {
    return this->Mesh.Values[static_cast<std::size_t>(point) * this->NC + channel];
  }

  void Validate() const;
  void ComputeGeometry();
  void BuildEdges();
  void BuildSectors();
  struct FitWorkspace
  {
    int Stamp = 0;
    std::vector<int> PointStamp;
    std::vector<int> TriangleStamp;
    std::vector<int> Points;
    std::vector<int> Triangles;
    // Least squares by modified Gram-Schmidt on the augmented matrix
    // [A | B]: column j of rows `Rows` at Columns[j * Rows].
    std::vector<double> Columns;
    std::vector<double> R; // 9 rows of (9 + NC) entries
    int Rows = 0;
    double Scale = 1.0;
    int Usable = 0; // independent leading columns of A
  };
  void GatherNeighbours(int s, int minPoints, int maxRings, FitWorkspace& w) const;
  void FactorFit(int v, int maxColumns, FitWorkspace& w) const;
  void SolveFit(int columns, FitWorkspace& w, double* out, int stride) const;
  void SolveCollinear(int v, FitWorkspace& w, double* out, int stride) const;
  void FitGradients();
  void EnforceLineContinuity();
  void EnforceNonNegativity();
  void BuildGrid();

  void ComputeNet(int t, int channel, Net& net) const;
  void ComputeZeroGradientNet(int t, int channel, Net& net) const;
  double LineDerivative(int v, int edge, int channel) const;
  void Evaluate(int t, const double bIn[3], double* value, double* gradient) const;
  void EvaluateWithNets(
    int t, const Net* nets, const double bIn[3], double* value, double* gradient) const;
  void ModelError(int t, const double b[3], const double* interpolated, double* error) const;
  void CalibrateWithProbes(const ErrorProbes* probes, const ErrorEstimateOptions& options,
    std::vector<double>& bound, std::vector<double>& modelScale) const;
  void Barycentric(int t, double u, double v, double b[3]) const;
};

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
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeGeometry()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  this->Geometry.resize(nt);
  for (int t = 0; t < nt; ++t)
  {
    TriangleGeometry& g = this->Geometry[t];
    const int* tri = this->T(t);
    const double* p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
    g.Area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    double len[3];
    for (int i = 0; i < 3; ++i)
    {
      // Edge opposite corner i, from corner i+1 to corner i+2.
      const double* a = p[Next(i)];
      const double* b = p[Prev(i)];
      const double eu = b[0] - a[0];
      const double ev = b[1] - a[1];
      len[i] = std::hypot(eu, ev);
      g.GradB[i][0] = -ev / g.Area2;
      g.GradB[i][1] = eu / g.Area2;
    }
    const double perimeter = len[0] + len[1] + len[2];
    g.Diameter = std::max({ len[0], len[1], len[2] });
    g.Split[0] = 0.0;
    g.Split[1] = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      // Incentre: barycentrics proportional to the opposite edge lengths.
      g.Sigma[i] = len[i] / perimeter;
      g.Split[0] += g.Sigma[i] * p[i][0];
      g.Split[1] += g.Sigma[i] * p[i][1];
    }
    for (int k = 0; k < 3; ++k)
    {
      // The incircle touches edge k at distance (semi-perimeter - |edge
      // opposite corner k+1|) from corner k+1: always strictly inside.
      const double fromP = 0.5 * perimeter - len[Next(k)];
      g.Tau[k] = std::min(1.0, std::max(0.0, fromP / len[k]));
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildEdges()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const std::uint64_t np = static_cast<std::uint64_t>(this->Mesh.GetNumberOfPoints());
  struct Entry
  {
    std::uint64_t Key;
    int Side; // 3 * t + k
  };
  std::vector<Entry> entries(3 * static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int k = 0; k < 3; ++k)
    {
      const std::uint64_t a = static_cast<std::uint64_t>(tri[Next(k)]);
      const std::uint64_t b = static_cast<std::uint64_t>(tri[Prev(k)]);
      entries[3 * t + k] = { std::min(a, b) * np + std::max(a, b), 3 * t + k };
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return x.Key < y.Key || (x.Key == y.Key && x.Side < y.Side);
  });

  // Constraint keys with their lowest order.
  const SampleMesh& m = this->Mesh;
  std::vector<std::pair<std::uint64_t, int>> constraints;
  constraints.reserve(m.EdgeOrders.size());
  for (std::size_t e = 0; e < m.EdgeOrders.size(); ++e)
  {
    const std::uint64_t a = static_cast<std::uint64_t>(m.ConstrainedEdges[2 * e]);
    const std::uint64_t b = static_cast<std::uint64_t>(m.ConstrainedEdges[2 * e + 1]);
    if (a == b)
    {
      continue;
    }
    constraints.emplace_back(std::min(a, b) * np + std::max(a, b), m.EdgeOrders[e]);
  }
  std::sort(constraints.begin(), constraints.end(),
    [](const std::pair<std::uint64_t, int>& x, const std::pair<std::uint64_t, int>& y) {
      return x.first < y.first || (x.first == y.first && OrderRank(x.second) < OrderRank(y.second));
    });

  this->TriangleEdge.assign(3 * static_cast<std::size_t>(nt), -1);
  this->EdgePoints.clear();
  this->EdgeSides.clear();
  this->EdgeKinds.clear();
  std::size_t c = 0;
  for (std::size_t i = 0; i < entries.size();)
  {
    std::size_t j = i;
    while (j < entries.size() && entries[j].Key == entries[i].Key)
    {
      ++j;
    }
    const int id = static_cast<int>(this->EdgeKinds.size());
    const int side0 = entries[i].Side;
    const int* tri0 = this->T(side0 / 3);
    const int a = tri0[Next(side0 % 3)];
    const int b = tri0[Prev(side0 % 3)];
    this->EdgePoints.push_back(std::min(a, b));
    this->EdgePoints.push_back(std::max(a, b));
    signed char kind = BoundaryEdge;
    int side1 = -1;
    if (j - i == 2)
    {
      side1 = entries[i + 1].Side;
      const int* tri1 = this->T(side1 / 3);
      // Consistently oriented neighbours traverse the edge in opposite directions.
      if (tri1[Next(side1 % 3)] == b && tri1[Prev(side1 % 3)] == a)
      {
        kind = SmoothEdge;
        while (c < constraints.size() && constraints[c].first < entries[i].Key)
        {
          ++c;
        }
        if (c < constraints.size() && constraints[c].first == entries[i].Key &&
          constraints[c].second != 2)
        {
          kind = ConstrainedEdge;
        }
      }
    }
    this->EdgeSides.push_back(side0);
    this->EdgeSides.push_back(kind == BoundaryEdge ? -1 : side1);
    this->EdgeKinds.push_back(kind);
    for (std::size_t k = i; k < j; ++k)
    {
      this->TriangleEdge[entries[k].Side] = id;
    }
    i = j;
  }

  // Constrained edges per point, and triangles per point.
  const int npi = this->Mesh.GetNumberOfPoints();
  this->PointEdgeStart.assign(npi + 1, 0);
  const int ne = static_cast<int>(this->EdgeKinds.size());
  for (int e = 0; e < ne; ++e)
  {
    if (this->EdgeKinds[e] == ConstrainedEdge)
    {
      ++this->PointEdgeStart[this->EdgePoints[2 * e] + 1];
      ++this->PointEdgeStart[this->EdgePoints[2 * e + 1] + 1];
    }
  }
  for (int i = 0; i < npi; ++i)
  {
    this->PointEdgeStart[i + 1] += this->PointEdgeStart[i];
  }
  this->PointEdges.assign(this->PointEdgeStart[npi], -1);
  {
    std::vector<int> fill(this->PointEdgeStart.begin(), this->PointEdgeStart.end() - 1);
    for (int e = 0; e < ne; ++e)
    {
      if (this->EdgeKinds[e] == ConstrainedEdge)
      {
        this->PointEdges[fill[this->EdgePoints[2 * e]]++] = e;
        this->PointEdges[fill[this->EdgePoints[2 * e + 1]]++] = e;
      }
    }
  }
  this->PointTriangleStart.assign(npi + 1, 0);
  for (int t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      ++this->PointTriangleStart[this->T(t)[k] + 1];
    }
  }
  for (int i = 0; i < npi; ++i)
  {
    this->PointTriangleStart[i + 1] += this->PointTriangleStart[i];
  }
  this->PointTriangles.assign(this->PointTriangleStart[npi], -1);
  {
    std::vector<int> fill(this->PointTriangleStart.begin(), this->PointTriangleStart.end() - 1);
    for (int t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->PointTriangles[fill[this->T(t)[k]]++] = t;
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildSectors()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int ncorners = 3 * nt;
  detail::UnionFind corners(ncorners);
  auto cornerOf = [this](int t, int point) {
    const int* tri = this->T(t);
    return 3 * t + (tri[0] == point ? 0 : (tri[1] == point ? 1 : 2));
  };
  const int ne = static_cast<int>(this->EdgeKinds.size());
  for (int e = 0; e < ne; ++e)
  {
    if (this->EdgeKinds[e] != SmoothEdge)
    {
      continue;
    }
    const int t0 = this->EdgeSides[2 * e] / 3;
    const int t1 = this->EdgeSides[2 * e + 1] / 3;
    for (int end = 0; end < 2; ++end)
    {
      const int point = this->EdgePoints[2 * e + end];
      corners.Union(cornerOf(t0, point), cornerOf(t1, point));
    }
  }
  this->CornerSector.assign(ncorners, -1);
  this->SectorPoint.clear();
  std::vector<int> rootSector(ncorners, -1);
  for (int i = 0; i < ncorners; ++i)
  {
    const int r = corners.Find(i);
    if (rootSector[r] < 0)
    {
      rootSector[r] = static_cast<int>(this->SectorPoint.size());
      this->SectorPoint.push_back(this->T(i / 3)[i % 3]);
    }
    this->CornerSector[i] = rootSector[r];
  }
  const int ns = static_cast<int>(this->SectorPoint.size());
  this->SectorCornerStart.assign(ns + 1, 0);
  for (int i = 0; i < ncorners; ++i)
  {
    ++this->SectorCornerStart[this->CornerSector[i] + 1];
  }
  for (int s = 0; s < ns; ++s)
  {
    this->SectorCornerStart[s + 1] += this->SectorCornerStart[s];
  }
  this->SectorCorners.assign(ncorners, -1);
  std::vector<int> fill(this->SectorCornerStart.begin(), this->SectorCornerStart.end() - 1);
  for (int i = 0; i < ncorners; ++i)
  {
    this->SectorCorners[fill[this->CornerSector[i]]++] = i;
  }
  this->Statistics.Sectors = ns;
}

//------------------------------------------------------------------------------
// Points around sector s on its side of every constraint: the sector's
// triangles, then ring by ring the triangles of the sectors of the points
// reached (never across a constrained edge or a cut), until at least
// `minPoints` points or `maxRings` rings. The sector's own point is excluded.
void Reconstruction::Internals::GatherNeighbours(
  int s, int minPoints, int maxRings, FitWorkspace& w) const
{
  const int stamp = ++w.Stamp;
  w.Points.clear();
  w.Triangles.clear();
  w.PointStamp[this->SectorPoint[s]] = stamp;
  auto addSector = [&](int sector) {
    for (int i = this->SectorCornerStart[sector]; i < this->SectorCornerStart[sector + 1]; ++i)
    {
      const int t = this->SectorCorners[i] / 3;
      if (w.TriangleStamp[t] == stamp)
      {
        continue;
      }
      w.TriangleStamp[t] = stamp;
      w.Triangles.push_back(t);
      const int* tri = this->T(t);
      for (int k = 0; k < 3; ++k)
      {
        if (w.PointStamp[tri[k]] != stamp)
        {
          w.PointStamp[tri[k]] = stamp;
          w.Points.push_back(tri[k]);
        }
      }
    }
  };
  addSector(s);
  std::size_t ringBegin = 0;
  for (int ring = 1; ring < maxRings && static_cast<int>(w.Points.size()) < minPoints; ++ring)
  {
    const std::size_t ringEnd = w.Triangles.size();
    for (std::size_t i = ringBegin; i < ringEnd; ++i)
    {
      const int t = w.Triangles[i];
      for (int k = 0; k < 3; ++k)
      {
        addSector(this->CornerSector[3 * t + k]);
      }
    }
    if (w.Triangles.size() == ringEnd)
    {
      break; // nothing more on this side
    }
    ringBegin = ringEnd;
  }
}

//------------------------------------------------------------------------------
// Weighted least-squares Taylor polynomial at point v through its value,
// fitted to w.Points. The columns are, in order, du, dv (degree 1), du^2/2,
// du dv, dv^2/2 (degree 2), du^3/6, du^2 dv/2, du dv^2/2, dv^3/6 (degree 3),
// offsets scaled by the largest distance for conditioning, rows weighted by
// the inverse distance. Modified Gram-Schmidt on [A | B] (backward stable
// for least squares) factors the first `maxColumns` columns once; since the
// columns are processed in order, the fits of degree 1, 2 and 3 are nested
// back-substitutions of the same factor. A column that keeps less than
// FitRankThreshold of its norm after orthogonalisation ends the usable
// prefix (the stencil cannot determine it).
void Reconstruction::Internals::FactorFit(int v, int maxColumns, FitWorkspace& w) const
{
  const int nc = this->NC;
  const int width = 9 + nc;
  const double* pv = this->P(v);
  double h2 = 0.0;
  for (int q : w.Points)
  {
    const double du = this->P(q)[0] - pv[0];
    const double dv = this->P(q)[1] - pv[1];
    h2 = std::max(h2, du * du + dv * dv);
  }
  const double h = std::sqrt(h2);
  w.Scale = h;
  w.Rows = 0;
  w.Usable = 0;
  if (!(h > 0.0))
  {
    return;
  }
  const int n = static_cast<int>(w.Points.size());
  w.Columns.resize(static_cast<std::size_t>(width) * n);
  w.R.assign(static_cast<std::size_t>(9) * width, 0.0);
  int rows = 0;
  for (int q : w.Points)
  {
    const double du = (this->P(q)[0] - pv[0]) / h;
    const double dv = (this->P(q)[1] - pv[1]) / h;
    const double d = std::sqrt(du * du + dv * dv);
    if (!(d > 1e-12))
    {
      continue; // coincident point: no information on derivatives
    }
    const double wgt = 1.0 / d;
    const double row[9] = { du, dv, 0.5 * du * du, du * dv, 0.5 * dv * dv, du * du * du / 6.0,
      0.5 * du * du * dv, 0.5 * du * dv * dv, dv * dv * dv / 6.0 };
    for (int j = 0; j < 9; ++j)
    {
      w.Columns[static_cast<std::size_t>(j) * n + rows] = wgt * row[j];
    }
    for (int c = 0; c < nc; ++c)
    {
      w.Columns[static_cast<std::size_t>(9 + c) * n + rows] =
        wgt * (this->Value(q, c) - this->Value(v, c));
    }
    ++rows;
  }
  w.Rows = rows;
  // Columns live at stride n (the allocated row count); only `rows` are used.
  const int m = std::min(maxColumns, rows);
  for (int k = 0; k < m; ++k)
  {
    double* a = w.Columns.data() + static_cast<std::size_t>(k) * n;
    double norm2 = 0.0;
    for (int i = 0; i < rows; ++i)
    {
      norm2 += a[i] * a[i];
    }
    // Norm before orthogonalisation: recompute from the projections.
    double projected2 = 0.0;
    for (int j = 0; j < k; ++j)
    {
      projected2 += w.R[j * width + k] * w.R[j * width + k];
    }
    const double rkk = std::sqrt(norm2);
    if (!(rkk > FitRankThreshold * std::sqrt(norm2 + projected2)))
    {
      break;
    }
    w.R[k * width + k] = rkk;
    for (int i = 0; i < rows; ++i)
    {
      a[i] /= rkk;
    }
    for (int j = k + 1; j < width; ++j)
    {
      if (j >= maxColumns && j < 9)
      {
        continue;
      }
      double* b = w.Columns.data() + static_cast<std::size_t>(j) * n;
      double r = 0.0;
      for (int i = 0; i < rows; ++i)
      {
        r += a[i] * b[i];
      }
      w.R[k * width + j] = r;
      for (int i = 0; i < rows; ++i)
      {
        b[i] -= r * a[i];
      }
    }
    w.Usable = k + 1;
  }
}

// Coefficients of the fit on the first `columns` (<= w.Usable) columns,
// unscaled, `stride` doubles per channel (the rest zero).
void Reconstruction::Internals::SolveFit(
  int columns, FitWorkspace& w, double* out, int stride) const
{
  const int nc = this->NC;
  const int width = 9 + nc;
  const double h = w.Scale;
  const double scale[9] = { h, h, h * h, h * h, h * h, h * h * h, h * h * h, h * h * h, h * h * h };
  std::fill(out, out + static_cast<std::size_t>(stride) * nc, 0.0);
  for (int c = 0; c < nc; ++c)
  {
    double x[9];
    for (int k = columns - 1; k >= 0; --k)
    {
      double r = w.R[k * width + 9 + c];
      for (int j = k + 1; j < columns; ++j)
      {
        r -= w.R[k * width + j] * x[j];
      }
      x[k] = r / w.R[k * width + k];
    }
    for (int k = 0; k < columns; ++k)
    {
      out[static_cast<std::size_t>(c) * stride + k] = x[k] / scale[k];
    }
  }
}

// Gradient when every neighbour lies on one line through v: the derivative
// along that line (minimum-norm least squares), zero across it.
void Reconstruction::Internals::SolveCollinear(
  int v, FitWorkspace& w, double* out, int stride) const
{
  const int nc = this->NC;
  std::fill(out, out + static_cast<std::size_t>(stride) * nc, 0.0);
  const double* pv = this->P(v);
  // Weighted least squares of f(q) - f(v) = D * (d . t) along the mean direction t.
  double tu = 0.0, tv = 0.0;
  for (int q : w.Points)
  {
    double du = this->P(q)[0] - pv[0];
    double dv = this->P(q)[1] - pv[1];
    if (du * tu + dv * tv < 0.0)
    {
      du = -du;
      dv = -dv;
    }
    tu += du;
    tv += dv;
  }
  const double tl = std::sqrt(tu * tu + tv * tv);
  if (!(tl > 0.0))
  {
    return;
  }
  tu /= tl;
  tv /= tl;
  for (int c = 0; c < nc; ++c)
  {
    double num = 0.0, den = 0.0;
    for (int q : w.Points)
    {
      const double s = (this->P(q)[0] - pv[0]) * tu + (this->P(q)[1] - pv[1]) * tv;
      const double d2 = (this->P(q)[0] - pv[0]) * (this->P(q)[0] - pv[0]) +
        (this->P(q)[1] - pv[1]) * (this->P(q)[1] - pv[1]);
      if (!(d2 > 0.0))
      {
        continue;
      }
      // Rows weighted by 1/distance, as in the other fits.
      num += s * (this->Value(q, c) - this->Value(v, c)) / d2;
      den += s * s / d2;
    }
    if (den > 0.0)
    {
      out[static_cast<std::size_t>(c) * stride] = num / den * tu;
      out[static_cast<std::size_t>(c) * stride + 1] = num / den * tv;
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::FitGradients()
{
  const int ns = static_cast<int>(this->SectorPoint.size());
  const int nc = this->NC;
  this->SectorFit.assign(static_cast<std::size_t>(ns) * 5 * nc, 0.0);
  this->SectorModel.assign(static_cast<std::size_t>(ns) * 9 * nc, 0.0);
  FitWorkspace w;
  w.PointStamp.assign(this->Mesh.GetNumberOfPoints(), 0);
  w.TriangleStamp.assign(this->Mesh.GetNumberOfTriangles(), 0);
  for (int s = 0; s < ns; ++s)
  {
    const int v = this->SectorPoint[s];
    // Gradient: quadratic fit on ring 1, ring 2 when ring 1 is small; the
    // same factor gives the cubic error model when the stencil is large enough.
    this->GatherNeighbours(s, this->Options.MinimumFitPoints, 2, w);
    const bool wantModel = this->Options.ErrorModel || this->Options.CubicGradients;
    const bool cubicHere = wantModel && static_cast<int>(w.Points.size()) >= CubicModelPoints;
    this->FactorFit(v, cubicHere ? 9 : 5, w);
    double* fit = this->SectorFit.data() + static_cast<std::size_t>(s) * 5 * nc;
    if (w.Usable >= 5)
    {
      this->SolveFit(5, w, fit, 5);
      ++this->Statistics.QuadraticFits;
    }
    else if (w.Usable >= 2)
    {
      this->SolveFit(2, w, fit, 5);
      ++this->Statistics.LinearFits;
    }
    else if (w.Rows >= 1)
    {
      this->SolveCollinear(v, w, fit, 5);
      ++this->Statistics.LinearFits;
    }
    else
    {
      ++this->Statistics.ZeroGradients;
    }
    // Error model: a cubic fit (on rings 2-3 when ring 2 is too small), or
    // the quadratic when the stencil cannot determine a cubic.
    double* model = this->SectorModel.data() + static_cast<std::size_t>(s) * 9 * nc;
    if (!cubicHere && !wantModel)
    {
      w.Usable = 0;
    }
    else if (!cubicHere)
    {
      this->GatherNeighbours(s, CubicModelPoints, 3, w);
      if (static_cast<int>(w.Points.size()) >= CubicModelPoints)
      {
        this->FactorFit(v, 9, w);
      }
      else
      {
        w.Usable = 0;
      }
    }
    if (w.Usable == 9)
    {
      this->SolveFit(9, w, model, 9);
      ++this->Statistics.CubicModels;
    }
    else
    {
      for (int c = 0; c < nc; ++c)
      {
        std::copy(fit + 5 * c, fit + 5 * c + 5, model + 9 * c);
      }
    }
  }

  // The interpolant's gradients (the cubic model's, when asked, starts with
  // the gradient; it is the quadratic fit where no cubic was possible).
  this->SectorGradient.assign(static_cast<std::size_t>(ns) * 2 * nc, 0.0);
  const bool cubic = this->Options.CubicGradients;
  for (std::size_t i = 0; i < static_cast<std::size_t>(ns) * nc; ++i)
  {
    const double* g = cubic ? this->SectorModel.data() + 9 * i : this->SectorFit.data() + 5 * i;
    this->SectorGradient[2 * i] = g[0];
    this->SectorGradient[2 * i + 1] = g[1];
  }
}

//------------------------------------------------------------------------------
// Derivative at point v along constrained edge `edge` (toward its other end),
// from the values along the straight constrained line through v: a parabola
// through three consecutive points (centred when the line continues through
// v, else one-sided), else the mean over the two sides' fitted gradients.
double Reconstruction::Internals::LineDerivative(int v, int edge, int channel) const
{
  const int w = this->EdgePoints[2 * edge] == v ? this->EdgePoints[2 * edge + 1]
                                                 : this->EdgePoints[2 * edge];
  const double* pv = this->P(v);
  const double* pw = this->P(w);
  const double L = std::hypot(pw[0] - pv[0], pw[1] - pv[1]);
  const double tu = (pw[0] - pv[0]) / L;
  const double tv = (pw[1] - pv[1]) / L;
  const double fv = this->Value(v, channel);
  const double fw = this->Value(w, channel);

  // The constrained edge at `from` (other than `exclude`) whose direction is
  // closest to (du, dv), if within CollinearSine.
  auto straightContinuation = [this](int from, int exclude, double du, double dv, int& to) {
    int best = -1;
    double bestDot = 0.0;
    for (int i = this->PointEdgeStart[from]; i < this->PointEdgeStart[from + 1]; ++i)
    {
      const int e = this->PointEdges[i];
      if (e == exclude)
      {
        continue;
      }
      const int o = this->EdgePoints[2 * e] == from ? this->EdgePoints[2 * e + 1]
                                                    : this->EdgePoints[2 * e];
      const double* pf = this->P(from);
      const double* po = this->P(o);
      const double l = std::hypot(po[0] - pf[0], po[1] - pf[1]);
      const double eu = (po[0] - pf[0]) / l;
      const double ev = (po[1] - pf[1]) / l;
      const double dot = eu * du + ev * dv;
      const double cross = std::abs(eu * dv - ev * du);
      if (dot > 0.0 && cross < CollinearSine && dot > bestDot)
      {
        bestDot = dot;
        best = e;
        to = o;
      }
    }
    return best;
  };

  int back = -1;
  if (straightContinuation(v, edge, -tu, -tv, back) >= 0)
  {
    const double* pb = this->P(back);
    const double a = std::hypot(pb[0] - pv[0], pb[1] - pv[1]);
    const double b = L;
    const double fb = this->Value(back, channel);
    return (a * a * (fw - fv) + b * b * (fv - fb)) / (a * b * (a + b));
  }
  int beyond = -1;
  if (straightContinuation(w, edge, tu, tv, beyond) >= 0 && beyond != v)
  {
    const double* pb = this->P(beyond);
    const double b = L;
    const double c = L + std::hypot(pb[0] - pw[0], pb[1] - pw[1]);
    const double fb = this->Value(beyond, channel);
    return (c * c * (fw - fv) - b * b * (fb - fv)) / (b * c * (c - b));
  }
  // Mean of the two sides' fitted gradients along the edge.
  double sum = 0.0;
  int count = 0;
  for (int side = 0; side < 2; ++side)
  {
    const int s3 = this->EdgeSides[2 * edge + side];
    if (s3 < 0)
    {
      continue;
    }
    const int t = s3 / 3;
    const int* tri = this->T(t);
    const int corner = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    const int sector = this->CornerSector[3 * t + corner];
    const double* fit =
      this->SectorFit.data() + (static_cast<std::size_t>(sector) * this->NC + channel) * 5;
    sum += fit[0] * tu + fit[1] * tv;
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::EnforceLineContinuity()
{
  const int ns = static_cast<int>(this->SectorPoint.size());
  const int nc = this->NC;
  std::vector<int> edges;
  std::vector<double> dirs;   // 2 per merged constraint
  std::vector<double> values; // nc per merged constraint
  for (int s = 0; s < ns; ++s)
  {
    const int v = this->SectorPoint[s];
    if (this->PointEdgeStart[v] == this->PointEdgeStart[v + 1])
    {
      continue;
    }
    // Constrained edges bounding this sector at v.
    edges.clear();
    for (int i = this->SectorCornerStart[s]; i < this->SectorCornerStart[s + 1]; ++i)
    {
      const int corner = this->SectorCorners[i];
      const int t = corner / 3;
      const int c = corner % 3;
      for (int k : { Next(c), Prev(c) })
      {
        const int e = this->TriangleEdge[3 * t + k];
        if (this->EdgeKinds[e] != ConstrainedEdge ||
          std::find(edges.begin(), edges.end(), e) != edges.end())
        {
          continue;
        }
        // An edge whose two sides share v's sector (the free end of a line)
        // needs no agreement: both sides use the same gradient.
        int sides[2];
        for (int j = 0; j < 2; ++j)
        {
          const int t2 = this->EdgeSides[2 * e + j] / 3;
          const int* tri2 = this->T(t2);
          sides[j] = this->CornerSector[3 * t2 + (tri2[0] == v ? 0 : (tri2[1] == v ? 1 : 2))];
        }
        if (sides[0] != sides[1])
        {
          edges.push_back(e);
        }
      }
    }
    if (edges.empty())
    {
      continue;
    }
    // Constraints g . t = D, nearly parallel ones merged into one.
    dirs.clear();
    values.clear();
    std::vector<int> merged;
    const double* pv = this->P(v);
    for (int e : edges)
    {
      const int w = this->EdgePoints[2 * e] == v ? this->EdgePoints[2 * e + 1]
                                                 : this->EdgePoints[2 * e];
      const double L = std::hypot(this->P(w)[0] - pv[0], this->P(w)[1] - pv[1]);
      const double tu = (this->P(w)[0] - pv[0]) / L;
      const double tv = (this->P(w)[1] - pv[1]) / L;
      int into = -1;
      for (std::size_t j = 0; j < merged.size(); ++j)
      {
        const double cross = std::abs(dirs[2 * j] * tv - dirs[2 * j + 1] * tu);
        if (cross < CollinearSine)
        {
          into = static_cast<int>(j);
          break;
        }
      }
      if (into < 0)
      {
        merged.push_back(1);
        dirs.push_back(tu);
        dirs.push_back(tv);
        for (int c = 0; c < nc; ++c)
        {
          values.push_back(this->LineDerivative(v, e, c));
        }
      }
      else
      {
        // g.t1 = D1 and g.t2 = D2 with t2 = +-t1 (nearly): one constraint
        // along the mean direction.
        const double sign = dirs[2 * into] * tu + dirs[2 * into + 1] * tv < 0.0 ? -1.0 : 1.0;
        const double mu = dirs[2 * into] + sign * tu;
        const double mv = dirs[2 * into + 1] + sign * tv;
        const double ml = std::hypot(mu, mv);
        for (int c = 0; c < nc; ++c)
        {
          const double d1 = values[into * nc + c];
          const double d2 = this->LineDerivative(v, e, c);
          values[into * nc + c] = (d1 + sign * d2) / ml;
        }
        dirs[2 * into] = mu / ml;
        dirs[2 * into + 1] = mv / ml;
        ++merged[into];
      }
    }
    const int m = static_cast<int>(merged.size());
    for (int c = 0; c < nc; ++c)
    {
      double* g = this->SectorGradient.data() + (static_cast<std::size_t>(s) * nc + c) * 2;
      if (m == 1)
      {
        // Least change: g += (D - g.t) t.
        const double r = values[c] - (g[0] * dirs[0] + g[1] * dirs[1]);
        g[0] += r * dirs[0];
        g[1] += r * dirs[1];
      }
      else
      {
        // Two or more independent directions determine g (least squares).
        double n00 = 0.0, n01 = 0.0, n11 = 0.0, r0 = 0.0, r1 = 0.0;
        for (int j = 0; j < m; ++j)
        {
          const double tu = dirs[2 * j];
          const double tv = dirs[2 * j + 1];
          n00 += tu * tu;
          n01 += tu * tv;
          n11 += tv * tv;
          r0 += tu * values[j * nc + c];
          r1 += tv * values[j * nc + c];
        }
        const double det = n00 * n11 - n01 * n01;
        g[0] = (n11 * r0 - n01 * r1) / det;
        g[1] = (n00 * r1 - n01 * r0) / det;
      }
    }
    ++this->Statistics.ConstrainedSectors;
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeNet(int t, int channel, Net& net) const
{
  const TriangleGeometry& geo = this->Geometry[t];
  const int* tri = this->T(t);
  const double* p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
  const double* g[3];
  for (int i = 0; i < 3; ++i)
  {
    net.F[i] = this->Value(tri[i], channel);
    g[i] = this->SectorGradient.data() +
      (static_cast<std::size_t>(this->CornerSector[3 * t + i]) * this->NC + channel) * 2;
  }
  // Gradient increments toward the neighbouring control points.
  double e[3][3];
  double a[3];
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      if (j != i)
      {
        e[i][j] = (g[i][0] * (p[j][0] - p[i][0]) + g[i][1] * (p[j][1] - p[i][1])) / 3.0;
        net.E[i][j] = net.F[i] + e[i][j];
      }
    }
    a[i] = (g[i][0] * (geo.Split[0] - p[i][0]) + g[i][1] * (geo.Split[1] - p[i][1])) / 3.0;
    net.A[i] = net.F[i] + a[i];
    net.E[i][i] = 0.0;
  }
  for (int k = 0; k < 3; ++k)
  {
    // Derivative along the normal of edge k linear along the edge; written
    // as a convex combination of the end values plus gradient terms, so that
    // zero gradients give a non-negative point exactly.
    const int P = Next(k);
    const int Q = Prev(k);
    const double tau = geo.Tau[k];
    net.M[k] = (1.0 - tau) * net.F[P] + tau * net.F[Q] +
      0.5 * (a[P] + a[Q] + (2.0 - 3.0 * tau) * e[P][Q] + (3.0 * tau - 1.0) * e[Q][P]);
  }
  // C1 across the three inner edges.
  for (int i = 0; i < 3; ++i)
  {
    net.C[i] = geo.Sigma[i] * net.A[i] + geo.Sigma[Next(i)] * net.M[Prev(i)] +
      geo.Sigma[Prev(i)] * net.M[Next(i)];
  }
  net.Z = geo.Sigma[0] * net.C[0] + geo.Sigma[1] * net.C[1] + geo.Sigma[2] * net.C[2];
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ComputeZeroGradientNet(int t, int channel, Net& net) const
{
  const TriangleGeometry& geo = this->Geometry[t];
  const int* tri = this->T(t);
  for (int i = 0; i < 3; ++i)
  {
    net.F[i] = this->Value(tri[i], channel);
  }
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      net.E[i][j] = j != i ? net.F[i] : 0.0;
    }
    net.A[i] = net.F[i];
  }
  for (int k = 0; k < 3; ++k)
  {
    net.M[k] = (1.0 - geo.Tau[k]) * net.F[Next(k)] + geo.Tau[k] * net.F[Prev(k)];
  }
  for (int i = 0; i < 3; ++i)
  {
    net.C[i] = geo.Sigma[i] * net.A[i] + geo.Sigma[Next(i)] * net.M[Prev(i)] +
      geo.Sigma[Prev(i)] * net.M[Next(i)];
  }
  net.Z = geo.Sigma[0] * net.C[0] + geo.Sigma[1] * net.C[1] + geo.Sigma[2] * net.C[2];
}

namespace
{

// The 19 control points of a net, in a fixed order.
inline void NetPoints(const Net& n, double out[19])
{
  out[0] = n.F[0];
  out[1] = n.F[1];
  out[2] = n.F[2];
  out[3] = n.E[0][1];
  out[4] = n.E[0][2];
  out[5] = n.E[1][0];
  out[6] = n.E[1][2];
  out[7] = n.E[2][0];
  out[8] = n.E[2][1];
  out[9] = n.A[0];
  out[10] = n.A[1];
  out[11] = n.A[2];
  out[12] = n.M[0];
  out[13] = n.M[1];
  out[14] = n.M[2];
  out[15] = n.C[0];
  out[16] = n.C[1];
  out[17] = n.C[2];
  out[18] = n.Z;
}

// Micro-triangle and its barycentrics (x, y, z) w.r.t. (corner k+1, corner
// k+2, split point) for macro barycentrics b (non-negative, summing to 1).
inline int MicroCoordinates(const TriangleGeometry& geo, const double b[3], double& x, double& y,
  double& z)
{
  int k = 0;
  double best = b[0] / geo.Sigma[0];
  for (int i = 1; i < 3; ++i)
  {
    const double r = b[i] / geo.Sigma[i];
    if (r < best)
    {
      best = r;
      k = i;
    }
  }
  z = best;
  x = std::max(0.0, b[Next(k)] - geo.Sigma[Next(k)] * z);
  y = std::max(0.0, b[Prev(k)] - geo.Sigma[Prev(k)] * z);
  return k;
}

// Value of the cubic on micro-triangle k at (x, y, z); optionally the
// derivatives with respect to x, y and z.
inline double EvaluateMicro(
  const Net& n, int k, double x, double y, double z, double* dx, double* dy, double* dz)
{
  const int P = Next(k);
  const int Q = Prev(k);
  const double b300 = n.F[P], b030 = n.F[Q], b003 = n.Z;
  const double b210 = n.E[P][Q], b120 = n.E[Q][P];
  const double b201 = n.A[P], b021 = n.A[Q];
  const double b111 = n.M[k];
  const double b102 = n.C[P], b012 = n.C[Q];
  if (dx)
  {
    const double xx = x * x, yy = y * y, zz = z * z;
    const double xy = 2.0 * x * y, xz = 2.0 * x * z, yz = 2.0 * y * z;
    *dx = 3.0 * (xx * b300 + xy * b210 + yy * b120 + xz * b201 + yz * b111 + zz * b102);
    *dy = 3.0 * (xx * b210 + xy * b120 + yy * b030 + xz * b111 + yz * b021 + zz * b012);
    *dz = 3.0 * (xx * b201 + xy * b111 + yy * b021 + xz * b102 + yz * b012 + zz * b003);
  }
  // de Casteljau: only non-negative weights, so a non-negative net gives a
  // non-negative value in floating point too.
  const double c200 = x * b300 + y * b210 + z * b201;
  const double c110 = x * b210 + y * b120 + z * b111;
  const double c020 = x * b120 + y * b030 + z * b021;
  const double c101 = x * b201 + y * b111 + z * b102;
  const double c011 = x * b111 + y * b021 + z * b012;
  const double c002 = x * b102 + y * b012 + z * b003;
  const double d100 = x * c200 + y * c110 + z * c101;
  const double d010 = x * c110 + y * c020 + z * c011;
  const double d001 = x * c101 + y * c011 + z * c002;
  return x * d100 + y * d010 + z * d001;
}

} // namespace

//------------------------------------------------------------------------------
void Reconstruction::Internals::EnforceNonNegativity()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int np = this->Mesh.GetNumberOfPoints();
  const int nc = this->NC;
  std::vector<double> alpha(static_cast<std::size_t>(np) * nc, 1.0);
  std::vector<double> base(static_cast<std::size_t>(this->SectorGradient.size()));
  base = this->SectorGradient;
  std::vector<int> scalings(nt, 0);
  std::vector<char> queued(nt, 1);
  std::vector<int> queue(nt);
  for (int t = 0; t < nt; ++t)
  {
    queue[t] = t;
  }
  std::size_t head = 0;
  // Apply a point's factors to all its sectors.
  auto applyPoint = [&](int point, int channel) {
    const double f = alpha[static_cast<std::size_t>(point) * nc + channel];
    for (int i = this->PointTriangleStart[point]; i < this->PointTriangleStart[point + 1]; ++i)
    {
      const int t = this->PointTriangles[i];
      const int* tri = this->T(t);
      const int corner = tri[0] == point ? 0 : (tri[1] == point ? 1 : 2);
      const std::size_t s = this->CornerSector[3 * t + corner];
      for (int d = 0; d < 2; ++d)
      {
        this->SectorGradient[(s * nc + channel) * 2 + d] = f * base[(s * nc + channel) * 2 + d];
      }
      if (!queued[t])
      {
        queued[t] = 1;
        queue.push_back(t);
      }
    }
  };
  // Rounding slack per triangle and channel: a net this far below the
  // samples' minimum is rounding, not negativity to repair (evaluation
  // clamps it). Relative to the channel's largest value and to the values
  // and gradients entering the net (gradient times the triangle's size),
  // the largest gradient of each point over all its sectors: the tangential
  // projections across order-1 edges mix the sectors' gradients (in an unlit
  // sector next to a lit one a net of zeros came out -8e-18; repaired, that
  // zeroed the lit sector's gradient too).
  std::vector<double> largestValue(nc, 0.0);
  for (int p = 0; p < np; ++p)
  {
    for (int c = 0; c < nc; ++c)
    {
      largestValue[c] = std::max(largestValue[c], std::abs(this->Value(p, c)));
    }
  }
  std::vector<double> largestGradient(static_cast<std::size_t>(np) * nc, 0.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::size_t s = this->CornerSector[3 * t + corner];
      for (int c = 0; c < nc; ++c)
      {
        double& g = largestGradient[static_cast<std::size_t>(tri[corner]) * nc + c];
        g = std::max(g, std::hypot(base[(s * nc + c) * 2], base[(s * nc + c) * 2 + 1]));
      }
    }
  }
  this->NetSlack.assign(static_cast<std::size_t>(nt) * nc, 0.0);
  for (int t = 0; t < nt; ++t)
  {
    const int* tri = this->T(t);
    for (int c = 0; c < nc; ++c)
    {
      double magnitude = largestValue[c];
      for (int i = 0; i < 3; ++i)
      {
        magnitude = std::max(magnitude,
          std::abs(this->Value(tri[i], c)) +
            this->Geometry[t].Diameter *
              largestGradient[static_cast<std::size_t>(tri[i]) * nc + c]);
      }
      this->NetSlack[static_cast<std::size_t>(t) * nc + c] = NetRoundingSlack * magnitude;
    }
  }
  Net net, zero;
  double cur[19], low[19];
  int passes = nt > 0 ? 1 : 0;
  std::size_t passEnd = queue.size();
  while (head < queue.size())
  {
    if (head == passEnd)
    {
      ++passes;
      passEnd = queue.size();
    }
    const int t = queue[head++];
    queued[t] = 0;
    const int* tri = this->T(t);
    for (int c = 0; c < nc; ++c)
    {
      const double f0 = this->Value(tri[0], c);
      const double f1 = this->Value(tri[1], c);
      const double f2 = this->Value(tri[2], c);
      const double lowest = std::min(0.0, std::min(f0, std::min(f1, f2)));
      const double slack = this->NetSlack[static_cast<std::size_t>(t) * nc + c];
      this->ComputeNet(t, c, net);
      NetPoints(net, cur);
      double minimum = cur[0];
      for (int j = 1; j < 19; ++j)
      {
        minimum = std::min(minimum, cur[j]);
      }
      if (minimum >= lowest - slack)
      {
        continue;
      }
      double lambda = 0.0;
      if (scalings[t] < MaximumScalingsPerTriangle)
      {
        // The net is affine in a common factor of the three points'
        // gradients: the largest factor keeping it above `lowest`.
        this->ComputeZeroGradientNet(t, c, zero);
        NetPoints(zero, low);
        lambda = 1.0;
        for (int j = 0; j < 19; ++j)
        {
          if (cur[j] < lowest)
          {
            const double room = std::max(0.0, low[j] - lowest);
            lambda = std::min(lambda, room / (low[j] - cur[j]));
          }
        }
        lambda = std::max(0.0, lambda * (1.0 - ScaleMargin));
      }
      ++scalings[t];
      for (int i = 0; i < 3; ++i)
      {
        double& a = alpha[static_cast<std::size_t>(tri[i]) * nc + c];
        if (a > 0.0)
        {
          a *= lambda;
          applyPoint(tri[i], c);
        }
      }
    }
  }
  this->Statistics.RepairPasses = passes;
  for (double a : alpha)
  {
    if (a < 1.0)
    {
      ++this->Statistics.ScaledGradients;
      if (a == 0.0)
      {
        ++this->Statistics.ZeroedGradients;
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::Barycentric(int t, double u, double v, double b[3]) const
{
  const int* tri = this->T(t);
  const double area2 = this->Geometry[t].Area2;
  for (int i = 0; i < 3; ++i)
  {
    const double* a = this->P(tri[Next(i)]);
    const double* c = this->P(tri[Prev(i)]);
    b[i] = ((c[0] - a[0]) * (v - a[1]) - (c[1] - a[1]) * (u - a[0])) / area2;
  }
}

namespace
{

// Clamp barycentrics to the triangle and renormalise.
inline void ClampBarycentric(const double in[3], double b[3])
{
  double sum = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    b[i] = in[i] > 0.0 ? in[i] : 0.0; // also maps NaN to 0
    sum += b[i];
  }
  if (!(sum > 0.0) || !std::isfinite(sum))
  {
    b[0] = b[1] = b[2] = 1.0 / 3.0;
    return;
  }
  for (int i = 0; i < 3; ++i)
  {
    b[i] /= sum;
  }
}

} // namespace

void Reconstruction::Internals::Evaluate(
  int t, const double bIn[3], double* value, double* gradient) const
{
  if (this->Options.Mode == ReconstructionMode::Linear)
  {
    this->EvaluateWithNets(t, nullptr, bIn, value, gradient);
    return;
  }
  Net nets[8] = {};
  std::vector<Net> many;
  Net* use = nets;
  if (this->NC > 8)
  {
    many.resize(this->NC);
    use = many.data();
  }
  for (int c = 0; c < this->NC; ++c)
  {
    this->ComputeNet(t, c, use[c]);
  }
  this->EvaluateWithNets(t, use, bIn, value, gradient);
}

//------------------------------------------------------------------------------
// Evaluate with nets already computed (one per channel; null in Linear mode).
void Reconstruction::Internals::EvaluateWithNets(
  int t, const Net* nets, const double bIn[3], double* value, double* gradient) const
{
  const Internals& in = *this;
  double b[3];
  ClampBarycentric(bIn, b);
  const int nc = in.NC;
  const int* tri = in.T(t);
  const TriangleGeometry& geo = in.Geometry[t];
  if (in.Options.Mode == ReconstructionMode::Linear || nets == nullptr)
  {
    for (int c = 0; c < nc; ++c)
    {
      const double f0 = in.Value(tri[0], c);
      const double f1 = in.Value(tri[1], c);
      const double f2 = in.Value(tri[2], c);
      value[c] = b[0] * f0 + b[1] * f1 + b[2] * f2;
      if (gradient)
      {
        gradient[2 * c] = f0 * geo.GradB[0][0] + f1 * geo.GradB[1][0] + f2 * geo.GradB[2][0];
        gradient[2 * c + 1] = f0 * geo.GradB[0][1] + f1 * geo.GradB[1][1] + f2 * geo.GradB[2][1];
      }
    }
    return;
  }
  double x, y, z;
  const int k = MicroCoordinates(geo, b, x, y, z);
  double gz[2] = { 0.0, 0.0 }, gx[2] = { 0.0, 0.0 }, gy[2] = { 0.0, 0.0 };
  if (gradient)
  {
    const int P = Next(k);
    const int Q = Prev(k);
    for (int d = 0; d < 2; ++d)
    {
      gz[d] = geo.GradB[k][d] / geo.Sigma[k];
      gx[d] = geo.GradB[P][d] - geo.Sigma[P] * gz[d];
      gy[d] = geo.GradB[Q][d] - geo.Sigma[Q] * gz[d];
    }
  }
  for (int c = 0; c < nc; ++c)
  {
    if (gradient)
    {
      double dx, dy, dz;
      value[c] = EvaluateMicro(nets[c], k, x, y, z, &dx, &dy, &dz);
      gradient[2 * c] = dx * gx[0] + dy * gy[0] + dz * gz[0];
      gradient[2 * c + 1] = dx * gx[1] + dy * gy[1] + dz * gz[1];
    }
    else
    {
      value[c] = EvaluateMicro(nets[c], k, x, y, z, nullptr, nullptr, nullptr);
    }
    if (!in.NetSlack.empty())
    {
      // The repair leaves nets up to a rounding slack below the samples'
      // minimum (or 0): clamp that, and only that.
      const double lowest = std::min(
        { 0.0, in.Value(tri[0], c), in.Value(tri[1], c), in.Value(tri[2], c) });
      if (value[c] < lowest &&
        value[c] >= lowest - in.NetSlack[static_cast<std::size_t>(t) * nc + c])
      {
        value[c] = lowest;
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ModelError(
  int t, const double bIn[3], const double* interpolated, double* error) const
{
  double b[3];
  ClampBarycentric(bIn, b);
  const int* tri = this->T(t);
  const double* p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
  const double u = b[0] * p[0][0] + b[1] * p[1][0] + b[2] * p[2][0];
  const double v = b[0] * p[0][1] + b[1] * p[1][1] + b[2] * p[2][1];
  for (int c = 0; c < this->NC; ++c)
  {
    error[c] = 0.0;
  }
  for (int i = 0; i < 3; ++i)
  {
    const double du = u - p[i][0];
    const double dv = v - p[i][1];
    const std::size_t s = this->CornerSector[3 * t + i];
    for (int c = 0; c < this->NC; ++c)
    {
      const double* q = this->SectorModel.data() + (s * this->NC + c) * 9;
      const double model = this->Value(tri[i], c) + q[0] * du + q[1] * dv +
        0.5 * q[2] * du * du + q[3] * du * dv + 0.5 * q[4] * dv * dv +
        q[5] * du * du * du / 6.0 + 0.5 * q[6] * du * du * dv + 0.5 * q[7] * du * dv * dv +
        q[8] * dv * dv * dv / 6.0;
      error[c] = std::max(error[c], std::abs(model - interpolated[c]));
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::BuildGrid()
{
  const int nt = this->Mesh.GetNumberOfTriangles();
  this->GridStart.clear();
  this->GridTriangles.clear();
  this->GridDims[0] = this->GridDims[1] = 0;
  if (nt == 0)
  {
    return;
  }
  const double inf = std::numeric_limits<double>::infinity();
  double lo[2] = { inf, inf };
  double hi[2] = { -lo[0], -lo[1] };
  for (int t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double* p = this->P(this->T(t)[k]);
      for (int d = 0; d < 2; ++d)
      {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
    }
  }
  const double w = std::max(hi[0] - lo[0], 1e-300);
  const double h = std::max(hi[1] - lo[1], 1e-300);
  // About one triangle per cell, at most 2048 x 2048 cells.
  const double cell = std::sqrt(w * h / nt);
  for (int d = 0; d < 2; ++d)
  {
    const double extent = d == 0 ? w : h;
    const double n = cell > 0.0 ? std::ceil(extent / cell) : 1.0;
    this->GridDims[d] = static_cast<int>(std::min(2048.0, std::max(1.0, n)));
    this->GridOrigin[d] = lo[d];
    this->GridInverseCell[d] = this->GridDims[d] / extent;
  }
  const int nx = this->GridDims[0];
  const int ny = this->GridDims[1];
  auto cellRange = [&](int t, int r[4]) {
    double blo[2] = { inf, inf };
    double bhi[2] = { -blo[0], -blo[1] };
    for (int k = 0; k < 3; ++k)
    {
      const double* p = this->P(this->T(t)[k]);
      for (int d = 0; d < 2; ++d)
      {
        blo[d] = std::min(blo[d], p[d]);
        bhi[d] = std::max(bhi[d], p[d]);
      }
    }
    for (int d = 0; d < 2; ++d)
    {
      const int n = this->GridDims[d];
      auto cellOf = [&](double x) {
        const double f = std::floor((x - this->GridOrigin[d]) * this->GridInverseCell[d]);
        return std::min(n - 1, std::max(0, static_cast<int>(f)));
      };
      r[2 * d] = cellOf(blo[d]);
      r[2 * d + 1] = cellOf(bhi[d]);
    }
  };
  this->GridStart.assign(static_cast<std::size_t>(nx) * ny + 1, 0);
  int r[4];
  for (int t = 0; t < nt; ++t)
  {
    cellRange(t, r);
    for (int j = r[2]; j <= r[3]; ++j)
    {
      for (int i = r[0]; i <= r[1]; ++i)
      {
        ++this->GridStart[static_cast<std::size_t>(j) * nx + i + 1];
      }
    }
  }
  for (std::size_t i = 0; i + 1 < this->GridStart.size(); ++i)
  {
    this->GridStart[i + 1] += this->GridStart[i];
  }
  this->GridTriangles.assign(this->GridStart.back(), -1);
  std::vector<int> fill(this->GridStart.begin(), this->GridStart.end() - 1);
  for (int t = 0; t < nt; ++t)
  {
    cellRange(t, r);
    for (int j = r[2]; j <= r[3]; ++j)
    {
      for (int i = r[0]; i <= r[1]; ++i)
      {
        this->GridTriangles[fill[static_cast<std::size_t>(j) * nx + i]++] = t;
      }
    }
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
  in->BuildSectors();
  in->FitGradients();
  in->EnforceLineContinuity();
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

namespace
{
void CheckTriangle(int t, int nt)
{
  if (t < 0 || t >= nt)
  {
    throw InputError("Reconstruction: triangle id " + std::to_string(t) + " out of range [0, " +
      std::to_string(nt) + ")");
  }
}
} // namespace

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
  const Internals& in = *this->Internal;
  if (in.GridDims[0] == 0 || !std::isfinite(u) || !std::isfinite(v))
  {
    return -1;
  }
  const double q[2] = { u, v };
  int cell[2];
  for (int d = 0; d < 2; ++d)
  {
    const double f = (q[d] - in.GridOrigin[d]) * in.GridInverseCell[d];
    const int n = in.GridDims[d];
    // Allow points just outside the box (tolerance); clamp to the grid.
    if (f < -1.0 || f > n + 1.0)
    {
      return -1;
    }
    cell[d] = std::min(n - 1, std::max(0, static_cast<int>(std::floor(f))));
  }
  const std::size_t c = static_cast<std::size_t>(cell[1]) * in.GridDims[0] + cell[0];
  int best = -1;
  double bestMin = -InsideTolerance;
  double b[3];
  for (int i = in.GridStart[c]; i < in.GridStart[c + 1]; ++i)
  {
    const int t = in.GridTriangles[i];
    in.Barycentric(t, u, v, b);
    const double m = std::min(b[0], std::min(b[1], b[2]));
    if (m >= bestMin)
    {
      bestMin = m;
      best = t;
      if (barycentric)
      {
        barycentric[0] = b[0];
        barycentric[1] = b[1];
        barycentric[2] = b[2];
      }
    }
  }
  return best;
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

namespace
{
void CheckErrorOptions(const ErrorEstimateOptions& o)
{
  if (!(o.ModelSafetyFactor >= 0.0 && o.ModelSafetyFactor <= 1e6))
  {
    throw InputError("Reconstruction: ModelSafetyFactor must be in [0, 1e6]");
  }
  if (!(o.ProbeSafetyFactor >= 0.0 && o.ProbeSafetyFactor <= 1e6))
  {
    throw InputError("Reconstruction: ProbeSafetyFactor must be in [0, 1e6]");
  }
  if (o.ModelLevel < 1 || o.ModelLevel > 64)
  {
    throw InputError("Reconstruction: ModelLevel must be in [1, 64]");
  }
}
} // namespace

void Reconstruction::EstimateErrors(int count, const int* triangles, const double* barycentrics,
  const ErrorProbes* probes, const ErrorEstimateOptions& options, double* errors) const
{
  const Internals& in = *this->Internal;
  CheckErrorOptions(options);
  const int nt = in.Mesh.GetNumberOfTriangles();
  for (int i = 0; i < count; ++i)
  {
    CheckTriangle(triangles[i], nt);
  }
  std::vector<double> probeBounds, modelScale;
  in.CalibrateWithProbes(probes, options, probeBounds, modelScale);
  const int nc = in.NC;
  std::vector<double> value(nc);
  for (int i = 0; i < count; ++i)
  {
    const int t = triangles[i];
    double* error = errors + static_cast<std::size_t>(i) * nc;
    in.Evaluate(t, barycentrics + 3 * i, value.data(), nullptr);
    in.ModelError(t, barycentrics + 3 * i, value.data(), error);
    for (int c = 0; c < nc; ++c)
    {
      const std::size_t at = static_cast<std::size_t>(t) * nc + c;
      error[c] *= options.ModelSafetyFactor * (modelScale.empty() ? 1.0 : modelScale[at]);
      if (!probeBounds.empty())
      {
        error[c] = std::max(error[c], probeBounds[at]);
      }
    }
  }
}

void Reconstruction::ComputeTriangleErrorBounds(const ErrorProbes* probes,
  const ErrorEstimateOptions& options, std::vector<double>& bounds) const
{
  const Internals& in = *this->Internal;
  CheckErrorOptions(options);
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int nc = in.NC;
  std::vector<double> probeBounds, modelScale;
  in.CalibrateWithProbes(probes, options, probeBounds, modelScale); // validates first
  bounds.assign(static_cast<std::size_t>(nt) * nc, 0.0);
  const int level = options.ModelLevel;
  const bool cubic = in.Options.Mode == ReconstructionMode::CloughTocher;
  std::vector<Net> nets(nc);
  std::vector<double> value(nc), error(nc);
  for (int t = 0; t < nt; ++t)
  {
    if (cubic)
    {
      for (int c = 0; c < nc; ++c)
      {
        in.ComputeNet(t, c, nets[c]);
      }
    }
    double* out = bounds.data() + static_cast<std::size_t>(t) * nc;
    for (int a = 0; a <= level; ++a)
    {
      for (int b = 0; a + b <= level; ++b)
      {
        const double bary[3] = { static_cast<double>(level - a - b) / level,
          static_cast<double>(a) / level, static_cast<double>(b) / level };
        in.EvaluateWithNets(t, cubic ? nets.data() : nullptr, bary, value.data(), nullptr);
        in.ModelError(t, bary, value.data(), error.data());
        for (int c = 0; c < nc; ++c)
        {
          const double scale =
            modelScale.empty() ? 1.0 : modelScale[static_cast<std::size_t>(t) * nc + c];
          out[c] = std::max(out[c], options.ModelSafetyFactor * scale * error[c]);
        }
      }
    }
    if (!probeBounds.empty())
    {
      for (int c = 0; c < nc; ++c)
      {
        out[c] = std::max(out[c], probeBounds[static_cast<std::size_t>(t) * nc + c]);
      }
    }
  }
}

//------------------------------------------------------------------------------
// Per triangle and channel (both empty without probes): bound =
// ProbeSafetyFactor * max |residual|, modelScale = the factor k_t of
// ErrorEstimateOptions (1 for a triangle without probes).
void Reconstruction::Internals::CalibrateWithProbes(const ErrorProbes* probes,
  const ErrorEstimateOptions& options, std::vector<double>& bound,
  std::vector<double>& modelScale) const
{
  bound.clear();
  modelScale.clear();
  if (!probes)
  {
    return;
  }
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int nc = this->NC;
  if (probes->Residuals.size() != probes->Triangles.size() * static_cast<std::size_t>(nc))
  {
    throw InputError("Reconstruction: ErrorProbes has " + std::to_string(probes->Residuals.size()) +
      " residuals for " + std::to_string(probes->Triangles.size()) + " probes of " +
      std::to_string(nc) + " channels");
  }
  std::vector<double> measured(static_cast<std::size_t>(nt) * nc, 0.0);
  std::vector<char> probed(nt, 0);
  for (std::size_t i = 0; i < probes->Triangles.size(); ++i)
  {
    const int t = probes->Triangles[i];
    if (t < 0 || t >= nt)
    {
      throw InputError("Reconstruction: probe " + std::to_string(i) + " has triangle id " +
        std::to_string(t) + " out of range [0, " + std::to_string(nt) + ")");
    }
    probed[t] = 1;
    for (int c = 0; c < nc; ++c)
    {
      const double r = probes->Residuals[i * nc + c];
      if (!std::isfinite(r))
      {
        throw InputError(
          "Reconstruction: probe " + std::to_string(i) + " has a non-finite residual");
      }
      double& m = measured[static_cast<std::size_t>(t) * nc + c];
      m = std::max(m, std::abs(r));
    }
  }
  bound.resize(measured.size());
  modelScale.assign(measured.size(), 1.0);
  std::vector<double> value(nc), error(nc), claimed(nc);
  const double midpoints[3][3] = { { 0.5, 0.5, 0.0 }, { 0.0, 0.5, 0.5 }, { 0.5, 0.0, 0.5 } };
  for (int t = 0; t < nt; ++t)
  {
    const std::size_t at = static_cast<std::size_t>(t) * nc;
    std::fill(claimed.begin(), claimed.end(), 0.0);
    if (probed[t])
    {
      for (const auto& b : midpoints)
      {
        this->Evaluate(t, b, value.data(), nullptr);
        this->ModelError(t, b, value.data(), error.data());
        for (int c = 0; c < nc; ++c)
        {
          claimed[c] = std::max(claimed[c], error[c]);
        }
      }
    }
    for (int c = 0; c < nc; ++c)
    {
      bound[at + c] = options.ProbeSafetyFactor * measured[at + c];
      if (claimed[c] > measured[at + c])
      {
        modelScale[at + c] = measured[at + c] / claimed[c];
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Resample(const ResampleOptions& options, ResampledMesh& output,
  const ErrorProbes* probes, const ErrorEstimateOptions& errorOptions) const
{
  const Internals& in = *this->Internal;
  if (options.SubdivisionLevel < 1 || options.SubdivisionLevel > 1024)
  {
    throw InputError("Reconstruction: SubdivisionLevel is " +
      std::to_string(options.SubdivisionLevel) + ", must be in [1, 1024]");
  }
  if (!(options.TargetEdgeLength >= 0.0) || !std::isfinite(options.TargetEdgeLength))
  {
    throw InputError("Reconstruction: TargetEdgeLength must be finite and >= 0");
  }
  if (options.MaximumSubdivisionLevel < 1 || options.MaximumSubdivisionLevel > 1024)
  {
    throw InputError("Reconstruction: MaximumSubdivisionLevel is " +
      std::to_string(options.MaximumSubdivisionLevel) + ", must be in [1, 1024]");
  }
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int nc = in.NC;
  const bool estimate = options.ComputeErrorEstimate;
  std::vector<double> probeBounds, modelScale, triangleBounds;
  if (estimate)
  {
    CheckErrorOptions(errorOptions);
    if (errorOptions.PerTriangle)
    {
      this->ComputeTriangleErrorBounds(probes, errorOptions, triangleBounds);
    }
    else
    {
      in.CalibrateWithProbes(probes, errorOptions, probeBounds, modelScale);
    }
  }

  output = ResampledMesh();
  output.NumberOfChannels = nc;

  // Segments per unique edge.
  const int ne = static_cast<int>(in.EdgeKinds.size());
  std::vector<int> segments(ne, options.SubdivisionLevel);
  if (options.TargetEdgeLength > 0.0)
  {
    for (int e = 0; e < ne; ++e)
    {
      const double* a = in.P(in.EdgePoints[2 * e]);
      const double* b = in.P(in.EdgePoints[2 * e + 1]);
      const double n = std::ceil(std::hypot(b[0] - a[0], b[1] - a[1]) / options.TargetEdgeLength);
      segments[e] = static_cast<int>(
        std::min(static_cast<double>(options.MaximumSubdivisionLevel), std::max(1.0, n)));
    }
  }
  // Output ids of input points and of edge points (first id of each edge).
  std::vector<int> pointId(in.Mesh.GetNumberOfPoints(), -1);
  std::vector<int> edgeFirst(ne, -1);

  {
    // Reserve the output (its size is known in advance).
    std::size_t points = 0, triangles = 0;
    for (int e = 0; e < ne; ++e)
    {
      points += static_cast<std::size_t>(segments[e] - 1);
    }
    for (int t = 0; t < nt; ++t)
    {
      const int n0 = segments[in.TriangleEdge[3 * t]];
      const int n1 = segments[in.TriangleEdge[3 * t + 1]];
      const int n2 = segments[in.TriangleEdge[3 * t + 2]];
      const std::size_t s = static_cast<std::size_t>(std::max(n0, std::max(n1, n2)));
      if (n0 == n1 && n1 == n2)
      {
        points += (s - 1) * (s - 2) / 2 + 3;
        triangles += s * s;
      }
      else
      {
        const std::size_t m = std::max<std::size_t>(s, 3) - 3;
        points += (m + 1) * (m + 2) / 2 + 3;
        triangles += m * m + static_cast<std::size_t>(n0 + n1 + n2) + 3 * m;
      }
    }
    output.Points.reserve(2 * points);
    output.Values.reserve(nc * points);
    output.SourcePoint.reserve(points);
    if (estimate)
    {
      output.ErrorEstimate.reserve(nc * points);
    }
    output.Triangles.reserve(3 * triangles);
    output.SourceTriangle.reserve(triangles);
  }

  std::vector<Net> nets(nc);
  std::vector<double> value(nc), error(nc);
  const bool cubic = in.Options.Mode == ReconstructionMode::CloughTocher;
  // Output points of the current triangle with their barycentrics in it,
  // for the error estimate.
  struct Contribution
  {
    int Id;
    double B[3];
  };
  std::vector<Contribution> contributions;

  auto newPoint = [&](int t, const double b[3], int source) {
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
      in.EvaluateWithNets(t, cubic ? nets.data() : nullptr, b, value.data(), nullptr);
      output.Values.insert(output.Values.end(), value.begin(), value.end());
    }
    output.SourcePoint.push_back(source);
    if (estimate)
    {
      output.ErrorEstimate.insert(output.ErrorEstimate.end(), nc, 0.0);
    }
    return id;
  };
  // Output id of the i-th of n points along edge k of triangle t, counted
  // from corner k+1 (0 and n are the corners).
  auto edgePoint = [&](int t, int k, int i, int n) {
    const int* tri = in.T(t);
    double b[3];
    b[k] = 0.0;
    b[Next(k)] = static_cast<double>(n - i) / n;
    b[Prev(k)] = static_cast<double>(i) / n;
    int id;
    if (i == 0 || i == n)
    {
      const int p = tri[i == 0 ? Next(k) : Prev(k)];
      if (pointId[p] < 0)
      {
        pointId[p] = newPoint(t, b, p);
      }
      id = pointId[p];
    }
    else
    {
      const int e = in.TriangleEdge[3 * t + k];
      const bool forward = in.EdgePoints[2 * e] == tri[Next(k)];
      if (edgeFirst[e] < 0)
      {
        // Create all the edge's points, from its smaller end point.
        edgeFirst[e] = output.GetNumberOfPoints();
        for (int j = 1; j < n; ++j)
        {
          const double s = static_cast<double>(forward ? j : n - j) / n;
          double bj[3];
          bj[k] = 0.0;
          bj[Next(k)] = 1.0 - s;
          bj[Prev(k)] = s;
          newPoint(t, bj, -1);
        }
      }
      id = edgeFirst[e] + (forward ? i : n - i) - 1;
    }
    if (estimate)
    {
      contributions.push_back({ id, { b[0], b[1], b[2] } });
    }
    return id;
  };

  std::vector<int> lattice;
  for (int t = 0; t < nt; ++t)
  {
    if (cubic)
    {
      for (int c = 0; c < nc; ++c)
      {
        in.ComputeNet(t, c, nets[c]);
      }
    }
    contributions.clear();
    int n[3];
    for (int k = 0; k < 3; ++k)
    {
      n[k] = segments[in.TriangleEdge[3 * t + k]];
    }
    const bool regular = n[0] == n[1] && n[1] == n[2];
    const int s = regular ? n[0] : std::max(3, std::max(n[0], std::max(n[1], n[2])));
    // Lattice point (a, b): barycentrics ((s-a-b)/s, a/s, b/s).
    auto index = [s](int a, int b) { return a * (s + 1) - a * (a - 1) / 2 + b; };
    lattice.assign(static_cast<std::size_t>((s + 1) * (s + 2) / 2), -1);
    auto addTriangle = [&](int p0, int p1, int p2) {
      output.Triangles.push_back(p0);
      output.Triangles.push_back(p1);
      output.Triangles.push_back(p2);
      output.SourceTriangle.push_back(t);
    };
    auto latticePoint = [&](int a, int b) {
      int& id = lattice[index(a, b)];
      if (id < 0)
      {
        const double bary[3] = { static_cast<double>(s - a - b) / s, static_cast<double>(a) / s,
          static_cast<double>(b) / s };
        id = newPoint(t, bary, -1);
        if (estimate)
        {
          contributions.push_back({ id, { bary[0], bary[1], bary[2] } });
        }
      }
      return id;
    };
    if (regular)
    {
      // Boundary lattice points come from the shared edges and corners.
      // Edge 0 (corner 1 -> 2): a + b = s, b counts from corner 1.
      // Edge 1 (corner 2 -> 0): a = 0, counted from corner 2 (b = s - i).
      // Edge 2 (corner 0 -> 1): b = 0, counted from corner 0 (a = i).
      for (int i = 0; i <= s; ++i)
      {
        lattice[index(s - i, i)] = edgePoint(t, 0, i, s);
        lattice[index(0, s - i)] = edgePoint(t, 1, i, s);
        lattice[index(i, 0)] = edgePoint(t, 2, i, s);
      }
      for (int a = 0; a < s; ++a)
      {
        for (int b = 0; a + b < s; ++b)
        {
          addTriangle(latticePoint(a, b), latticePoint(a + 1, b), latticePoint(a, b + 1));
          if (a + b + 1 < s)
          {
            addTriangle(latticePoint(a + 1, b), latticePoint(a + 1, b + 1), latticePoint(a, b + 1));
          }
        }
      }
    }
    else
    {
      // Irregular: the lattice points with all indices >= 1 (an inner
      // triangle of level s - 3), and a strip along each edge zipping the
      // edge's points to the inner triangle's side.
      for (int a = 1; a + 1 < s; ++a)
      {
        for (int b = 1; a + b + 1 <= s; ++b)
        {
          if (a + b <= s - 2)
          {
            addTriangle(latticePoint(a, b), latticePoint(a + 1, b), latticePoint(a, b + 1));
          }
          if (a + b <= s - 3)
          {
            addTriangle(latticePoint(a + 1, b), latticePoint(a + 1, b + 1), latticePoint(a, b + 1));
          }
        }
      }
      const int m = s - 3; // segments of each inner side
      for (int k = 0; k < 3; ++k)
      {
        // Inner side parallel to edge k, from near corner k+1 to near
        // corner k+2: lattice index of corner k equal to 1.
        auto inner = [&](int q) {
          int idx[3];
          idx[k] = 1;
          idx[Next(k)] = s - 2 - q;
          idx[Prev(k)] = 1 + q;
          return latticePoint(idx[1], idx[2]);
        };
        const int nk = n[k];
        int p = 0;
        int q = 0;
        while (p < nk || q < m)
        {
          // Advance on the side whose next point comes first along the edge.
          const double nextOuter = static_cast<double>(p + 1) / nk;
          const double nextInner = (q + 1.5) / (s - 1);
          if (q == m || (p < nk && nextOuter <= nextInner))
          {
            addTriangle(edgePoint(t, k, p, nk), edgePoint(t, k, p + 1, nk), inner(q));
            ++p;
          }
          else
          {
            addTriangle(edgePoint(t, k, p, nk), inner(q + 1), inner(q));
            ++q;
          }
        }
      }
    }
    if (estimate)
    {
      // Each point gets the largest estimate of the triangles holding it.
      const std::size_t at = static_cast<std::size_t>(t) * nc;
      const double* probe = probeBounds.empty() ? nullptr : probeBounds.data() + at;
      const double* whole = triangleBounds.empty() ? nullptr : triangleBounds.data() + at;
      for (const Contribution& c : contributions)
      {
        double* e = output.ErrorEstimate.data() + static_cast<std::size_t>(c.Id) * nc;
        if (whole)
        {
          for (int j = 0; j < nc; ++j)
          {
            e[j] = std::max(e[j], whole[j]);
          }
          continue;
        }
        const double* interpolated = output.Values.data() + static_cast<std::size_t>(c.Id) * nc;
        in.ModelError(t, c.B, interpolated, error.data());
        for (int j = 0; j < nc; ++j)
        {
          const double scale = modelScale.empty() ? 1.0 : modelScale[at + j];
          e[j] = std::max(e[j], errorOptions.ModelSafetyFactor * scale * error[j]);
          if (probe)
          {
            e[j] = std::max(e[j], probe[j]);
          }
        }
      }
    }
  }

  // The constrained edges of the input as polylines of output points.
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
      const int n = segments[lo];
      output.LinePoints.push_back(pointId[a]);
      for (int j = 1; j < n; ++j)
      {
        output.LinePoints.push_back(edgeFirst[lo] + (a < b ? j : n - j) - 1);
      }
      output.LinePoints.push_back(pointId[b]);
    }
    output.LineOffsets.push_back(static_cast<int>(output.LinePoints.size()));
  }
}

} // namespace penumbra
