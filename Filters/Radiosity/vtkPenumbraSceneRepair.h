// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraSceneRepair
 * @brief   Repair what an imported scene safely allows, warn about scenes that
 * will come out black, and validate the rest.
 *
 * Input: a scene vtkPolyData (data contract: polygon cells with cell arrays
 * `Reflectance` and `Emission`). Output: the repaired scene
 * (penumbra::RepairScene): near-duplicate vertices welded (WeldTolerance,
 * relative to the scene's size), repeated consecutive vertices removed,
 * zero-area and duplicate polygons dropped, polygons bent beyond
 * FlatnessTolerance triangulated keeping their front side and material;
 * vertex and line cells (edges exported beside the faces) are dropped. Every
 * kind of repair is reported as one warning line (vtkWarningMacro, and
 * GetWarning() for programs), e.g. "12 non-planar polygons triangulated into
 * 24 triangles (largest distance from the plane 0.0017)". Every other cell
 * array of the input follows its polygons; when anything changed, the cell
 * array `InputCellId` gives each output polygon's input cell.
 *
 * The repaired scene is then validated as vtkPenumbraSceneValidator does; what
 * cannot be repaired without guessing (non-finite numbers, reflectance >= 1,
 * negative emission, self-intersecting outlines, strip cells, a scene without
 * polygons) is an error naming the input cell. With Strict on, nothing is
 * repaired: the input is validated as it is, with the validator's errors.
 *
 * In both modes the lighting is diagnosed (penumbra::DiagnoseLighting) when
 * CheckLighting is on: warnings for a scene without emitters, emitters facing
 * away from every surface, and emitters whose light falls on the backs of
 * surfaces (inside a closed solid, or surfaces facing the wrong way).
 *
 * @sa vtkPenumbraSceneValidator vtkPenumbraOBJReader
 */
#ifndef vtkPenumbraSceneRepair_h
#define vtkPenumbraSceneRepair_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

#include <string> // for std::string

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraSceneRepair : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraSceneRepair* New();
  vtkTypeMacro(vtkPenumbraSceneRepair, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Repair nothing: validate the input as it is. Default off.
   */
  vtkSetMacro(Strict, bool);
  vtkGetMacro(Strict, bool);
  vtkBooleanMacro(Strict, bool);
  ///@}

  ///@{
  /**
   * Vertices closer than this times the scene's size are welded
   * (penumbra::RepairOptions::WeldTolerance). Default 1e-6, range [0, 1e-3].
   */
  vtkSetClampMacro(WeldTolerance, double, 0.0, 1e-3);
  vtkGetMacro(WeldTolerance, double);
  ///@}

  ///@{
  /**
   * Largest distance of a vertex from its polygon's plane, relative to the
   * polygon's diameter, below which the polygon is kept whole; beyond it the
   * polygon is triangulated (penumbra::RepairOptions::FlatnessTolerance: the
   * pipeline takes polygons as exactly planar). Default 1e-9, range [0, 1].
   * Not used in Strict mode.
   */
  vtkSetClampMacro(FlatnessTolerance, double, 0.0, 1.0);
  vtkGetMacro(FlatnessTolerance, double);
  ///@}

  ///@{
  /**
   * In Strict mode, the largest distance of a vertex from its polygon's plane,
   * relative to the polygon's diameter, that is accepted
   * (vtkPenumbraSceneValidator's). Default 1e-6, range [0, 1].
   */
  vtkSetClampMacro(PlanarityTolerance, double, 0.0, 1.0);
  vtkGetMacro(PlanarityTolerance, double);
  ///@}

  ///@{
  /**
   * Smallest edge length and polygon width, relative to the polygon's
   * diameter; thinner polygons are dropped (in Strict mode: rejected).
   * Default 1e-9, range [0, 1].
   */
  vtkSetClampMacro(DegeneracyTolerance, double, 0.0, 1.0);
  vtkGetMacro(DegeneracyTolerance, double);
  ///@}

  ///@{
  /**
   * Warn about scenes that will come out black or odd (no emitter, emitters
   * facing away, emitters lighting backs). Default on.
   */
  vtkSetMacro(CheckLighting, bool);
  vtkGetMacro(CheckLighting, bool);
  vtkBooleanMacro(CheckLighting, bool);
  ///@}

  /**
   * The message of the last failed check, empty after a successful run.
   */
  vtkGetCharFromStdStringMacro(LastErrorMessage);

protected:
  vtkPenumbraSceneRepair();
  ~vtkPenumbraSceneRepair() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool Strict;
  double WeldTolerance;
  double FlatnessTolerance;
  double PlanarityTolerance;
  double DegeneracyTolerance;
  bool CheckLighting;
  std::string LastErrorMessage;

private:
  vtkPenumbraSceneRepair(const vtkPenumbraSceneRepair&) = delete;
  void operator=(const vtkPenumbraSceneRepair&) = delete;
};

#endif
