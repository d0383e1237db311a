// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSceneSource.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include "penumbraSceneLibrary.h"

vtkStandardNewMacro(vtkPenumbraSceneSource);

vtkPenumbraSceneSource::vtkPenumbraSceneSource()
{
  this->SetNumberOfInputPorts(0);
}

int vtkPenumbraSceneSource::GetNumberOfScenes()
{
  return static_cast<int>(penumbra::ListBuiltinScenes().size());
}

std::string vtkPenumbraSceneSource::GetSceneName(int index)
{
  const auto scenes = penumbra::ListBuiltinScenes();
  return index >= 0 && index < static_cast<int>(scenes.size()) ? scenes[index].Name
                                                                : std::string();
}

std::string vtkPenumbraSceneSource::GetSceneDescription(int index)
{
  const auto scenes = penumbra::ListBuiltinScenes();
  return index >= 0 && index < static_cast<int>(scenes.size()) ? scenes[index].Description
                                                                : std::string();
}

int vtkPenumbraSceneSource::Execute(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  try
  {
    penumbra::SceneToPolyData(penumbra::MakeBuiltinScene(this->SceneName), output);
  }
  catch (const penumbra::InputError& e)
  {
    vtkErrorMacro(<< "SceneName: " << e.what());
    return 0;
  }
  return 1;
}

void vtkPenumbraSceneSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SceneName: " << this->SceneName << "\n";
}
