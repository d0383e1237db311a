// SPDX-License-Identifier: GPL-3.0-or-later
// The main() of every core test program:
//   TestX            runs every case
//   TestX Case       runs one case (what each CTest entry does)
//   TestX --list     prints the case names
// Exit status 0 when every expectation of the cases run held.
#include "penumbraTesting.h"

#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace
{

// An exception escaping a case fails that case and lets the others run.
void RunCase(const penumbra::testing::Case& c)
{
  try
  {
    c.Function();
  }
  catch (const std::exception& e)
  {
    penumbra::testing::Report(
      false, __FILE__, __LINE__, std::string("uncaught exception: ") + e.what());
  }
  catch (...)
  {
    penumbra::testing::Report(false, __FILE__, __LINE__, "uncaught non-standard exception");
  }
}

} // namespace

int main(int argc, char* argv[])
{
  using penumbra::testing::Case;
  const std::vector<Case>& cases = penumbra::testing::Cases();
  if (argc > 2)
  {
    std::cerr << "usage: " << argv[0] << " [case | --list]" << std::endl;
    return 2;
  }
  if (argc == 2 && std::strcmp(argv[1], "--list") == 0)
  {
    for (const Case& c : cases)
    {
      std::cout << c.Name << std::endl;
    }
    return 0;
  }

  std::vector<const Case*> selected;
  for (const Case& c : cases)
  {
    if (argc == 1 || std::strcmp(argv[1], c.Name) == 0)
    {
      selected.push_back(&c);
    }
  }
  if (selected.empty())
  {
    std::cerr << argv[0] << ": no test case '" << (argc == 2 ? argv[1] : "")
              << "' (--list prints the cases)" << std::endl;
    return 2;
  }

  int failedCases = 0;
  for (const Case* c : selected)
  {
    penumbra::testing::CurrentCase() = c->Name;
    const int before = penumbra::testing::FailureCount();
    RunCase(*c);
    const int failures = penumbra::testing::FailureCount() - before;
    penumbra::testing::CurrentCase() = nullptr;
    if (failures == 0)
    {
      std::cout << c->Name << ": passed" << std::endl;
    }
    else
    {
      ++failedCases;
      std::cerr << c->Name << ": " << failures << " expectation(s) failed" << std::endl;
    }
  }
  if (selected.size() > 1)
  {
    std::cout << selected.size() - failedCases << " of " << selected.size() << " cases passed"
              << std::endl;
  }
  return failedCases == 0 ? 0 : 1;
}
