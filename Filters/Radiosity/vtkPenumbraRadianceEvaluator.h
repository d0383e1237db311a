// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraRadianceEvaluator
 * @brief   Radiance at sample points from the scene's shooters (paper §5).
 *
 * Input port 0 holds the sample points: any vtkPolyData whose points lie on
 * the scene's surfaces, each point's surface given by a `SurfaceId` point
 * array or, failing that, by the `SurfaceId` cell array of a cell that uses
 * the point (the output of vtkPenumbraDiscontinuityMesher is such a mesh). Input
 * port 1 is the scene (see vtkPenumbraSceneValidator for its contract).
 *
 * For every sample x on receiver i the filter computes the radiance
 * contributed by each selected shooter j of constant radiance L^e_j,
 *
 *   L_ij(x) = rho_i / pi * E_ij(x),   E_ij(x) = pi L^e_j F_j(x),
 *
 * where F_j(x) is the form factor from x to the part of shooter j visible
 * from x, and writes the point array `Radiance` (3 components, W sr^-1 m^-2,
 * active scalars) = L^e_i (when IncludeEmission is on) + sum_j L_ij(x).
 * Method Exact clips each shooter to x's front half-space, subtracts the
 * shadows of the occluders found by shaft and pyramid culling and integrates
 * the visible region in closed form (Lambert). Method RayCast estimates the
 * same integral by adaptive subdivision of the shooter with Embree occlusion
 * rays (paper Eq. 6). The output is the input with this array added.
 *
 * Non-uniform shooters: optional input port 2 (SetShooterRadianceConnection)
 * takes triangles with cell data `SurfaceId` and point data `Radiance`: for
 * each surface present there, its radiance is that piecewise-linear function
 * over its triangles instead of its constant Emission (e.g. the unshot
 * radiance of a secondary shooter), integrated as such by both methods
 * (EXACT: the linear-source closed form over each triangle's visible part).
 * With no ShooterIds, the shooters are every emitter and every surface on
 * port 2.
 *
 * Adaptive sampling (paper §4, on by default): when the samples are a
 * triangle mesh (vtkPenumbraDiscontinuityMesher's output: triangles with
 * `SurfaceId`, lines with `DiscontinuityOrder` and `SourceId`, points on
 * order-0 lines duplicated per side), each surface's mesh is refined by
 * constrained Delaunay point insertions that keep every boundary, until
 * the radiance at the midpoints of every edge agrees with the C1 cubic
 * interpolant of the samples within SamplingTolerance of the surface's mean
 * radiance (or the triangle is narrower than MinimumFeatureSize, or the
 * surface has MaximumSamplesPerSurface samples). The output is then the
 * refined mesh, with the same arrays plus the cell array
 * `SamplingResidual` (3 components: the largest |true - interpolated|
 * radiance found at the triangle's last probes; -1 where the triangle was
 * not probed; 0 on lines), which
 * vtkPenumbraRadianceReconstructor turns into its error estimate, and the field
 * array `Evaluations`.
 *
 * Work is spread over threads with vtkSMPTools; every point is computed
 * independently, so the output does not depend on the number of threads.
 *
 * @sa vtkPenumbraDiscontinuityMesher vtkPenumbraSceneValidator
 */
#ifndef vtkPenumbraRadianceEvaluator_h
#define vtkPenumbraRadianceEvaluator_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"
#include "vtkWrappingHints.h" // for VTK_WRAPEXCLUDE

#include <memory> // for std::unique_ptr
#include <vector> // for std::vector

namespace penumbra
{
struct SampledSurfaceCache;
}

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraRadianceEvaluator : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraRadianceEvaluator* New();
  vtkTypeMacro(vtkPenumbraRadianceEvaluator, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Evaluation methods.
  enum Methods
  {
    EXACT = 0,   ///< visible region + closed-form integral (default)
    RAY_CAST = 1 ///< adaptive shooter subdivision with occlusion rays
  };

  ///@{
  /**
   * How contributed radiance is computed: EXACT (0, default) or RAY_CAST (1).
   */
  vtkSetClampMacro(Method, int, EXACT, RAY_CAST);
  vtkGetMacro(Method, int);
  void SetMethodToExact() { this->SetMethod(EXACT); }
  void SetMethodToRayCast() { this->SetMethod(RAY_CAST); }
  ///@}

  ///@{
  /**
   * Relative tolerance of the ray-cast method's adaptive subdivision of the
   * shooter: a piece is split while splitting changes its estimate by more
   * than this fraction. Default 1e-3, range [1e-9, 1]. Ignored by EXACT.
   */
  vtkSetClampMacro(RayCastTolerance, double, 1e-9, 1.0);
  vtkGetMacro(RayCastTolerance, double);
  ///@}

  ///@{
  /**
   * Refine triangle meshes adaptively (see the class description). Default
   * on; off evaluates the given points only.
   */
  vtkSetMacro(AdaptiveSampling, bool);
  vtkGetMacro(AdaptiveSampling, bool);
  vtkBooleanMacro(AdaptiveSampling, bool);
  ///@}

  ///@{
  /**
   * Adaptive sampling tolerance, relative to each surface's mean radiance
   * (per channel). Default 0.002, range [1e-6, 1].
   */
  vtkSetClampMacro(SamplingTolerance, double, 1e-6, 1.0);
  vtkGetMacro(SamplingTolerance, double);
  ///@}

  ///@{
  /**
   * Adaptive sampling budget per surface (samples). Default 200000, range
   * [3, 100000000].
   */
  vtkSetClampMacro(MaximumSamplesPerSurface, int, 3, 100000000);
  vtkGetMacro(MaximumSamplesPerSurface, int);
  ///@}

  ///@{
  /**
   * Adaptive sampling budget of the whole scene (samples), shared among the
   * surfaces in proportion to their area: a surface of area a gets at most
   * max(MaximumSamples * a / (total sampled area), MaximumSamples / (number
   * of surfaces)) samples (the second so that slivers and small parts keep
   * what they need; at most MaximumSamplesPerSurface; the initial mesh is
   * always kept whole), so the total stays below twice the budget. It
   * bounds time and memory on scenes of many thousands of polygons, where
   * SamplingTolerance alone asks for thousands of samples per polygon; small
   * scenes never reach it (the Cornell box uses 13% of it). Where it binds,
   * the largest residuals are refined first, and the filter warns (the
   * number of surfaces it stopped, and the first). Default 500000, range
   * [0, 2000000000]; 0 = no scene budget.
   */
  vtkSetClampMacro(MaximumSamples, vtkIdType, 0, 2000000000);
  vtkGetMacro(MaximumSamples, vtkIdType);
  ///@}

  ///@{
  /**
   * Longest sample-triangle edge after adaptive sampling, as a fraction of
   * the scene's bounding-box diagonal: longer edges are split whatever the
   * shooters' radiance does there, so that light arriving later by
   * interreflection (vtkPenumbraProgressiveShooter), which varies where the direct
   * light does not (in umbrae, on evenly lit or unlit surfaces), has
   * samples to land on. 0 turns the limit off. Default 1/32 (the Cornell
   * box: 3 cm), range [0, 1].
   */
  vtkSetClampMacro(MaximumSampleSpacing, double, 0.0, 1.0);
  vtkGetMacro(MaximumSampleSpacing, double);
  ///@}

  ///@{
  /**
   * Triangles narrower than this fraction of their surface's diameter are
   * not refined (features no finite sampling resolves, such as penumbrae
   * shrinking to a point at a contact corner). Near a feature whose shadow
   * lines are shorter than a tenth of the surface's diameter, the fraction
   * is of ten times their length instead, so small features are resolved
   * like large ones (penumbra::AdaptiveSamplingSettings::MinimumFeatureSize).
   * Default 1e-4, range [0, 1].
   */
  vtkSetClampMacro(MinimumFeatureSize, double, 0.0, 1.0);
  vtkGetMacro(MinimumFeatureSize, double);
  ///@}

  ///@{
  /**
   * Whether `Radiance` includes the receiver's own emission L^e_i (on, the
   * default) or only the contributed radiance.
   */
  vtkSetMacro(IncludeEmission, bool);
  vtkGetMacro(IncludeEmission, bool);
  vtkBooleanMacro(IncludeEmission, bool);
  ///@}

  ///@{
  /**
   * The shooters: scene cell ids. Empty (the default) means every surface
   * with non-zero Emission. An id that is not a scene cell is an error.
   */
  void AddShooterId(vtkIdType id);
  void RemoveAllShooterIds();
  vtkIdType GetNumberOfShooterIds() const;
  vtkIdType GetShooterId(vtkIdType index) const;
  ///@}

  /**
   * C++ only (vtkPenumbraSolver's second pass for the secondary shooters):
   * keep what the adaptive sampling gave each surface, and on the next
   * execution reuse it for every surface whose input mesh and sample budget
   * are unchanged, the settings, scene and shooters being unchanged too,
   * instead of sampling it again. The sampling is deterministic, so the
   * output is the same. Off by default; turning it off drops what was kept.
   */
  VTK_WRAPEXCLUDE void SetReuseUnchangedSurfaces(bool reuse);
  /// C++ only: the surfaces the last execution reused (SetReuseUnchangedSurfaces).
  VTK_WRAPEXCLUDE int GetNumberOfReusedSurfaces() const;

  /**
   * Connect the scene (input port 1).
   */
  void SetSceneConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSceneData(vtkDataObject* scene) { this->SetInputData(1, scene); }

  /**
   * Connect the optional non-uniform shooter radiance (input port 2).
   */
  void SetShooterRadianceConnection(vtkAlgorithmOutput* output)
  {
    this->SetInputConnection(2, output);
  }
  void SetShooterRadianceData(vtkDataObject* radiance) { this->SetInputData(2, radiance); }

protected:
  vtkPenumbraRadianceEvaluator();
  ~vtkPenumbraRadianceEvaluator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Method;
  double RayCastTolerance;
  bool IncludeEmission;
  bool AdaptiveSampling;
  double SamplingTolerance;
  int MaximumSamplesPerSurface;
  vtkIdType MaximumSamples;
  double MaximumSampleSpacing;
  double MinimumFeatureSize;
  std::vector<vtkIdType> ShooterIds;

private:
  /// What the last execution sampled, when reuse is on (else null).
  std::unique_ptr<penumbra::SampledSurfaceCache> Reuse;
  int ReusedSurfaces = 0;

  vtkPenumbraRadianceEvaluator(const vtkPenumbraRadianceEvaluator&) = delete;
  void operator=(const vtkPenumbraRadianceEvaluator&) = delete;
};

#endif
