// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReconstructionInternals.h
 * @brief The state of a built Reconstruction (Reconstruction::Internals)
 * and the declaration of its steps. Private to Penumbra::Reconstruction.
 *
 * Each group of members is defined in the file of its concept:
 * - penumbraReconstruction.cxx: validation, Build and the public queries;
 * - penumbraSampleMeshTopology.cxx: unique edges, incidences, sectors;
 * - penumbraGradientFit.cxx: least-squares fits per sector;
 * - penumbraLineContinuity.cxx: agreement across order-1 lines;
 * - penumbraCloughTocher.cxx: element geometry, control nets, evaluation;
 * - penumbraNonNegativity.cxx: the gradient repair and its rounding slack;
 * - penumbraPointLocation.cxx: barycentrics and the location grid;
 * - penumbraErrorModel.cxx: corner models and probe calibration;
 * - penumbraResampling.cxx: subdivision for display.
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraReconstructionInternals_h
#define penumbraReconstructionInternals_h

#include "penumbraCloughTocher.h"
#include "penumbraGradientFit.h"
#include "penumbraReconstruction.h"

#include <cstddef>
#include <vector>

namespace penumbra
{
namespace detail
{

/// Throws InputError for a triangle id out of [0, nt).
void CheckTriangle(int t, int nt);

} // namespace detail

struct Reconstruction::Internals
{
  using TriangleGeometry = detail::TriangleGeometry;
  using Net = detail::Net;
  using FitWorkspace = detail::FitWorkspace;

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

  // penumbraReconstruction.cxx
  void Validate() const;

  // penumbraSampleMeshTopology.cxx
  void BuildEdges();
  void BuildPointIncidences();
  void BuildSectors();

  // penumbraGradientFit.cxx
  void GatherNeighbours(int s, int minPoints, int maxRings, FitWorkspace& w) const;
  void FactorFit(int v, int maxColumns, FitWorkspace& w) const;
  void SolveFit(int columns, FitWorkspace& w, double* out, int stride) const;
  void SecantBounds(int v, const FitWorkspace& w, std::vector<double>& bounds) const;
  void LimitGradient(const std::vector<double>& bounds, double* fit, int stride);
  void SolveCollinear(int v, FitWorkspace& w, double* out, int stride) const;
  void FitGradients();

  // penumbraLineContinuity.cxx
  double EdgeDirection(int v, int edge, int& w, double& tu, double& tv) const;
  double LineDerivative(int v, int edge, int channel) const;
  void EnforceLineContinuity();

  // penumbraCloughTocher.cxx
  void ComputeGeometry();
  void ComputeNet(int t, int channel, Net& net) const;
  void ComputeZeroGradientNet(int t, int channel, Net& net) const;
  void Evaluate(int t, const double bIn[3], double* value, double* gradient) const;
  void EvaluateWithNets(
    int t, const Net* nets, const double bIn[3], double* value, double* gradient) const;

  // penumbraNonNegativity.cxx
  void ComputeNetSlack(const std::vector<double>& base);
  void ProjectCornerGradients();
  void EnforceNonNegativity();

  // penumbraOvershoot.cxx
  void LimitOvershoot();

  // penumbraPointLocation.cxx
  void Barycentric(int t, double u, double v, double b[3]) const;
  void BuildGrid();
  int FindTriangle(double u, double v, double barycentric[3]) const;

  // penumbraErrorModel.cxx
  void ModelError(int t, const double b[3], const double* interpolated, double* error) const;
  void CalibrateWithProbes(const ErrorProbes* probes, const ErrorEstimateOptions& options,
    std::vector<double>& bound, std::vector<double>& modelScale) const;

  // penumbraResampling.cxx
  class Resampler;
};

} // namespace penumbra

#endif
