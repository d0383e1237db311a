// SPDX-License-Identifier: GPL-3.0-or-later
// The whole pipeline in C++ on the built-in Cornell box, as a user composes it:
// scene source -> mesher -> evaluator -> shooter -> reconstructor. Checks the
// output contract (finite, non-negative radiance on every point; a SurfaceId
// per triangle; the light brighter than every reflector) and the shooter's
// report. It is also the program that Testing/Scripts/valgrind.sh runs under
// memcheck, so it needs no display and links no rendering.
//
// Usage: TestCornellSolve [unshot fraction, default 0.01]
//          [sampling tolerance, default 0.002 (vtkPenumbraRadianceEvaluator's)]
// (the test suite runs it coarse, 0.1 and 0.05, for time).
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkNew.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPenumbraProgressiveShooter.h"
#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraRadianceReconstructor.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>

int TestCornellSolve(int argc, char* argv[])
{
  const double unshotFraction = argc > 1 ? std::atof(argv[1]) : 0.01;
  const double samplingTolerance = argc > 2 ? std::atof(argv[2]) : 0.002;
  const auto start = std::chrono::steady_clock::now();

  vtkNew<vtkPenumbraSceneSource> scene;
  scene->SetSceneName("cornell");
  vtkNew<vtkPenumbraDiscontinuityMesher> mesher;
  mesher->SetInputConnection(scene->GetOutputPort());
  vtkNew<vtkPenumbraRadianceEvaluator> evaluator;
  evaluator->SetInputConnection(0, mesher->GetOutputPort());
  evaluator->SetSceneConnection(scene->GetOutputPort());
  evaluator->SetSamplingTolerance(samplingTolerance);
  vtkNew<vtkPenumbraProgressiveShooter> shooter;
  shooter->SetInputConnection(0, evaluator->GetOutputPort());
  shooter->SetSceneConnection(scene->GetOutputPort());
  shooter->SetUnshotFraction(unshotFraction);
  // As penumbra.solve: secondary shots by the hierarchical method.
  shooter->SetExactPowerFraction(1.0);
  vtkNew<vtkPenumbraRadianceReconstructor> reconstructor;
  reconstructor->SetInputConnection(shooter->GetOutputPort());
  reconstructor->Update();

  vtkPolyData* result = reconstructor->GetOutput();
  vtkDataArray* radiance = result->GetPointData()->GetArray("Radiance");
  vtkDataArray* surfaceId = result->GetCellData()->GetArray("SurfaceId");
  int failures = 0;
  if (!radiance || radiance->GetNumberOfComponents() != 3 || !surfaceId ||
    result->GetNumberOfPolys() == 0)
  {
    std::cerr << "FAIL: no Radiance, no SurfaceId or no triangles" << std::endl;
    return EXIT_FAILURE;
  }
  double brightest = 0.0;
  for (vtkIdType i = 0; i < radiance->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      const double value = radiance->GetComponent(i, c);
      if (!std::isfinite(value) || value < 0.0)
      {
        if (failures++ < 5)
        {
          std::cerr << "FAIL: point " << i << " channel " << c << " radiance " << value
                    << std::endl;
        }
      }
      brightest = std::max(brightest, value);
    }
  }
  // The light's radiance (17, 12, 4) plus what it reflects: the brightest value
  // is at least the emission and far below it plus the reflected light's bound.
  if (!(brightest >= 17.0 && brightest < 17.0 + 0.8 * 17.0))
  {
    std::cerr << "FAIL: brightest radiance " << brightest << ", expected in [17, 30.6)"
              << std::endl;
    ++failures;
  }
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "Cornell box: " << result->GetNumberOfPolys() << " triangles, "
            << result->GetNumberOfPoints() << " points, brightest " << brightest << ", "
            << seconds << " s" << std::endl;
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

int main(int argc, char* argv[])
{
  return TestCornellSolve(argc, argv);
}
