// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraLightingDiagnostics.h
 * @brief Warnings for scenes that will come out black or odd: no emitter,
 * emitters facing away from every surface, emitters whose light falls on the
 * backs of surfaces (inside a closed solid, or with flipped normals).
 *
 * These scenes are valid (the solve is right for them) but rarely what the
 * user meant, and a black result says nothing about why.
 */
#ifndef penumbraLightingDiagnostics_h
#define penumbraLightingDiagnostics_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraScene.h"

#include <string>
#include <vector>

namespace penumbra
{

/// Settings of DiagnoseLighting.
struct LightingDiagnosticsOptions
{
  /// Rays traced from each emitter, cosine-distributed from points spread
  /// over it. [256], in [1, 65536]
  int RaysPerEmitter = 256;
  /// Warn when more than this fraction of an emitter's rays meets the backs
  /// of surfaces (the back of a one-sided surface absorbs). [0.5], in [0, 1]
  double BackFraction = 0.5;
};

/**
 * One warning line per finding, empty for a scene whose emitters light the
 * front of something. Emitters are the surfaces with positive Emission. The
 * scene must be valid (ValidateScene). Cells are named by their index, or by
 * cellNumbers[i] when given.
 */
PENUMBRAVISIBILITY_EXPORT std::vector<std::string> DiagnoseLighting(const Scene& scene,
  const LightingDiagnosticsOptions& options = LightingDiagnosticsOptions(),
  const std::vector<std::size_t>* cellNumbers = nullptr);

} // namespace penumbra

#endif
