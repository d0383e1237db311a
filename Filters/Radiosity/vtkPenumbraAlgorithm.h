// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraAlgorithm
 * @brief   Base of Penumbra's filters: errors never cross RequestData.
 *
 * Every Penumbra filter derives from this class and implements Execute()
 * instead of RequestData(). RequestData() runs Execute() and turns any
 * exception it lets through, thrown on the calling thread or inside a
 * vtkSMPTools worker run through the core's ParallelFor, into vtkErrorMacro
 * and a return value of 0 with an empty output: bad input (the core's
 * InputError, whose text names the offending cell or setting), failures of
 * Embree or CGAL (std::runtime_error), std::bad_alloc ("out of memory") and
 * anything else ("unknown exception").
 *
 * Warnings (input that was repaired, scenes that will come out black) are
 * kept one line each for GetWarning() as well as reported with
 * vtkWarningMacro, so that programs read them without parsing VTK's format;
 * they are cleared when the filter runs again.
 *
 * ErrorText() is the one parser of VTK's error format in Penumbra: the
 * composed solver uses it to relay a stage's message and the Python package
 * to turn errors into exceptions.
 *
 * @sa vtkPenumbraSolver
 */
#ifndef vtkPenumbraAlgorithm_h
#define vtkPenumbraAlgorithm_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::shared_ptr
#include <string> // for std::string
#include <vector> // for std::vector

namespace penumbra
{
class PreparedScene;
struct Scene;
}

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraAlgorithm : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkPenumbraAlgorithm, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The text of the first error in `message`, without VTK's header: given
   * one message or the whole output of a vtkStringOutputWindow ("ERROR: In
   * file, line N\nvtkClass (0x...): text" blocks), returns the first
   * error's text with runs of white space made single, skipping the
   * executive's "returned failure for request" that follows a filter's own
   * error and warnings ("Warning: In ..." blocks of vtkWarningMacro); a
   * message without the header is returned as it is. Empty when there is none.
   */
  static std::string ErrorText(const std::string& message);

  /**
   * The warnings of the last run, one line each, in order.
   */
  int GetNumberOfWarnings() const;
  const char* GetWarning(int i) const;

#ifndef __VTK_WRAP__
  /**
   * C++ only: keep `message` for GetWarning() and report it with
   * vtkWarningMacro. For the filter's own code and the helpers it runs.
   */
  void Warn(const std::string& message);

  /**
   * C++ only: keep the warnings of `stage` (a filter this one ran, already
   * reported by it) for GetWarning(), each as "<prefix>: <warning>". Does
   * nothing for a filter that is not a vtkPenumbraAlgorithm.
   */
  void KeepWarningsOf(vtkAlgorithm* stage, const std::string& prefix);
#endif

#ifndef __VTK_WRAP__
  /**
   * C++ only: a scene prepared (validated, with its occluder set and Embree
   * scene) by another stage of the same solve; vtkPenumbraSolver hands the
   * mesher's to the evaluator and the shooter, so that a solve validates and
   * prepares its scene once. A stage uses it only when its own scene is
   * identical to the prepared one, and prepares its own otherwise. After a
   * run, GetPreparedScene() is the scene the stage used (null for stages
   * that prepare none).
   */
  void SetPreparedScene(std::shared_ptr<const penumbra::PreparedScene> scene);
  std::shared_ptr<const penumbra::PreparedScene> GetPreparedScene() const;
#endif

protected:
  vtkPenumbraAlgorithm() = default;
  ~vtkPenumbraAlgorithm() override = default;

  /// Runs Execute(); see the class documentation.
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) final;

  /// The filter's work, with RequestData's arguments and return value.
  virtual int Execute(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) = 0;

#ifndef __VTK_WRAP__
  /// The prepared scene for `scene`: the one set if identical, else a new
  /// one (which validates `scene`, throwing penumbra::InputError).
  std::shared_ptr<const penumbra::PreparedScene> Prepare(const penumbra::Scene& scene);
#endif

private:
#ifndef __VTK_WRAP__
  std::shared_ptr<const penumbra::PreparedScene> Prepared;
#endif
  std::vector<std::string> Warnings;
  vtkPenumbraAlgorithm(const vtkPenumbraAlgorithm&) = delete;
  void operator=(const vtkPenumbraAlgorithm&) = delete;
};

#endif
