// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraRadianceReconstructor
 * @brief   Piecewise-smooth reconstruction of radiance from samples (paper §6).
 *
 * Input: a sample mesh with point data `Radiance` (3 components): triangles
 * with cell data `SurfaceId`, and optionally lines with cell data
 * `DiscontinuityOrder` (and `SourceId`) marking the discontinuities, as
 * produced by vtkPenumbraDiscontinuityMesher followed by vtkPenumbraRadianceEvaluator.
 * Points along order-0 lines must be duplicated (one copy per side).
 * The optional cell array `SamplingResidual` (3 components, from the
 * adaptive sampling of vtkPenumbraRadianceEvaluator: the largest |true -
 * interpolated| radiance seen at each triangle's last probes; negative
 * where a triangle was not probed) feeds the error estimate.
 *
 * For each surface the radiance is reconstructed with a C1 piecewise cubic
 * (Clough–Tocher) inside each smooth region, vertex gradients fitted by
 * least-squares quadratics among neighbours on the same side of order-0 and
 * order-1 lines; C0 across order-1 lines, a jump across order-0 lines, C1
 * across order-2 lines. Patches that would dip below zero are repaired by
 * scaling gradients, keeping continuity: the output is never negative. Mode
 * LINEAR interpolates the samples linearly instead (for comparison).
 *
 * Output (design contract): triangles covering every surface of the input,
 * each input triangle subdivided SubdivisionLevel times per edge (or as
 * finely as DisplayTolerance needs, or to TargetEdgeLength), then merged
 * where the display allows (CompactTolerance), with no T-junction, cell
 * data `SurfaceId`; point data `Radiance` (active
 * scalars; displaying it linearly interpolated is the reconstruction) and
 * `RadianceErrorEstimate` (3 components, same units: an estimate of the
 * reconstruction error at each point, from the sampling residuals and the
 * difference between the cubic and a wider cubic model); the input lines
 * carried through as polylines of output points with their
 * `DiscontinuityOrder` and `SourceId` (lines of one order and source that
 * continue each other straight may be joined into one).
 *
 * @sa vtkPenumbraRadianceEvaluator vtkPenumbraDiscontinuityMesher
 */
#ifndef vtkPenumbraRadianceReconstructor_h
#define vtkPenumbraRadianceReconstructor_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraRadianceReconstructor : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraRadianceReconstructor* New();
  vtkTypeMacro(vtkPenumbraRadianceReconstructor, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Reconstruction modes.
  enum Modes
  {
    LINEAR = 0,       ///< linear over each sample triangle (C0; Mach bands)
    CLOUGH_TOCHER = 1 ///< C1 piecewise cubic in each smooth region (default)
  };

  ///@{
  /**
   * The interpolant: LINEAR (0) or CLOUGH_TOCHER (1, default).
   */
  vtkSetClampMacro(Mode, int, LINEAR, CLOUGH_TOCHER);
  vtkGetMacro(Mode, int);
  void SetModeToLinear() { this->SetMode(LINEAR); }
  void SetModeToCloughTocher() { this->SetMode(CLOUGH_TOCHER); }
  ///@}

  ///@{
  /**
   * Display resampling: each input triangle is cut only as finely as needed
   * for the displayed radiance (linear over the output triangles) to stay
   * within this fraction of the surface's mean radiance of the reconstructed
   * cubic (see penumbra::ResampleOptions::DisplayTolerance). Default 0 (the
   * uniform display, SubdivisionLevel everywhere), range [0, 1].
   * Ignored when TargetEdgeLength is positive.
   */
  vtkSetClampMacro(DisplayTolerance, double, 0.0, 1.0);
  vtkGetMacro(DisplayTolerance, double);
  ///@}

  ///@{
  /**
   * Compact output: after the display resampling, output points are removed
   * wherever the displayed radiance stays within a tolerance of the dense
   * display (at the removed points and the midpoints of the removed edges);
   * the outline and the discontinuity lines keep their shape. The tolerance
   * is the larger of this fraction of the surface's mean radiance and
   * CompactIndirectTolerance's (see
   * penumbra::ResampleOptions::CompactTolerance). Default 5e-4, range
   * [0, 1]; 0 with CompactIndirectTolerance 0 gives the dense display.
   */
  vtkSetClampMacro(CompactTolerance, double, 0.0, 1.0);
  vtkGetMacro(CompactTolerance, double);
  ///@}

  ///@{
  /**
   * Compact output with interreflections: a tolerance of this fraction of
   * the scene's mean indirect radiance (the input's field
   * `MeanIndirectRadiance`, from vtkPenumbraProgressiveShooter; without it,
   * none), per channel, about the interreflections' own error (see
   * penumbra::ResampleOptions::CompactIndirectTolerance). Default 0.01,
   * range [0, 1].
   */
  vtkSetClampMacro(CompactIndirectTolerance, double, 0.0, 1.0);
  vtkGetMacro(CompactIndirectTolerance, double);
  ///@}

  ///@{
  /**
   * Uniform display resampling, when DisplayTolerance is 0: each input
   * triangle edge is divided into this many pieces (level s gives s*s output
   * triangles per input triangle). Default 2, range [1, 64]. Ignored when
   * TargetEdgeLength or DisplayTolerance is positive. Higher levels follow the
   * cubic interpolant more closely (see
   * penumbra::ResampleOptions::SubdivisionLevel) for s*s times the output.
   */
  vtkSetClampMacro(SubdivisionLevel, int, 1, 64);
  vtkGetMacro(SubdivisionLevel, int);
  ///@}

  ///@{
  /**
   * When positive, divide each input edge into pieces no longer than this
   * (scene units; at most 64 pieces per edge) instead of DisplayTolerance and
   * SubdivisionLevel.
   * Default 0 (off), range [0, 1e300].
   */
  vtkSetClampMacro(TargetEdgeLength, double, 0.0, 1e300);
  vtkGetMacro(TargetEdgeLength, double);
  ///@}

  ///@{
  /**
   * Repair cubic patches that would dip below zero (keeps continuity).
   * Default on. Off only to study the raw interpolant.
   */
  vtkSetMacro(EnforceNonNegativity, bool);
  vtkGetMacro(EnforceNonNegativity, bool);
  vtkBooleanMacro(EnforceNonNegativity, bool);
  ///@}

  ///@{
  /**
   * Compute the `RadianceErrorEstimate` point array. Default on.
   */
  vtkSetMacro(ComputeErrorEstimate, bool);
  vtkGetMacro(ComputeErrorEstimate, bool);
  vtkBooleanMacro(ComputeErrorEstimate, bool);
  ///@}

protected:
  vtkPenumbraRadianceReconstructor();
  ~vtkPenumbraRadianceReconstructor() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode;
  double DisplayTolerance;
  double CompactTolerance;
  double CompactIndirectTolerance;
  int SubdivisionLevel;
  double TargetEdgeLength;
  bool EnforceNonNegativity;
  bool ComputeErrorEstimate;

private:
  vtkPenumbraRadianceReconstructor(const vtkPenumbraRadianceReconstructor&) = delete;
  void operator=(const vtkPenumbraRadianceReconstructor&) = delete;
};

#endif
