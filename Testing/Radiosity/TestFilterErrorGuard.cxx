// SPDX-License-Identifier: GPL-3.0-or-later
// vtkPenumbraAlgorithm's guard: an exception thrown by a filter's work, on
// the calling thread or inside a vtkSMPTools worker of the core's parallel
// loop, becomes a filter error with an empty output and Update() returning
// 0; the process survives. ErrorText() recovers the text of VTK's messages.
#include "vtkPenumbraAlgorithm.h"
#include "vtkPenumbraSceneConversion.h" // SMPParallelFor (private header)

#include "penumbraTesting.h"

#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSMPTools.h"

#include <atomic>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>

namespace
{
enum class Failure
{
  None,
  RuntimeErrorOnCaller,
  BadAllocInWorker,
  NonStandardInWorker
};

/// A filter whose work writes a point and then fails as told.
class FailingFilter : public vtkPenumbraAlgorithm
{
public:
  static FailingFilter* New();
  vtkTypeMacro(FailingFilter, vtkPenumbraAlgorithm);
  Failure Mode = Failure::None;
  std::atomic<int> ChunksRun{ 0 };

protected:
  FailingFilter() { this->SetNumberOfInputPorts(0); }
  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkPolyData* output = vtkPolyData::GetData(out);
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(0.0, 0.0, 0.0);
    output->SetPoints(points);
    if (this->Mode == Failure::RuntimeErrorOnCaller)
    {
      throw std::runtime_error("Embree could not build its scene");
    }
    penumbra::SMPParallelFor()(0, 100000, [this](std::size_t first, std::size_t last) {
      ++this->ChunksRun;
      if (first <= 50000 && 50000 < last)
      {
        if (this->Mode == Failure::BadAllocInWorker)
        {
          throw std::bad_alloc();
        }
        if (this->Mode == Failure::NonStandardInWorker)
        {
          throw 42;
        }
      }
    });
    return 1;
  }
};
vtkStandardNewMacro(FailingFilter);

struct ErrorCatcher : vtkCommand
{
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* callData) override
  {
    this->Text = vtkPenumbraAlgorithm::ErrorText(callData ? static_cast<const char*>(callData) : "");
  }
  std::string Text;
};

void Run(Failure mode, const std::string& expectedText)
{
  vtkNew<FailingFilter> filter;
  filter->Mode = mode;
  vtkNew<ErrorCatcher> catcher;
  filter->AddObserver(vtkCommand::ErrorEvent, catcher);
  const int status = filter->GetExecutive()->Update();
  const std::string what = "mode " + std::to_string(static_cast<int>(mode)) + ": ";
  if (expectedText.empty())
  {
    PENUMBRA_EXPECT_MSG(status == 1, what + "a filter that succeeds returns 1");
    PENUMBRA_EXPECT_MSG(catcher->Text.empty(), what + "no error, got '" + catcher->Text + "'");
    PENUMBRA_EXPECT_MSG(filter->GetOutput()->GetNumberOfPoints() == 1, what + "output kept");
    return;
  }
  PENUMBRA_EXPECT_MSG(status == 0, what + "Update returns 0");
  PENUMBRA_EXPECT_MSG(catcher->Text == expectedText,
    what + "error text '" + catcher->Text + "', expected '" + expectedText + "'");
  PENUMBRA_EXPECT_MSG(filter->GetOutput()->GetNumberOfPoints() == 0, what + "output emptied");
}
} // namespace

int TestFilterErrorGuard(int, char*[])
{
  vtkSMPTools::Initialize(2);
  Run(Failure::None, "");
  Run(Failure::RuntimeErrorOnCaller, "Embree could not build its scene");
  Run(Failure::BadAllocInWorker, "out of memory");
  Run(Failure::NonStandardInWorker, "unknown exception");

  // VTK's message format, as the output window and ErrorEvent give it.
  const std::string window = "ERROR: In /src/vtkX.cxx, line 12\nvtkX (0x55d0): missing cell "
                             "array 'Reflectance'\n   (cell 3)\n\nERROR: In /src/vtkExecutive.cxx, "
                             "line 741\nvtkCompositeDataPipeline (0x1): Algorithm vtkX returned "
                             "failure for request: vtkInformation\n\n";
  PENUMBRA_EXPECT_MSG(vtkPenumbraAlgorithm::ErrorText(window) == "missing cell array 'Reflectance' (cell 3)",
    "first error of an output window: '" + vtkPenumbraAlgorithm::ErrorText(window) + "'");
  PENUMBRA_EXPECT_MSG(vtkPenumbraAlgorithm::ErrorText(window.substr(window.find("ERROR: In /src/vtkE"))).empty(),
    "the executive's failure alone is no error text");
  PENUMBRA_EXPECT_MSG(vtkPenumbraAlgorithm::ErrorText("plain text\n") == "plain text", "plain message");
  PENUMBRA_EXPECT_MSG(vtkPenumbraAlgorithm::ErrorText("").empty(), "empty message");

  const int failures = penumbra::testing::FailureCount();
  std::cout << (failures == 0 ? "all expectations passed" : "expectations failed") << std::endl;
  return failures == 0 ? 0 : 1;
}

int main(int argc, char* argv[])
{
  return TestFilterErrorGuard(argc, argv);
}
