// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSolver.h"
#include "vtkPenumbraSceneConversion.h"

#include "penumbraDiscontinuityMesher.h"
#include "penumbraEvaluationSettings.h"
#include "penumbraReconstruction.h"
#include "penumbraSecondaryShooters.h"
#include "penumbraTransportSettings.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPenumbraDiscontinuityMesher.h"
#include "vtkPenumbraProgressiveShooter.h"
#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraRadianceReconstructor.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkDoubleArray.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <sstream>
#include <string>
#include <utility>
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
  this->JumpThreshold = meshing.JumpThreshold;
  this->SamplingTolerance = evaluation.Sampling.SamplingTolerance;
  this->MaximumSamples = static_cast<vtkIdType>(evaluation.MaximumSamples);
  this->MaximumSampleSpacing = evaluation.MaximumSampleSpacing;
  this->UnshotFraction = transport.Shooting.UnshotFraction;
  this->ExactPowerFraction = transport.Shooting.ExactPowerFraction;
  this->ReuseTransport = transport.Shooting.ReuseTransport;
  this->MaximumIndirectSamples = static_cast<vtkIdType>(transport.MaximumIndirectSamples);
  this->DisplayTolerance = display.DisplayTolerance;
  this->CompactTolerance = display.CompactTolerance;
  this->CompactIndirectTolerance = display.CompactIndirectTolerance;
  this->SubdivisionLevel = display.SubdivisionLevel;
  this->SecondaryShooterFraction = transport.SecondaryShooterFraction;
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

/// Maximum number of secondary shooters (SecondaryShooterFraction).
constexpr int MaximumSecondaryShooters = 4;

/// Per scene cell: pi * integral of (Radiance - Emission) over `direct`'s
/// triangles of that surface, mean of RGB (linear interpolant).
std::vector<double> ReflectedPower(vtkPolyData* direct, vtkPolyData* scene)
{
  std::vector<double> reflected(static_cast<std::size_t>(scene->GetNumberOfCells()), 0.0);
  vtkDataArray* radiance = direct->GetPointData()->GetArray("Radiance");
  vtkDataArray* ids = direct->GetCellData()->GetArray("SurfaceId");
  vtkDataArray* emission = scene->GetCellData()->GetArray("Emission");
  if (!radiance || !ids || !emission)
  {
    return reflected;
  }
  const auto surfaces = static_cast<vtkIdType>(reflected.size());
  penumbra::ForEachCell(direct,
    [&](vtkIdType cellId, int kind, vtkIdType count, const vtkIdType* points) {
      const auto surface = static_cast<vtkIdType>(ids->GetComponent(cellId, 0));
      if (kind != 2 || count != 3 || surface < 0 || surface >= surfaces)
      {
        return true;
      }
      double p[3][3], e[3], mean = 0.0;
      emission->GetTuple(surface, e);
      for (int k = 0; k < 3; ++k)
      {
        direct->GetPoint(points[k], p[k]);
        double value[3];
        radiance->GetTuple(points[k], value);
        mean += ((value[0] - e[0]) + (value[1] - e[1]) + (value[2] - e[2])) / 9.0;
      }
      double u[3], v[3], w[3];
      vtkMath::Subtract(p[1], p[0], u);
      vtkMath::Subtract(p[2], p[0], v);
      vtkMath::Cross(u, v, w);
      reflected[static_cast<std::size_t>(surface)] += vtkMath::Pi() * 0.5 * vtkMath::Norm(w) * mean;
      return true;
    });
  return reflected;
}

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
  mesher->SetJumpThreshold(this->JumpThreshold);
  vtkNew<vtkPenumbraRadianceEvaluator> evaluator;
  evaluator->SetInputConnection(0, mesher->GetOutputPort());
  evaluator->SetSceneData(scene);
  evaluator->SetSamplingTolerance(this->SamplingTolerance);
  evaluator->SetMaximumSamples(this->MaximumSamples);
  evaluator->SetMaximumSampleSpacing(this->MaximumSampleSpacing);
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
  reconstructor->SetDisplayTolerance(this->DisplayTolerance);
  reconstructor->SetCompactTolerance(this->CompactTolerance);
  reconstructor->SetCompactIndirectTolerance(this->CompactIndirectTolerance);
  reconstructor->SetSubdivisionLevel(this->SubdivisionLevel);

  // Shares of the progress bar: about the shares of the time on the Cornell
  // box. The secondary shooters' second pass of the mesher and the evaluator
  // has a share of its own, after the evaluator's, so that the bar never
  // moves back (it is skipped when the pass is not needed).
  constexpr double SecondaryMesherShare = 0.02;
  constexpr double SecondaryEvaluatorShare = 0.08;
  std::vector<Stage> stages = { { mesher, "mesher", 0.02 }, { evaluator, "evaluator", 0.13 },
    { shooter, "shooter", 0.70 }, { reconstructor, "reconstructor", 0.05 } };
  if (!this->Indirect)
  {
    stages = { { mesher, "mesher", 0.1 }, { evaluator, "evaluator", 0.8 },
      { reconstructor, "reconstructor", 0.1 } };
  }
  std::vector<StageObserver> observers(stages.size());
  std::vector<vtkNew<vtkCallbackCommand>> progress(stages.size()), errors(stages.size());
  double start = 0.0;
  double secondaryStart = 0.0;
  for (std::size_t k = 0; k < stages.size(); ++k)
  {
    observers[k].Solver = this;
    observers[k].Name = stages[k].Name;
    observers[k].Start = start;
    observers[k].Weight = stages[k].Weight;
    start += stages[k].Weight;
    if (k == 1 && this->Indirect)
    {
      secondaryStart = start;
      start += SecondaryMesherShare + SecondaryEvaluatorShare;
    }
    progress[k]->SetCallback(OnStageProgress);
    progress[k]->SetClientData(&observers[k]);
    stages[k].Filter->AddObserver(vtkCommand::ProgressEvent, progress[k]);
    errors[k]->SetCallback(OnStageError);
    errors[k]->SetClientData(&observers[k]);
    stages[k].Filter->AddObserver(vtkCommand::ErrorEvent, errors[k]);
  }

  // Stage by stage, so that an error names its stage.
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  };
  const Clock::time_point solveStart = Clock::now();
  std::vector<double> stageSeconds(stages.size(), 0.0);
  double secondarySeconds = 0.0;
  for (std::size_t k = 0; k < stages.size(); ++k)
  {
    const Clock::time_point stageStart = Clock::now();
    const int ok = stages[k].Filter->GetExecutive()->Update();
    stageSeconds[k] = seconds(stageStart);
    this->KeepWarningsOf(stages[k].Filter, stages[k].Name);
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
      // The secondary shooters' pass changes the meshes of their receivers
      // only: the evaluator keeps the others' samples and reuses them.
      evaluator->SetReuseUnchangedSurfaces(this->Indirect);
    }
    if (k == 1 && this->Indirect)
    {
      // Secondary shooters: mesh and evaluate again, the receivers now
      // following the shadows those surfaces cast too.
      const std::vector<penumbra::SecondaryShooter> secondary = penumbra::SelectSecondaryShooters(
        *mesher->GetPreparedScene(), ReflectedPower(evaluator->GetOutput(), scene),
        this->SecondaryShooterFraction, MaximumSecondaryShooters);
      if (!secondary.empty())
      {
        vtkDataArray* emission = scene->GetCellData()->GetArray("Emission");
        for (vtkIdType c = 0; c < scene->GetNumberOfCells(); ++c)
        {
          double e[3];
          emission->GetTuple(c, e);
          if (e[0] != 0.0 || e[1] != 0.0 || e[2] != 0.0)
          {
            mesher->AddShooterId(c);
          }
        }
        for (const penumbra::SecondaryShooter& entry : secondary)
        {
          vtkNew<vtkIdList> receivers;
          for (const int id : entry.Receivers)
          {
            receivers->InsertNextId(id);
          }
          mesher->AddShooterId(entry.Shooter, receivers);
        }
        // The same filters again, in the pass's own share of the bar.
        observers[0].Name = "secondary shooters: mesher";
        observers[0].Start = secondaryStart;
        observers[0].Weight = SecondaryMesherShare;
        observers[1].Name = "secondary shooters: evaluator";
        observers[1].Start = secondaryStart + SecondaryMesherShare;
        observers[1].Weight = SecondaryEvaluatorShare;
        this->SetProgressText("secondary shooters");
        const Clock::time_point secondaryTime = Clock::now();
        const bool secondaryOk =
          mesher->GetExecutive()->Update() && evaluator->GetExecutive()->Update();
        secondarySeconds = seconds(secondaryTime);
        this->KeepWarningsOf(mesher, "secondary shooters: mesher");
        this->KeepWarningsOf(evaluator, "secondary shooters: evaluator");
        if (!secondaryOk || !observers[0].Error.empty() || !observers[1].Error.empty())
        {
          vtkErrorMacro(<< "secondary shooters: "
                        << (observers[0].Error.empty() ? observers[1].Error : observers[0].Error));
          return 0;
        }
        if (this->GetAbortExecute())
        {
          return 1;
        }
      }
      evaluator->SetReuseUnchangedSurfaces(false); // drop what it kept
    }
  }
  output->ShallowCopy(reconstructor->GetOutput());
  if (this->Indirect)
  {
    // Keep the shooter's report (shots, unshot fraction, energy) with the result.
    output->GetFieldData()->PassData(shooter->GetOutput()->GetFieldData());
  }
  // The solve's record, for `penumbra info` and anyone auditing a result.
  const auto addSeconds = [output](const std::string& name, double value) {
    vtkNew<vtkDoubleArray> array;
    array->SetName(name.c_str());
    array->InsertNextValue(value);
    output->GetFieldData()->AddArray(array);
  };
  for (std::size_t k = 0; k < stages.size(); ++k)
  {
    std::string name = stages[k].Name;
    name[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
    addSeconds(name + "Seconds", stageSeconds[k]);
  }
  if (this->Indirect)
  {
    addSeconds("SecondaryShootersSeconds", secondarySeconds);
  }
  addSeconds("SolveSeconds", seconds(solveStart));
  std::ostringstream settings;
  settings << "Indirect=" << (this->Indirect ? 1 : 0) << " UnshotFraction=" << this->UnshotFraction
           << " ExactPowerFraction=" << this->ExactPowerFraction
           << " MaximumIndirectSamples=" << this->MaximumIndirectSamples
           << " ReuseTransport=" << (this->ReuseTransport ? 1 : 0)
           << " SamplingTolerance=" << this->SamplingTolerance
           << " MaximumSamples=" << this->MaximumSamples
           << " MaximumSampleSpacing=" << this->MaximumSampleSpacing
           << " MinimumAngle=" << this->MinimumAngle
           << " JumpThreshold=" << this->JumpThreshold
           << " SubdivisionLevel=" << this->SubdivisionLevel
           << " DisplayTolerance=" << this->DisplayTolerance
           << " CompactTolerance=" << this->CompactTolerance
           << " CompactIndirectTolerance=" << this->CompactIndirectTolerance
           << " SecondaryShooterFraction=" << this->SecondaryShooterFraction;
  vtkNew<vtkStringArray> record;
  record->SetName("SolverSettings");
  record->InsertNextValue(settings.str());
  output->GetFieldData()->AddArray(record);
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
  os << indent << "MaximumSampleSpacing: " << this->MaximumSampleSpacing << "\n";
  os << indent << "MinimumAngle: " << this->MinimumAngle << "\n";
  os << indent << "JumpThreshold: " << this->JumpThreshold << "\n";
  os << indent << "DisplayTolerance: " << this->DisplayTolerance << "\n";
  os << indent << "CompactTolerance: " << this->CompactTolerance << "\n";
  os << indent << "CompactIndirectTolerance: " << this->CompactIndirectTolerance << "\n";
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "SecondaryShooterFraction: " << this->SecondaryShooterFraction << "\n";
}
