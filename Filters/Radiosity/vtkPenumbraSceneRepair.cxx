// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSceneRepair.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include "penumbraLightingDiagnostics.h"
#include "penumbraSceneRepair.h"

#include <string>
#include <vector>

vtkStandardNewMacro(vtkPenumbraSceneRepair);

namespace
{

/// The input without its vertex and line cells (cell data following).
vtkSmartPointer<vtkPolyData> PolygonsOnly(vtkPolyData* input)
{
  auto polygons = vtkSmartPointer<vtkPolyData>::New();
  polygons->SetPoints(input->GetPoints());
  polygons->SetPolys(input->GetPolys());
  polygons->SetStrips(input->GetStrips());
  polygons->GetPointData()->PassData(input->GetPointData());
  polygons->GetFieldData()->PassData(input->GetFieldData());
  const vtkIdType skipped = input->GetNumberOfVerts() + input->GetNumberOfLines();
  const vtkIdType kept = input->GetNumberOfPolys() + input->GetNumberOfStrips();
  vtkCellData* from = input->GetCellData();
  vtkCellData* to = polygons->GetCellData();
  to->CopyAllocate(from, kept);
  for (vtkIdType i = 0; i < kept; ++i)
  {
    to->CopyData(from, skipped + i, i);
  }
  return polygons;
}

/// The input's cell arrays other than the materials, for the repaired cells.
void CopyOtherCellArrays(
  vtkPolyData* input, vtkPolyData* output, const std::vector<std::size_t>& sourceCell)
{
  vtkCellData* from = input->GetCellData();
  for (int a = 0; a < from->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = from->GetAbstractArray(a);
    const char* name = array->GetName();
    if (name &&
      (std::string(name) == "Reflectance" || std::string(name) == "Emission" ||
        std::string(name) == "InputCellId"))
    {
      continue;
    }
    auto copy = vtk::TakeSmartPointer(array->NewInstance());
    copy->SetName(name);
    copy->SetNumberOfComponents(array->GetNumberOfComponents());
    copy->SetNumberOfTuples(static_cast<vtkIdType>(sourceCell.size()));
    for (std::size_t i = 0; i < sourceCell.size(); ++i)
    {
      copy->SetTuple(static_cast<vtkIdType>(i), static_cast<vtkIdType>(sourceCell[i]), array);
    }
    output->GetCellData()->AddArray(copy);
  }
}

} // namespace

vtkPenumbraSceneRepair::vtkPenumbraSceneRepair()
{
  const penumbra::RepairOptions defaults;
  this->Strict = false;
  this->WeldTolerance = defaults.WeldTolerance;
  this->FlatnessTolerance = defaults.FlatnessTolerance;
  this->PlanarityTolerance = defaults.Validation.Planarity;
  this->DegeneracyTolerance = defaults.Validation.Degeneracy;
  this->CheckLighting = true;
}

int vtkPenumbraSceneRepair::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  std::vector<std::string> warnings;
  this->LastErrorMessage.clear();
  penumbra::RepairOptions options;
  options.WeldTolerance = this->WeldTolerance;
  options.FlatnessTolerance = this->FlatnessTolerance;
  options.Validation.Planarity = this->PlanarityTolerance;
  options.Validation.Degeneracy = this->DegeneracyTolerance;
  try
  {
    vtkSmartPointer<vtkPolyData> polygons = input;
    const vtkIdType extras = input->GetNumberOfVerts() + input->GetNumberOfLines();
    if (extras > 0 && !this->Strict)
    {
      polygons = PolygonsOnly(input);
      warnings.push_back(std::to_string(extras) +
        " vertex and line cells dropped (a scene is polygons; lines do not reflect light)");
    }
    const penumbra::Scene scene = penumbra::SceneFromPolyData(polygons);
    if (scene.Surfaces.empty())
    {
      throw penumbra::InputError("the scene has no polygons");
    }
    if (this->Strict)
    {
      penumbra::ValidateScene(scene, options.Validation);
      output->ShallowCopy(input);
      if (this->CheckLighting)
      {
        for (const std::string& w : penumbra::DiagnoseLighting(scene))
        {
          warnings.push_back(w);
        }
      }
    }
    else
    {
      penumbra::RepairReport report;
      std::vector<std::size_t> sourceCell;
      const penumbra::Scene repaired =
        penumbra::RepairScene(scene, options, report, sourceCell);
      if (repaired.Surfaces.empty())
      {
        std::string cells;
        for (std::size_t c : report.ZeroAreaCells)
        {
          cells += (cells.empty() ? "" : ", ") + std::to_string(c);
        }
        throw penumbra::InputError("the scene has no polygons left: all " +
          std::to_string(scene.Surfaces.size()) + " have zero area (cell " + cells +
          (report.ZeroAreaCells.size() < scene.Surfaces.size() ? ", ...)" : ")"));
      }
      penumbra::ValidateScene(repaired, options.Validation, &sourceCell);
      for (const std::string& m : report.Messages())
      {
        warnings.push_back(m);
      }
      if (report.Empty())
      {
        output->ShallowCopy(polygons);
      }
      else
      {
        output->Initialize();
        penumbra::SceneToPolyData(repaired, output);
        CopyOtherCellArrays(polygons, output, sourceCell);
        vtkNew<vtkIdTypeArray> inputCell;
        inputCell->SetName("InputCellId");
        inputCell->SetNumberOfTuples(static_cast<vtkIdType>(sourceCell.size()));
        for (std::size_t i = 0; i < sourceCell.size(); ++i)
        {
          inputCell->SetValue(static_cast<vtkIdType>(i), static_cast<vtkIdType>(sourceCell[i]));
        }
        output->GetCellData()->AddArray(inputCell);
        output->GetFieldData()->PassData(input->GetFieldData());
      }
      if (this->CheckLighting)
      {
        for (const std::string& w :
          penumbra::DiagnoseLighting(repaired, penumbra::LightingDiagnosticsOptions(), &sourceCell))
        {
          warnings.push_back(w);
        }
      }
    }
  }
  catch (const penumbra::InputError& e)
  {
    this->LastErrorMessage = e.what();
    output->Initialize();
    vtkErrorMacro(<< "invalid scene: " << e.what());
    return 0;
  }
  for (const std::string& w : warnings)
  {
    this->Warn(w);
  }
  return 1;
}

void vtkPenumbraSceneRepair::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Strict: " << (this->Strict ? "On" : "Off") << "\n";
  os << indent << "WeldTolerance: " << this->WeldTolerance << "\n";
  os << indent << "FlatnessTolerance: " << this->FlatnessTolerance << "\n";
  os << indent << "PlanarityTolerance: " << this->PlanarityTolerance << "\n";
  os << indent << "DegeneracyTolerance: " << this->DegeneracyTolerance << "\n";
  os << indent << "CheckLighting: " << (this->CheckLighting ? "On" : "Off") << "\n";
  os << indent << "LastErrorMessage: " << this->LastErrorMessage << "\n";
}
