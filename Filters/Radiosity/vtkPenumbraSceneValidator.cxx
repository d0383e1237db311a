// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSceneValidator.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

vtkStandardNewMacro(vtkPenumbraSceneValidator);

vtkPenumbraSceneValidator::vtkPenumbraSceneValidator()
{
  const penumbra::ValidationTolerances defaults;
  this->PlanarityTolerance = defaults.Planarity;
  this->DegeneracyTolerance = defaults.Degeneracy;
}

int vtkPenumbraSceneValidator::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->LastErrorMessage.clear();
  try
  {
    penumbra::ValidationTolerances tolerances;
    tolerances.Planarity = this->PlanarityTolerance;
    tolerances.Degeneracy = this->DegeneracyTolerance;
    penumbra::ValidateScene(penumbra::SceneFromPolyData(input), tolerances);
  }
  catch (const penumbra::InputError& e)
  {
    this->LastErrorMessage = e.what();
    output->Initialize();
    vtkErrorMacro(<< "invalid scene: " << e.what());
    return 0;
  }
  output->ShallowCopy(input);
  return 1;
}

void vtkPenumbraSceneValidator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PlanarityTolerance: " << this->PlanarityTolerance << "\n";
  os << indent << "DegeneracyTolerance: " << this->DegeneracyTolerance << "\n";
  os << indent << "LastErrorMessage: " << this->LastErrorMessage << "\n";
}
