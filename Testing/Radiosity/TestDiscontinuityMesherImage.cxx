// SPDX-License-Identifier: GPL-3.0-or-later
// Baseline image of the Cornell floor's discontinuity mesh seen from above:
// triangles in grey, constrained lines colored by order (0 red: contacts,
// 1 green, 2 blue, -1 white: outline).
#include "penumbraTestRendering.h"

#include "vtkCellArray.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkIntArray.h"
#include "vtkPenumbraSceneSource.h"
#include "vtkPoints.h"
#include "vtkProperty.h"
#include "vtkRegressionTestImage.h"

#include <iostream>

int main(int argc, char* argv[])
{
  vtkNew<vtkPenumbraSceneSource> source;
  source->SetSceneName("cornell");
  vtkNew<vtkPenumbraDiscontinuityMesher> mesher;
  mesher->SetInputConnection(source->GetOutputPort());
  mesher->Update();
  vtkPolyData* mesh = mesher->GetOutput();

  // The floor is the scene cell lying in y = 0 with the largest extent.
  vtkPolyData* scene = source->GetOutput();
  vtkIdType floor = -1;
  for (vtkIdType i = 0; i < scene->GetNumberOfCells() && floor < 0; ++i)
  {
    double bounds[6];
    scene->GetCell(i)->GetBounds(bounds);
    if (bounds[2] == 0.0 && bounds[3] == 0.0 && bounds[1] - bounds[0] > 0.5)
    {
      floor = i;
    }
  }
  if (floor < 0)
  {
    std::cerr << "no floor in the Cornell scene" << std::endl;
    return 1;
  }

  auto* surface = vtkIntArray::SafeDownCast(mesh->GetCellData()->GetArray("SurfaceId"));
  auto* order = vtkIntArray::SafeDownCast(mesh->GetCellData()->GetArray("DiscontinuityOrder"));
  vtkNew<vtkCellArray> triangles, lines;
  vtkNew<vtkUnsignedCharArray> lineColors;
  lineColors->SetNumberOfComponents(3);
  lineColors->SetName("DisplayColor");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    if (surface->GetValue(c) != floor)
    {
      continue;
    }
    mesh->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() == 3)
    {
      triangles->InsertNextCell(ids);
    }
    else
    {
      lines->InsertNextCell(ids);
      const int o = order->GetValue(c);
      const unsigned char rgb[4][3] = { { 255, 255, 255 }, { 255, 40, 40 }, { 40, 220, 40 },
        { 60, 120, 255 } };
      lineColors->InsertNextTypedTuple(rgb[o + 1]);
    }
  }
  vtkNew<vtkPolyData> wire, boundaries;
  wire->SetPoints(mesh->GetPoints());
  wire->SetPolys(triangles);
  boundaries->SetPoints(mesh->GetPoints());
  boundaries->SetLines(lines);
  boundaries->GetCellData()->SetScalars(lineColors);

  vtkNew<vtkPolyDataMapper> wireMapper;
  wireMapper->SetInputData(wire);
  vtkNew<vtkActor> wireActor;
  wireActor->SetMapper(wireMapper);
  wireActor->GetProperty()->SetRepresentationToWireframe();
  wireActor->GetProperty()->SetColor(0.45, 0.45, 0.45);
  wireActor->GetProperty()->LightingOff();
  vtkNew<vtkPolyDataMapper> lineMapper;
  lineMapper->SetInputData(boundaries);
  lineMapper->SetColorModeToDirectScalars();
  vtkNew<vtkActor> lineActor;
  lineActor->SetMapper(lineMapper);
  lineActor->GetProperty()->SetLineWidth(2.0);
  lineActor->GetProperty()->LightingOff();

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(wireActor);
  renderer->AddActor(lineActor);
  renderer->SetBackground(0.0, 0.0, 0.0);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(0.278, 2.0, 0.28);
  camera->SetFocalPoint(0.278, 0.0, 0.28);
  camera->SetViewUp(0.0, 0.0, 1.0);
  camera->ParallelProjectionOn();
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetSize(400, 400);
  window->AddRenderer(renderer);
  window->Render();
  return vtkRegressionTestImage(window) == vtkRegressionTester::FAILED ? 1 : 0;
}
