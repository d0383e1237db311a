// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraAdaptiveSampler.h
 * @brief Adaptive supersampling of one receiver inside the regions bounded by
 * its discontinuities (Lischinski, Tampieri and Greenberg 1991, section 4),
 * done in 2D on the discontinuity mesh and judged against the reconstruction
 * that will be displayed (section 6); and a uniform baseline for comparisons.
 *
 * Holds the evaluation function type (RadianceBatchFunction), the settings
 * (AdaptiveSamplingSettings), the result and its statistics, and the entry
 * points SampleReceiver and SampleReceiverUniform. The same mesh, settings
 * and function give the same output, whatever order or thread count the
 * function uses inside a batch; the functions are thread-safe and call the
 * evaluation function only from the calling thread. Plain C++ with no VTK or
 * CGAL type; the triangulation lives in the core's CGAL translation unit.
 *
 * Design notes: Documentation/design/sampling.md
 */
#ifndef penumbraAdaptiveSampler_h
#define penumbraAdaptiveSampler_h

#include "penumbraMeshingModule.h" // for export macro
#include "penumbraDiscontinuityMesher.h"
#include "penumbraReconstruction.h"
#include "penumbraVector.h"

#include <functional>
#include <vector>

namespace penumbra
{

/**
 * Evaluates the radiance at `count` points of the receiver (3D, in its
 * plane): fills values[0 .. count - 1]. Called from the sampler's thread
 * with a batch per pass; may evaluate in parallel. It must be a function of
 * the point (same point, same value) for the result to be deterministic.
 */
using RadianceBatchFunction = std::function<void(const Vec3* points, int count, RGB* values)>;

/// Settings of SampleReceiver; defaults in brackets.
struct AdaptiveSamplingSettings
{
  /// Tolerance on |value - interpolant| at candidate points, relative to the
  /// receiver's mean radiance, per channel. [0.002], in [0, 1]; 0 means
  /// AbsoluteTolerance alone.
  double SamplingTolerance = 0.002;
  /// Absolute floor of the tolerance, in the units of the values
  /// (W sr^-1 m^-2). [0], >= 0. With both tolerances 0, refinement stops
  /// only at the budget, the passes or the minimum edge length.
  double AbsoluteTolerance = 0.0;
  /// Sample budget of the receiver: number of point copies (values),
  /// initial ones included. No insertion is made beyond it (the initial mesh
  /// is always kept whole). [200000], >= 1
  int MaximumSamplesPerSurface = 200000;
  /// Minimum feature size, relative to the receiver's diameter (bounding-box
  /// diagonal): triangles narrower than this (smallest altitude) are not
  /// refined, nor edges shorter than it split. For a receiver narrower than
  /// it is long, the width bound is this fraction of its width (2 area /
  /// diameter) instead, so a thin strip is still refined along its length.
  /// Near a small feature, one whose discontinuity lines are shorter than a
  /// tenth of the receiver's diameter (e.g. the shadow of an occluder 1e-4
  /// the receiver's size), the bound is this fraction of ten times their
  /// length instead: a feature is resolved to the same fraction of its own
  /// size, whatever its size. Bounds the cost at features no finite sampling
  /// resolves (penumbrae shrinking to nothing at contact corners, slivers
  /// between nearly coincident lines, unmeshed EEE curves). Whatever the
  /// value, 0 included, nothing narrower than 1e-9 of the diameter, or than
  /// 2.2e-9 of the receiver's largest coordinate (1e7 ulps: the output is
  /// written in 3D and projected again), is refined. [1e-4], in [0, 1]
  double MinimumFeatureSize = 1e-4;
  /// Longest edge allowed, in scene units (absolute, so that a caller can
  /// give all receivers one sample spacing): longer edges are split whatever
  /// their residuals. Room for light that arrives later (interreflection,
  /// weaker shooters) and varies where this pass's light does not, e.g. in
  /// an umbra. [0 = no limit], >= 0
  double MaximumEdgeLength = 0.0;
  /// Largest number of refinement passes. [100], in [0, 10000]
  int MaximumPasses = 100;
  /// Also probe each triangle at its centroid (besides its edge midpoints).
  /// Measured on the direct-light floors of "seven", "blind" and "cornell"
  /// (penumbraDirectAccuracyBenchmark, tolerance 0.002): sample counts
  /// within 1% and errors within 7% of the default's, for 1.8 times the
  /// evaluations; a safety net for features strictly inside triangles
  /// (none arise between the discontinuity lines of direct light). [false]
  bool ProbeCentroids = false;
  /// Distance, relative to the receiver's diameter, by which a point on an
  /// order-0 line or the outline is moved into its side before evaluation
  /// (see the file documentation): far above rounding (1e-16), far below
  /// any feature; the value then differs from the limit on the line by
  /// about gradient * SideOffset * diameter. [1e-9], in (0, 1e-2]
  double SideOffset = 1e-9;
  /// The interpolant candidates are compared with: use the reconstruction
  /// that will be displayed. [CloughTocher, default options]
  ReconstructionOptions Interpolant;
};

/// What SampleReceiver (or SampleReceiverUniform) did.
struct AdaptiveSamplingStatistics
{
  int InitialSamples = 0;      ///< point copies of the input mesh
  int Samples = 0;             ///< point copies (values) of the output mesh
  long long Evaluations = 0;   ///< points passed to the evaluation function
  int Passes = 0;              ///< refinement passes that inserted points
  int LocalizedPasses = 0;     ///< passes that rebuilt the interpolant only around the
                               ///< points the previous pass inserted
  int FaceInsertions = 0;      ///< centroids inserted
  int EdgeInsertions = 0;      ///< edge midpoints inserted (constrained or not)
  int ConstrainedSplits = 0;   ///< of which on constrained edges
  int RejectedInsertions = 0;  ///< insertions refused (would be degenerate; should be rare)
  int UnrefinedFailures = 0;   ///< failing triangles of the last pass left as they are
                               ///< (narrower than MinimumFeatureSize, or budget/passes exhausted)
  int Irregularities = 0;      ///< input vertices merged / constraints crossing after
                               ///< rounding to the plane frame (0 for a valid mesh)
  bool BudgetReached = false;  ///< MaximumSamplesPerSurface stopped refinement
  bool Converged = false;      ///< the last pass found no failing refinable triangle
  double MaximumResidual = 0;  ///< largest |residual| / tol over the final probes
  double Seconds = 0;          ///< wall time, evaluation included
  double EvaluationSeconds = 0; ///< wall time spent in the evaluation function
};

/**
 * Output: the refined mesh and its samples, in two equivalent forms (the
 * 3D ReceiverMesh of the mesher's contract, and the 2D SampleMesh of the
 * reconstruction: same point and triangle ids), and the error probes.
 */
struct AdaptiveSamplingResult
{
  /// Refined mesh: input points keep their exact 3D position; points are
  /// duplicated across order-0 lines; PointVertex holds the refined
  /// triangulation's vertex ids (the input's geometric vertices renumbered
  /// in order of first use, then the inserted ones); Segments cover every
  /// input segment (split where points were inserted) with its order and
  /// source, PointA/PointB on the segment's left side (its right when the
  /// left is not meshed), as in the mesher's output.
  ReceiverMesh Mesh;
  /// Radiance of each point of Mesh (one value per side on order-0 lines).
  std::vector<RGB> Values;
  /// The same samples in the plane frame below: points (u, v), values,
  /// triangles, constrained edges with orders (order-0 edges once per side).
  /// Ready for Reconstruction::Build.
  SampleMesh Samples;
  /// Residuals (value - interpolant) of the final pass's candidates, three
  /// per triangle of Samples (edge midpoints; four with ProbeCentroids),
  /// against the interpolant of Samples with the settings' Interpolant
  /// options; empty for the uniform baseline.
  ErrorProbes Probes;
  /// Plane frame: a plane point (u, v) is Origin + u AxisU + v AxisV; Normal
  /// is the receiver's front normal (AxisU x AxisV).
  Vec3 Origin;
  Vec3 AxisU;
  Vec3 AxisV;
  Vec3 Normal;
  /// The receiver's mean radiance used as reference, and the tolerance, per
  /// channel, at the final pass.
  RGB ReferenceRadiance;
  RGB Tolerance;
  AdaptiveSamplingStatistics Statistics;
};

/**
 * Adaptively sample receiver `mesh` (a DiscontinuityMesher::MeshReceiver
 * output or any mesh of that layout) with the radiance function `evaluate`.
 * Throws InputError for an empty or inconsistent mesh (ids out of range, no
 * triangle, zero area), a missing function, or settings out of range.
 */
PENUMBRAMESHING_EXPORT AdaptiveSamplingResult SampleReceiver(const ReceiverMesh& mesh,
  const RadianceBatchFunction& evaluate,
  const AdaptiveSamplingSettings& settings = AdaptiveSamplingSettings());

/**
 * Uniform baseline: about `numberOfSamples` samples on `mesh`'s receiver
 * (its boundary vertices, i.e. those of the edges with a single kept side,
 * plus the nodes of a square grid of cell centres inside the kept region;
 * the grid spacing is adjusted so that the total is within about 1% of
 * `numberOfSamples` where possible), triangulated with the boundary edges as
 * the only constraints (interior discontinuity lines are ignored, as in a
 * classic radiosity mesh), every point evaluated with `evaluate` (order-0
 * boundary points inside their side, as in SampleReceiver). Probes are empty;
 * reconstruct it with ReconstructionMode::Linear for the classic result.
 * `settings` gives only SideOffset. Throws InputError as SampleReceiver,
 * and for numberOfSamples < 3.
 */
PENUMBRAMESHING_EXPORT AdaptiveSamplingResult SampleReceiverUniform(const ReceiverMesh& mesh,
  int numberOfSamples, const RadianceBatchFunction& evaluate,
  const AdaptiveSamplingSettings& settings = AdaptiveSamplingSettings());

} // namespace penumbra

#endif
