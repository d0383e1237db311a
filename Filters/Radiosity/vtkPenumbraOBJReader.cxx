// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraOBJReader.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include "penumbraObjReader.h"

#include <string>
#include <vector>

vtkStandardNewMacro(vtkPenumbraOBJReader);

vtkPenumbraOBJReader::vtkPenumbraOBJReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkPenumbraOBJReader::Execute(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "FileName is not set");
    return 0;
  }
  std::vector<std::string> warnings;
  try
  {
    penumbra::ObjReadOptions options;
    options.Strict = this->Strict;
    penumbra::SceneToPolyData(penumbra::ReadObjScene(this->FileName, options, &warnings), output);
  }
  catch (const penumbra::InputError& e)
  {
    output->Initialize();
    vtkErrorMacro(<< e.what());
    return 0;
  }
  for (const std::string& w : warnings)
  {
    this->Warn(w);
  }
  return 1;
}

void vtkPenumbraOBJReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "Strict: " << (this->Strict ? "On" : "Off") << "\n";
}
