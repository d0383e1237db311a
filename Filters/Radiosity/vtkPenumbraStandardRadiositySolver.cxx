// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraStandardRadiositySolver.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "penumbraStandardRadiosity.h"

#include <memory>
#include <stdexcept>

vtkStandardNewMacro(vtkPenumbraStandardRadiositySolver);

vtkPenumbraStandardRadiositySolver::vtkPenumbraStandardRadiositySolver()
{
  const penumbra::StandardRadiositySettings defaults;
  this->PatchSize = defaults.PatchSize;
  this->ElementSize = defaults.ElementSize;
  this->ShooterSamples = defaults.ShooterSamples;
  this->SubdivisionThreshold = defaults.SubdivisionThreshold;
  this->MaximumSubdivisionDepth = defaults.MaximumSubdivisionDepth;
  this->UnshotFraction = defaults.UnshotFraction;
  this->MaximumShots = defaults.MaximumShots;
  this->FormFactorMode = static_cast<int>(defaults.FormFactor);
}

namespace
{
/// The solver's mesh as the output polydata: points with `Radiance`, boundary
/// edges then triangles with the mesh cell arrays.
void WriteMesh(const penumbra::StandardRadiosityMesh& mesh, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.Points.size()));
  vtkNew<vtkDoubleArray> radiance;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  radiance->SetNumberOfTuples(static_cast<vtkIdType>(mesh.Points.size()));
  vtkNew<vtkDoubleArray> irradiance;
  irradiance->SetName("Irradiance");
  irradiance->SetNumberOfComponents(3);
  irradiance->SetNumberOfTuples(static_cast<vtkIdType>(mesh.Points.size()));
  for (std::size_t k = 0; k < mesh.Points.size(); ++k)
  {
    const vtkIdType id = static_cast<vtkIdType>(k);
    points->SetPoint(id, mesh.Points[k].X, mesh.Points[k].Y, mesh.Points[k].Z);
    radiance->SetTuple3(id, mesh.Radiance[k].R, mesh.Radiance[k].G, mesh.Radiance[k].B);
    irradiance->SetTuple3(id, mesh.Irradiance[k].R, mesh.Irradiance[k].G, mesh.Irradiance[k].B);
  }
  vtkNew<vtkCellArray> lines;
  for (const auto& edge : mesh.BoundaryEdges)
  {
    const vtkIdType ids[2] = { edge[0], edge[1] };
    lines->InsertNextCell(2, ids);
  }
  vtkNew<vtkCellArray> polys;
  for (const auto& triangle : mesh.Triangles)
  {
    const vtkIdType ids[3] = { triangle[0], triangle[1], triangle[2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPoints(points);
  output->SetLines(lines);
  output->SetPolys(polys);
  const std::vector<int> boundary(mesh.BoundaryEdges.size(), -1);
  penumbra::AddMeshCellArrays(
    output, mesh.BoundaryEdgeSurface, boundary, boundary, mesh.TriangleSurface);
  output->GetPointData()->AddArray(radiance);
  output->GetPointData()->SetActiveScalars("Radiance");
  output->GetPointData()->AddArray(irradiance);
}

/// The solve's summary as field arrays.
void AddSummaryFields(vtkFieldData* fieldData, const penumbra::StandardRadiositySummary& summary)
{
  penumbra::AddField(fieldData, "Shots", summary.Shots);
  penumbra::AddField(fieldData, "UnshotFraction", summary.UnshotFraction);
  penumbra::AddField(fieldData, "SolveSeconds", summary.Seconds);
  penumbra::AddField(fieldData, "Elements", summary.Elements);
  penumbra::AddField(fieldData, "Vertices", summary.Vertices);
  penumbra::AddField(fieldData, "Patches", summary.Patches);
  penumbra::AddField(fieldData, "SubdividedElements", summary.SubdividedElements);
  penumbra::AddField(fieldData, "Rays", static_cast<double>(summary.Rays));
  penumbra::AddField(fieldData, "EmittedPower", summary.Energy.Emitted);
  penumbra::AddField(fieldData, "AbsorbedPower", summary.Energy.Absorbed());
  penumbra::AddField(fieldData, "EscapedPower", summary.Energy.Escaped());
  penumbra::AddField(fieldData, "ResidualPower", summary.Energy.Residual());
  penumbra::AddField(fieldData, "UnshotPower", summary.Energy.Unshot);
}
}

int vtkPenumbraStandardRadiositySolver::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* sceneData = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  if (!sceneData || sceneData->GetNumberOfCells() == 0)
  {
    return 1;
  }

  penumbra::StandardRadiositySettings settings;
  settings.PatchSize = this->PatchSize;
  settings.ElementSize = this->ElementSize;
  settings.ShooterSamples = this->ShooterSamples;
  settings.FormFactor = this->FormFactorMode == DISC ? penumbra::FormFactorMode::Disc
                                                     : penumbra::FormFactorMode::AnalyticVisibility;
  settings.SubdivisionThreshold = this->SubdivisionThreshold;
  settings.MaximumSubdivisionDepth = this->MaximumSubdivisionDepth;
  settings.UnshotFraction = this->UnshotFraction;
  settings.MaximumShots = this->MaximumShots;

  std::unique_ptr<penumbra::StandardRadiosity> solver;
  try
  {
    solver.reset(new penumbra::StandardRadiosity(penumbra::SceneFromPolyData(sceneData)));
    solver->SetSettings(settings);
  }
  catch (const penumbra::InputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const std::runtime_error& e) // Embree could not build its scene
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  solver->SetParallelFor(penumbra::SMPParallelFor());

  this->UpdateProgress(0.0);
  const penumbra::StandardRadiositySummary summary =
    solver->Run([this](const penumbra::ShotRecord&, double progress) {
      this->UpdateProgress(progress);
      return !this->GetAbortExecute();
    });
  const penumbra::StandardRadiosityMesh mesh = solver->GetMesh();

  WriteMesh(mesh, output);
  AddSummaryFields(output->GetFieldData(), summary);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPenumbraStandardRadiositySolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PatchSize: " << this->PatchSize << "\n";
  os << indent << "ElementSize: " << this->ElementSize << "\n";
  os << indent << "ShooterSamples: " << this->ShooterSamples << "\n";
  os << indent << "FormFactorMode: "
     << (this->FormFactorMode == DISC ? "DISC" : "ANALYTIC_VISIBILITY") << "\n";
  os << indent << "SubdivisionThreshold: " << this->SubdivisionThreshold << "\n";
  os << indent << "MaximumSubdivisionDepth: " << this->MaximumSubdivisionDepth << "\n";
  os << indent << "UnshotFraction: " << this->UnshotFraction << "\n";
  os << indent << "MaximumShots: " << this->MaximumShots << "\n";
}
