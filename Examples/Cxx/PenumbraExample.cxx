// SPDX-License-Identifier: GPL-3.0-or-later
// Solve the Cornell box (direct light and interreflections) and write the
// result as a .vtp that ParaView opens: usage `PenumbraExample OUT.vtp`.
#include "vtkNew.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPenumbraSolver.h"
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
  vtkNew<vtkPenumbraSolver> solver; // mesher, evaluator, shooter, reconstructor
  solver->SetInputConnection(scene->GetOutputPort());
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputConnection(solver->GetOutputPort());
  writer->SetDataModeToBinary(); // inline data: what every ParaView reads
  writer->SetFileName(argv[1]);
  return writer->Write() ? 0 : 1; // errors name the offending cell or setting
}
