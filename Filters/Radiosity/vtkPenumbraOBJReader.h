// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraOBJReader
 * @brief   Read a Wavefront OBJ + MTL file as a Penumbra scene.
 *
 * Every OBJ face becomes one polygon cell, kept as a polygon (not
 * triangulated), in file order. The face's material (`usemtl`, defined in the
 * files named by `mtllib`) gives the cell arrays `Reflectance` (from `Kd`) and
 * `Emission` (from `Ke`, zero if absent). Texture coordinates, normals, groups
 * and smoothing groups are ignored. A malformed file is an error that names the
 * file and line; the output is then empty. A material library that cannot be
 * opened and a material no library defines are warnings (those faces get the
 * default grey), unless Strict is on; GetWarning() lists them ("file:line:
 * what") for programs.
 * Geometry is repaired and validated downstream (vtkPenumbraSceneRepair).
 *
 * @sa vtkPenumbraSceneSource vtkPenumbraSceneValidator
 */
#ifndef vtkPenumbraOBJReader_h
#define vtkPenumbraOBJReader_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

#include <string> // for std::string

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraOBJReader : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraOBJReader* New();
  vtkTypeMacro(vtkPenumbraOBJReader, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Path of the .obj file. Default empty (an error when the reader runs).
   * MTL files are looked up relative to the folder of this file.
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /**
   * Missing material libraries and undefined materials are errors, not
   * warnings. Default off.
   */
  vtkSetMacro(Strict, bool);
  vtkGetMacro(Strict, bool);
  vtkBooleanMacro(Strict, bool);
  ///@}


protected:
  vtkPenumbraOBJReader();
  ~vtkPenumbraOBJReader() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  bool Strict = false;

private:
  vtkPenumbraOBJReader(const vtkPenumbraOBJReader&) = delete;
  void operator=(const vtkPenumbraOBJReader&) = delete;
};

#endif
