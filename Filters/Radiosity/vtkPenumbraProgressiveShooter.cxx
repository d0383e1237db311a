// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraProgressiveShooter.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include "penumbraIndirectSampling.h"
#include "penumbraProgressiveShooter.h"
#include "penumbraTransportSettings.h"

#include <algorithm>
#include <array>
#include <memory>
#include <sstream>
#include <unordered_map>

vtkStandardNewMacro(vtkPenumbraProgressiveShooter);

vtkPenumbraProgressiveShooter::vtkPenumbraProgressiveShooter()
{
  const penumbra::TransportSettings defaults;
  this->UnshotFraction = defaults.Shooting.UnshotFraction;
  this->MaximumShots = defaults.Shooting.MaximumShots;
  this->ExactPowerFraction = defaults.Shooting.ExactPowerFraction;
  this->OpeningAngle = defaults.Shooting.OpeningAngle;
  this->CoarseShotFraction = defaults.Shooting.CoarseShotFraction;
  this->GroupWeakShots = defaults.Shooting.GroupWeakShots;
  this->GroupAcrossOrientations = defaults.Shooting.GroupAcrossOrientations;
  this->ReuseTransport = defaults.Shooting.ReuseTransport;
  this->ReceiverClusterSize = defaults.Shooting.ReceiverClusterSize;
  this->MaximumIndirectSamples = static_cast<vtkIdType>(defaults.MaximumIndirectSamples);
  this->SetNumberOfInputPorts(2);
}

int vtkPenumbraProgressiveShooter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
/// The core's shooting settings from the filter's.
penumbra::ProgressiveShooterSettings ShootingSettings(vtkPenumbraProgressiveShooter* self)
{
  penumbra::ProgressiveShooterSettings settings;
  settings.UnshotFraction = self->GetUnshotFraction();
  settings.MaximumShots = self->GetMaximumShots();
  settings.ExactPowerFraction = self->GetExactPowerFraction();
  settings.OpeningAngle = self->GetOpeningAngle();
  settings.CoarseShotFraction = self->GetCoarseShotFraction();
  settings.GroupWeakShots = self->GetGroupWeakShots();
  settings.GroupAcrossOrientations = self->GetGroupAcrossOrientations();
  settings.ReuseTransport = self->GetReuseTransport();
  settings.ReceiverClusterSize = self->GetReceiverClusterSize();
  return settings;
}

/// Per surface: the samples of its triangles in local numbering, and the
/// global ids to write them back to. Throws penumbra::InputError.
void CollectSurfaceSamples(vtkPolyData* samples, vtkDataArray* radiance,
  vtkDataArray* surfaceIds, const penumbra::Scene& scene,
  std::unordered_map<int, penumbra::SurfaceSamples>& bySurface,
  std::unordered_map<int, std::vector<vtkIdType>>& global)
{
  const int numberOfSurfaces = static_cast<int>(scene.Surfaces.size());
  std::unordered_map<int, std::unordered_map<vtkIdType, int>> local;
  auto localId = [&](int surface, vtkIdType id) {
    auto& map = local[surface];
    auto found = map.find(id);
    if (found != map.end())
    {
      return found->second;
    }
    penumbra::SurfaceSamples& s = bySurface[surface];
    double p[3], value[3];
    samples->GetPoint(id, p);
    radiance->GetTuple(id, value);
    const penumbra::RGB total(value[0], value[1], value[2]);
    const penumbra::RGB& emission = scene.Surfaces[surface].Emission;
    s.Points.emplace_back(p[0], p[1], p[2]);
    s.Total.push_back(total);
    // The evaluator has shot every emitter: what is left to shoot is the
    // reflected part of the radiance (none on black channels).
    const penumbra::RGB share = penumbra::ReflectedShare(scene.Surfaces[surface].Reflectance);
    s.Unshot.emplace_back(share.R * std::max(0.0, total.R - emission.R),
      share.G * std::max(0.0, total.G - emission.G), share.B * std::max(0.0, total.B - emission.B));
    global[surface].push_back(id);
    const int k = static_cast<int>(s.Points.size()) - 1;
    map.emplace(id, k);
    return k;
  };
  // Discontinuity lines of order 0 and 1, where the radiance may kink or
  // jump: their segments become the surfaces' creases once the triangles
  // have numbered the points.
  vtkDataArray* orders = samples->GetCellData()->GetArray("DiscontinuityOrder");
  std::vector<std::pair<int, std::array<vtkIdType, 2>>> creases;
  penumbra::ForEachCell(samples,
    [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
      if (kind == 1 && orders)
      {
        const double order = orders->GetComponent(cellId, 0);
        const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
        if ((order == 0.0 || order == 1.0) && surface >= 0 && surface < numberOfSurfaces)
        {
          for (vtkIdType k = 0; k + 1 < npts; ++k)
          {
            creases.push_back({ surface, { pts[k], pts[k + 1] } });
          }
        }
        return true;
      }
      if (kind != 2)
      {
        return true; // only the triangles carry samples to shoot from
      }
      const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
      if (surface < 0 || surface >= numberOfSurfaces)
      {
        std::ostringstream os;
        os << "cell " << cellId << " has SurfaceId " << surface << ", not a scene cell";
        throw penumbra::InputError(os.str());
      }
      if (npts != 3)
      {
        throw penumbra::InputError(
          "cell " + std::to_string(cellId) + " is not a triangle; the samples must be triangles");
      }
      bySurface[surface].Triangles.push_back(
        { localId(surface, pts[0]), localId(surface, pts[1]), localId(surface, pts[2]) });
      return true;
    });
  for (const auto& crease : creases)
  {
    const auto map = local.find(crease.first);
    if (map == local.end())
    {
      continue;
    }
    const auto a = map->second.find(crease.second[0]);
    const auto b = map->second.find(crease.second[1]);
    if (a != map->second.end() && b != map->second.end())
    {
      bySurface[crease.first].Creases.push_back({ a->second, b->second });
    }
  }
}

/// The output's `Radiance`: the input's, with the shot samples' totals.
/// Returns the area-mean of what the shots added (the indirect radiance)
/// over the sample triangles of all surfaces.
penumbra::RGB WriteTotals(vtkDataArray* radiance,
  const std::unordered_map<int, std::vector<vtkIdType>>& global,
  const penumbra::IndirectSampling& sampling, const penumbra::ProgressiveShooter& shooter,
  vtkPolyData* output)
{
  vtkNew<vtkDoubleArray> total;
  total->DeepCopy(radiance);
  total->SetName("Radiance");
  penumbra::RGB indirect;
  double area = 0.0;
  for (const auto& entry : global)
  {
    const penumbra::SurfaceSamples& s = sampling.GetSamples(entry.first, shooter);
    std::vector<penumbra::RGB> added(entry.second.size());
    for (std::size_t k = 0; k < entry.second.size(); ++k)
    {
      double direct[3];
      radiance->GetTuple(entry.second[k], direct);
      added[k] = penumbra::RGB(s.Total[k].R - direct[0], s.Total[k].G - direct[1],
        s.Total[k].B - direct[2]);
      total->SetTuple3(entry.second[k], s.Total[k].R, s.Total[k].G, s.Total[k].B);
    }
    for (const std::array<int, 3>& tri : s.Triangles)
    {
      const double a = 0.5 *
        penumbra::Length(penumbra::Cross(s.Points[tri[1]] - s.Points[tri[0]],
          s.Points[tri[2]] - s.Points[tri[0]]));
      area += a;
      indirect = indirect + (added[tri[0]] + added[tri[1]] + added[tri[2]]) * (a / 3.0);
    }
  }
  output->GetPointData()->AddArray(total);
  output->GetPointData()->SetActiveScalars("Radiance");
  return area > 0.0 ? indirect * (1.0 / area) : penumbra::RGB();
}

/// The shooting summary as field arrays (see the class description).
void AddShootingFields(vtkFieldData* fieldData, const penumbra::ShootingSummary& summary,
  const penumbra::ProgressiveShooter& shooter, double indirectSpacing)
{
  penumbra::AddField(fieldData, "Shots", summary.Shots);
  penumbra::AddField(fieldData, "ExactShots", summary.ExactShots);
  penumbra::AddField(fieldData, "FastShots", summary.FastShots);
  penumbra::AddField(fieldData, "UnshotFraction", summary.UnshotFraction);
  penumbra::AddField(fieldData, "EmittedPower", summary.Energy.Emitted);
  penumbra::AddField(fieldData, "AbsorbedPower", summary.Energy.Absorbed());
  penumbra::AddField(fieldData, "EscapedPower", summary.Energy.Escaped());
  penumbra::AddField(fieldData, "ResidualPower", summary.Energy.Residual());
  penumbra::AddField(fieldData, "UnshotPower", summary.Energy.Unshot);
  penumbra::AddField(fieldData, "ShootingSeconds", summary.Seconds);
  // The points the shots were evaluated at, and the coarse level's spacing (0: none).
  vtkIdType shootingSamples = 0;
  for (int i = 0; i < shooter.GetNumberOfSurfaces(); ++i)
  {
    shootingSamples += static_cast<vtkIdType>(shooter.GetEvaluationPoints(i).size());
  }
  penumbra::AddField(fieldData, "IndirectSamples", static_cast<double>(shootingSamples));
  penumbra::AddField(fieldData, "IndirectSpacing", indirectSpacing);
  // Per shot: the shooter (the strongest of a group), the surfaces shot
  // together, the occlusion rays traced and the wall-clock seconds.
  vtkNew<vtkIntArray> order, groupSize;
  vtkNew<vtkDoubleArray> rays, seconds;
  order->SetName("ShotOrder");
  groupSize->SetName("ShotGroupSize");
  rays->SetName("ShotRays");
  seconds->SetName("ShotSeconds");
  for (const penumbra::ShotRecord& shot : summary.History)
  {
    order->InsertNextValue(shot.Shooter);
    groupSize->InsertNextValue(shot.GroupSize);
    rays->InsertNextValue(static_cast<double>(shot.Rays));
    seconds->InsertNextValue(shot.Seconds);
  }
  fieldData->AddArray(order);
  fieldData->AddArray(groupSize);
  fieldData->AddArray(rays);
  fieldData->AddArray(seconds);
}
}

int vtkPenumbraProgressiveShooter::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* samples = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* sceneData = vtkPolyData::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->ShallowCopy(samples);
  if (samples->GetNumberOfPolys() == 0)
  {
    return 1;
  }
  vtkDataArray* radiance = samples->GetPointData()->GetArray("Radiance");
  vtkDataArray* surfaceIds = samples->GetCellData()->GetArray("SurfaceId");
  if (!radiance || radiance->GetNumberOfComponents() != 3 || !surfaceIds)
  {
    output->Initialize();
    vtkErrorMacro(<< "the samples need a 3-component point array 'Radiance' (the direct "
                     "solution of vtkPenumbraRadianceEvaluator) and a cell array 'SurfaceId'");
    return 0;
  }

  std::unordered_map<int, penumbra::SurfaceSamples> bySurface;
  std::unordered_map<int, std::vector<vtkIdType>> global;
  std::unique_ptr<penumbra::ProgressiveShooter> shooter;
  // Large inputs: shoot on the coarse level (see MaximumIndirectSamples).
  penumbra::IndirectSampling sampling;
  try
  {
    const penumbra::Scene scene = penumbra::SceneFromPolyData(sceneData);
    const auto prepared = this->Prepare(scene); // validates the scene
    CollectSurfaceSamples(samples, radiance, surfaceIds, scene, bySurface, global);
    shooter.reset(new penumbra::ProgressiveShooter(prepared));
    shooter->SetSettings(ShootingSettings(this));
    shooter->SetParallelFor(penumbra::SMPParallelFor());
    sampling.Assign(scene, bySurface,
      this->MaximumIndirectSamples > 0 ? static_cast<std::size_t>(this->MaximumIndirectSamples) : 0,
      *prepared->GetRayCaster(), penumbra::SMPParallelFor(), *shooter);
  }
  catch (const penumbra::InputError& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }

  this->UpdateProgress(0.0);
  // The first sweep through a recorded transport traces the rays of all
  // later ones (most of the shooting time of a large scene): it moves the
  // bar over half of what is left. The bar never goes back.
  double shown = 0.0;
  shooter->SetShotProgressCallback([this, &shown](double fraction) {
    this->UpdateProgress(shown + 0.5 * (1.0 - shown) * fraction);
  });
  const penumbra::ShootingSummary summary =
    shooter->Run([this, &shown](const penumbra::ShotRecord&, double progress) {
      shown = std::max(shown, std::max(progress, this->GetProgress()));
      this->UpdateProgress(shown);
      return !this->GetAbortExecute();
    });

  sampling.Prolong(*shooter);
  const penumbra::RGB indirect = WriteTotals(radiance, global, sampling, *shooter, output);
  AddShootingFields(output->GetFieldData(), summary, *shooter, sampling.GetSpacing());
  penumbra::AddField(output->GetFieldData(), "MeanIndirectRadiance", indirect);
  penumbra::AddField(output->GetFieldData(), "IndirectSeparatePoints",
    static_cast<double>(sampling.GetNumberOfSeparatePoints()));
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPenumbraProgressiveShooter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "UnshotFraction: " << this->UnshotFraction << "\n";
  os << indent << "MaximumShots: " << this->MaximumShots << "\n";
  os << indent << "ExactPowerFraction: " << this->ExactPowerFraction << "\n";
  os << indent << "OpeningAngle: " << this->OpeningAngle << "\n";
  os << indent << "CoarseShotFraction: " << this->CoarseShotFraction << "\n";
  os << indent << "GroupWeakShots: " << (this->GroupWeakShots ? "On" : "Off") << "\n";
  os << indent << "GroupAcrossOrientations: " << (this->GroupAcrossOrientations ? "On" : "Off")
     << "\n";
  os << indent << "ReuseTransport: " << (this->ReuseTransport ? "On" : "Off") << "\n";
  os << indent << "ReceiverClusterSize: " << this->ReceiverClusterSize << "\n";
  os << indent << "MaximumIndirectSamples: " << this->MaximumIndirectSamples << "\n";
}
