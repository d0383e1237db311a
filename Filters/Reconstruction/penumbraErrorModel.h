// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraErrorModel.h
 * @brief Checks shared by the reconstruction's error estimate and its
 * resampling. Private to Penumbra::Reconstruction.
 *
 * The error model itself (the corner models and the probe calibration) is
 * made of Reconstruction::Internals members (penumbraErrorModel.cxx).
 * Design notes: Documentation/design/reconstruction.md
 */
#ifndef penumbraErrorModel_h
#define penumbraErrorModel_h

#include "penumbraReconstruction.h"

namespace penumbra
{
namespace detail
{

/// Throws InputError for ErrorEstimateOptions out of range.
void CheckErrorOptions(const ErrorEstimateOptions& o);

} // namespace detail
} // namespace penumbra

#endif
