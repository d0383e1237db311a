// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraObjReader.h
 * @brief Wavefront OBJ + MTL reader producing a Penumbra Scene.
 *
 * One face = one Surface, in file order; polygons are kept as they are (no
 * triangulation) and the geometry is not validated here (ValidateScene does
 * that, naming the cell). Supported:
 * - OBJ: `v x y z [w]` (w is read and ignored; the common `v x y z r g b`
 *   vertex-colour extension is accepted, colours ignored), `f`/`fo` with
 *   `i`, `i/t`, `i//n`, `i/t/n` vertices and negative (relative) indices,
 *   `mtllib` (one or more names, relative to the OBJ's folder; a name
 *   containing spaces is tried whole first), `usemtl`, `#` comments, blank
 *   lines, CRLF line ends and backslash line continuation. Texture/normal
 *   indices are checked for syntax only. `vt vn vp o g s l p mg` and the
 *   free-form curve/surface and display statements of the OBJ specification
 *   are ignored; any other statement is an error (so that a file that is not
 *   an OBJ at all is not read as an empty scene).
 * - MTL: `newmtl`, `Kd` (-> Reflectance) and `Ke` (-> Emission), each with
 *   one value (grey) or three (RGB); other statements are ignored. A material
 *   without Kd gets ObjDefaultReflectance grey, without Ke no emission; faces
 *   before any usemtl get that same default material. When a name is defined
 *   twice, the last definition wins. Values are not clamped: a Kd of 1 is
 *   reported by ValidateScene, not silently changed.
 * - Lenient by default (ObjReadOptions::Strict off), because real exports
 *   carry such flaws: a material library that cannot be opened and a
 *   `usemtl` naming a material no library defines are warnings, and those
 *   faces get the default material; a name that differs from a defined one
 *   only in case or spacing uses that material, with a warning. In strict
 *   mode both are errors.
 *
 * Indices are resolved when the face is read, against the vertices defined
 * so far (as the OBJ specification intends). Errors throw InputError with
 * "file:line: what", e.g. "scene.obj:17: face index 9 out of range
 * (8 vertices)": unreadable files, non-numeric, missing, non-finite or
 * overflowing numbers, faces with fewer than 3 vertices, index 0 or out of
 * range, unknown materials, missing material libraries, malformed Kd/Ke,
 * lines longer than ObjMaxLineLength.
 */
#ifndef penumbraObjReader_h
#define penumbraObjReader_h

#include "penumbraCommonModule.h" // for export macro
#include "penumbraScene.h"

#include <cstddef>
#include <functional>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace penumbra
{

/// Reflectance (each channel) of faces without a material or without Kd.
constexpr double ObjDefaultReflectance = 0.5;
/// Longest accepted logical line (continuations joined), in characters.
constexpr std::size_t ObjMaxLineLength = std::size_t(1) << 20;

/// Opens a material library named in an `mtllib` statement; returns nullptr
/// if it cannot be opened.
using ObjMaterialOpener = std::function<std::unique_ptr<std::istream>(const std::string& name)>;

/// How forgiving the reader is.
struct ObjReadOptions
{
  /// Missing material libraries and undefined materials are errors, not
  /// warnings. [false]
  bool Strict = false;
};

/// Read an OBJ file and the MTL files it names (relative to its folder);
/// warnings (one line each, naming file and line) are appended to `warnings`.
PENUMBRACOMMON_EXPORT Scene ReadObjScene(const std::string& objPath,
  const ObjReadOptions& options = ObjReadOptions(), std::vector<std::string>* warnings = nullptr);

/// Parse OBJ text from a stream; `objName` is used in messages and
/// `openMtl` resolves material libraries (e.g. from strings in tests).
PENUMBRACOMMON_EXPORT Scene ParseObjScene(std::istream& obj, const std::string& objName,
  const ObjMaterialOpener& openMtl, const ObjReadOptions& options = ObjReadOptions(),
  std::vector<std::string>* warnings = nullptr);

} // namespace penumbra

#endif
