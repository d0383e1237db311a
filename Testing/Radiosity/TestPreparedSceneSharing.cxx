// SPDX-License-Identifier: GPL-3.0-or-later
// A solve validates and prepares its scene once: the evaluator and the shooter
// use the scene the mesher prepared when they are handed it (as
// vtkPenumbraSolver does), with the same results as when each prepares its
// own; a prepared scene of another scene is not used.
#include "penumbraPreparedScene.h"
#include "penumbraTesting.h"

#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkPenumbraProgressiveShooter.h"
#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <iostream>
#include <string>

namespace
{
/// Radiance of the shooter's output, channel 0, at every point.
std::vector<double> Radiance(vtkPolyData* data)
{
  vtkDataArray* array = data->GetPointData()->GetArray("Radiance");
  std::vector<double> values;
  for (vtkIdType i = 0; array && i < array->GetNumberOfTuples(); ++i)
  {
    values.push_back(array->GetComponent(i, 0));
  }
  return values;
}

/// Mesher -> evaluator -> shooter on `sceneName`; with `share`, the later
/// stages are handed the mesher's prepared scene (or `foreign` when given).
std::vector<double> Solve(const char* sceneName, bool share,
  std::shared_ptr<const penumbra::PreparedScene> foreign, bool& shared)
{
  vtkNew<vtkPenumbraSceneSource> source;
  source->SetSceneName(sceneName);
  vtkNew<vtkPenumbraDiscontinuityMesher> mesher;
  mesher->SetInputConnection(source->GetOutputPort());
  mesher->Update();
  vtkNew<vtkPenumbraRadianceEvaluator> evaluator;
  evaluator->SetInputConnection(0, mesher->GetOutputPort());
  evaluator->SetSceneConnection(source->GetOutputPort());
  vtkNew<vtkPenumbraProgressiveShooter> shooter;
  shooter->SetInputConnection(0, evaluator->GetOutputPort());
  shooter->SetSceneConnection(source->GetOutputPort());
  shooter->SetUnshotFraction(0.05);
  const auto prepared = foreign ? foreign : mesher->GetPreparedScene();
  if (share)
  {
    evaluator->SetPreparedScene(prepared);
    shooter->SetPreparedScene(prepared);
  }
  shooter->Update();
  shared = evaluator->GetPreparedScene() == prepared && shooter->GetPreparedScene() == prepared;
  PENUMBRA_EXPECT_MSG(mesher->GetPreparedScene() != nullptr, "the mesher prepares its scene");
  return Radiance(shooter->GetOutput());
}
} // namespace

int main()
{
  bool shared = false;
  const std::vector<double> own = Solve("cornell", false, nullptr, shared);
  PENUMBRA_EXPECT_MSG(!shared, "without sharing, each stage prepares its own scene");
  const std::vector<double> fromMesher = Solve("cornell", true, nullptr, shared);
  PENUMBRA_EXPECT_MSG(shared, "handed the mesher's prepared scene, the evaluator and the shooter use it");
  PENUMBRA_EXPECT_MSG(!own.empty() && own == fromMesher, "sharing the prepared scene changes no value");

  // A prepared scene of another scene is ignored: the stages prepare their own.
  vtkNew<vtkPenumbraSceneSource> other;
  other->SetSceneName("seven");
  vtkNew<vtkPenumbraDiscontinuityMesher> otherMesher;
  otherMesher->SetInputConnection(other->GetOutputPort());
  otherMesher->Update();
  const std::vector<double> foreign =
    Solve("cornell", true, otherMesher->GetPreparedScene(), shared);
  PENUMBRA_EXPECT_MSG(!shared, "a prepared scene of another scene is not used");
  PENUMBRA_EXPECT_MSG(foreign == own, "and the result is the scene's own");

  const int failures = penumbra::testing::FailureCount();
  std::cout << (failures == 0 ? "all expectations passed" : "expectations failed") << std::endl;
  return failures == 0 ? 0 : 1;
}
