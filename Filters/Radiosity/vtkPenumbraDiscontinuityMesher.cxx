// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraDiscontinuityMesher.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include "penumbraDiscontinuityMesher.h"

#include <algorithm>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPenumbraDiscontinuityMesher);

vtkPenumbraDiscontinuityMesher::vtkPenumbraDiscontinuityMesher()
{
  const penumbra::DiscontinuityMeshSettings defaults;
  this->ShooterPowerFraction = defaults.ShooterPowerFraction;
  this->MinimumAngle = defaults.MinimumAngle;
  this->OccluderOccluderEvents = defaults.OccluderOccluderEvents;
  this->InteriorEvents = defaults.InteriorEvents;
  this->PlaneEvents = defaults.PlaneEvents;
  this->Contacts = defaults.Contacts;
  this->JumpThreshold = defaults.JumpThreshold;
  this->ContactTolerance = defaults.ContactTolerance;
  this->CullWedges = defaults.CullWedges;
}

void vtkPenumbraDiscontinuityMesher::AddShooterId(vtkIdType id)
{
  this->AddShooterId(id, nullptr);
}

void vtkPenumbraDiscontinuityMesher::AddShooterId(vtkIdType id, vtkIdList* receivers)
{
  this->ShooterIds.push_back(id);
  std::vector<vtkIdType> list;
  for (vtkIdType k = 0; receivers && k < receivers->GetNumberOfIds(); ++k)
  {
    list.push_back(receivers->GetId(k));
  }
  this->ShooterReceivers.push_back(std::move(list));
  this->Modified();
}

void vtkPenumbraDiscontinuityMesher::RemoveAllShooterIds()
{
  if (!this->ShooterIds.empty())
  {
    this->ShooterIds.clear();
    this->ShooterReceivers.clear();
    this->Modified();
  }
}

void vtkPenumbraDiscontinuityMesher::GetShooterReceivers(
  vtkIdType index, vtkIdList* receivers) const
{
  receivers->Reset();
  if (index >= 0 && index < this->GetNumberOfShooterIds())
  {
    for (const vtkIdType id : this->ShooterReceivers[index])
    {
      receivers->InsertNextId(id);
    }
  }
}

vtkIdType vtkPenumbraDiscontinuityMesher::GetNumberOfShooterIds() const
{
  return static_cast<vtkIdType>(this->ShooterIds.size());
}

vtkIdType vtkPenumbraDiscontinuityMesher::GetShooterId(vtkIdType index) const
{
  return index >= 0 && index < this->GetNumberOfShooterIds() ? this->ShooterIds[index] : -1;
}

namespace
{
void AddCount(vtkFieldData* fieldData, const char* name, double value)
{
  vtkNew<vtkIdTypeArray> array;
  array->SetName(name);
  array->InsertNextValue(static_cast<vtkIdType>(value));
  fieldData->AddArray(array);
}

/// Mesh the receivers in parallel, in batches between which progress is
/// reported and abort honoured; the results are joined in receiver order.
/// Returns the first error ("surface <id>: ..."), empty if none.
std::string MeshReceivers(vtkPenumbraDiscontinuityMesher* self,
  const penumbra::DiscontinuityMesher& mesher, const penumbra::DiscontinuityMeshSettings& settings,
  std::vector<penumbra::ReceiverMesh>& meshes, penumbra::DiscontinuityMeshStatistics& total)
{
  const int numberOfSurfaces = static_cast<int>(meshes.size());
  vtkSMPThreadLocal<penumbra::DiscontinuityMeshStatistics> statistics;
  std::mutex errorMutex;
  std::string error;
  const int batches = std::min(numberOfSurfaces, 50);
  self->UpdateProgress(0.0);
  for (int batch = 0; batch < batches && !self->GetAbortExecute() && error.empty(); ++batch)
  {
    const vtkIdType begin = static_cast<vtkIdType>(numberOfSurfaces) * batch / batches;
    const vtkIdType end = static_cast<vtkIdType>(numberOfSurfaces) * (batch + 1) / batches;
    vtkSMPTools::For(begin, end, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType i = first; i < last; ++i)
      {
        try
        {
          meshes[i] = mesher.MeshReceiver(static_cast<int>(i), settings, &statistics.Local());
        }
        catch (const std::exception& e)
        {
          std::lock_guard<std::mutex> lock(errorMutex);
          if (error.empty())
          {
            error = "surface " + std::to_string(i) + ": " + e.what();
          }
        }
      }
    });
    self->UpdateProgress(static_cast<double>(batch + 1) / batches);
  }
  for (const auto& local : statistics)
  {
    total += local;
  }
  return error;
}

/// The receivers' meshes, in receiver order, as the output polydata, with
/// the mesher's statistics as field arrays.
void WriteMeshes(const std::vector<penumbra::ReceiverMesh>& meshes,
  const penumbra::DiscontinuityMeshStatistics& total, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIntArray> pointSurface;
  pointSurface->SetName("SurfaceId");
  std::vector<int> lineOrder, lineSource, lineSurface, polySurface;
  for (const penumbra::ReceiverMesh& mesh : meshes)
  {
    const vtkIdType offset = points->GetNumberOfPoints();
    for (const penumbra::Vec3& p : mesh.Points)
    {
      points->InsertNextPoint(p.X, p.Y, p.Z);
      pointSurface->InsertNextValue(mesh.ReceiverId);
    }
    for (const auto& t : mesh.Triangles)
    {
      const vtkIdType ids[3] = { offset + t[0], offset + t[1], offset + t[2] };
      polys->InsertNextCell(3, ids);
      polySurface.push_back(mesh.ReceiverId);
    }
    for (const penumbra::DiscontinuitySegment& s : mesh.Segments)
    {
      const vtkIdType ids[2] = { offset + s.PointA, offset + s.PointB };
      lines->InsertNextCell(2, ids);
      lineOrder.push_back(s.Order);
      lineSource.push_back(s.SourceId);
      lineSurface.push_back(s.ReceiverId);
    }
  }
  output->SetPoints(points);
  output->SetLines(lines);
  output->SetPolys(polys);

  penumbra::AddMeshCellArrays(output, lineSurface, lineOrder, lineSource, polySurface);
  output->GetPointData()->AddArray(pointSurface);

  vtkFieldData* fieldData = output->GetFieldData();
  AddCount(fieldData, "SegmentsGenerated", static_cast<double>(total.SegmentsGenerated));
  AddCount(fieldData, "SegmentsKept", static_cast<double>(total.SegmentsKept));
  AddCount(fieldData, "ContactSegments", static_cast<double>(total.ContactSegments));
  AddCount(fieldData, "CoverSegments", static_cast<double>(total.CoverSegments));
  AddCount(fieldData, "Constraints", static_cast<double>(total.Constraints));
  AddCount(fieldData, "ConstraintFailures", static_cast<double>(total.ConstraintFailures));
  AddCount(fieldData, "Triangles", static_cast<double>(total.Triangles));
  AddCount(fieldData, "Wedges", static_cast<double>(total.Wedges));
}
}

int vtkPenumbraDiscontinuityMesher::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  if (!input || input->GetNumberOfCells() == 0)
  {
    return 1;
  }

  penumbra::DiscontinuityMeshSettings settings;
  bool restricted = false;
  for (std::size_t k = 0; k < this->ShooterIds.size(); ++k)
  {
    settings.Shooters.push_back(static_cast<int>(this->ShooterIds[k]));
    restricted = restricted || !this->ShooterReceivers[k].empty();
  }
  if (restricted)
  {
    for (const std::vector<vtkIdType>& receivers : this->ShooterReceivers)
    {
      settings.ShooterReceivers.emplace_back(receivers.begin(), receivers.end());
    }
  }
  settings.ShooterPowerFraction = this->ShooterPowerFraction;
  settings.MinimumAngle = this->MinimumAngle;
  settings.OccluderOccluderEvents = this->OccluderOccluderEvents;
  settings.InteriorEvents = this->InteriorEvents;
  settings.PlaneEvents = this->PlaneEvents;
  settings.Contacts = this->Contacts;
  settings.JumpThreshold = this->JumpThreshold;
  settings.ContactTolerance = this->ContactTolerance;
  settings.CullWedges = this->CullWedges;

  std::unique_ptr<penumbra::DiscontinuityMesher> mesher;
  int numberOfSurfaces = 0;
  try
  {
    const penumbra::Scene scene = penumbra::SceneFromPolyData(input);
    mesher.reset(new penumbra::DiscontinuityMesher(this->Prepare(scene))); // validates it
    numberOfSurfaces = mesher->GetNumberOfSurfaces();
    for (vtkIdType id : this->ShooterIds)
    {
      if (id < 0 || id >= numberOfSurfaces)
      {
        throw penumbra::InputError("ShooterIds: " + std::to_string(id) +
          " is not a scene cell (0 to " + std::to_string(numberOfSurfaces - 1) + ")");
      }
    }
    mesher->SelectShooters(settings);
  }
  catch (const penumbra::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }

  std::vector<penumbra::ReceiverMesh> meshes(static_cast<std::size_t>(numberOfSurfaces));
  penumbra::DiscontinuityMeshStatistics total;
  const std::string error = MeshReceivers(this, *mesher, settings, meshes, total);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  if (this->GetAbortExecute())
  {
    return 1;
  }
  WriteMeshes(meshes, total, output);
  if (total.ConstraintFailures > 0)
  {
    vtkWarningMacro(<< total.ConstraintFailures << " constraint insertions failed");
  }
  return 1;
}

void vtkPenumbraDiscontinuityMesher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ShooterIds:";
  if (this->ShooterIds.empty())
  {
    os << " (every emitter above ShooterPowerFraction)";
  }
  for (std::size_t k = 0; k < this->ShooterIds.size(); ++k)
  {
    os << " " << this->ShooterIds[k];
    if (!this->ShooterReceivers[k].empty())
    {
      os << " (on";
      for (const vtkIdType id : this->ShooterReceivers[k])
      {
        os << " " << id;
      }
      os << ")";
    }
  }
  os << "\n";
  os << indent << "ShooterPowerFraction: " << this->ShooterPowerFraction << "\n";
  os << indent << "MinimumAngle: " << this->MinimumAngle << "\n";
  os << indent << "OccluderOccluderEvents: " << (this->OccluderOccluderEvents ? "On" : "Off")
     << "\n";
  os << indent << "InteriorEvents: " << (this->InteriorEvents ? "On" : "Off") << "\n";
  os << indent << "PlaneEvents: " << (this->PlaneEvents ? "On" : "Off") << "\n";
  os << indent << "Contacts: " << (this->Contacts ? "On" : "Off") << "\n";
  os << indent << "JumpThreshold: " << this->JumpThreshold << "\n";
  os << indent << "ContactTolerance: " << this->ContactTolerance << "\n";
  os << indent << "CullWedges: " << (this->CullWedges ? "On" : "Off") << "\n";
}
