// SPDX-License-Identifier: GPL-3.0-or-later
// Build the Cornell box, check it against the data contract and write it as
// a .vtp that ParaView opens: usage `PenumbraExample OUT.vtp`.
#include "vtkNew.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPenumbraSceneValidator.h"
#include "vtkXMLPolyDataWriter.h"

#include <iostream>

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: " << argv[0] << " OUT.vtp" << std::endl;
    return 2;
  }
  vtkNew<vtkPenumbraSceneSource> scene;
  scene->SetSceneName("cornell");
  vtkNew<vtkPenumbraSceneValidator> validator;
  validator->SetInputConnection(scene->GetOutputPort());
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputConnection(validator->GetOutputPort());
  writer->SetDataModeToBinary(); // inline data: what every ParaView reads
  writer->SetFileName(argv[1]);
  if (!writer->Write())
  {
    std::cerr << "could not write " << argv[1] << std::endl;
    return 1;
  }
  std::cout << "wrote " << argv[1] << std::endl;
  return 0;
}
