// SPDX-License-Identifier: GPL-3.0-or-later
// Proves that the image comparison can fail: the strip-light scene is compared
// against the Cornell box baseline and the comparison must report a failure.
#include "penumbraTestRendering.h"

#include "vtkPenumbraSceneSource.h"
#include "vtkRegressionTestImage.h"

#include <fstream>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  // Without the baseline any comparison fails: that would prove nothing.
  for (int i = 1; i + 1 < argc; ++i)
  {
    if (std::string(argv[i]) == "-V" && !std::ifstream(argv[i + 1]).good())
    {
      std::cerr << "baseline " << argv[i + 1] << " is missing" << std::endl;
      return 1;
    }
  }
  vtkNew<vtkPenumbraSceneSource> source;
  source->SetSceneName("strip");
  source->Update();
  vtkNew<vtkRenderWindow> window;
  penumbraSetUpSceneView(source->GetOutput(), window);
  window->Render();
  const int result = vtkRegressionTestImage(window);
  if (result != vtkRegressionTester::FAILED)
  {
    std::cerr << "a different image passed the baseline comparison (result " << result << ")"
              << std::endl;
    return 1;
  }
  std::cout << "the mismatching image was rejected, as it must be" << std::endl;
  return 0;
}
