// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraSceneValidator
 * @brief   Check a scene against Penumbra's data contract and pass it through.
 *
 * The input must be a vtkPolyData of planar polygon cells (one cell = one
 * surface, counter-clockwise seen from the front) with 3-component cell arrays
 * `Reflectance` (each channel in [0, 1)) and `Emission` (each channel >= 0,
 * W sr^-1 m^-2). On success the output is the input, shallow-copied. On
 * failure the filter reports an error naming the offending array or cell
 * (missing or malformed arrays; vertex, line or strip cells; polygons with
 * fewer than three vertices, coincident vertices, zero area, non-planar or
 * self-intersecting outlines; non-finite values; reflectance outside [0, 1);
 * negative emission), keeps the message in GetLastErrorMessage(), and leaves
 * the output empty. Every Penumbra stage applies the same checks.
 *
 * @sa vtkPenumbraSceneSource vtkPenumbraOBJReader
 */
#ifndef vtkPenumbraSceneValidator_h
#define vtkPenumbraSceneValidator_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

#include <string> // for std::string

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraSceneValidator : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraSceneValidator* New();
  vtkTypeMacro(vtkPenumbraSceneValidator, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Largest allowed distance of a vertex from its polygon's plane, relative to
   * the polygon's diameter. Default 1e-6, range [0, 1].
   */
  vtkSetClampMacro(PlanarityTolerance, double, 0.0, 1.0);
  vtkGetMacro(PlanarityTolerance, double);
  ///@}

  ///@{
  /**
   * Smallest allowed edge length and polygon width, relative to the polygon's
   * diameter; anything thinner is degenerate. Default 1e-9, range [0, 1].
   */
  vtkSetClampMacro(DegeneracyTolerance, double, 0.0, 1.0);
  vtkGetMacro(DegeneracyTolerance, double);
  ///@}

  /**
   * The message of the last failed check, empty after a successful run.
   */
  vtkGetCharFromStdStringMacro(LastErrorMessage);

protected:
  vtkPenumbraSceneValidator();
  ~vtkPenumbraSceneValidator() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double PlanarityTolerance;
  double DegeneracyTolerance;
  std::string LastErrorMessage;

private:
  vtkPenumbraSceneValidator(const vtkPenumbraSceneValidator&) = delete;
  void operator=(const vtkPenumbraSceneValidator&) = delete;
};

#endif
