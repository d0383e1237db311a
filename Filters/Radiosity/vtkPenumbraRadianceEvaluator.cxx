// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraRadianceEvaluator.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include "penumbraAdaptiveSampler.h"
#include "penumbraEvaluationSettings.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraExactEvaluator.h"
#include "penumbraLinearSource.h"
#include "penumbraShooterRadiance.h"
#include "penumbraRayCastEvaluator.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <unordered_map>

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
  penumbra::ForEachCell(data, [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
    if (kind != 2)
    {
      return true;
    }
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
    return true;
  });
  for (auto& entry : meshes)
  {
    functions.emplace(entry.first,
      penumbra::ShooterRadiance(std::move(entry.second.Points), std::move(entry.second.Triangles),
        std::move(entry.second.Values)));
  }
  return functions;
}
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
/// The adaptive-sampling path of RequestData (see the class description);
/// false after an error.
bool SampleAdaptively(vtkPenumbraRadianceEvaluator* self, vtkPolyData* samples, vtkPolyData* output,
  double sceneDiagonal,
  const std::function<penumbra::RGB(int, const penumbra::Vec3&)>& evaluatePoint)
{
  vtkDataArray* surfaceIds = samples->GetCellData()->GetArray("SurfaceId");
  vtkDataArray* orders = samples->GetCellData()->GetArray("DiscontinuityOrder");
  vtkDataArray* sources = samples->GetCellData()->GetArray("SourceId");
  if (!surfaceIds)
  {
    output->Initialize();
    vtkErrorWithObjectMacro(self, << "adaptive sampling needs the cell array 'SurfaceId' on the triangles");
    return false;
  }

  // Rebuild each surface's mesh (mesher layout) from the triangles and lines.
  std::map<int, penumbra::ReceiverMesh> meshes;
  std::map<int, std::unordered_map<vtkIdType, int>> localIds;
  std::map<int, std::map<std::array<double, 3>, int>> vertexIds;
  auto localId = [&](int surface, vtkIdType id) {
    auto& ids = localIds[surface];
    auto found = ids.find(id);
    if (found != ids.end())
    {
      return found->second;
    }
    penumbra::ReceiverMesh& mesh = meshes[surface];
    double p[3];
    samples->GetPoint(id, p);
    auto& vertices = vertexIds[surface];
    const auto vertex = vertices.emplace(std::array<double, 3>{ p[0], p[1], p[2] },
      static_cast<int>(vertices.size()));
    mesh.Points.emplace_back(p[0], p[1], p[2]);
    mesh.PointVertex.push_back(vertex.first->second);
    const int k = static_cast<int>(mesh.Points.size()) - 1;
    ids.emplace(id, k);
    return k;
  };
  std::vector<std::array<vtkIdType, 2>> lines;
  std::vector<vtkIdType> lineCells;
  vtkIdType badCell = -1;
  penumbra::ForEachCell(
    samples, [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
      if (kind == 1)
      {
        for (vtkIdType k = 0; k + 1 < npts; ++k)
        {
          lines.push_back({ pts[k], pts[k + 1] });
          lineCells.push_back(cellId);
        }
      }
      else if (kind == 2)
      {
        if (npts != 3)
        {
          badCell = cellId;
          return false;
        }
        const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
        const int a = localId(surface, pts[0]), b = localId(surface, pts[1]),
                  c = localId(surface, pts[2]);
        meshes[surface].ReceiverId = surface;
        meshes[surface].Triangles.push_back({ a, b, c });
      }
      return kind < 3; // strips: nothing to sample
    });
  if (badCell >= 0)
  {
    output->Initialize();
    vtkErrorWithObjectMacro(self, << "cell " << badCell << " is not a triangle; adaptive sampling "
                  << "needs a triangle mesh (vtkPenumbraDiscontinuityMesher's output)");
    return false;
  }
  for (std::size_t k = 0; k < lines.size(); ++k)
  {
    const int surface = static_cast<int>(surfaceIds->GetComponent(lineCells[k], 0));
    auto ids = localIds.find(surface);
    if (ids == localIds.end())
    {
      continue;
    }
    auto a = ids->second.find(lines[k][0]);
    auto b = ids->second.find(lines[k][1]);
    if (a == ids->second.end() || b == ids->second.end())
    {
      continue;
    }
    penumbra::DiscontinuitySegment segment;
    penumbra::ReceiverMesh& mesh = meshes[surface];
    segment.A = mesh.Points[a->second];
    segment.B = mesh.Points[b->second];
    segment.PointA = a->second;
    segment.PointB = b->second;
    segment.Order = orders ? static_cast<int>(orders->GetComponent(lineCells[k], 0)) : 2;
    segment.SourceId = sources ? static_cast<int>(sources->GetComponent(lineCells[k], 0)) : -1;
    segment.ReceiverId = surface;
    mesh.Segments.push_back(segment);
  }

  penumbra::AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = self->GetSamplingTolerance();
  settings.MaximumSamplesPerSurface = self->GetMaximumSamplesPerSurface();
  settings.MinimumFeatureSize = self->GetMinimumFeatureSize();
  settings.MaximumEdgeLength = self->GetMaximumSampleSpacing() * sceneDiagonal;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> outLines, outPolys;
  vtkNew<vtkDoubleArray> radiance, residual;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  residual->SetName("SamplingResidual");
  residual->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> pointSurface;
  pointSurface->SetName("SurfaceId");
  std::vector<int> lineSurface, lineOrder, lineSource, polySurface;
  std::vector<std::array<double, 3>> polyResidual;
  long long evaluations = 0;

  // Receivers are sampled in parallel, largest initial mesh first (the
  // sampler's passes run on one thread per receiver; each receiver's batch
  // evaluations run in parallel too, nested). Results are assembled in
  // surface order afterwards, so the output does not depend on scheduling.
  std::vector<const std::pair<const int, penumbra::ReceiverMesh>*> work;
  for (const auto& entry : meshes)
  {
    work.push_back(&entry);
  }
  std::vector<std::size_t> order(work.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    order[k] = k;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return work[a]->second.Triangles.size() > work[b]->second.Triangles.size();
  });
  // Each surface's share of the scene budget, by area.
  std::vector<int> budgets(work.size(), settings.MaximumSamplesPerSurface);
  if (self->GetMaximumSamples() > 0)
  {
    std::vector<double> areas(work.size(), 0.0);
    double totalArea = 0.0;
    for (std::size_t w = 0; w < work.size(); ++w)
    {
      const penumbra::ReceiverMesh& mesh = work[w]->second;
      for (const auto& t : mesh.Triangles)
      {
        areas[w] += 0.5 *
          penumbra::Length(penumbra::Cross(mesh.Points[t[1]] - mesh.Points[t[0]],
            mesh.Points[t[2]] - mesh.Points[t[0]]));
      }
      totalArea += areas[w];
    }
    // At least an equal share: a sliver or a tiny part has next to no area
    // but may still need its samples (so the total is at most twice the
    // budget).
    const double budget = static_cast<double>(self->GetMaximumSamples());
    const double equalShare = budget / static_cast<double>(std::max<std::size_t>(1, work.size()));
    for (std::size_t w = 0; w < work.size() && totalArea > 0.0; ++w)
    {
      const double share = std::max(equalShare, budget * areas[w] / totalArea);
      budgets[w] = static_cast<int>(std::max(3.0, std::min<double>(share, budgets[w])));
    }
  }
  std::vector<penumbra::AdaptiveSamplingResult> results(work.size());
  std::vector<std::string> errors(work.size());
  std::atomic<std::size_t> finished(0);
  const std::thread::id mainThread = std::this_thread::get_id();
  vtkSMPTools::For(0, static_cast<vtkIdType>(order.size()), 1, [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType k = first; k < last; ++k)
    {
      if (self->GetAbortExecute())
      {
        return;
      }
      const std::size_t w = order[k];
      const int surface = work[w]->first;
      try
      {
        const penumbra::RadianceBatchFunction evaluate =
          [&](const penumbra::Vec3* x, int count, penumbra::RGB* values) {
            vtkSMPTools::For(0, count, [&](vtkIdType a, vtkIdType b) {
              for (vtkIdType i = a; i < b; ++i)
              {
                values[i] = evaluatePoint(surface, x[i]);
              }
            });
          };
        penumbra::AdaptiveSamplingSettings receiverSettings = settings;
        receiverSettings.MaximumSamplesPerSurface = budgets[w];
        results[w] = penumbra::SampleReceiver(work[w]->second, evaluate, receiverSettings);
      }
      catch (const penumbra::InputError& e)
      {
        errors[w] = e.what();
      }
      const std::size_t done = ++finished;
      // Observers (Python ones included) are only called from the calling thread.
      if (std::this_thread::get_id() == mainThread)
      {
        self->UpdateProgress(static_cast<double>(done) / work.size());
      }
    }
  });
  if (self->GetAbortExecute())
  {
    output->Initialize();
    return true;
  }
  for (std::size_t w = 0; w < work.size(); ++w)
  {
    if (!errors[w].empty())
    {
      output->Initialize();
      vtkErrorWithObjectMacro(self, << "surface " << work[w]->first << ": " << errors[w]);
      return false;
    }
  }
  for (std::size_t w = 0; w < work.size(); ++w)
  {
    const int surface = work[w]->first;
    penumbra::AdaptiveSamplingResult result = std::move(results[w]);
    evaluations += result.Statistics.Evaluations;
    const vtkIdType offset = points->GetNumberOfPoints();
    for (std::size_t p = 0; p < result.Mesh.Points.size(); ++p)
    {
      const penumbra::Vec3& x = result.Mesh.Points[p];
      points->InsertNextPoint(x.X, x.Y, x.Z);
      radiance->InsertNextTuple3(result.Values[p].R, result.Values[p].G, result.Values[p].B);
      pointSurface->InsertNextValue(surface);
    }
    // -1: not probed; the reconstructor then relies on its model alone there.
    std::vector<std::array<double, 3>> worst(result.Mesh.Triangles.size(), { -1.0, -1.0, -1.0 });
    for (std::size_t q = 0; q < result.Probes.Triangles.size(); ++q)
    {
      auto& w = worst[static_cast<std::size_t>(result.Probes.Triangles[q])];
      for (int c = 0; c < 3; ++c)
      {
        w[c] = std::max(w[c], std::abs(result.Probes.Residuals[3 * q + c]));
      }
    }
    for (std::size_t t = 0; t < result.Mesh.Triangles.size(); ++t)
    {
      const auto& tri = result.Mesh.Triangles[t];
      const vtkIdType ids[3] = { offset + tri[0], offset + tri[1], offset + tri[2] };
      outPolys->InsertNextCell(3, ids);
      polySurface.push_back(surface);
      polyResidual.push_back(worst[t]);
    }
    for (const penumbra::DiscontinuitySegment& segment : result.Mesh.Segments)
    {
      const vtkIdType ids[2] = { offset + segment.PointA, offset + segment.PointB };
      outLines->InsertNextCell(2, ids);
      lineSurface.push_back(surface);
      lineOrder.push_back(segment.Order);
      lineSource.push_back(segment.SourceId);
    }
  }

  output->Initialize();
  output->SetPoints(points);
  output->SetLines(outLines);
  output->SetPolys(outPolys);
  output->GetPointData()->AddArray(radiance);
  output->GetPointData()->SetActiveScalars("Radiance");
  output->GetPointData()->AddArray(pointSurface);
  penumbra::AddMeshCellArrays(output, lineSurface, lineOrder, lineSource, polySurface);
  for (std::size_t k = 0; k < lineSurface.size(); ++k)
  {
    residual->InsertNextTuple3(0.0, 0.0, 0.0);
  }
  for (const auto& r : polyResidual)
  {
    residual->InsertNextTuple(r.data());
  }
  output->GetCellData()->AddArray(residual);
  vtkNew<vtkIdTypeArray> evaluationCount;
  evaluationCount->SetName("Evaluations");
  evaluationCount->InsertNextValue(static_cast<vtkIdType>(evaluations));
  output->GetFieldData()->AddArray(evaluationCount);
  return true;
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

  vtkSMPThreadLocal<penumbra::VisibilityWorkspace> workspaces;
  vtkSMPThreadLocal<penumbra::LinearSourceWorkspace> linearWorkspaces;
  std::vector<const penumbra::ShooterRadiance*> shooterFunction(numberOfShooters, nullptr);
  for (std::size_t k = 0; k < numberOfShooters; ++k)
  {
    auto found = functions.find(shooters[k]);
    shooterFunction[k] = found == functions.end() ? nullptr : &found->second;
  }

  // The radiance at x on surface i: emission + sum over shooters. Thread-safe.
  auto evaluatePoint = [&](int i, const penumbra::Vec3& x) {
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
        : evaluator.FormFactor(x, normals[i], i, shooters[k], candidates[pair], workspaces.Local());
      irradianceOverPi += scene.Surfaces[shooters[k]].Emission * f;
    }
    penumbra::RGB value = receiver.Reflectance * irradianceOverPi;
    if (this->IncludeEmission)
    {
      value += receiver.Emission;
    }
    return value;
  };

  if (this->AdaptiveSampling && samples->GetNumberOfPolys() > 0)
  {
    return SampleAdaptively(this, samples, output, sceneData->GetLength(), evaluatePoint) ? 1 : 0;
  }

  const vtkIdType numberOfPoints = samples->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> radiance;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  radiance->SetNumberOfTuples(numberOfPoints);
  vtkPoints* points = samples->GetPoints();

  // Batches between which progress is reported and abort is honoured.
  const vtkIdType batches = std::min<vtkIdType>(100, numberOfPoints);
  for (vtkIdType batch = 0; batch < batches && !this->GetAbortExecute(); ++batch)
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
}
