// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraReconstruction.h
 * @brief Piecewise-smooth reconstruction of a radiance function from its
 * samples on one receiver (Lischinski, Tampieri and Greenberg 1991, section
 * 6, done in 2D): C1 inside each smooth region, C0 across order-1
 * discontinuities, a jump across order-0 ones, non-negative everywhere;
 * resampling for display and an error estimate.
 *
 * Holds the input (SampleMesh), the settings (ReconstructionOptions,
 * ResampleOptions, ErrorEstimateOptions), the outputs and diagnostics
 * (ReconstructionStatistics, ResampledMesh), the probe residuals an adaptive
 * sampler may supply (ErrorProbes), and the Reconstruction class. Plain C++
 * with no VTK or third-party type. A built Reconstruction is immutable: its
 * const queries are thread-safe.
 *
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraReconstruction_h
#define penumbraReconstruction_h

#include "penumbraReconstructionModule.h" // for export macro
#include "penumbraVector.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{

/**
 * One receiver's samples, in its own 2D plane coordinates.
 *
 * - Points: (u, v) pairs, 2 doubles per point.
 * - Values: NumberOfChannels doubles per point (e.g. RGB radiance).
 * - Triangles: 3 point ids per triangle, counter-clockwise (positive area).
 *   Points used by no triangle are ignored.
 * - ConstrainedEdges: 2 point ids per edge, with one entry of EdgeOrders per
 *   edge: 1 = slope discontinuity (C0 across), 2 = second-derivative
 *   discontinuity (C1 across: treated as a smooth edge), -1 = receiver
 *   outline, 0 = value discontinuity. Order-0 lines must be represented by
 *   duplicated points (the mesh is cut there); an edge labelled 0 or -1 that
 *   is nevertheless shared by two triangles is treated like order 1 (C0).
 *   Edges that border no triangle are ignored; duplicates are allowed (the
 *   lowest order wins, -1 counting as lowest).
 * - EdgeLabels: optional, one per constrained edge (e.g. the light or
 *   occluder the line comes from). The compact display joins two edges
 *   that continue each other in a straight line into one polyline only
 *   when their orders and labels agree.
 */
struct SampleMesh
{
  int NumberOfChannels = 3;           ///< channels per value, >= 1 [3]
  std::vector<double> Points;         ///< (u, v) per point
  std::vector<double> Values;         ///< NumberOfChannels per point
  std::vector<int> Triangles;         ///< 3 point ids per triangle, CCW
  std::vector<int> ConstrainedEdges;  ///< 2 point ids per constrained edge
  std::vector<int> EdgeOrders;        ///< one order per constrained edge
  std::vector<int> EdgeLabels;        ///< empty, or one label per constrained edge

  /// Number of points (Points.size() / 2).
  int GetNumberOfPoints() const { return static_cast<int>(this->Points.size() / 2); }
  /// Number of triangles (Triangles.size() / 3).
  int GetNumberOfTriangles() const { return static_cast<int>(this->Triangles.size() / 3); }
  /// Append a point with NumberOfChannels values; returns its id.
  int AddPoint(double u, double v, const double* values)
  {
    this->Points.push_back(u);
    this->Points.push_back(v);
    this->Values.insert(this->Values.end(), values, values + this->NumberOfChannels);
    return this->GetNumberOfPoints() - 1;
  }
  /// Append a point with an RGB value (NumberOfChannels must be 3).
  int AddPoint(double u, double v, const RGB& value)
  {
    const double values[3] = { value.R, value.G, value.B };
    return this->AddPoint(u, v, values);
  }
  /// Append a triangle (counter-clockwise); returns its id.
  int AddTriangle(int a, int b, int c)
  {
    this->Triangles.push_back(a);
    this->Triangles.push_back(b);
    this->Triangles.push_back(c);
    return this->GetNumberOfTriangles() - 1;
  }
  /// Append a constrained edge between points a and b with the given order.
  void AddConstrainedEdge(int a, int b, int order)
  {
    this->ConstrainedEdges.push_back(a);
    this->ConstrainedEdges.push_back(b);
    this->EdgeOrders.push_back(order);
  }
};

/// Interpolation scheme.
enum class ReconstructionMode
{
  Linear,      ///< linear over each sample triangle (C0, Mach bands)
  CloughTocher ///< C1 piecewise cubic inside smooth regions [default]
};

/// Settings of Reconstruction::Build; defaults in brackets.
struct ReconstructionOptions
{
  /// Interpolation scheme. [CloughTocher]
  ReconstructionMode Mode = ReconstructionMode::CloughTocher;
  /// Gradient fits use the ring-1 neighbours of a point (within its sector)
  /// and add ring 2 when ring 1 has fewer points than this. [9], in [5, 1000]
  int MinimumFitPoints = 9;
  /// Scale gradients toward zero where a control net dips below zero, so
  /// non-negative samples give a non-negative interpolant. [true]
  bool EnforceNonNegativity = true;
  /// Take each sector's gradient from its cubic fit (the error model's:
  /// wider stencil, one order more accurate) where that fit exists, instead
  /// of the quadratic fit. Measured on jittered grids: RMS error 5-10 times
  /// lower on a smooth bump at 40^2-80^2 cells, only 1.4 times lower with
  /// an unlabelled curvature jump (max error sometimes higher), and the
  /// error estimate, which then shares the interpolant's gradients, is less
  /// reliable on coarse meshes (covered 80% instead of 98% of points on 10^2
  /// cells). [false]
  bool CubicGradients = false;
  /// Fit the cubic error model (a second, wider least-squares fit per
  /// sector) used by EstimateErrors and Resample's error arrays. Without it
  /// the model is the quadratic gradient fit, and Build is about twice as
  /// fast: for interpolants rebuilt many times and never asked for errors
  /// (the adaptive sampler's passes). Ignored (the model is fitted) when
  /// CubicGradients is on. [true]
  bool ErrorModel = true;
  /// Scale each point's gradients so that along every edge of its triangles
  /// the interpolant changes by at most 3 times the spread of the values
  /// around the point (or the change of the value along the edge): no
  /// overshoot over triangles much larger than the point's smallest, such
  /// as a corner of a contact shadow sampled a fraction of a millimetre
  /// apart that is also the corner of a triangle 30 cm long (design notes,
  /// "Overshoot over large triangles"). The adaptive sampler's interpolants
  /// turn it off: they look for where the samples are too sparse, which the
  /// overshoot shows. [true]
  bool LimitOvershoot = true;
};

/// What Build did, for diagnostics and tests.
struct ReconstructionStatistics
{
  int Sectors = 0;            ///< (point, sector) pairs with a gradient
  int QuadraticFits = 0;      ///< sectors fitted with a quadratic
  int LinearFits = 0;         ///< sectors that fell back to a linear fit
  int ZeroGradients = 0;      ///< sectors with no usable neighbour (gradient 0)
  /// (sector, channel) fitted gradients scaled down to twice the steepest
  /// secant to a point of their stencil (a nearly degenerate stencil)
  int LimitedGradients = 0;
  /// (sector, channel) gradients scaled down so that the interpolant does not
  /// overshoot over triangles much larger than the point's smallest
  int OvershootGradients = 0;
  int CubicModels = 0;        ///< sectors whose error model is a cubic fit
  int ConstrainedSectors = 0; ///< sectors projected for continuity across order-1 edges
  int ProjectedGradients = 0; ///< (point, channel) gradients moved for non-negative corners
  int ScaledGradients = 0;    ///< (point, channel) gradients reduced for non-negativity
  int ZeroedGradients = 0;    ///< of which reduced to zero
  int RepairPasses = 0;       ///< passes of the non-negativity repair
};

/**
 * Settings of Reconstruction::Resample; defaults in brackets.
 *
 * The display is linear over the output triangles. Three ways to choose how
 * finely each input triangle is cut, the first that applies: per-edge counts
 * from TargetEdgeLength when it is positive; adaptive counts from
 * DisplayTolerance when it is positive; else SubdivisionLevel everywhere.
 */
struct ResampleOptions
{
  /// Uniform subdivision level s, used when TargetEdgeLength and
  /// DisplayTolerance are 0: every input triangle becomes s^2 congruent
  /// sub-triangles (1 keeps it). On the direct-light floors of strip,
  /// occluder, seven and blind its RMS error against exact values is
  /// 0.05-0.13% at 2, below the sampling tolerance (0.2%), and 0.02-0.07% at 4
  /// for 4 times the output (Benchmarks/defaults_benchmark.py). [2], in [1, 1024]
  int SubdivisionLevel = 2;
  /// Adaptive display: when > 0 (and TargetEdgeLength is 0), each input
  /// triangle is cut only as finely as needed for the display to stay within
  /// this tolerance of the interpolant, relative to the receiver's mean value
  /// (area-weighted, per channel): the smallest level n, up to
  /// MaximumSubdivisionLevel, at which the linear interpolant over its n^2
  /// sub-triangles is within it at a lattice of points in each. An edge gets
  /// the larger level of its two triangles, so shared edges are split
  /// identically (no T-junction). 0 = SubdivisionLevel everywhere. Measured
  /// against level 2 (Documentation/benchmarks.md): at 0.005 the direct-light
  /// floors are 1.5 to 2.2 times smaller with smaller largest and
  /// 99th-percentile errors but up to twice the RMS error, and the Cornell box
  /// twice as large; so the default stays the uniform display. [0], in [0, 1]
  double DisplayTolerance = 0.0;
  /// When > 0, each input edge is split into ceil(length / TargetEdgeLength)
  /// segments (clamped to [1, MaximumSubdivisionLevel]); a triangle whose
  /// three edges get the same count is subdivided regularly, others get a
  /// lattice inside and strips along their edges. Shared edges are split
  /// identically on both sides, so the output has no T-junction. [0], >= 0,
  /// in the units of the points.
  double TargetEdgeLength = 0.0;
  /// Upper bound of the per-edge count with TargetEdgeLength or
  /// DisplayTolerance. [64], in [1, 1024]
  int MaximumSubdivisionLevel = 64;
  /// Compact display: the output is merged (DecimateDisplay,
  /// penumbraDisplayDecimation.h) wherever the linear display stays within a
  /// tolerance of the dense display (the uniform SubdivisionLevel) at every
  /// dense point, and of the display it is merged from at the midpoint of
  /// every edge it removes; the outline and the constrained edges keep their
  /// shape. With SubdivisionLevel 2 and CloughTocher, an input edge is only
  /// halved where the interpolant at its midpoint is more than half the
  /// tolerance off the chord, so nearly linear regions are not cut first. Each
  /// channel's tolerance is the larger of this fraction of the receiver's
  /// mean value (area-weighted over the samples) and
  /// CompactIndirectTolerance times IndirectRadiance. This part is for
  /// values exact up to the reconstruction: on the direct-light floors
  /// (0.05-0.13% RMS against exact values) 5e-4 gives 1.5 to 3.1 times fewer
  /// triangles for at most 6% more error, the Cornell box 1.5 times fewer at
  /// the same error (Documentation/benchmarks.md, "Compact display"). Both
  /// parts 0 (or this one 0 and no IndirectRadiance): the dense display.
  /// [5e-4], in [0, 1]
  double CompactTolerance = 5e-4;
  /// Compact display, interreflections: the display may also move by this
  /// fraction of IndirectRadiance, per channel, though by no more than a
  /// quarter of the value at the point (dark places, such as the ceiling
  /// inside a light fixture, keep what light they have). Interreflections
  /// computed on the coarse level are off by at least that much, in absolute
  /// terms rather than relative to each surface: against a path-traced
  /// reference, furnished_room(1000)'s floors by 0.85% of the scene's mean
  /// indirect radiance (RMS), its desk tops, walls and ceilings by 2-4.5%,
  /// its book faces alike (several % of their own radiance). 0.01 gives that
  /// room 7.3 times fewer triangles for at most 8% more error at the
  /// reference's probes. [0.01], in [0, 1]
  double CompactIndirectTolerance = 0.01;
  /// Per channel, the scene's area-mean indirect radiance (what the
  /// interreflections add to the direct light), in the units of the values,
  /// where the values' error scales with it: vtkPenumbraRadianceReconstructor
  /// passes vtkPenumbraProgressiveShooter's MeanIndirectRadiance when the
  /// shots ran on the coarse level (a large scene); empty otherwise. [],
  /// NumberOfChannels entries >= 0
  std::vector<double> IndirectRadiance;
  /// Fill ResampledMesh::ErrorEstimate (see ErrorEstimateOptions). [true]
  bool ComputeErrorEstimate = true;
};

/**
 * Probe residuals from an adaptive sampler: at candidate points of some
 * triangles, the true value minus the interpolant (any sign), e.g. the
 * candidates of the last refinement pass that were found good enough. They
 * should be taken against this Reconstruction's interpolant (same mode and
 * samples); residuals against a linear interpolant bound the Linear mode's
 * error and over-estimate CloughTocher's.
 */
struct ErrorProbes
{
  std::vector<int> Triangles;    ///< input triangle of each probe
  std::vector<double> Residuals; ///< NumberOfChannels per probe: true - interpolant

  /// Append one probe of triangle `triangle` with `channels` residuals.
  void Add(int triangle, const double* residuals, int channels)
  {
    this->Triangles.push_back(triangle);
    this->Residuals.insert(this->Residuals.end(), residuals, residuals + channels);
  }
};

/**
 * Settings of the error estimate; defaults in brackets.
 *
 * Meaning: an estimate (not a proof) of |true - reconstructed| at a point, in
 * the units of the values, per channel, assuming exact samples (add the
 * evaluator's own error if it has any). It is meant to be at least the true
 * error at most points (>= 90%) and on average (ratio of the means over a
 * surface) within a small factor of it (<= 10). At a point x of triangle t:
 *
 *   max( ModelSafetyFactor * k_t * max_c |T_c(x) - I(x)|,
 *        ProbeSafetyFactor * max |probe residual of t| ),
 *
 * T_c the local cubic model of corner c (a cubic Taylor polynomial fitted
 * per sector), I the interpolant, and k_t = min(1, a / m) for a triangle
 * with probes (1 without): a the largest |probe residual| of t, m the largest
 * model term max_c |T_c - I| at t's edge midpoints, where an adaptive
 * sampler's probes lie: where the model claims more error than was measured
 * it is scaled down to the measurement. With PerTriangle the first term is
 * replaced by its maximum over t (more conservative, constant per triangle).
 * An output point of Resample gets the largest value over the input
 * triangles holding it. The coverage measured with the default factors is
 * in the design notes.
 */
struct ErrorEstimateOptions
{
  /// Multiplies the model estimate. [1.5], in [0, 1e6]
  double ModelSafetyFactor = 1.5;
  /// Multiplies the largest |probe residual| of a triangle. [2], in [0, 1e6]
  double ProbeSafetyFactor = 2.0;
  /// Lattice level at which the model is maximised over a triangle (for
  /// ComputeTriangleErrorBounds and PerTriangle). [4], in [1, 64]
  int ModelLevel = 4;
  /// Use the per-triangle maximum of the model instead of its pointwise
  /// value. [false]
  bool PerTriangle = false;
};

/// Output of Reconstruction::Resample.
struct ResampledMesh
{
  int NumberOfChannels = 0;
  std::vector<double> Points;        ///< (u, v) per output point
  std::vector<double> Values;        ///< NumberOfChannels per output point
  std::vector<int> Triangles;        ///< 3 output point ids per triangle, CCW
  std::vector<int> SourceTriangle;   ///< input triangle of each output triangle
  std::vector<int> SourcePoint;      ///< input point of each output point, or -1
  std::vector<double> ErrorEstimate; ///< NumberOfChannels per point (or empty)
  /// The input's constrained edges as polylines of output points: edge i of
  /// SampleMesh::ConstrainedEdges runs through LinePoints[LineOffsets[i]] ..
  /// LinePoints[LineOffsets[i + 1] - 1], from its first point to its second
  /// (none when it borders no triangle). LineOffsets has one entry per edge + 1.
  std::vector<int> LineOffsets;
  std::vector<int> LinePoints;

  /// Number of output points.
  int GetNumberOfPoints() const { return static_cast<int>(this->Points.size() / 2); }
  /// Number of output triangles.
  int GetNumberOfTriangles() const { return static_cast<int>(this->Triangles.size() / 3); }
};

/**
 * The reconstructed function of one receiver. Build it from a SampleMesh,
 * then evaluate it anywhere, resample it for display, estimate its error.
 */
class PENUMBRARECONSTRUCTION_EXPORT Reconstruction
{
public:
  Reconstruction();
  ~Reconstruction();
  Reconstruction(const Reconstruction&);
  Reconstruction& operator=(const Reconstruction&);
  Reconstruction(Reconstruction&&) noexcept;
  Reconstruction& operator=(Reconstruction&&) noexcept;

  /**
   * Build the interpolant of `mesh` (copied). Throws InputError naming the
   * problem for bad input: array sizes, point ids out of range, non-finite
   * coordinates or values, a triangle that is not counter-clockwise or has
   * zero area, an unknown edge order, or a setting out of range.
   */
  void Build(
    const SampleMesh& mesh, const ReconstructionOptions& options = ReconstructionOptions());

  /// The mesh given to Build.
  const SampleMesh& GetMesh() const;
  /// The options given to Build.
  const ReconstructionOptions& GetOptions() const;
  /// Diagnostics of the last Build.
  const ReconstructionStatistics& GetStatistics() const;
  /// Channels per value (the mesh's NumberOfChannels; 0 before Build).
  int GetNumberOfChannels() const;

  /**
   * Value (NumberOfChannels doubles) and optionally gradient (2 doubles per
   * channel: d/du, d/dv) of the interpolant at the point of triangle
   * `triangle` with barycentric coordinates `barycentric` (w.r.t. its three
   * points in order; clamped to the triangle and renormalised). On an edge
   * or a point it returns this triangle's side (all sides agree except
   * across order-0 cuts, and for the gradient across order-1 edges).
   */
  void Evaluate(int triangle, const double barycentric[3], double* value,
    double* gradient = nullptr) const;

  /**
   * Same at plane point (u, v), taken in triangle `triangle` (a point
   * outside it is moved into it by clamping its barycentric coordinates).
   * Returns false when (u, v) lies outside the triangle by more than 1e-9
   * in barycentric coordinates.
   */
  bool EvaluateAt(int triangle, double u, double v, double* value,
    double* gradient = nullptr) const;

  /**
   * Barycentric coordinates of (u, v) in triangle `triangle` (unclamped).
   */
  void GetBarycentric(int triangle, double u, double v, double barycentric[3]) const;

  /**
   * The triangle containing (u, v) (barycentric coordinates >= -1e-9), by a
   * uniform grid built in Build; -1 if none. Fills `barycentric` when given
   * (unclamped). On a shared edge or at a cut any of the triangles there may
   * be returned.
   */
  int FindTriangle(double u, double v, double barycentric[3] = nullptr) const;

  /**
   * Gradient of the sector of corner `corner` (0..2) of `triangle`: 2
   * doubles per channel (d/du, d/dv), after the continuity projection and
   * the non-negativity scaling: the interpolant's gradient at that corner in
   * CloughTocher mode. In Linear mode it is the fitted gradient (not used by
   * the interpolant).
   */
  void GetCornerGradient(int triangle, int corner, double* gradient) const;

  /**
   * Pointwise error estimate of ErrorEstimateOptions at `count` points: the
   * point i lies in triangle triangles[i] at barycentric coordinates
   * barycentrics[3i..3i+2] (clamped). Writes NumberOfChannels non-negative
   * doubles per point into `errors`. `probes` may be null (model term
   * only). PerTriangle is not used here. Throws InputError as
   * ComputeTriangleErrorBounds does, or for a triangle id out of range.
   */
  void EstimateErrors(int count, const int* triangles, const double* barycentrics,
    const ErrorProbes* probes, const ErrorEstimateOptions& options, double* errors) const;

  /**
   * Per-triangle error bounds: NumberOfChannels doubles per input triangle,
   * max(ModelSafetyFactor * (model maximised over a lattice of ModelLevel),
   * ProbeSafetyFactor * max |residual| of its probes). `probes` may be
   * null. Throws InputError for a probe with a bad triangle id, a residual
   * count that is not NumberOfChannels per probe, a non-finite residual, or
   * settings out of range.
   */
  void ComputeTriangleErrorBounds(const ErrorProbes* probes,
    const ErrorEstimateOptions& options, std::vector<double>& bounds) const;

  /**
   * Resample for display: every input triangle is subdivided (see
   * ResampleOptions) and the interpolant evaluated at the new points (input
   * points keep their sample values exactly). Output points on an edge
   * shared by two triangles are shared (no cracks; also across order-1
   * edges, where the values agree); across order-0 cuts they are duplicated
   * (same position, each side's value). Output triangles are
   * counter-clockwise. With ComputeErrorEstimate, ErrorEstimate gets the
   * estimate described at ErrorEstimateOptions, using `probes` when given.
   * Throws InputError for bad settings or probes.
   */
  void Resample(const ResampleOptions& options, ResampledMesh& output,
    const ErrorProbes* probes = nullptr,
    const ErrorEstimateOptions& errorOptions = ErrorEstimateOptions()) const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace penumbra

#endif
