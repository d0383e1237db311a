// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraSensorEvaluator.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include "penumbraExactEvaluator.h"
#include "penumbraLinearSource.h"
#include "penumbraPreparedScene.h"
#include "penumbraSensorIrradiance.h"

#include <cmath>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkPenumbraSensorEvaluator);

vtkPenumbraSensorEvaluator::vtkPenumbraSensorEvaluator()
{
  this->SetNumberOfInputPorts(3);
}

int vtkPenumbraSensorEvaluator::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 2)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

namespace
{
/// The sensors' positions and unit normals; throws InputError naming a bad point.
void ReadSensors(vtkPolyData* sensors, std::vector<penumbra::Vec3>& positions,
  std::vector<penumbra::Vec3>& normals)
{
  const vtkIdType count = sensors->GetNumberOfPoints();
  vtkDataArray* array = sensors->GetPointData()->GetArray("Normals");
  if (count > 0 && (!array || array->GetNumberOfComponents() != 3))
  {
    throw penumbra::InputError("the sensors need a 3-component point array 'Normals' (the "
                               "direction each sensor faces)");
  }
  positions.resize(static_cast<std::size_t>(count));
  normals.resize(static_cast<std::size_t>(count));
  for (vtkIdType i = 0; i < count; ++i)
  {
    double p[3], n[3];
    sensors->GetPoint(i, p);
    array->GetTuple(i, n);
    const penumbra::Vec3 position(p[0], p[1], p[2]);
    const penumbra::Vec3 normal(n[0], n[1], n[2]);
    const double length = penumbra::Length(normal);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      std::ostringstream os;
      os << "sensor " << i << ": its position is not finite";
      throw penumbra::InputError(os.str());
    }
    if (!std::isfinite(length) || length <= 0.0)
    {
      std::ostringstream os;
      os << "sensor " << i << ": its normal (" << n[0] << ", " << n[1] << ", " << n[2]
         << ") has no direction";
      throw penumbra::InputError(os.str());
    }
    positions[i] = position;
    normals[i] = normal / length;
  }
}
}

int vtkPenumbraSensorEvaluator::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* sensors = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* sceneData = vtkPolyData::GetData(inputVector[1]);
  vtkPolyData* solution =
    inputVector[2]->GetNumberOfInformationObjects() ? vtkPolyData::GetData(inputVector[2]) : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  if (!sceneData)
  {
    vtkErrorMacro(<< "no scene on input port 1 (SetSceneConnection)");
    return 0;
  }
  std::vector<penumbra::Vec3> positions, normals;
  ReadSensors(sensors, positions, normals);
  const penumbra::Scene scene = penumbra::SceneFromPolyData(sceneData);
  const auto prepared = this->Prepare(scene); // validates the scene
  std::vector<penumbra::RGB> emission;
  for (const penumbra::Surface& s : scene.Surfaces)
  {
    emission.push_back(s.Emission);
  }
  const std::map<int, penumbra::ShooterRadiance> reflected = penumbra::RadianceFunctions(
    solution, static_cast<int>(scene.Surfaces.size()), "the solution (port 2)", &emission);
  const penumbra::ExactEvaluator evaluator(prepared);

  const vtkIdType count = static_cast<vtkIdType>(positions.size());
  vtkNew<vtkDoubleArray> total, direct;
  total->SetName("Irradiance");
  direct->SetName("DirectIrradiance");
  for (vtkDoubleArray* a : { total.Get(), direct.Get() })
  {
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(count);
  }
  vtkSMPThreadLocal<penumbra::VisibilityWorkspace> visibility;
  vtkSMPThreadLocal<penumbra::LinearSourceWorkspace> linear;
  const vtkIdType batches = std::min<vtkIdType>(100, count);
  this->UpdateProgress(0.0);
  for (vtkIdType batch = 0; batch < batches && !this->GetAbortExecute(); ++batch)
  {
    vtkSMPTools::For(count * batch / batches, count * (batch + 1) / batches,
      [&](vtkIdType first, vtkIdType last) {
        for (vtkIdType i = first; i < last; ++i)
        {
          const penumbra::SensorIrradiance e = penumbra::EvaluateSensor(evaluator, scene,
            reflected, positions[i], normals[i], visibility.Local(), linear.Local());
          const penumbra::RGB sum = e.Direct + e.Indirect;
          total->SetTuple3(i, sum.R, sum.G, sum.B);
          direct->SetTuple3(i, e.Direct.R, e.Direct.G, e.Direct.B);
        }
      });
    this->UpdateProgress(static_cast<double>(batch + 1) / batches);
  }
  if (this->GetAbortExecute())
  {
    return 1;
  }
  output->SetPoints(sensors->GetPoints());
  output->GetPointData()->AddArray(sensors->GetPointData()->GetArray("Normals"));
  output->GetPointData()->AddArray(total);
  output->GetPointData()->AddArray(direct);
  output->GetPointData()->SetActiveScalars("Irradiance");
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPenumbraSensorEvaluator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "(no settings: the scene on port 1, an optional solution on port 2)\n";
}
