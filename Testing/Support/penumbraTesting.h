// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraTesting.h
 * @brief Minimal assertion helpers for the core unit tests (pbrt-style
 * EXPECT_NEAR on closed forms). A test is a main() that returns
 * penumbra::testing::Result(): non-zero if any expectation failed.
 */
#ifndef penumbraTesting_h
#define penumbraTesting_h

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>

namespace penumbra
{
namespace testing
{

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
    std::cerr << file << ":" << line << ": FAILED: " << what << std::endl;
  }
}

inline int Result()
{
  if (FailureCount() == 0)
  {
    std::cout << "all expectations passed" << std::endl;
    return 0;
  }
  std::cerr << FailureCount() << " expectation(s) failed" << std::endl;
  return 1;
}

/// Relative difference |a-b| / max(|b|, tiny), used by EXPECT_REL.
inline double RelativeError(double actual, double expected)
{
  const double scale = std::max(std::abs(expected), 1e-300);
  return std::abs(actual - expected) / scale;
}

} // namespace testing
} // namespace penumbra

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
