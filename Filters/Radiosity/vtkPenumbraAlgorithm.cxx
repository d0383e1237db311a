// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraAlgorithm.h"


#include "penumbraPreparedScene.h"

#include "vtkDataObject.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"

#include <exception>
#include <new>
#include <sstream>

int vtkPenumbraAlgorithm::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  std::string error;
  this->Warnings.clear();
  try
  {
    return this->Execute(request, inputVector, outputVector);
  }
  catch (const std::bad_alloc&)
  {
    error = "out of memory";
  }
  catch (const std::exception& e)
  {
    error = e.what();
  }
  catch (...)
  {
    error = "unknown exception";
  }
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    if (vtkDataObject* output = vtkDataObject::GetData(outputVector, port))
    {
      output->Initialize();
    }
  }
  vtkErrorMacro(<< (error.empty() ? std::string("unknown error") : error));
  return 0;
}

int vtkPenumbraAlgorithm::GetNumberOfWarnings() const
{
  return static_cast<int>(this->Warnings.size());
}

const char* vtkPenumbraAlgorithm::GetWarning(int i) const
{
  return i >= 0 && i < this->GetNumberOfWarnings() ? this->Warnings[i].c_str() : nullptr;
}

void vtkPenumbraAlgorithm::Warn(const std::string& message)
{
  this->Warnings.push_back(message);
  vtkWarningMacro(<< message);
}

void vtkPenumbraAlgorithm::KeepWarningsOf(vtkAlgorithm* stage, const std::string& prefix)
{
  vtkPenumbraAlgorithm* filter = vtkPenumbraAlgorithm::SafeDownCast(stage);
  if (filter && filter != this)
  {
    for (const std::string& warning : filter->Warnings)
    {
      this->Warnings.push_back(prefix + ": " + warning);
    }
  }
}

std::string vtkPenumbraAlgorithm::ErrorText(const std::string& message)
{
  static const std::string header = "ERROR: In ";
  static const std::string executiveFailure = "returned failure for request";
  std::size_t start = message.find(header);
  if (start == std::string::npos)
  {
    start = 0;
  }
  while (start < message.size())
  {
    const std::size_t next = message.find(header, start + 1);
    std::string block = message.substr(start, next == std::string::npos ? next : next - start);
    // A warning that follows (or, without an error, is) the text is not an error.
    for (const char* warning : { "Generic Warning: In ", "Warning: In " })
    {
      block = block.substr(0, block.find(warning));
    }
    if (block.compare(0, header.size(), header) == 0)
    {
      // Drop "ERROR: In file, line N" and the "vtkClass (0x...): " prefix.
      const std::size_t lineEnd = block.find('\n');
      block = lineEnd == std::string::npos ? std::string() : block.substr(lineEnd + 1);
      const std::size_t prefix = block.find("): ");
      const std::size_t firstLineEnd = block.find('\n');
      if (prefix != std::string::npos && prefix < firstLineEnd)
      {
        block = block.substr(prefix + 3);
      }
    }
    std::istringstream words(block);
    std::string text, word;
    while (words >> word)
    {
      text += (text.empty() ? "" : " ") + word;
    }
    if (!text.empty() && text.find(executiveFailure) == std::string::npos &&
      text.compare(0, 8, "WARNING:") != 0)
    {
      return text;
    }
    if (next == std::string::npos)
    {
      break;
    }
    start = next;
  }
  return std::string();
}

void vtkPenumbraAlgorithm::SetPreparedScene(std::shared_ptr<const penumbra::PreparedScene> scene)
{
  this->Prepared = std::move(scene);
}

std::shared_ptr<const penumbra::PreparedScene> vtkPenumbraAlgorithm::GetPreparedScene() const
{
  return this->Prepared;
}

std::shared_ptr<const penumbra::PreparedScene> vtkPenumbraAlgorithm::Prepare(
  const penumbra::Scene& scene)
{
  if (!this->Prepared || !this->Prepared->GetScene().IsIdentical(scene))
  {
    this->Prepared = std::make_shared<const penumbra::PreparedScene>(scene);
  }
  return this->Prepared;
}

void vtkPenumbraAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PreparedScene: " << (this->Prepared ? "set" : "none") << "\n";
  os << indent << "Warnings: " << this->Warnings.size() << "\n";
  for (const std::string& w : this->Warnings)
  {
    os << indent.GetNextIndent() << w << "\n";
  }
}
