// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraGLTFReader
 * @brief   Read a glTF 2.0 file (.gltf or .glb) as a Penumbra scene.
 *
 * The file is loaded by VTK's vtkGLTFDocumentLoader. The nodes of the default
 * scene (the first scene when the file names none) are visited recursively,
 * each with its global transform (its ancestors' transforms times its own
 * matrix or translation, rotation and scale), and every triangle of every
 * primitive of a node's mesh becomes one polygon cell, in world coordinates,
 * in the order nodes, primitives and triangles appear. Triangle strips and
 * fans are split into their triangles; primitives without triangles (points,
 * lines) are skipped with a warning. Under a transform of negative determinant
 * (a mirror) the triangles' vertex order is reversed, since glTF then takes
 * clockwise faces as front faces and Penumbra counter-clockwise ones.
 * Triangles are not merged into larger polygons, and vertex attributes other
 * than POSITION (normals, texture coordinates, colours), skins, morph targets,
 * animations, cameras and punctual lights are ignored.
 *
 * Each cell takes its primitive's material:
 * - `Reflectance` = the RGB of pbrMetallicRoughness.baseColorFactor (glTF's
 *   default 1 when the material has none), times the mean of the linear
 *   (sRGB-decoded) pixels of baseColorTexture when the material has one, with
 *   a warning naming the material (the texture's variation is lost);
 *   metallicFactor, roughness and alpha are ignored (surfaces are diffuse).
 *   Values are not clamped: a factor of 1 is reported by scene validation, as
 *   the OBJ reader's Kd of 1 is.
 * - `Emission` = emissiveFactor times KHR_materials_emissive_strength's
 *   emissiveStrength (1 without the extension), read from the file's JSON
 *   since VTK's loader does not parse that extension; an emissiveTexture is
 *   ignored with a warning.
 * A primitive without a material gets penumbra::ObjDefaultReflectance grey
 * and no emission, as an OBJ face without a material does.
 *
 * Units: glTF positions are metres and the scene is read as it is (+Y up);
 * the emission is taken as radiance (W sr^-1 m^-2) in the scene's units, so a
 * file whose emissive values mean something else (e.g. nits, or Blender's
 * strength under another exposure) needs scaling by the user.
 *
 * Errors name the file and what is wrong, and leave the output empty: no file
 * name, a file that cannot be opened or is not glTF 2.0 (the loader's message
 * is relayed), a .glb that is not binary glTF or a binary glTF not named .glb,
 * a file that requires an extension other than KHR_materials_emissive_strength,
 * KHR_materials_unlit, KHR_texture_transform and KHR_lights_punctual (e.g.
 * compressed meshes), nodes that do not form trees (a node that is its own
 * ancestor or has two parents), accessors or buffer views that run past the
 * end of their data, out-of-range indices, and non-finite coordinates,
 * transforms or material factors. Extensions, nodes and accessors are checked
 * on the file's JSON before VTK's loader reads it, since the loader ignores
 * extensionsRequired, recurses without end on a cycle and reads past the end
 * of a buffer.
 *
 * @sa vtkPenumbraOBJReader vtkPenumbraSceneValidator vtkGLTFDocumentLoader
 */
#ifndef vtkPenumbraGLTFReader_h
#define vtkPenumbraGLTFReader_h

#include "vtkPenumbraAlgorithm.h"
#include "vtkPenumbraFiltersModule.h" // for export macro

#include <string> // for std::string

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraGLTFReader : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraGLTFReader* New();
  vtkTypeMacro(vtkPenumbraGLTFReader, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Path of the .gltf or .glb file. Default empty (an error when the reader
   * runs). Buffers and images named by relative URIs are looked up relative to
   * the folder of this file.
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkPenumbraGLTFReader();
  ~vtkPenumbraGLTFReader() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkPenumbraGLTFReader(const vtkPenumbraGLTFReader&) = delete;
  void operator=(const vtkPenumbraGLTFReader&) = delete;
};

#endif
