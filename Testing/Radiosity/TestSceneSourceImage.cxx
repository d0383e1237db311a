// SPDX-License-Identifier: GPL-3.0-or-later
// Baseline image of the built-in Cornell box in its reflectance colors, seen
// from the Cornell camera: checks geometry, winding-independent placement and
// materials at a glance.
#include "penumbraTestRendering.h"

#include "vtkPenumbraSceneSource.h"
#include "vtkRegressionTestImage.h"

int TestSceneSourceImage(int argc, char* argv[])
{
  vtkNew<vtkPenumbraSceneSource> source;
  source->SetSceneName("cornell");
  source->Update();
  vtkNew<vtkRenderWindow> window;
  penumbraSetUpSceneView(source->GetOutput(), window);
  window->Render();
  const int result = vtkRegressionTestImage(window);
  return result == vtkRegressionTester::FAILED ? 1 : 0;
}

int main(int argc, char* argv[])
{
  return TestSceneSourceImage(argc, argv);
}
