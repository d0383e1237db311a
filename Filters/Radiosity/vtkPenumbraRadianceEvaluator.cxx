// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraRadianceEvaluator.h"

#include "vtkPenumbraAdaptiveSampling.h"
#include "vtkPenumbraSceneConversion.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include "penumbraEvaluationSettings.h"
#include "penumbraExactEvaluator.h"
#include "penumbraPreparedScene.h"
#include "penumbraLinearSource.h"
#include "penumbraShooterRadiance.h"
#include "penumbraRayCastEvaluator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkPenumbraRadianceEvaluator);

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
    penumbra::ForEachCell(
      samples, [&](vtkIdType cellId, int, vtkIdType npts, const vtkIdType* pts) {
        const int surface = static_cast<int>(cellIds->GetComponent(cellId, 0));
        for (vtkIdType k = 0; k < npts; ++k)
        {
          if (surfaceOf[pts[k]] < 0)
          {
            surfaceOf[pts[k]] = surface;
          }
        }
        return true;
      });
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

vtkPenumbraRadianceEvaluator::vtkPenumbraRadianceEvaluator()
{
  const penumbra::EvaluationSettings defaults;
  this->Method = static_cast<int>(defaults.Method);
  this->RayCastTolerance = defaults.RayCast.Tolerance;
  this->IncludeEmission = defaults.IncludeEmission;
  this->AdaptiveSampling = defaults.AdaptiveSampling;
  this->SamplingTolerance = defaults.Sampling.SamplingTolerance;
  this->MaximumSamplesPerSurface = defaults.Sampling.MaximumSamplesPerSurface;
  this->MaximumSamples = static_cast<vtkIdType>(defaults.MaximumSamples);
  this->MaximumSampleSpacing = defaults.MaximumSampleSpacing;
  this->MinimumFeatureSize = defaults.Sampling.MinimumFeatureSize;
  this->SetNumberOfInputPorts(3);
}

int vtkPenumbraRadianceEvaluator::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 2)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

void vtkPenumbraRadianceEvaluator::AddShooterId(vtkIdType id)
{
  this->ShooterIds.push_back(id);
  this->Modified();
}

void vtkPenumbraRadianceEvaluator::RemoveAllShooterIds()
{
  if (!this->ShooterIds.empty())
  {
    this->ShooterIds.clear();
    this->Modified();
  }
}

vtkIdType vtkPenumbraRadianceEvaluator::GetNumberOfShooterIds() const
{
  return static_cast<vtkIdType>(this->ShooterIds.size());
}

vtkIdType vtkPenumbraRadianceEvaluator::GetShooterId(vtkIdType index) const
{
  return index >= 0 && index < this->GetNumberOfShooterIds() ? this->ShooterIds[index] : -1;
}

namespace
{
/// The shooters: the ShooterIds, checked against the scene, or with none
/// every emitter and every surface with a shooter radiance function.
std::vector<int> SelectShooters(const std::vector<vtkIdType>& shooterIds,
  const penumbra::Scene& scene, const std::map<int, penumbra::ShooterRadiance>& functions)
{
  const int numberOfSurfaces = static_cast<int>(scene.Surfaces.size());
  std::vector<int> shooters;
  for (vtkIdType id : shooterIds)
  {
    if (id < 0 || id >= numberOfSurfaces)
    {
      std::ostringstream os;
      os << "ShooterIds: " << id << " is not a scene cell (0 to " << numberOfSurfaces - 1 << ")";
      throw penumbra::InputError(os.str());
    }
    shooters.push_back(static_cast<int>(id));
  }
  if (shooterIds.empty())
  {
    for (int j = 0; j < numberOfSurfaces; ++j)
    {
      if (!scene.Surfaces[j].Emission.IsZero() || functions.count(j))
      {
        shooters.push_back(j);
      }
    }
  }
  return shooters;
}

/// The radiance at a point x of surface i: its emission (if included) plus
/// the radiance reflected from each shooter. Thread-safe.
class PointRadiance
{
public:
  PointRadiance(const std::shared_ptr<const penumbra::PreparedScene>& prepared,
    const std::vector<int>& shooters, const std::map<int, penumbra::ShooterRadiance>& functions,
    const std::vector<int>& surfaceOf, bool rayCast, double rayCastTolerance,
    bool includeEmission);

  penumbra::RGB operator()(int i, const penumbra::Vec3& x) const;

private:
  const penumbra::Scene& Scene;
  const std::vector<int>& Shooters;
  const bool IncludeEmission;
  const penumbra::ExactEvaluator Evaluator;
  std::unique_ptr<penumbra::RayCastEvaluator> RayCaster;
  std::vector<penumbra::Vec3> Normals;
  /// Per (receiver, shooter) pair: shaft candidates, and whether they exchange light.
  std::vector<std::vector<int>> Candidates;
  std::vector<char> Exchanges;
  /// Per shooter: its radiance function, null for its constant Emission.
  std::vector<const penumbra::ShooterRadiance*> ShooterFunction;
  mutable vtkSMPThreadLocal<penumbra::VisibilityWorkspace> Workspaces;
  mutable vtkSMPThreadLocal<penumbra::LinearSourceWorkspace> LinearWorkspaces;
};

PointRadiance::PointRadiance(const std::shared_ptr<const penumbra::PreparedScene>& prepared,
  const std::vector<int>& shooters, const std::map<int, penumbra::ShooterRadiance>& functions,
  const std::vector<int>& surfaceOf, bool rayCast, double rayCastTolerance, bool includeEmission)
  : Scene(prepared->GetScene())
  , Shooters(shooters)
  , IncludeEmission(includeEmission)
  , Evaluator(prepared)
{
  const penumbra::Scene& scene = this->Scene;
  if (rayCast)
  {
    this->RayCaster.reset(new penumbra::RayCastEvaluator(scene));
    this->RayCaster->SetTolerance(rayCastTolerance);
  }
  this->Normals.resize(scene.Surfaces.size());
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    this->Normals[i] = penumbra::ComputePolygonGeometry(scene.Surfaces[i].Vertices).Normal;
  }

  // Shaft candidates once per (receiver, shooter) pair that has samples.
  const std::size_t numberOfShooters = shooters.size();
  std::vector<char> hasSamples(scene.Surfaces.size(), 0);
  for (int s : surfaceOf)
  {
    hasSamples[s] = 1;
  }
  this->Candidates.resize(scene.Surfaces.size() * numberOfShooters);
  this->Exchanges.assign(this->Candidates.size(), 0);
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    for (std::size_t k = 0; hasSamples[i] && k < numberOfShooters; ++k)
    {
      const std::size_t pair = i * numberOfShooters + k;
      this->Exchanges[pair] = shooters[k] != static_cast<int>(i) &&
        this->Evaluator.ShaftCandidates(shooters[k], static_cast<int>(i), this->Candidates[pair]);
    }
  }

  this->ShooterFunction.assign(numberOfShooters, nullptr);
  for (std::size_t k = 0; k < numberOfShooters; ++k)
  {
    auto found = functions.find(shooters[k]);
    this->ShooterFunction[k] = found == functions.end() ? nullptr : &found->second;
  }
}

penumbra::RGB PointRadiance::operator()(int i, const penumbra::Vec3& x) const
{
  const penumbra::Surface& receiver = this->Scene.Surfaces[i];
  const std::size_t numberOfShooters = this->Shooters.size();
  penumbra::RGB irradianceOverPi; // sum_j L^e_j F_j
  for (std::size_t k = 0; k < numberOfShooters; ++k)
  {
    const std::size_t pair = static_cast<std::size_t>(i) * numberOfShooters + k;
    if (!this->Exchanges[pair])
    {
      continue;
    }
    const int j = this->Shooters[k];
    if (const penumbra::ShooterRadiance* function = this->ShooterFunction[k])
    {
      const penumbra::RGB e = this->RayCaster
        ? this->RayCaster->Irradiance(x, this->Normals[i], i, j, *function)
        : penumbra::ExactShooterIrradiance(this->Evaluator, x, this->Normals[i], i, j, *function,
            this->LinearWorkspaces.Local());
      irradianceOverPi += e * (1.0 / M_PI);
      continue;
    }
    const double f = this->RayCaster
      ? this->RayCaster->FormFactor(x, this->Normals[i], i, j)
      : this->Evaluator.FormFactor(
          x, this->Normals[i], i, j, this->Candidates[pair], this->Workspaces.Local());
    irradianceOverPi += this->Scene.Surfaces[j].Emission * f;
  }
  penumbra::RGB value = penumbra::TrackedReflectance(receiver.Reflectance) * irradianceOverPi;
  if (this->IncludeEmission)
  {
    value += receiver.Emission;
  }
  return value;
}

/// The path without adaptive sampling: `Radiance` at the given points, in
/// batches between which progress is reported and abort is honoured.
void EvaluatePoints(vtkPenumbraRadianceEvaluator* self, vtkPolyData* samples,
  const std::vector<int>& surfaceOf, const PointRadiance& evaluatePoint, vtkPolyData* output)
{
  const vtkIdType numberOfPoints = samples->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> radiance;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  radiance->SetNumberOfTuples(numberOfPoints);
  vtkPoints* points = samples->GetPoints();

  const vtkIdType batches = std::min<vtkIdType>(100, numberOfPoints);
  for (vtkIdType batch = 0; batch < batches && !self->GetAbortExecute(); ++batch)
  {
    const vtkIdType begin = numberOfPoints * batch / batches;
    const vtkIdType end = numberOfPoints * (batch + 1) / batches;
    vtkSMPTools::For(begin, end, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType p = first; p < last; ++p)
      {
        double xyz[3];
        points->GetPoint(p, xyz);
        const penumbra::RGB value =
          evaluatePoint(surfaceOf[p], penumbra::Vec3(xyz[0], xyz[1], xyz[2]));
        radiance->SetTuple3(p, value.R, value.G, value.B);
      }
    });
    self->UpdateProgress(static_cast<double>(batch + 1) / batches);
  }
  if (self->GetAbortExecute())
  {
    output->Initialize();
    return;
  }
  output->GetPointData()->AddArray(radiance);
  output->GetPointData()->SetActiveScalars("Radiance");
}
}

int vtkPenumbraRadianceEvaluator::Execute(
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
  std::shared_ptr<const penumbra::PreparedScene> prepared;
  std::vector<int> surfaceOf;
  std::vector<int> shooters;
  std::map<int, penumbra::ShooterRadiance> functions;
  try
  {
    scene = penumbra::SceneFromPolyData(sceneData);
    prepared = this->Prepare(scene); // validates the scene
    const int numberOfSurfaces = static_cast<int>(scene.Surfaces.size());
    surfaceOf = SampleSurfaces(samples, numberOfSurfaces);
    functions = penumbra::RadianceFunctions(shooterData, numberOfSurfaces, "shooter radiance (port 2)");
    shooters = SelectShooters(this->ShooterIds, scene, functions);
  }
  catch (const penumbra::InputError& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }
  this->UpdateProgress(0.0);
  const PointRadiance evaluatePoint(prepared, shooters, functions, surfaceOf,
    this->Method == RAY_CAST, this->RayCastTolerance, this->IncludeEmission);

  this->ReusedSurfaces = 0;
  if (this->AdaptiveSampling && samples->GetNumberOfPolys() > 0)
  {
    // What the kept results depend on besides each surface's input mesh.
    std::ostringstream context;
    context.precision(17);
    context << this->Method << " " << this->RayCastTolerance << " " << this->IncludeEmission << " "
            << this->SamplingTolerance << " " << this->MaximumSamplesPerSurface << " "
            << this->MaximumSamples << " " << this->MaximumSampleSpacing << " "
            << this->MinimumFeatureSize << " " << prepared.get() << " " << sceneData
            << " " << sceneData->GetMTime() << " " << shooterData << " "
            << (shooterData ? shooterData->GetMTime() : 0) << " shooters";
    for (const int id : shooters)
    {
      context << " " << id;
    }
    if (!penumbra::SampleAdaptively(this, samples, output, sceneData->GetLength(),
          [&](int i, const penumbra::Vec3& x) { return evaluatePoint(i, x); }, this->Reuse.get(),
          context.str(), &this->ReusedSurfaces))
    {
      return 0;
    }
  }
  else
  {
    EvaluatePoints(this, samples, surfaceOf, evaluatePoint, output);
  }
  // The reconstructor turns the values into Radiance and Irradiance with them.
  if (output->GetNumberOfPoints() > 0)
  {
    output->GetFieldData()->RemoveArray("SurfaceReflectance");
    output->GetFieldData()->RemoveArray("SurfaceEmission");
    penumbra::AddSurfaceMaterials(output->GetFieldData(), scene, this->IncludeEmission);
  }
  return 1;
}

vtkPenumbraRadianceEvaluator::~vtkPenumbraRadianceEvaluator() = default;

void vtkPenumbraRadianceEvaluator::SetReuseUnchangedSurfaces(bool reuse)
{
  if (!reuse)
  {
    this->Reuse.reset();
  }
  else if (!this->Reuse)
  {
    this->Reuse.reset(new penumbra::SampledSurfaceCache);
  }
}

int vtkPenumbraRadianceEvaluator::GetNumberOfReusedSurfaces() const
{
  return this->ReusedSurfaces;
}

void vtkPenumbraRadianceEvaluator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << (this->Method == EXACT ? "EXACT" : "RAY_CAST") << "\n";
  os << indent << "RayCastTolerance: " << this->RayCastTolerance << "\n";
  os << indent << "AdaptiveSampling: " << (this->AdaptiveSampling ? "On" : "Off") << "\n";
  os << indent << "SamplingTolerance: " << this->SamplingTolerance << "\n";
  os << indent << "MaximumSamplesPerSurface: " << this->MaximumSamplesPerSurface << "\n";
  os << indent << "MaximumSamples: " << this->MaximumSamples << "\n";
  os << indent << "MaximumSampleSpacing: " << this->MaximumSampleSpacing << "\n";
  os << indent << "MinimumFeatureSize: " << this->MinimumFeatureSize << "\n";
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
  os << indent << "ReuseUnchangedSurfaces: " << (this->Reuse ? "On" : "Off")
     << " (reused by the last execution: " << this->ReusedSurfaces << ")\n";
}
