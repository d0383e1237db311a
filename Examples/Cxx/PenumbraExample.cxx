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
  solver->SetUnshotFraction(1e-3); // stop when 0.1% of the emitted power is left
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputConnection(solver->GetOutputPort());
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
