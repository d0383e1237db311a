// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraTesting.h
 * @brief Minimal test cases and assertion helpers for the core unit tests
 * (pbrt-style EXPECT_NEAR on closed forms).
 *
 * PENUMBRA_TEST(Name) { ... } defines and registers a case. The shared main()
 * (penumbraTestMain.cxx) runs the case named by its first argument, or every
 * case, and `--list` prints the names. A case fails when any expectation in it
 * fails; CMake registers one CTest entry per case, read from the source.
 */
#ifndef penumbraTesting_h
#define penumbraTesting_h

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace penumbra
{
namespace testing
{

/// A registered test case. A plain function pointer: the registry is built
/// during static initialisation, before main().
struct Case
{
  const char* Name;
  void (*Function)();
};

/// The cases of this program, in definition order.
inline std::vector<Case>& Cases()
{
  static std::vector<Case> cases;
  return cases;
}

inline bool Register(const char* name, void (*function)())
{
  Cases().push_back({ name, function });
  return true;
}

/// The case being run, printed with each failure (null outside a case).
inline const char*& CurrentCase()
{
  static const char* name = nullptr;
  return name;
}

inline int& FailureCount()
{
  static int count = 0;
  return count;
}

inline void Report(bool ok, const char* file, int line, const std::string& what)
{
  if (!ok)
  {
    ++FailureCount();
    if (CurrentCase())
    {
      std::cerr << "[" << CurrentCase() << "] ";
    }
    std::cerr << file << ":" << line << ": FAILED: " << what << std::endl;
  }
}

/// Relative difference |a-b| / max(|b|, tiny), used by EXPECT_REL.
inline double RelativeError(double actual, double expected)
{
  const double scale = std::max(std::abs(expected), 1e-300);
  return std::abs(actual - expected) / scale;
}

} // namespace testing
} // namespace penumbra

/// Define and register the test case `name` (a function of no arguments).
#define PENUMBRA_TEST(name)                                                                        \
  static void name();                                                                              \
  [[maybe_unused]] static const bool penumbraRegistered##name##_ =                                 \
    penumbra::testing::Register(#name, &name);                                                     \
  static void name()

/// An expectation with its own message (e.g. naming the values compared).
#define PENUMBRA_EXPECT_MSG(cond, message)                                                         \
  penumbra::testing::Report(static_cast<bool>(cond), __FILE__, __LINE__, (message))

#define PENUMBRA_EXPECT(cond)                                                                      \
  penumbra::testing::Report(static_cast<bool>(cond), __FILE__, __LINE__, #cond)

#define PENUMBRA_EXPECT_NEAR(actual, expected, tolerance)                                          \
  do                                                                                               \
  {                                                                                                \
    const double penumbraActual_ = (actual);                                                       \
    const double penumbraExpected_ = (expected);                                                   \
    const bool penumbraOk_ = std::abs(penumbraActual_ - penumbraExpected_) <= (tolerance);         \
    penumbra::testing::Report(penumbraOk_, __FILE__, __LINE__,                                     \
      std::string(#actual " = ") + std::to_string(penumbraActual_) + ", expected " +               \
        std::to_string(penumbraExpected_) + " within " + std::to_string(tolerance));              \
  } while (false)

#define PENUMBRA_EXPECT_REL(actual, expected, relTolerance)                                        \
  do                                                                                               \
  {                                                                                                \
    const double penumbraActual_ = (actual);                                                       \
    const double penumbraExpected_ = (expected);                                                   \
    const double penumbraRel_ =                                                                    \
      penumbra::testing::RelativeError(penumbraActual_, penumbraExpected_);                        \
    char penumbraBuffer_[256];                                                                     \
    std::snprintf(penumbraBuffer_, sizeof(penumbraBuffer_),                                        \
      " = %.17g, expected %.17g, relative error %.3g > %.3g", penumbraActual_,                     \
      penumbraExpected_, penumbraRel_, static_cast<double>(relTolerance));                         \
    penumbra::testing::Report(                                                                     \
      penumbraRel_ <= (relTolerance), __FILE__, __LINE__, std::string(#actual) + penumbraBuffer_); \
  } while (false)

/// Expect that `statement` throws ExceptionType whose what() contains `fragment`.
#define PENUMBRA_EXPECT_THROW(statement, ExceptionType, fragment)                                  \
  do                                                                                               \
  {                                                                                                \
    bool penumbraThrown_ = false;                                                                  \
    std::string penumbraMessage_;                                                                  \
    try                                                                                            \
    {                                                                                              \
      statement;                                                                                   \
    }                                                                                              \
    catch (const ExceptionType& e)                                                                 \
    {                                                                                              \
      penumbraThrown_ = true;                                                                      \
      penumbraMessage_ = e.what();                                                                 \
    }                                                                                              \
    penumbra::testing::Report(penumbraThrown_, __FILE__, __LINE__,                                 \
      std::string(#statement " did not throw " #ExceptionType));                                   \
    penumbra::testing::Report(!penumbraThrown_ ||                                                  \
        penumbraMessage_.find(fragment) != std::string::npos,                                      \
      __FILE__, __LINE__,                                                                          \
      std::string("message '") + penumbraMessage_ + "' lacks '" + (fragment) + "'");               \
  } while (false)

#endif
