// SPDX-License-Identifier: GPL-3.0-or-later
// vtkPenumbraRadianceEvaluator's reuse of unchanged surfaces (the solver's
// second pass for the secondary shooters): with reuse on, a second execution
// on the same meshes reuses every surface; after the mesher traces a
// secondary shooter's boundaries on two receivers, exactly the surfaces whose
// meshes changed are sampled again, and the output is the same, to the bit,
// as a fresh evaluator's on the same meshes; a changed setting reuses nothing.
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cstdlib>
#include <iostream>
#include <set>

namespace
{

/// The same points, radiance and triangles, to the bit.
bool Identical(vtkPolyData* a, vtkPolyData* b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints() ||
    a->GetNumberOfPolys() != b->GetNumberOfPolys() || a->GetNumberOfLines() != b->GetNumberOfLines())
  {
    return false;
  }
  vtkDataArray* ra = a->GetPointData()->GetArray("Radiance");
  vtkDataArray* rb = b->GetPointData()->GetArray("Radiance");
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    double pa[3], pb[3];
    a->GetPoint(p, pa);
    b->GetPoint(p, pb);
    for (int c = 0; c < 3; ++c)
    {
      if (pa[c] != pb[c] || ra->GetComponent(p, c) != rb->GetComponent(p, c))
      {
        return false;
      }
    }
  }
  return true;
}

/// The surfaces of the mesher's output (SurfaceId of its triangles).
std::set<int> SurfacesOf(vtkPolyData* mesh)
{
  std::set<int> ids;
  vtkDataArray* surface = mesh->GetCellData()->GetArray("SurfaceId");
  const vtkIdType first = mesh->GetNumberOfVerts() + mesh->GetNumberOfLines();
  for (vtkIdType c = first; c < mesh->GetNumberOfCells(); ++c)
  {
    ids.insert(static_cast<int>(surface->GetComponent(c, 0)));
  }
  return ids;
}

} // namespace

int TestEvaluatorReuse(int, char*[])
{
  int failures = 0;
  const auto expect = [&](bool ok, const char* what) {
    if (!ok)
    {
      std::cerr << "FAIL: " << what << std::endl;
      ++failures;
    }
  };
  vtkNew<vtkPenumbraSceneSource> scene;
  scene->SetSceneName("cornell");
  vtkNew<vtkPenumbraDiscontinuityMesher> mesher;
  mesher->SetInputConnection(scene->GetOutputPort());
  vtkNew<vtkPenumbraRadianceEvaluator> evaluator;
  evaluator->SetInputConnection(0, mesher->GetOutputPort());
  evaluator->SetSceneConnection(scene->GetOutputPort());
  evaluator->SetSamplingTolerance(0.01);
  evaluator->SetReuseUnchangedSurfaces(true);
  evaluator->Update();
  const int surfaces = static_cast<int>(SurfacesOf(mesher->GetOutput()).size());
  expect(evaluator->GetNumberOfReusedSurfaces() == 0, "the first execution reuses nothing");
  vtkNew<vtkPolyData> first;
  first->DeepCopy(evaluator->GetOutput());

  // The same meshes again: every surface reused, the same output.
  mesher->Modified();
  evaluator->Update();
  expect(evaluator->GetNumberOfReusedSurfaces() == surfaces, "unchanged meshes are all reused");
  expect(Identical(first, evaluator->GetOutput()), "reused output equals the sampled one");

  // The floor (cell 0) as a secondary shooter on the ceiling (1) and the
  // back wall (3): their meshes gain its boundaries, the others stay.
  vtkNew<vtkPolyData> before;
  before->DeepCopy(mesher->GetOutput());
  vtkNew<vtkIdList> receivers;
  receivers->InsertNextId(1);
  receivers->InsertNextId(3);
  mesher->AddShooterId(2); // the light, as the solver adds the emitters
  mesher->AddShooterId(0, receivers);
  evaluator->Update();
  const int reused = evaluator->GetNumberOfReusedSurfaces();
  std::cout << "secondary pass: " << reused << " of " << surfaces << " surfaces reused"
            << std::endl;
  expect(reused >= surfaces - 2 && reused < surfaces,
    "only the receivers of the secondary shooter are sampled again");
  vtkNew<vtkPenumbraRadianceEvaluator> fresh;
  fresh->SetInputConnection(0, mesher->GetOutputPort());
  fresh->SetSceneConnection(scene->GetOutputPort());
  fresh->SetSamplingTolerance(0.01);
  fresh->Update();
  expect(fresh->GetNumberOfReusedSurfaces() == 0, "reuse is off by default");
  expect(Identical(fresh->GetOutput(), evaluator->GetOutput()),
    "the output with reuse equals a fresh evaluator's, to the bit");

  // Another setting: nothing reused.
  evaluator->SetSamplingTolerance(0.02);
  evaluator->Update();
  expect(evaluator->GetNumberOfReusedSurfaces() == 0, "a changed setting reuses nothing");
  // Reuse off: nothing kept.
  evaluator->SetReuseUnchangedSurfaces(false);
  mesher->Modified();
  evaluator->Update();
  expect(evaluator->GetNumberOfReusedSurfaces() == 0, "reuse off reuses nothing");
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

int main(int argc, char* argv[])
{
  return TestEvaluatorReuse(argc, argv);
}
