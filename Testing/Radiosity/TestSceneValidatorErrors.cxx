// SPDX-License-Identifier: GPL-3.0-or-later
// Every malformed-scene case of the data contract gives an error naming the
// cell or array, an empty output, and no crash; a valid scene passes through.
#include "penumbraTestRendering.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkPenumbraSceneValidator.h"
#include "vtkPoints.h"

#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <vector>

namespace
{
struct Polygon
{
  std::vector<std::array<double, 3>> Vertices;
  std::array<double, 3> Reflectance{ 0.5, 0.5, 0.5 };
  std::array<double, 3> Emission{ 0.0, 0.0, 0.0 };
};

Polygon Square(double z = 0.0)
{
  Polygon p;
  p.Vertices = { { 0, 0, z }, { 1, 0, z }, { 1, 1, z }, { 0, 1, z } };
  return p;
}

vtkSmartPointer<vtkPolyData> MakeScene(const std::vector<Polygon>& polygons)
{
  auto scene = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkDoubleArray> reflectance;
  reflectance->SetName("Reflectance");
  reflectance->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> emission;
  emission->SetName("Emission");
  emission->SetNumberOfComponents(3);
  for (const Polygon& p : polygons)
  {
    cells->InsertNextCell(static_cast<vtkIdType>(p.Vertices.size()));
    for (const auto& v : p.Vertices)
    {
      cells->InsertCellPoint(points->InsertNextPoint(v.data()));
    }
    reflectance->InsertNextTuple(p.Reflectance.data());
    emission->InsertNextTuple(p.Emission.data());
  }
  scene->SetPoints(points);
  scene->SetPolys(cells);
  scene->GetCellData()->AddArray(reflectance);
  scene->GetCellData()->AddArray(emission);
  return scene;
}

int failures = 0;

// Run the validator on `scene`; expect an error containing every fragment.
void ExpectError(const char* name, vtkPolyData* scene, const std::vector<std::string>& fragments)
{
  vtkNew<vtkPenumbraSceneValidator> validator;
  penumbraErrorCollector errors;
  errors.Observe(validator);
  errors.Observe(validator->GetExecutive());
  validator->SetInputData(scene);
  validator->Update();
  bool ok = validator->GetOutput()->GetNumberOfCells() == 0;
  for (const std::string& f : fragments)
  {
    ok = ok && errors.Contains(f) &&
      std::string(validator->GetLastErrorMessage()).find(f) != std::string::npos;
  }
  if (!ok)
  {
    ++failures;
    std::cerr << "FAILED " << name << ": errors were '" << errors.Messages << "'\n";
  }
}
}

int main(int, char*[])
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  // A valid two-surface scene passes through unchanged.
  {
    Polygon light = Square(1.0);
    std::reverse(light.Vertices.begin(), light.Vertices.end()); // faces down
    light.Emission = { 1, 1, 1 };
    auto scene = MakeScene({ Square(), light });
    vtkNew<vtkPenumbraSceneValidator> validator;
    validator->SetInputData(scene);
    validator->Update();
    if (validator->GetOutput()->GetNumberOfCells() != 2 ||
      std::string(validator->GetLastErrorMessage()) != "")
    {
      ++failures;
      std::cerr << "FAILED valid scene: " << validator->GetLastErrorMessage() << "\n";
    }
  }
  // Empty input: empty output, no error.
  {
    vtkNew<vtkPolyData> empty;
    vtkNew<vtkPenumbraSceneValidator> validator;
    penumbraErrorCollector errors;
    errors.Observe(validator);
    validator->SetInputData(empty);
    validator->Update();
    if (!errors.Messages.empty() || validator->GetOutput()->GetNumberOfCells() != 0)
    {
      ++failures;
      std::cerr << "FAILED empty scene: " << errors.Messages << "\n";
    }
  }
  {
    auto scene = MakeScene({ Square() });
    scene->GetCellData()->RemoveArray("Emission");
    ExpectError("missing Emission", scene, { "missing cell array 'Emission'" });
  }
  {
    auto scene = MakeScene({ Square() });
    scene->GetCellData()->RemoveArray("Reflectance");
    ExpectError("missing Reflectance", scene, { "missing cell array 'Reflectance'" });
  }
  {
    auto scene = MakeScene({ Square() });
    vtkNew<vtkFloatArray> two;
    two->SetName("Reflectance");
    two->SetNumberOfComponents(2);
    two->InsertNextTuple2(0.5, 0.5);
    scene->GetCellData()->RemoveArray("Reflectance");
    scene->GetCellData()->AddArray(two);
    ExpectError("wrong component count", scene, { "'Reflectance' has 2 components" });
  }
  {
    Polygon p = Square();
    p.Vertices[2][2] = 0.1;
    ExpectError("non-planar", MakeScene({ Square(2.0), p }), { "cell 1", "non-planar" });
  }
  {
    Polygon p;
    p.Vertices = { { 0, 0, 0 }, { 1, 0, 0 } };
    ExpectError("two vertices", MakeScene({ p }), { "cell 0", "degenerate", "2 vertices" });
  }
  {
    Polygon p;
    p.Vertices = { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 } };
    ExpectError("collinear", MakeScene({ Square(), p }), { "cell 1", "zero area" });
  }
  {
    Polygon p = Square();
    p.Vertices.insert(p.Vertices.begin() + 1, p.Vertices[0]);
    ExpectError("coincident vertices", MakeScene({ p }), { "cell 0", "coincide" });
  }
  {
    Polygon p; // a pentagon whose third edge crosses its first
    p.Vertices = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 2, 0 }, { 1, -1, 0 }, { 0, 2, 0 } };
    ExpectError("self-intersecting", MakeScene({ Square(3.0), Square(4.0), p }),
      { "cell 2", "self-intersecting" });
  }
  {
    Polygon p = Square();
    p.Vertices[1][0] = nan;
    ExpectError("NaN coordinate", MakeScene({ p }), { "cell 0", "non-finite" });
  }
  {
    Polygon p = Square();
    p.Emission = { 0, inf, 0 };
    ExpectError("infinite emission", MakeScene({ p }), { "cell 0", "Emission green", "finite" });
  }
  {
    Polygon p = Square();
    p.Reflectance = { 0.5, 0.5, nan };
    ExpectError("NaN reflectance", MakeScene({ p }), { "cell 0", "Reflectance blue" });
  }
  {
    Polygon p = Square();
    p.Reflectance = { 1.0, 0.5, 0.5 };
    ExpectError("reflectance 1", MakeScene({ Square(1.0), p }), { "cell 1", "outside [0, 1)" });
  }
  {
    Polygon p = Square();
    p.Reflectance = { 0.5, -0.1, 0.5 };
    ExpectError("negative reflectance", MakeScene({ p }), { "cell 0", "outside [0, 1)" });
  }
  {
    Polygon p = Square();
    p.Emission = { -1, 0, 0 };
    ExpectError("negative emission", MakeScene({ p }), { "cell 0", "negative" });
  }
  {
    auto scene = MakeScene({ Square() });
    vtkNew<vtkCellArray> lines;
    lines->InsertNextCell({ 0, 1 });
    scene->SetLines(lines);
    ExpectError("line cells", scene, { "1 line", "polygons only" });
  }
  if (failures == 0)
  {
    std::cout << "all validation cases behaved" << std::endl;
  }
  return failures == 0 ? 0 : 1;
}
