// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <sstream>

namespace penumbra
{
namespace
{
vtkDataArray* RequireColorArray(vtkPolyData* input, const char* name)
{
  vtkDataArray* array = input->GetCellData()->GetArray(name);
  if (!array)
  {
    if (input->GetCellData()->GetAbstractArray(name))
    {
      throw InputError(std::string("cell array '") + name + "' is not numeric");
    }
    throw InputError(std::string("missing cell array '") + name +
      "' (3-component RGB per polygon, see the data contract)");
  }
  if (array->GetNumberOfComponents() != 3)
  {
    std::ostringstream os;
    os << "cell array '" << name << "' has " << array->GetNumberOfComponents()
       << " components; it must have 3 (RGB)";
    throw InputError(os.str());
  }
  if (array->GetNumberOfTuples() != input->GetNumberOfCells())
  {
    std::ostringstream os;
    os << "cell array '" << name << "' has " << array->GetNumberOfTuples() << " tuples for "
       << input->GetNumberOfCells() << " cells";
    throw InputError(os.str());
  }
  return array;
}
}

Scene SceneFromPolyData(vtkPolyData* input)
{
  Scene scene;
  if (!input || input->GetNumberOfCells() == 0)
  {
    return scene;
  }
  const vtkIdType others =
    input->GetNumberOfVerts() + input->GetNumberOfLines() + input->GetNumberOfStrips();
  if (others > 0)
  {
    std::ostringstream os;
    os << "the scene has " << input->GetNumberOfVerts() << " vertex, "
       << input->GetNumberOfLines() << " line and " << input->GetNumberOfStrips()
       << " strip cells; a scene must contain polygons only (one polygon = one surface)";
    throw InputError(os.str());
  }
  vtkDataArray* reflectance = RequireColorArray(input, "Reflectance");
  vtkDataArray* emission = RequireColorArray(input, "Emission");
  vtkPoints* points = input->GetPoints();
  vtkCellArray* polys = input->GetPolys();
  scene.Surfaces.resize(static_cast<std::size_t>(polys->GetNumberOfCells()));
  vtkIdType npts = 0;
  const vtkIdType* ids = nullptr;
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  vtkIdType cell = 0;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cell)
  {
    it->GetCurrentCell(npts, ids);
    Surface& s = scene.Surfaces[static_cast<std::size_t>(cell)];
    s.Vertices.resize(static_cast<std::size_t>(npts));
    for (vtkIdType k = 0; k < npts; ++k)
    {
      if (ids[k] < 0 || ids[k] >= input->GetNumberOfPoints())
      {
        std::ostringstream os;
        os << "cell " << cell << ": point id " << ids[k] << " out of range ("
           << input->GetNumberOfPoints() << " points)";
        throw InputError(os.str());
      }
      double p[3];
      points->GetPoint(ids[k], p);
      s.Vertices[static_cast<std::size_t>(k)] = Vec3(p[0], p[1], p[2]);
    }
    double c[3];
    reflectance->GetTuple(cell, c);
    s.Reflectance = RGB(c[0], c[1], c[2]);
    emission->GetTuple(cell, c);
    s.Emission = RGB(c[0], c[1], c[2]);
  }
  return scene;
}

void AddMeshCellArrays(vtkPolyData* output, const std::vector<int>& lineSurface,
  const std::vector<int>& lineOrder, const std::vector<int>& lineSource,
  const std::vector<int>& triangleSurface)
{
  auto add = [&](const char* name, const std::vector<int>& lineValues,
               const std::vector<int>* triangleValues, int triangleDefault) {
    vtkNew<vtkIntArray> array;
    array->SetName(name);
    array->SetNumberOfTuples(static_cast<vtkIdType>(lineValues.size() + triangleSurface.size()));
    vtkIdType k = 0;
    for (int v : lineValues)
    {
      array->SetValue(k++, v);
    }
    for (std::size_t t = 0; t < triangleSurface.size(); ++t)
    {
      array->SetValue(k++, triangleValues ? (*triangleValues)[t] : triangleDefault);
    }
    output->GetCellData()->AddArray(array);
  };
  add("SurfaceId", lineSurface, &triangleSurface, 0);
  add("DiscontinuityOrder", lineOrder, nullptr, -2);
  add("SourceId", lineSource, nullptr, -1);
}

void AddField(vtkFieldData* fieldData, const char* name, const double* values, int count)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfComponents(count);
  array->InsertNextTuple(values);
  fieldData->AddArray(array);
}

void AddField(vtkFieldData* fieldData, const char* name, double value)
{
  AddField(fieldData, name, &value, 1);
}

void AddField(vtkFieldData* fieldData, const char* name, const RGB& value)
{
  const double rgb[3] = { value.R, value.G, value.B };
  AddField(fieldData, name, rgb, 3);
}

void AddSurfaceMaterials(vtkFieldData* fieldData, const Scene& scene, bool includeEmission)
{
  vtkNew<vtkDoubleArray> reflectance, emission;
  reflectance->SetName("SurfaceReflectance");
  emission->SetName("SurfaceEmission");
  reflectance->SetNumberOfComponents(3);
  emission->SetNumberOfComponents(3);
  for (const Surface& s : scene.Surfaces)
  {
    reflectance->InsertNextTuple3(s.Reflectance.R, s.Reflectance.G, s.Reflectance.B);
    const RGB e = includeEmission ? s.Emission : RGB();
    emission->InsertNextTuple3(e.R, e.G, e.B);
  }
  fieldData->AddArray(reflectance);
  fieldData->AddArray(emission);
}

bool GetSurfaceMaterials(vtkFieldData* fieldData, SurfaceMaterials& materials)
{
  vtkDataArray* reflectance = fieldData ? fieldData->GetArray("SurfaceReflectance") : nullptr;
  vtkDataArray* emission = fieldData ? fieldData->GetArray("SurfaceEmission") : nullptr;
  if (!reflectance || !emission || reflectance->GetNumberOfComponents() != 3 ||
    emission->GetNumberOfComponents() != 3 ||
    reflectance->GetNumberOfTuples() != emission->GetNumberOfTuples())
  {
    return false;
  }
  const vtkIdType n = reflectance->GetNumberOfTuples();
  materials.Reflectance.resize(static_cast<std::size_t>(n));
  materials.Emission.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double r[3], e[3];
    reflectance->GetTuple(i, r);
    emission->GetTuple(i, e);
    materials.Reflectance[i] = RGB(r[0], r[1], r[2]);
    materials.Emission[i] = RGB(e[0], e[1], e[2]);
  }
  return true;
}

std::map<int, ShooterRadiance> RadianceFunctions(vtkPolyData* data, int numberOfSurfaces,
  const std::string& what, const std::vector<RGB>* subtract)
{
  std::map<int, ShooterRadiance> functions;
  if (!data || data->GetNumberOfPolys() == 0)
  {
    return functions;
  }
  vtkDataArray* radiance = data->GetPointData()->GetArray("Radiance");
  vtkDataArray* surfaceIds = data->GetCellData()->GetArray("SurfaceId");
  if (!radiance || radiance->GetNumberOfComponents() != 3 || !surfaceIds)
  {
    throw InputError(what + " needs a 3-component point array 'Radiance' and a cell array "
                         "'SurfaceId'");
  }
  struct Mesh
  {
    std::vector<Vec3> Points;
    std::vector<std::array<int, 3>> Triangles;
    std::vector<RGB> Values;
    std::map<vtkIdType, int> Local;
  };
  std::map<int, Mesh> meshes;
  ForEachCell(data, [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
    if (kind != 2)
    {
      return true;
    }
    const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
    if (npts != 3 || surface < 0 || surface >= numberOfSurfaces)
    {
      std::ostringstream os;
      os << what << " cell " << cellId
         << (npts != 3 ? " is not a triangle" : " has a SurfaceId that is not a scene cell");
      throw InputError(os.str());
    }
    Mesh& mesh = meshes[surface];
    std::array<int, 3> triangle;
    for (int k = 0; k < 3; ++k)
    {
      auto found = mesh.Local.find(pts[k]);
      if (found == mesh.Local.end())
      {
        double p[3], v[3];
        data->GetPoint(pts[k], p);
        radiance->GetTuple(pts[k], v);
        found = mesh.Local.emplace(pts[k], static_cast<int>(mesh.Points.size())).first;
        mesh.Points.emplace_back(p[0], p[1], p[2]);
        RGB value(v[0], v[1], v[2]);
        if (subtract)
        {
          const RGB& less = (*subtract)[surface];
          value = RGB(std::max(0.0, value.R - less.R), std::max(0.0, value.G - less.G),
            std::max(0.0, value.B - less.B));
        }
        mesh.Values.push_back(value);
      }
      triangle[k] = found->second;
    }
    mesh.Triangles.push_back(triangle);
    return true;
  });
  for (auto& entry : meshes)
  {
    functions.emplace(entry.first,
      ShooterRadiance(std::move(entry.second.Points), std::move(entry.second.Triangles),
        std::move(entry.second.Values)));
  }
  return functions;
}

void ForEachCell(vtkPolyData* data, const CellVisitor& visit)
{
  vtkCellArray* kinds[4] = { data->GetVerts(), data->GetLines(), data->GetPolys(),
    data->GetStrips() };
  vtkIdType cellId = 0;
  for (int kind = 0; kind < 4; ++kind)
  {
    auto it = vtk::TakeSmartPointer(kinds[kind]->NewIterator());
    vtkIdType count;
    const vtkIdType* points;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      it->GetCurrentCell(count, points);
      if (!visit(cellId, kind, count, points))
      {
        return;
      }
    }
  }
}

ParallelFor SMPParallelFor()
{
  return [](std::size_t begin, std::size_t end,
           const std::function<void(std::size_t, std::size_t)>& body) {
    // The first exception of any worker is rethrown on the calling thread
    // (an exception escaping a worker would end the process with some SMP
    // backends); once one is caught, the remaining chunks are skipped.
    std::mutex mutex;
    std::exception_ptr failure;
    std::atomic<bool> failed(false);
    vtkSMPTools::For(static_cast<vtkIdType>(begin), static_cast<vtkIdType>(end),
      [&](vtkIdType first, vtkIdType last) {
        if (failed.load(std::memory_order_relaxed))
        {
          return;
        }
        try
        {
          body(static_cast<std::size_t>(first), static_cast<std::size_t>(last));
        }
        catch (...)
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (!failure)
          {
            failure = std::current_exception();
          }
          failed = true;
        }
      });
    if (failure)
    {
      std::rethrow_exception(failure);
    }
  };
}

void SceneToPolyData(const Scene& scene, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkDoubleArray> reflectance;
  reflectance->SetName("Reflectance");
  reflectance->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> emission;
  emission->SetName("Emission");
  emission->SetNumberOfComponents(3);
  for (const Surface& s : scene.Surfaces)
  {
    polys->InsertNextCell(static_cast<vtkIdType>(s.Vertices.size()));
    for (const Vec3& v : s.Vertices)
    {
      polys->InsertCellPoint(points->InsertNextPoint(v.X, v.Y, v.Z));
    }
    reflectance->InsertNextTuple3(s.Reflectance.R, s.Reflectance.G, s.Reflectance.B);
    emission->InsertNextTuple3(s.Emission.R, s.Emission.G, s.Emission.B);
  }
  output->Initialize();
  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetCellData()->AddArray(reflectance);
  output->GetCellData()->AddArray(emission);
}
}
