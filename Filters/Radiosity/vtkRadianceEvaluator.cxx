// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkRadianceEvaluator.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include "penumbraExactVisibility.h"
#include "penumbraLinearSource.h"
#include "penumbraShooterRadiance.h"
#include "penumbraRayCastEvaluator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

vtkStandardNewMacro(vtkRadianceEvaluator);

namespace
{
/// The surface of every sample point: from a `SurfaceId` point array, else
/// from the `SurfaceId` cell array of the first cell using the point.
std::vector<int> SampleSurfaces(vtkPolyData* samples, int numberOfSurfaces)
{
  const vtkIdType n = samples->GetNumberOfPoints();
  std::vector<int> surfaceOf(static_cast<std::size_t>(n), -1);
  if (vtkDataArray* ids = samples->GetPointData()->GetArray("SurfaceId"))
  {
    for (vtkIdType p = 0; p < n; ++p)
    {
      surfaceOf[p] = static_cast<int>(ids->GetComponent(p, 0));
    }
  }
  else if (vtkDataArray* cellIds = samples->GetCellData()->GetArray("SurfaceId"))
  {
    vtkIdType cellId = 0;
    auto visit = [&](vtkCellArray* cells) {
      auto it = vtk::TakeSmartPointer(cells->NewIterator());
      vtkIdType npts;
      const vtkIdType* pts;
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
      {
        it->GetCurrentCell(npts, pts);
        const int surface = static_cast<int>(cellIds->GetComponent(cellId, 0));
        for (vtkIdType k = 0; k < npts; ++k)
        {
          if (surfaceOf[pts[k]] < 0)
          {
            surfaceOf[pts[k]] = surface;
          }
        }
      }
    };
    // Cell ids run over verts, lines, polys and strips in that order.
    visit(samples->GetVerts());
    visit(samples->GetLines());
    visit(samples->GetPolys());
    visit(samples->GetStrips());
  }
  else
  {
    throw penumbra::InputError("the samples have no 'SurfaceId' point or cell array");
  }
  for (vtkIdType p = 0; p < n; ++p)
  {
    if (surfaceOf[p] < 0 || surfaceOf[p] >= numberOfSurfaces)
    {
      std::ostringstream os;
      os << "sample point " << p << " has SurfaceId " << surfaceOf[p] << ", not a scene cell (0 to "
         << numberOfSurfaces - 1 << ")";
      if (surfaceOf[p] == -1)
      {
        os << "; is it used by no cell?";
      }
      throw penumbra::InputError(os.str());
    }
  }
  return surfaceOf;
}
}

vtkRadianceEvaluator::vtkRadianceEvaluator()
{
  this->SetNumberOfInputPorts(3);
}

int vtkRadianceEvaluator::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 2)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

namespace
{
/// Piecewise-linear shooter radiance per surface from port 2's triangles.
std::map<int, penumbra::ShooterRadiance> ShooterFunctions(
  vtkPolyData* data, int numberOfSurfaces)
{
  std::map<int, penumbra::ShooterRadiance> functions;
  if (!data || data->GetNumberOfPolys() == 0)
  {
    return functions;
  }
  vtkDataArray* radiance = data->GetPointData()->GetArray("Radiance");
  vtkDataArray* surfaceIds = data->GetCellData()->GetArray("SurfaceId");
  if (!radiance || radiance->GetNumberOfComponents() != 3 || !surfaceIds)
  {
    throw penumbra::InputError("shooter radiance (port 2) needs a 3-component point array "
                               "'Radiance' and a cell array 'SurfaceId'");
  }
  struct Mesh
  {
    std::vector<penumbra::Vec3> Points;
    std::vector<std::array<int, 3>> Triangles;
    std::vector<penumbra::RGB> Values;
    std::map<vtkIdType, int> Local;
  };
  std::map<int, Mesh> meshes;
  vtkIdType cellId = data->GetNumberOfVerts() + data->GetNumberOfLines();
  auto it = vtk::TakeSmartPointer(data->GetPolys()->NewIterator());
  vtkIdType npts;
  const vtkIdType* pts;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
  {
    it->GetCurrentCell(npts, pts);
    const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
    if (npts != 3 || surface < 0 || surface >= numberOfSurfaces)
    {
      std::ostringstream os;
      os << "shooter radiance (port 2) cell " << cellId
         << (npts != 3 ? " is not a triangle" : " has a SurfaceId that is not a scene cell");
      throw penumbra::InputError(os.str());
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
        mesh.Values.emplace_back(v[0], v[1], v[2]);
      }
      triangle[k] = found->second;
    }
    mesh.Triangles.push_back(triangle);
  }
  for (auto& entry : meshes)
  {
    functions.emplace(entry.first,
      penumbra::ShooterRadiance(std::move(entry.second.Points), std::move(entry.second.Triangles),
        std::move(entry.second.Values)));
  }
  return functions;
}
}

void vtkRadianceEvaluator::AddShooterId(vtkIdType id)
{
  this->ShooterIds.push_back(id);
  this->Modified();
}

void vtkRadianceEvaluator::RemoveAllShooterIds()
{
  if (!this->ShooterIds.empty())
  {
    this->ShooterIds.clear();
    this->Modified();
  }
}

vtkIdType vtkRadianceEvaluator::GetNumberOfShooterIds() const
{
  return static_cast<vtkIdType>(this->ShooterIds.size());
}

vtkIdType vtkRadianceEvaluator::GetShooterId(vtkIdType index) const
{
  return index >= 0 && index < this->GetNumberOfShooterIds() ? this->ShooterIds[index] : -1;
}

int vtkRadianceEvaluator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* samples = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* sceneData = vtkPolyData::GetData(inputVector[1]);
  vtkPolyData* shooterData =
    inputVector[2]->GetNumberOfInformationObjects() ? vtkPolyData::GetData(inputVector[2]) : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->ShallowCopy(samples);
  if (samples->GetNumberOfPoints() == 0)
  {
    return 1;
  }
  if (!sceneData)
  {
    vtkErrorMacro(<< "no scene on input port 1 (SetSceneConnection)");
    return 0;
  }

  penumbra::Scene scene;
  std::vector<int> surfaceOf;
  std::vector<int> shooters;
  std::map<int, penumbra::ShooterRadiance> functions;
  try
  {
    scene = penumbra::SceneFromPolyData(sceneData);
    penumbra::ValidateScene(scene);
    const int numberOfSurfaces = static_cast<int>(scene.Surfaces.size());
    surfaceOf = SampleSurfaces(samples, numberOfSurfaces);
    functions = ShooterFunctions(shooterData, numberOfSurfaces);
    for (vtkIdType id : this->ShooterIds)
    {
      if (id < 0 || id >= numberOfSurfaces)
      {
        std::ostringstream os;
        os << "ShooterIds: " << id << " is not a scene cell (0 to " << numberOfSurfaces - 1 << ")";
        throw penumbra::InputError(os.str());
      }
      shooters.push_back(static_cast<int>(id));
    }
    if (this->ShooterIds.empty())
    {
      for (int j = 0; j < numberOfSurfaces; ++j)
      {
        if (!scene.Surfaces[j].Emission.IsZero() || functions.count(j))
        {
          shooters.push_back(j);
        }
      }
    }
  }
  catch (const penumbra::InputError& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }
  this->UpdateProgress(0.0);
  const penumbra::ExactEvaluator evaluator(scene);
  std::unique_ptr<penumbra::RayCastEvaluator> rayCaster;
  if (this->Method == RAY_CAST)
  {
    rayCaster.reset(new penumbra::RayCastEvaluator(scene));
    rayCaster->SetTolerance(this->RayCastTolerance);
  }
  std::vector<penumbra::Vec3> normals(scene.Surfaces.size());
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    normals[i] = penumbra::ComputePolygonGeometry(scene.Surfaces[i].Vertices).Normal;
  }

  // Shaft candidates once per (receiver, shooter) pair that has samples.
  const std::size_t numberOfShooters = shooters.size();
  std::vector<char> hasSamples(scene.Surfaces.size(), 0);
  for (int s : surfaceOf)
  {
    hasSamples[s] = 1;
  }
  std::vector<std::vector<int>> candidates(scene.Surfaces.size() * numberOfShooters);
  std::vector<char> exchanges(candidates.size(), 0);
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    for (std::size_t k = 0; hasSamples[i] && k < numberOfShooters; ++k)
    {
      const std::size_t pair = i * numberOfShooters + k;
      exchanges[pair] = shooters[k] != static_cast<int>(i) &&
        evaluator.ShaftCandidates(shooters[k], static_cast<int>(i), candidates[pair]);
    }
  }

  const vtkIdType numberOfPoints = samples->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> radiance;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  radiance->SetNumberOfTuples(numberOfPoints);
  vtkSMPThreadLocal<penumbra::VisibilityWorkspace> workspaces;
  vtkSMPThreadLocal<penumbra::LinearSourceWorkspace> linearWorkspaces;
  std::vector<const penumbra::ShooterRadiance*> shooterFunction(numberOfShooters, nullptr);
  for (std::size_t k = 0; k < numberOfShooters; ++k)
  {
    auto found = functions.find(shooters[k]);
    shooterFunction[k] = found == functions.end() ? nullptr : &found->second;
  }
  vtkPoints* points = samples->GetPoints();

  // Batches between which progress is reported and abort is honoured.
  const vtkIdType batches = std::min<vtkIdType>(100, numberOfPoints);
  for (vtkIdType batch = 0; batch < batches && !this->GetAbortExecute(); ++batch)
  {
    const vtkIdType begin = numberOfPoints * batch / batches;
    const vtkIdType end = numberOfPoints * (batch + 1) / batches;
    vtkSMPTools::For(begin, end, [&](vtkIdType first, vtkIdType last) {
      penumbra::VisibilityWorkspace& workspace = workspaces.Local();
      for (vtkIdType p = first; p < last; ++p)
      {
        const int i = surfaceOf[p];
        double xyz[3];
        points->GetPoint(p, xyz);
        const penumbra::Vec3 x(xyz[0], xyz[1], xyz[2]);
        const penumbra::Surface& receiver = scene.Surfaces[i];
        penumbra::RGB irradianceOverPi; // sum_j L^e_j F_j
        for (std::size_t k = 0; k < numberOfShooters; ++k)
        {
          const std::size_t pair = static_cast<std::size_t>(i) * numberOfShooters + k;
          if (!exchanges[pair])
          {
            continue;
          }
          if (const penumbra::ShooterRadiance* function = shooterFunction[k])
          {
            const penumbra::RGB e = rayCaster
              ? rayCaster->Irradiance(x, normals[i], i, shooters[k], *function)
              : penumbra::ExactShooterIrradiance(
                  evaluator, x, normals[i], i, shooters[k], *function, linearWorkspaces.Local());
            irradianceOverPi += e * (1.0 / M_PI);
            continue;
          }
          const double f = rayCaster
            ? rayCaster->FormFactor(x, normals[i], i, shooters[k])
            : evaluator.FormFactor(x, normals[i], i, shooters[k], candidates[pair], workspace);
          irradianceOverPi += scene.Surfaces[shooters[k]].Emission * f;
        }
        penumbra::RGB value = receiver.Reflectance * irradianceOverPi;
        if (this->IncludeEmission)
        {
          value += receiver.Emission;
        }
        radiance->SetTuple3(p, value.R, value.G, value.B);
      }
    });
    this->UpdateProgress(static_cast<double>(batch + 1) / batches);
  }
  if (this->GetAbortExecute())
  {
    output->Initialize();
    return 1;
  }
  output->GetPointData()->AddArray(radiance);
  output->GetPointData()->SetActiveScalars("Radiance");
  return 1;
}

void vtkRadianceEvaluator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << (this->Method == EXACT ? "EXACT" : "RAY_CAST") << "\n";
  os << indent << "RayCastTolerance: " << this->RayCastTolerance << "\n";
  os << indent << "IncludeEmission: " << (this->IncludeEmission ? "On" : "Off") << "\n";
  os << indent << "ShooterIds:";
  if (this->ShooterIds.empty())
  {
    os << " (every emitter)";
  }
  for (vtkIdType id : this->ShooterIds)
  {
    os << " " << id;
  }
  os << "\n";
}
