// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraProgressiveShooter
 * @brief   Global illumination by progressive shooting of radiance functions (paper §3).
 *
 * Input port 0: the sample mesh with the direct solution, as produced by
 * vtkPenumbraRadianceEvaluator with its default shooters (every emitter): triangles
 * with cell data `SurfaceId`, point data `Radiance` = emission + direct
 * light. Input port 1: the scene.
 *
 * Each surface's total and unshot radiance are piecewise-linear functions
 * over its samples; the unshot radiance starts as the reflected direct light
 * (Radiance minus the surface's Emission). Each shot picks the surface with
 * the largest unshot power pi * integral of its unshot radiance (ranked by
 * the mean of the RGB channels), adds its contribution at every sample of
 * every surface that sees it, and zeroes its unshot radiance. Shooters are
 * non-uniform and integrated as such: shots carrying at least
 * ExactPowerFraction of the emitted power exactly (visible region of the
 * shooter, closed-form integral of the linear radiance over each of its
 * triangles), weaker shots by a hierarchy of the shooter with one
 * occlusion ray per node (OpeningAngle). Shooting stops when the unshot
 * power falls below UnshotFraction of the emitted power, or at
 * MaximumShots. Samples are not added during shooting: every shot is
 * evaluated at every existing sample.
 *
 * Output: the input with `Radiance` = the total radiance (active scalars)
 * and field data: `Shots`, `ExactShots`, `FastShots`, `UnshotFraction`
 * (remaining unshot power / emitted power), `EmittedPower`, `AbsorbedPower`,
 * `EscapedPower` (RGB, watts: power that left an open scene or was lost to
 * discretisation), `UnshotPower`, `ShootingSeconds`, `ShotOrder` (the
 * shooters in order), `MeanIndirectRadiance` (RGB: what the shots added,
 * averaged over the area of all sample triangles; the scale of the
 * interreflections' error that vtkPenumbraRadianceReconstructor's
 * CompactIndirectTolerance refers to). Progress is reported per shot and abort is honoured
 * between shots.
 *
 * @sa vtkPenumbraRadianceEvaluator vtkPenumbraRadianceReconstructor
 */
#ifndef vtkPenumbraProgressiveShooter_h
#define vtkPenumbraProgressiveShooter_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraProgressiveShooter : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraProgressiveShooter* New();
  vtkTypeMacro(vtkPenumbraProgressiveShooter, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Stop when the unshot power is at most this fraction of the emitted
   * power and could add at most this fraction of its own reflected power to
   * any lit surface (penumbra::ProgressiveShooterSettings::UnshotFraction).
   * Default 1e-3, range [0, 1].
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

  ///@{
  /**
   * Shots whose power is at least this fraction of the emitted power are
   * integrated exactly; weaker ones by the hierarchical ray-cast method,
   * which resolves visibility per node of the shooter and so blurs the
   * shadows a strong secondary shooter casts onto a dim surface, but costs a
   * small fraction of an exact shot on large meshes. Default 1, range [0, 1]
   * (0: every shot exact; 1: only shots as strong as all the emission). The
   * trade-off is measured in penumbra::ProgressiveShooterSettings.
   */
  vtkSetClampMacro(ExactPowerFraction, double, 0.0, 1.0);
  vtkGetMacro(ExactPowerFraction, double);
  ///@}

  ///@{
  /**
   * Hierarchical ray-cast method: a node of the shooter is used as one
   * point source when its radius over its distance is below this. Smaller is
   * more accurate and slower. Default 0.3, range [0.01, 2].
   */
  vtkSetClampMacro(OpeningAngle, double, 0.01, 2.0);
  vtkGetMacro(OpeningAngle, double);
  ///@}

  ///@{
  /**
   * Shots weaker than this fraction f of the emitted power are computed
   * coarser, their error mattering less: a shot of power S uses the opening
   * angle OpeningAngle * min(2, sqrt(f * emitted / S)). 0 turns it off.
   * Default 0.003, range [0, 1] (measured: the Cornell box solve takes a third
   * less time for the same error; the furnace stays within 7e-5).
   */
  vtkSetClampMacro(CoarseShotFraction, double, 0.0, 1.0);
  vtkGetMacro(CoarseShotFraction, double);
  ///@}

  ///@{
  /**
   * Shoot all weak surfaces of one orientation together: a fast shot also
   * shoots every other surface with the same front normal whose unshot
   * power calls for the fast method, over one hierarchy of all their
   * pieces (penumbra::ProgressiveShooterSettings::GroupWeakShots).
   * Default on.
   */
  vtkSetMacro(GroupWeakShots, bool);
  vtkGetMacro(GroupWeakShots, bool);
  vtkBooleanMacro(GroupWeakShots, bool);
  ///@}

  ///@{
  /**
   * With GroupWeakShots, also group the weak surfaces facing other ways
   * whose unshot power is at least a tenth of the shooter's: Jacobi sweeps
   * instead of single shots (penumbra::ProgressiveShooterSettings::
   * GroupAcrossOrientations: fewer shots, each as costly as its members
   * shot alone). Default off.
   */
  vtkSetMacro(GroupAcrossOrientations, bool);
  vtkGetMacro(GroupAcrossOrientations, bool);
  vtkBooleanMacro(GroupAcrossOrientations, bool);
  ///@}

  ///@{
  /**
   * Once every remaining shot is fast, shoot all surfaces at once (Jacobi
   * sweeps) through a transport recorded on the first sweep: the cut of
   * the hierarchy and its visibility at every receiving point are kept and
   * later sweeps trace no rays (penumbra::ProgressiveShooterSettings::
   * ReuseTransport; GroupWeakShots, GroupAcrossOrientations and
   * CoarseShotFraction, which shape weak shots, then have no effect).
   * Costs memory (about 4 bytes per node used per point). Default on.
   */
  vtkSetMacro(ReuseTransport, bool);
  vtkGetMacro(ReuseTransport, bool);
  vtkBooleanMacro(ReuseTransport, bool);
  ///@}

  ///@{
  /**
   * Fast shots evaluate the receiving points in clusters of at most this
   * many points facing the same way: a node of the shooter's hierarchy far
   * from the whole cluster is tested by rays from four of its points, not
   * one ray per point, and where those rays disagree (a shadow edge crosses
   * the cluster) each point tests it on its own
   * (penumbra::ProgressiveShooterSettings::ReceiverClusterSize).
   * Default 16, range [0, 4096]; 0 or 1 = every point on its own.
   */
  vtkSetClampMacro(ReceiverClusterSize, int, 0, 4096);
  vtkGetMacro(ReceiverClusterSize, int);
  ///@}

  ///@{
  /**
   * Largest number of samples the interreflections are computed at. When
   * the input has more samples (large scenes), the shots run on a coarse
   * level instead: a uniform lattice mesh of every surface, its spacing
   * chosen so that the level has about this many points, the initial
   * values restricted from the samples (each surface's power kept) and the
   * indirect light interpolated back onto every sample, never across an
   * occluder (samples in pockets narrower than the spacing, such as behind
   * a fixture hung just below a ceiling, are shot on their own; field
   * IndirectSeparatePoints) (penumbra::IndirectLevel). The direct light
   * keeps every sample.
   * Default 100000, range [0, 2000000000]; 0 = always every sample.
   */
  vtkSetClampMacro(MaximumIndirectSamples, vtkIdType, 0, 2000000000);
  vtkGetMacro(MaximumIndirectSamples, vtkIdType);
  ///@}

  /**
   * Connect the scene (input port 1).
   */
  void SetSceneConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSceneData(vtkDataObject* scene) { this->SetInputData(1, scene); }

protected:
  vtkPenumbraProgressiveShooter();
  ~vtkPenumbraProgressiveShooter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double UnshotFraction;
  int MaximumShots;
  double ExactPowerFraction;
  double OpeningAngle;
  double CoarseShotFraction;
  bool GroupWeakShots;
  bool GroupAcrossOrientations;
  bool ReuseTransport;
  int ReceiverClusterSize;
  vtkIdType MaximumIndirectSamples;

private:
  vtkPenumbraProgressiveShooter(const vtkPenumbraProgressiveShooter&) = delete;
  void operator=(const vtkPenumbraProgressiveShooter&) = delete;
};

#endif
