// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraSceneSource
 * @brief   Built-in test scenes for the Penumbra radiosity pipeline.
 *
 * Produces one of Penumbra's built-in scenes as a scene vtkPolyData: one
 * planar polygon cell per surface, counter-clockwise seen from its front, with
 * the cell arrays `Reflectance` (RGB diffuse reflectance in [0, 1)) and
 * `Emission` (RGB emitted radiance, W sr^-1 m^-2). Units are metres, +y up.
 *
 * Scenes: `cornell` (the measured Cornell box), `strip` (a strip light over a
 * floor, paper Fig. 2), `occluder` (one occluder, Fig. 3), `seven` (seven
 * occluders, Fig. 4) and `blind` (a venetian blind). See
 * GetNumberOfScenes(), GetSceneName() and GetSceneDescription().
 *
 * @sa vtkPenumbraOBJReader vtkPenumbraSceneValidator
 */
#ifndef vtkPenumbraSceneSource_h
#define vtkPenumbraSceneSource_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

#include <string> // for std::string

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraSceneSource : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraSceneSource* New();
  vtkTypeMacro(vtkPenumbraSceneSource, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Name of the built-in scene to produce. Default "cornell". Valid values are
   * the names returned by GetSceneName(); an unknown name is an error.
   */
  vtkSetStdStringFromCharMacro(SceneName);
  vtkGetCharFromStdStringMacro(SceneName);
  ///@}

  ///@{
  /**
   * The catalogue of built-in scenes: count, names and one-line descriptions.
   * An index outside [0, GetNumberOfScenes()) returns an empty string.
   */
  static int GetNumberOfScenes();
  static std::string GetSceneName(int index);
  static std::string GetSceneDescription(int index);
  ///@}

protected:
  vtkPenumbraSceneSource();
  ~vtkPenumbraSceneSource() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string SceneName = "cornell";

private:
  vtkPenumbraSceneSource(const vtkPenumbraSceneSource&) = delete;
  void operator=(const vtkPenumbraSceneSource&) = delete;
};

#endif
