// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraTestRendering.h
 * @brief Shared pieces of the C++ filter tests: an error observer that keeps
 * VTK error messages, and a render window showing a scene in its reflectance
 * colors from the Cornell box camera.
 */
#ifndef penumbraTestRendering_h
#define penumbraTestRendering_h

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <string>

/// Collects the messages of ErrorEvents of the objects it observes.
class penumbraErrorCollector
{
public:
  void Observe(vtkObject* object)
  {
    this->Callback->SetCallback(&penumbraErrorCollector::OnError);
    this->Callback->SetClientData(this);
    object->AddObserver(vtkCommand::ErrorEvent, this->Callback);
  }
  void Clear() { this->Messages.clear(); }
  bool Contains(const std::string& fragment) const
  {
    return this->Messages.find(fragment) != std::string::npos;
  }
  std::string Messages;

private:
  static void OnError(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<penumbraErrorCollector*>(clientData);
    self->Messages += callData ? static_cast<const char*>(callData) : "(no message)";
    self->Messages += "\n";
  }
  vtkNew<vtkCallbackCommand> Callback;
};

/// Color each cell by its Reflectance (emitters white) and render from the
/// Cornell box camera (metres), lit by a headlight.
inline void penumbraSetUpSceneView(vtkPolyData* scene, vtkRenderWindow* window)
{
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("DisplayColor");
  colors->SetNumberOfComponents(3);
  vtkDataArray* reflectance = scene->GetCellData()->GetArray("Reflectance");
  vtkDataArray* emission = scene->GetCellData()->GetArray("Emission");
  for (vtkIdType i = 0; i < scene->GetNumberOfCells(); ++i)
  {
    double rgb[3];
    reflectance->GetTuple(i, rgb);
    const double* e = emission->GetTuple3(i);
    const bool emits = std::max({ e[0], e[1], e[2] }) > 0.0;
    colors->InsertNextTuple3(emits ? 255 : 255 * rgb[0], emits ? 255 : 255 * rgb[1],
      emits ? 255 : 255 * rgb[2]);
  }
  scene->GetCellData()->AddArray(colors);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(scene);
  mapper->SetScalarModeToUseCellFieldData();
  mapper->SelectColorArray("DisplayColor");
  mapper->SetColorModeToDirectScalars();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  // Walls seen edge-on from a headlight would be black: mostly ambient.
  actor->GetProperty()->SetAmbient(0.6);
  actor->GetProperty()->SetDiffuse(0.4);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(0.278, 0.273, -0.8);
  camera->SetFocalPoint(0.278, 0.273, 0.0);
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetViewAngle(39.3076);
  renderer->ResetCameraClippingRange();
  window->SetSize(300, 300);
  window->AddRenderer(renderer);
}

#endif
