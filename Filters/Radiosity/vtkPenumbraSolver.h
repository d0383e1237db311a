// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraSolver
 * @brief   The whole Penumbra pipeline in one filter, with good defaults:
 * scene in, solved and reconstructed radiance out.
 *
 * Runs vtkPenumbraDiscontinuityMesher -> vtkPenumbraRadianceEvaluator (exact direct light,
 * adaptive sampling) -> vtkPenumbraProgressiveShooter (interreflections; skipped
 * when Indirect is off) -> vtkPenumbraRadianceReconstructor on the scene of input
 * port 0 (design contract: polygons with cell data `Reflectance` and
 * `Emission`). The output is the reconstructor's (triangles with `SurfaceId`,
 * point data `Radiance` and `RadianceErrorEstimate`, lines with
 * `DiscontinuityOrder` and `SourceId`), with the shooter's field data
 * (`Shots`, `UnshotFraction`, energy bookkeeping, ...) when it ran.
 *
 * Progress runs over the whole solve; the progress text names the stage
 * running ("mesher", "evaluator", "shooter", "reconstructor"). Abort is
 * passed on to the stage running. An error of a stage is reported by this
 * filter, prefixed with the stage's name, and the output is left empty.
 *
 * Only the most used settings are here; compose the four filters by hand
 * for the others.
 *
 * @sa vtkPenumbraDiscontinuityMesher vtkPenumbraRadianceEvaluator vtkPenumbraProgressiveShooter
 * vtkPenumbraRadianceReconstructor
 */
#ifndef vtkPenumbraSolver_h
#define vtkPenumbraSolver_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraSolver : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraSolver* New();
  vtkTypeMacro(vtkPenumbraSolver, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Compute the interreflections (vtkPenumbraProgressiveShooter); off gives direct
   * light only. Default on.
   */
  vtkSetMacro(Indirect, bool);
  vtkGetMacro(Indirect, bool);
  vtkBooleanMacro(Indirect, bool);
  ///@}

  ///@{
  /**
   * Stop shooting when the unshot power is below this fraction of the
   * emitted power and of each lit surface's own reflected power
   * (vtkPenumbraProgressiveShooter::UnshotFraction). Default 1e-3,
   * range [0, 1].
   */
  vtkSetClampMacro(UnshotFraction, double, 0.0, 1.0);
  vtkGetMacro(UnshotFraction, double);
  ///@}

  ///@{
  /**
   * Secondary shots at least this fraction of the emitted power use the
   * exact method, weaker ones the hierarchical ray-cast method
   * (vtkPenumbraProgressiveShooter::ExactPowerFraction). Default 1, range
   * [0, 1].
   */
  vtkSetClampMacro(ExactPowerFraction, double, 0.0, 1.0);
  vtkGetMacro(ExactPowerFraction, double);
  ///@}

  ///@{
  /**
   * Adaptive sampling tolerance, relative to each surface's mean radiance
   * (vtkPenumbraRadianceEvaluator::SamplingTolerance). Default 0.002, range
   * [1e-6, 1].
   */
  vtkSetClampMacro(SamplingTolerance, double, 1e-6, 1.0);
  vtkGetMacro(SamplingTolerance, double);
  ///@}

  ///@{
  /**
   * Adaptive sampling budget of the whole scene, shared among surfaces by
   * area (vtkPenumbraRadianceEvaluator::MaximumSamples). Default 500000 (the
   * Cornell box uses 13% of it; a 20,000-polygon room reaches it, with a
   * warning), range [0, 2000000000]; 0 = no scene budget.
   */
  vtkSetClampMacro(MaximumSamples, vtkIdType, 0, 2000000000);
  vtkGetMacro(MaximumSamples, vtkIdType);
  ///@}

  ///@{
  /**
   * Longest sample-triangle edge, as a fraction of the scene's bounding-box
   * diagonal: the resolution of light that arrives by interreflection where
   * the direct light is even (vtkPenumbraRadianceEvaluator::
   * MaximumSampleSpacing). Default 1/32, range [0, 1]; 0 = no limit. The
   * `high` quality preset halves it (Documentation/benchmarks.md, "Quality
   * presets").
   */
  vtkSetClampMacro(MaximumSampleSpacing, double, 0.0, 1.0);
  vtkGetMacro(MaximumSampleSpacing, double);
  ///@}

  ///@{
  /**
   * Largest number of samples the interreflections are computed at; larger
   * inputs shoot on a coarse level and interpolate the indirect light onto
   * every sample (vtkPenumbraProgressiveShooter::MaximumIndirectSamples). Default
   * 100000, range [0, 2000000000]; 0 = always every sample.
   */
  vtkSetClampMacro(MaximumIndirectSamples, vtkIdType, 0, 2000000000);
  vtkGetMacro(MaximumIndirectSamples, vtkIdType);
  ///@}

  ///@{
  /**
   * Once every remaining shot is weak, shoot all surfaces at once (Jacobi
   * sweeps) through a transport recorded on the first sweep, later sweeps
   * tracing no rays (vtkPenumbraProgressiveShooter::ReuseTransport). Off: weak
   * shots one orientation at a time, each tracing its rays. Default on.
   */
  vtkSetMacro(ReuseTransport, bool);
  vtkGetMacro(ReuseTransport, bool);
  vtkBooleanMacro(ReuseTransport, bool);
  ///@}

  ///@{
  /**
   * Secondary shooters: a surface (not an emitter) whose direct light
   * reflects at least this fraction of the emitted power also shoots for the
   * discontinuity mesher (at most the 4 strongest), so that the sample
   * meshes follow the shadows it casts (a floor lit only by a panel gets
   * the panel's shadow boundaries); the mesher and the evaluator then run a
   * second time with them. Default 0.1, range [0, 1]; 1 = off.
   */
  vtkSetClampMacro(SecondaryShooterFraction, double, 0.0, 1.0);
  vtkGetMacro(SecondaryShooterFraction, double);
  ///@}

  ///@{
  /**
   * Quality refinement of the discontinuity meshes: smallest angle in
   * degrees (vtkPenumbraDiscontinuityMesher::MinimumAngle). Default 0 (none), range
   * [0, 20.6] (the mesher's limit).
   */
  vtkSetClampMacro(MinimumAngle, double, 0.0, 20.6);
  vtkGetMacro(MinimumAngle, double);
  ///@}

  ///@{
  /**
   * Shadow boundaries whose estimated radiance jump is below this fraction
   * of the largest direct radiance the receiver gets are not meshed
   * (vtkPenumbraDiscontinuityMesher::JumpThreshold). Default 0 (keep all),
   * range [0, 1].
   */
  vtkSetClampMacro(JumpThreshold, double, 0.0, 1.0);
  vtkGetMacro(JumpThreshold, double);
  ///@}

  ///@{
  /**
   * Display resampling: each sample triangle is cut only as finely as needed
   * for the displayed radiance to stay within this fraction of the surface's
   * mean radiance of the reconstruction
   * (vtkPenumbraRadianceReconstructor::DisplayTolerance). Default 0
   * (SubdivisionLevel everywhere), range [0, 1].
   */
  vtkSetClampMacro(DisplayTolerance, double, 0.0, 1.0);
  vtkGetMacro(DisplayTolerance, double);
  ///@}

  ///@{
  /**
   * Compact output: output points are removed wherever the displayed
   * radiance stays within this fraction of the surface's mean radiance of
   * the dense display, or within CompactIndirectTolerance's tolerance where
   * that is larger (vtkPenumbraRadianceReconstructor::CompactTolerance).
   * Default 5e-4, range [0, 1]; both 0 give the dense display.
   */
  vtkSetClampMacro(CompactTolerance, double, 0.0, 1.0);
  vtkGetMacro(CompactTolerance, double);
  ///@}

  ///@{
  /**
   * Compact output with interreflections: the displayed radiance may also
   * move by this fraction of the scene's mean indirect radiance, per channel
   * (vtkPenumbraRadianceReconstructor::CompactIndirectTolerance). Default
   * 0.01, range [0, 1]; ignored when Indirect is off.
   */
  vtkSetClampMacro(CompactIndirectTolerance, double, 0.0, 1.0);
  vtkGetMacro(CompactIndirectTolerance, double);
  ///@}

  ///@{
  /**
   * Uniform display resampling, when DisplayTolerance is 0: each sample
   * triangle's edges are cut in this many pieces
   * (vtkPenumbraRadianceReconstructor::SubdivisionLevel). Default 2, range
   * [1, 64].
   */
  vtkSetClampMacro(SubdivisionLevel, int, 1, 64);
  vtkGetMacro(SubdivisionLevel, int);
  ///@}

protected:
  vtkPenumbraSolver();
  ~vtkPenumbraSolver() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool Indirect = true;
  double UnshotFraction;
  double ExactPowerFraction;
  double SamplingTolerance;
  vtkIdType MaximumSamples;
  double MaximumSampleSpacing;
  vtkIdType MaximumIndirectSamples;
  bool ReuseTransport;
  double MinimumAngle;
  double JumpThreshold;
  double DisplayTolerance;
  double CompactTolerance;
  double CompactIndirectTolerance;
  int SubdivisionLevel;
  double SecondaryShooterFraction;

private:
  vtkPenumbraSolver(const vtkPenumbraSolver&) = delete;
  void operator=(const vtkPenumbraSolver&) = delete;
};

#endif
