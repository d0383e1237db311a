// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraStandardRadiositySolver
 * @brief   Standard radiosity, the baseline the paper beat: uniform mesh,
 * progressive refinement, ray-cast form factors, adaptive subdivision,
 * Gouraud display.
 *
 * Input: a scene (design contract: polygons with cell data `Reflectance` and
 * `Emission`). Each surface is cut uniformly into patches (PatchSize) and
 * each patch into constant-radiosity elements (ElementSize). Progressive
 * refinement (Cohen et al. 1988): the patch with the most unshot power
 * shoots it to every mesh vertex, with vertex-to-patch form factors from
 * ShooterSamples^2 occlusion rays per patch (Wallace, Elmquist and Haines
 * 1989; by default the closed-form unoccluded form factor times the
 * ray-cast visible fraction, see FormFactorMode); elements whose vertices'
 * radiances differ by more than SubdivisionThreshold are split in four, up
 * to MaximumSubdivisionDepth times (Cohen et al. 1986), and their new
 * vertices gather every past shot. Stops when the unshot power falls below
 * UnshotFraction of the emitted power, or at MaximumShots. The core is
 * penumbra::StandardRadiosity (penumbraStandardRadiosity.h).
 *
 * Output (design contract, as vtkPenumbraRadianceReconstructor's): lines first (the
 * surfaces' outline edges, `DiscontinuityOrder` -1, `SourceId` -1), then
 * triangles (the elements, T-vertices included, so linear interpolation
 * has no cracks) with cell data `SurfaceId`; point data `Radiance`
 * (3 components, W sr^-1 m^-2, active scalars: the vertex radiosities,
 * displayed by linear interpolation). Field data: `Shots`,
 * `UnshotFraction` (unshot / emitted power), `SolveSeconds`, `Elements`,
 * `Vertices`, `Patches`, `SubdividedElements`, `Rays`, and the energy
 * bookkeeping `EmittedPower`, `AbsorbedPower`, `EscapedPower`,
 * `UnshotPower` (RGB, watts; emitted = absorbed + escaped + unshot).
 * Progress is reported per shot; abort is honoured between shots.
 *
 * @sa vtkPenumbraProgressiveShooter vtkPenumbraRadianceReconstructor
 */
#ifndef vtkPenumbraStandardRadiositySolver_h
#define vtkPenumbraStandardRadiositySolver_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraStandardRadiositySolver : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraStandardRadiositySolver* New();
  vtkTypeMacro(vtkPenumbraStandardRadiositySolver, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// How a vertex-to-patch form factor is computed.
  enum FormFactorModes
  {
    /// Closed-form unoccluded form factor times the visible fraction of the
    /// patch's samples, weighted by Wallace et al.'s disc terms (default).
    ANALYTIC_VISIBILITY = 0,
    /// Wallace et al. as published: sum of the disc terms of the visible samples.
    DISC = 1
  };

  ///@{
  /**
   * Longest patch (shooter) edge, relative to the scene's largest extent.
   * Default 0.5, range [0.001, 1]. Smaller patches shoot the indirect light
   * more faithfully but need more shots: on the Cornell box 0.2 took the
   * error from 3.6 % to 1.7 % RMS (floor) in about 6 times the time.
   */
  vtkSetClampMacro(PatchSize, double, 0.001, 1.0);
  vtkGetMacro(PatchSize, double);
  ///@}

  ///@{
  /**
   * Longest element edge of the initial uniform mesh, relative to the
   * scene's largest extent (the mesh density). Default 0.05, range [0.001, 1].
   */
  vtkSetClampMacro(ElementSize, double, 0.001, 1.0);
  vtkGetMacro(ElementSize, double);
  ///@}

  ///@{
  /**
   * Visibility samples per patch edge: ShooterSamples^2 occlusion rays from
   * each vertex to each shooting patch. Default 4, range [1, 32].
   */
  vtkSetClampMacro(ShooterSamples, int, 1, 32);
  vtkGetMacro(ShooterSamples, int);
  ///@}

  ///@{
  /**
   * ANALYTIC_VISIBILITY (0, default) or DISC (1); see FormFactorModes.
   */
  vtkSetClampMacro(FormFactorMode, int, ANALYTIC_VISIBILITY, DISC);
  vtkGetMacro(FormFactorMode, int);
  void SetFormFactorModeToAnalyticVisibility() { this->SetFormFactorMode(ANALYTIC_VISIBILITY); }
  void SetFormFactorModeToDisc() { this->SetFormFactorMode(DISC); }
  ///@}

  ///@{
  /**
   * Split an element when its vertices' radiances differ by more than this
   * fraction of its brightest vertex's radiance (or of the emitted power
   * spread over all surfaces, whichever is larger). Default 0.2, range
   * [1e-6, 1e300] (a huge value never splits). Sharp shadows want less:
   * 0.05 took the venetian blind's floor from 12 % to 2 % RMS error at
   * ElementSize 0.025, for 2.6 times the time.
   */
  vtkSetClampMacro(SubdivisionThreshold, double, 1e-6, 1e300);
  vtkGetMacro(SubdivisionThreshold, double);
  ///@}

  ///@{
  /**
   * Deepest adaptive subdivision (each level quarters an element; 0 keeps
   * the uniform mesh). Default 3, range [0, 12].
   */
  vtkSetClampMacro(MaximumSubdivisionDepth, int, 0, 12);
  vtkGetMacro(MaximumSubdivisionDepth, int);
  ///@}

  ///@{
  /**
   * Stop when the unshot power is at most this fraction of the emitted
   * power. Default 1e-3, range [0, 1].
   */
  vtkSetClampMacro(UnshotFraction, double, 0.0, 1.0);
  vtkGetMacro(UnshotFraction, double);
  ///@}

  ///@{
  /**
   * Stop after this many shots. Default 10000, range [0, 100000000].
   */
  vtkSetClampMacro(MaximumShots, int, 0, 100000000);
  vtkGetMacro(MaximumShots, int);
  ///@}

protected:
  vtkPenumbraStandardRadiositySolver();
  ~vtkPenumbraStandardRadiositySolver() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double PatchSize;
  double ElementSize;
  int ShooterSamples;
  int FormFactorMode;
  double SubdivisionThreshold;
  int MaximumSubdivisionDepth;
  double UnshotFraction;
  int MaximumShots;

private:
  vtkPenumbraStandardRadiositySolver(const vtkPenumbraStandardRadiositySolver&) = delete;
  void operator=(const vtkPenumbraStandardRadiositySolver&) = delete;
};

#endif
