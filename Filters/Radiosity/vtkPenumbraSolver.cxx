// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSolver.h"

#include "penumbraDiscontinuityMesher.h"
#include "penumbraEvaluationSettings.h"
#include "penumbraReconstruction.h"
#include "penumbraTransportSettings.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkPenumbraProgressiveShooter.h"
#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraRadianceReconstructor.h"
#include "vtkPolyData.h"

#include <string>
#include <vector>

vtkStandardNewMacro(vtkPenumbraSolver);

vtkPenumbraSolver::vtkPenumbraSolver()
{
  // The stages' defaults: the solver composes them and changes none.
  const penumbra::DiscontinuityMeshSettings meshing;
  const penumbra::EvaluationSettings evaluation;
  const penumbra::TransportSettings transport;
  const penumbra::ResampleOptions display;
  this->MinimumAngle = meshing.MinimumAngle;
  this->SamplingTolerance = evaluation.Sampling.SamplingTolerance;
  this->MaximumSamples = static_cast<vtkIdType>(evaluation.MaximumSamples);
  this->UnshotFraction = transport.Shooting.UnshotFraction;
  this->ExactPowerFraction = transport.Shooting.ExactPowerFraction;
  this->ReuseTransport = transport.Shooting.ReuseTransport;
  this->MaximumIndirectSamples = static_cast<vtkIdType>(transport.MaximumIndirectSamples);
  this->SubdivisionLevel = display.SubdivisionLevel;
}

namespace
{
/// One stage of the solve: its filter, name and share of the progress bar.
struct Stage
{
  vtkAlgorithm* Filter;
  const char* Name;
  double Weight;
};

/// What the observers of a stage need: the solver, the stage's progress
/// range, and the last error message the stage reported.
struct StageObserver
{
  vtkPenumbraSolver* Solver = nullptr;
  const char* Name = "";
  double Start = 0.0;
  double Weight = 0.0;
  std::string Error;
};

void OnStageProgress(vtkObject* caller, unsigned long, void* clientData, void*)
{
  auto* observer = static_cast<StageObserver*>(clientData);
  auto* filter = static_cast<vtkAlgorithm*>(caller);
  if (observer->Solver->GetAbortExecute())
  {
    filter->SetAbortExecute(1);
  }
  observer->Solver->SetProgressText(observer->Name);
  observer->Solver->UpdateProgress(observer->Start + observer->Weight * filter->GetProgress());
}

void OnStageError(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* observer = static_cast<StageObserver*>(clientData);
  const std::string message =
    vtkPenumbraAlgorithm::ErrorText(callData ? static_cast<const char*>(callData) : "");
  observer->Error = message.empty() ? "unknown error" : message;
}
} // namespace

int vtkPenumbraSolver::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  if (!input)
  {
    vtkErrorMacro(<< "no scene on input port 0");
    return 0;
  }
  vtkNew<vtkPolyData> scene;
  scene->ShallowCopy(input);

  vtkNew<vtkPenumbraDiscontinuityMesher> mesher;
  mesher->SetInputData(scene);
  mesher->SetMinimumAngle(this->MinimumAngle);
  vtkNew<vtkPenumbraRadianceEvaluator> evaluator;
  evaluator->SetInputConnection(0, mesher->GetOutputPort());
  evaluator->SetSceneData(scene);
  evaluator->SetSamplingTolerance(this->SamplingTolerance);
  evaluator->SetMaximumSamples(this->MaximumSamples);
  vtkNew<vtkPenumbraProgressiveShooter> shooter;
  shooter->SetInputConnection(0, evaluator->GetOutputPort());
  shooter->SetSceneData(scene);
  shooter->SetUnshotFraction(this->UnshotFraction);
  shooter->SetExactPowerFraction(this->ExactPowerFraction);
  shooter->SetMaximumIndirectSamples(this->MaximumIndirectSamples);
  shooter->SetReuseTransport(this->ReuseTransport);
  vtkNew<vtkPenumbraRadianceReconstructor> reconstructor;
  reconstructor->SetInputConnection(
    this->Indirect ? shooter->GetOutputPort() : evaluator->GetOutputPort());
  reconstructor->SetSubdivisionLevel(this->SubdivisionLevel);

  // Shares of the progress bar: about the shares of the time on the Cornell box.
  std::vector<Stage> stages = { { mesher, "mesher", 0.02 }, { evaluator, "evaluator", 0.15 },
    { shooter, "shooter", 0.78 }, { reconstructor, "reconstructor", 0.05 } };
  if (!this->Indirect)
  {
    stages = { { mesher, "mesher", 0.1 }, { evaluator, "evaluator", 0.8 },
      { reconstructor, "reconstructor", 0.1 } };
  }
  std::vector<StageObserver> observers(stages.size());
  std::vector<vtkNew<vtkCallbackCommand>> progress(stages.size()), errors(stages.size());
  double start = 0.0;
  for (std::size_t k = 0; k < stages.size(); ++k)
  {
    observers[k].Solver = this;
    observers[k].Name = stages[k].Name;
    observers[k].Start = start;
    observers[k].Weight = stages[k].Weight;
    start += stages[k].Weight;
    progress[k]->SetCallback(OnStageProgress);
    progress[k]->SetClientData(&observers[k]);
    stages[k].Filter->AddObserver(vtkCommand::ProgressEvent, progress[k]);
    errors[k]->SetCallback(OnStageError);
    errors[k]->SetClientData(&observers[k]);
    stages[k].Filter->AddObserver(vtkCommand::ErrorEvent, errors[k]);
  }

  // Stage by stage, so that an error names its stage.
  for (std::size_t k = 0; k < stages.size(); ++k)
  {
    const int ok = stages[k].Filter->GetExecutive()->Update();
    if (this->GetAbortExecute())
    {
      return 1;
    }
    if (!ok || !observers[k].Error.empty())
    {
      vtkErrorMacro(<< stages[k].Name << ": "
                    << (observers[k].Error.empty() ? "failed" : observers[k].Error));
      return 0;
    }
    if (k == 0)
    {
      // The scene is validated and prepared once, by the mesher.
      evaluator->SetPreparedScene(mesher->GetPreparedScene());
      shooter->SetPreparedScene(mesher->GetPreparedScene());
    }
  }
  output->ShallowCopy(reconstructor->GetOutput());
  if (this->Indirect)
  {
    // Keep the shooter's report (shots, unshot fraction, energy) with the result.
    output->GetFieldData()->PassData(shooter->GetOutput()->GetFieldData());
  }
  this->SetProgressText(nullptr);
  return 1;
}

void vtkPenumbraSolver::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Indirect: " << (this->Indirect ? "On" : "Off") << "\n";
  os << indent << "UnshotFraction: " << this->UnshotFraction << "\n";
  os << indent << "ExactPowerFraction: " << this->ExactPowerFraction << "\n";
  os << indent << "MaximumIndirectSamples: " << this->MaximumIndirectSamples << "\n";
  os << indent << "ReuseTransport: " << (this->ReuseTransport ? "On" : "Off") << "\n";
  os << indent << "SamplingTolerance: " << this->SamplingTolerance << "\n";
  os << indent << "MaximumSamples: " << this->MaximumSamples << "\n";
  os << indent << "MinimumAngle: " << this->MinimumAngle << "\n";
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
}
