// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file vtkPenumbraSceneConversion.h
 * @brief Private: conversion between a scene vtkPolyData (design contract) and
 * penumbra::Scene. Not installed, not wrapped.
 */
#ifndef vtkPenumbraSceneConversion_h
#define vtkPenumbraSceneConversion_h

#include "penumbraProgressiveShooter.h" // for ParallelFor
#include "penumbraScene.h"
#include "penumbraShooterRadiance.h"

#include "vtkType.h" // for vtkIdType

#include <functional>
#include <map>
#include <string>
#include <vector>

class vtkFieldData;
class vtkPolyData;

namespace penumbra
{
/**
 * Read a scene from polydata: every polygon cell is a surface, with cell
 * arrays `Reflectance` and `Emission` (3 components each). Throws
 * penumbra::InputError naming the offending array or cell. Does not validate
 * geometry; call ValidateScene for that.
 */
Scene SceneFromPolyData(vtkPolyData* input);

/**
 * Add the design contract's cell arrays to a mesh whose cells are lines
 * followed by triangles: `SurfaceId` (lines: their surface; triangles:
 * theirs), `DiscontinuityOrder` (lines: their order; triangles: -2, not an
 * edge) and `SourceId` (lines: their shooter; triangles: -1).
 */
void AddMeshCellArrays(vtkPolyData* output, const std::vector<int>& lineSurface,
  const std::vector<int>& lineOrder, const std::vector<int>& lineSource,
  const std::vector<int>& triangleSurface);

/// Add a one-tuple double array `name` of `count` components to field data.
void AddField(vtkFieldData* fieldData, const char* name, const double* values, int count);
/// Add a one-value double array to field data.
void AddField(vtkFieldData* fieldData, const char* name, double value);
/// Add a one-tuple RGB (3-component double) array to field data.
void AddField(vtkFieldData* fieldData, const char* name, const RGB& value);

/**
 * The surfaces' materials as the samples carry them to the reconstructor:
 * field arrays `SurfaceReflectance` and `SurfaceEmission`, one RGB tuple per
 * scene surface (emission zero when the values exclude it). From them and a
 * sampled value V (see BlackTrackingReflectance) the reconstructor writes
 * Radiance = L^e + ReflectedShare (V - L^e) and Irradiance = pi (V - L^e) / rho_t.
 */
struct SurfaceMaterials
{
  std::vector<RGB> Reflectance;
  std::vector<RGB> Emission;
};
/// Add the scene's SurfaceMaterials to field data (see SurfaceMaterials).
void AddSurfaceMaterials(vtkFieldData* fieldData, const Scene& scene, bool includeEmission);
/// Read SurfaceMaterials back; false when absent or not one RGB per surface.
bool GetSurfaceMaterials(vtkFieldData* fieldData, SurfaceMaterials& materials);

/**
 * Piecewise-linear radiance per surface from `data`'s triangles (cell data
 * `SurfaceId`, point data `Radiance`), less `subtract[surface]` (clamped at
 * zero) when given. Throws InputError naming `what` and the offending cell.
 */
std::map<int, ShooterRadiance> RadianceFunctions(vtkPolyData* data, int numberOfSurfaces,
  const std::string& what, const std::vector<RGB>* subtract = nullptr);

/// The core's parallel loop run by vtkSMPTools::For (VTK's threads).
ParallelFor SMPParallelFor();

/// What ForEachCell passes for each cell: its id (verts, lines, polys and
/// strips numbered in that order, as VTK's cell data is), its kind (0 vertex,
/// 1 line, 2 polygon, 3 strip) and its point ids. Return false to stop.
using CellVisitor =
  std::function<bool(vtkIdType cellId, int kind, vtkIdType count, const vtkIdType* points)>;

/// Visit every cell of `data` in cell-id order (see CellVisitor).
void ForEachCell(vtkPolyData* data, const CellVisitor& visit);

/// Write a scene as polydata: one polygon per surface, cell arrays
/// `Reflectance` and `Emission` (double, 3 components).
void SceneToPolyData(const Scene& scene, vtkPolyData* output);
}

#endif
