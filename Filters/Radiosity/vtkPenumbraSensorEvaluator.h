// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraSensorEvaluator
 * @brief   Irradiance at sensor points anywhere in a scene (illuminance meters).
 *
 * Input port 0 holds the sensors: the points of any vtkPolyData, with a
 * 3-component point array `Normals` giving the direction each sensor faces
 * (normalised here; a zero or non-finite normal or position is an error
 * naming the point). Sensors need not lie on surfaces: a work plane above a
 * floor, a vertical plane in mid-air. Input port 1 is the scene
 * (SetSceneConnection). Optional input port 2 (SetSolutionConnection) is a
 * solution of that scene, such as vtkPenumbraSolver's output (triangles with
 * cell data `SurfaceId` and point data `Radiance`).
 *
 * The output is the sensors' points with point data `Irradiance` (3
 * components, W m^-2, lux for luminance in cd m^-2; active scalars) and
 * `DirectIrradiance`. The direct part is exact: for each emitter, the part
 * visible from the sensor (exact visibility, as for the solver's samples)
 * integrated in closed form. The indirect part is the light of every
 * surface's reflected radiance in the solution (Radiance less Emission, a
 * piecewise-linear function over its triangles), integrated exactly over
 * its visible part; without a solution it is zero. Its accuracy is the
 * solution's.
 *
 * The work grows with sensors x triangles of the solution; each sensor is
 * computed independently on vtkSMPTools threads, so the output does not
 * depend on the number of threads. Progress and abort are honoured between
 * batches of sensors.
 *
 * @sa vtkPenumbraSolver
 */
#ifndef vtkPenumbraSensorEvaluator_h
#define vtkPenumbraSensorEvaluator_h

#include "vtkPenumbraFiltersModule.h" // for export macro

#include "vtkPenumbraAlgorithm.h"

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraSensorEvaluator : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraSensorEvaluator* New();
  vtkTypeMacro(vtkPenumbraSensorEvaluator, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The scene (input port 1).
  void SetSceneConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  /// A solution of the scene (input port 2, optional): the indirect light.
  void SetSolutionConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(2, output); }

protected:
  vtkPenumbraSensorEvaluator();
  ~vtkPenumbraSensorEvaluator() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int Execute(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

private:
  vtkPenumbraSensorEvaluator(const vtkPenumbraSensorEvaluator&) = delete;
  void operator=(const vtkPenumbraSensorEvaluator&) = delete;
};

#endif
