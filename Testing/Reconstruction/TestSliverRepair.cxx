// SPDX-License-Identifier: GPL-3.0-or-later
// RepairSlivers: a sliver turned clockwise by rounding is merged into its
// neighbour (or dropped on the outline), constrained edges through its apex
// are split, the repaired mesh covers the same area and reconstructs a
// linear field exactly; real clockwise triangles are left for Build to reject.
#include "penumbraReconstruction.h"
#include "penumbraScene.h" // InputError
#include "penumbraSliverRepair.h"
#include "penumbraTesting.h"

#include <cmath>
#include <cstdio>

using namespace penumbra;

namespace
{

double Linear(double u, double v)
{
  return 1.0 + 2.0 * u + 3.0 * v;
}

int AddLinearPoint(SampleMesh& m, double u, double v)
{
  const double value = Linear(u, v);
  return m.AddPoint(u, v, &value);
}

double TotalArea(const SampleMesh& m)
{
  double area = 0.0;
  for (int t = 0; t < m.GetNumberOfTriangles(); ++t)
  {
    const int* p = m.Triangles.data() + 3 * t;
    const double* a = m.Points.data() + 2 * p[0];
    const double* b = m.Points.data() + 2 * p[1];
    const double* c = m.Points.data() + 2 * p[2];
    area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
  }
  return area;
}

/// Largest error of the reconstruction of Linear at points inside the mesh.
double LinearError(const Reconstruction& r, double vMin)
{
  double worst = 0.0;
  const double samples[][2] = { { 0.5, 0.5 * vMin }, { 0.3, 0.1 }, { 0.7, 0.05 }, { 0.5, 0.4 },
    { 0.45, 0.5 * vMin + 0.05 } };
  for (const auto& s : samples)
  {
    double b[3];
    const int t = r.FindTriangle(s[0], s[1], b);
    PENUMBRA_EXPECT_MSG(t >= 0, "sample point outside the repaired mesh");
    if (t >= 0)
    {
      double value;
      r.Evaluate(t, b, &value);
      worst = std::max(worst, std::abs(value - Linear(s[0], s[1])));
    }
  }
  return worst;
}

/// a(0,0) b(1,0) e(0.5,1), apex c 1e-17 below a-b: triangle a-b-c is
/// clockwise; with `below`, the neighbour b-a-d with d(0.5,-1) shares a-b.
SampleMesh Sliver(bool below)
{
  SampleMesh m;
  m.NumberOfChannels = 1;
  const int a = AddLinearPoint(m, 0.0, 0.0);
  const int b = AddLinearPoint(m, 1.0, 0.0);
  const int c = AddLinearPoint(m, 0.5, -1e-17);
  const int e = AddLinearPoint(m, 0.5, 1.0);
  m.AddTriangle(a, b, c);
  if (below)
  {
    const int d = AddLinearPoint(m, 0.5, -1.0);
    m.AddTriangle(b, a, d);
  }
  m.AddTriangle(a, c, e);
  m.AddTriangle(c, b, e);
  m.AddConstrainedEdge(a, b, 1);
  m.EdgeLabels.push_back(7);
  m.AddConstrainedEdge(b, e, 0);
  m.EdgeLabels.push_back(8);
  return m;
}

} // namespace

PENUMBRA_TEST(TestInteriorSliverMerged)
{
  std::printf("-- interior sliver merged into its neighbour\n");
  SampleMesh m = Sliver(true);
  Reconstruction r;
  PENUMBRA_EXPECT_THROW(r.Build(m), InputError, "triangle 0 is not counter-clockwise");
  const SliverRepairResult repair = RepairSlivers(m);
  PENUMBRA_EXPECT(repair.Split == 1 && repair.Dropped == 0 && repair.Unrepaired == 0);
  PENUMBRA_EXPECT(m.GetNumberOfTriangles() == 4);
  PENUMBRA_EXPECT((repair.TriangleMap == std::vector<int>{ 0, 1, 2, 3 }));
  // The quad a-d-b-e keeps its area (diagonals 1 and 2).
  PENUMBRA_EXPECT_NEAR(TotalArea(m), 1.0, 1e-15);
  // a-b is now a-c and c-b, both order 1 with label 7, from input edge 0.
  PENUMBRA_EXPECT((m.ConstrainedEdges == std::vector<int>{ 0, 2, 1, 3, 2, 1 }));
  PENUMBRA_EXPECT((m.EdgeOrders == std::vector<int>{ 1, 0, 1 }));
  PENUMBRA_EXPECT((m.EdgeLabels == std::vector<int>{ 7, 8, 7 }));
  PENUMBRA_EXPECT((repair.EdgeOrigin == std::vector<int>{ 0, 1, 0 }));
  r.Build(m);
  PENUMBRA_EXPECT(LinearError(r, -1.0) < 1e-12);
}

PENUMBRA_TEST(TestOutlineSliverDropped)
{
  std::printf("-- sliver on the outline dropped\n");
  SampleMesh m = Sliver(false);
  const SliverRepairResult repair = RepairSlivers(m);
  PENUMBRA_EXPECT(repair.Split == 0 && repair.Dropped == 1 && repair.Unrepaired == 0);
  PENUMBRA_EXPECT((repair.TriangleMap == std::vector<int>{ -1, 0, 1 }));
  PENUMBRA_EXPECT_NEAR(TotalArea(m), 0.5, 1e-15);
  PENUMBRA_EXPECT((repair.EdgeOrigin == std::vector<int>{ 0, 1, 0 }));
  Reconstruction r;
  r.Build(m);
  PENUMBRA_EXPECT(LinearError(r, 0.0) < 1e-12);
}

PENUMBRA_TEST(TestClockwiseTriangleNotRepaired)
{
  std::printf("-- a clockwise triangle of real size is left for Build to reject\n");
  SampleMesh m;
  m.NumberOfChannels = 1;
  AddLinearPoint(m, 0.0, 0.0);
  AddLinearPoint(m, 1.0, 0.0);
  AddLinearPoint(m, 0.5, -1e-3);
  m.AddTriangle(0, 1, 2);
  const SampleMesh before = m;
  const SliverRepairResult repair = RepairSlivers(m);
  PENUMBRA_EXPECT(repair.GetNumberOfRepairs() == 0 && repair.Unrepaired == 1);
  PENUMBRA_EXPECT(m.Triangles == before.Triangles);
  Reconstruction r;
  PENUMBRA_EXPECT_THROW(r.Build(m), InputError, "triangle 0 is not counter-clockwise");
}

PENUMBRA_TEST(TestValidMeshUnchanged)
{
  std::printf("-- a valid mesh is unchanged\n");
  SampleMesh m = Sliver(true);
  m.Points[5] = 1e-17; // the apex above a-b: every triangle counter-clockwise
  const SampleMesh before = m;
  const SliverRepairResult repair = RepairSlivers(m);
  PENUMBRA_EXPECT(repair.GetNumberOfRepairs() == 0 && repair.Unrepaired == 0);
  PENUMBRA_EXPECT(m.Triangles == before.Triangles && m.ConstrainedEdges == before.ConstrainedEdges);
  PENUMBRA_EXPECT((repair.TriangleMap == std::vector<int>{ 0, 1, 2, 3 }));
}
