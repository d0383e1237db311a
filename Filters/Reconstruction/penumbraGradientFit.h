// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraGradientFit.h
 * @brief Workspace of the per-sector least-squares fits of the
 * reconstruction (gradients, and the cubic error model). Private to
 * Penumbra::Reconstruction.
 *
 * The fits are Reconstruction::Internals members (penumbraGradientFit.cxx).
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraGradientFit_h
#define penumbraGradientFit_h

#include <vector>

namespace penumbra
{
namespace detail
{

/// Stencil and factorisation of one sector's fit, reused across sectors.
struct FitWorkspace
{
  int Stamp = 0;
  std::vector<int> PointStamp;
  std::vector<int> TriangleStamp;
  std::vector<int> Points;
  std::vector<int> Triangles;
  // Least squares by modified Gram-Schmidt on the augmented matrix
  // [A | B]: column j of rows `Rows` at Columns[j * Rows].
  std::vector<double> Columns;
  std::vector<double> R; // 9 rows of (9 + NC) entries
  int Rows = 0;
  double Scale = 1.0;
  int Usable = 0; // independent leading columns of A
};

} // namespace detail
} // namespace penumbra

#endif
