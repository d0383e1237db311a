// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraTransportSettings.h
 * @brief The settings of the transport stage (vtkPenumbraProgressiveShooter):
 * the progressive shooting loop and the coarse level of large scenes. The
 * member initialisers are the only place their defaults are written.
 */
#ifndef penumbraTransportSettings_h
#define penumbraTransportSettings_h

#include "penumbraProgressiveShooter.h" // for ProgressiveShooterSettings

namespace penumbra
{

/// Settings of the transport stage; defaults in brackets.
struct TransportSettings
{
  /// The shooting loop.
  ProgressiveShooterSettings Shooting;
  /// Largest number of points the interreflections are shot onto: above it,
  /// shots run on a coarse lattice over each surface (IndirectLevel) whose
  /// indirect light is interpolated back onto every sample, never across an
  /// occluder (IndirectLevel::SeparateOccluded); the direct light
  /// keeps every sample. [100000], >= 0; 0 = always every sample.
  long long MaximumIndirectSamples = 100000;
  /// Secondary shooters as the paper means them: a surface (not an
  /// emitter) whose direct light reflects at least this fraction of the
  /// emitted power also shoots for the discontinuity mesher, so that the
  /// receivers' sample meshes follow the shadows it casts; the composed
  /// solver then meshes and evaluates the direct light a second time. At
  /// most the 4 strongest such surfaces. [0.1], in [0, 1]; 1 = off.
  double SecondaryShooterFraction = 0.1;
};

} // namespace penumbra

#endif
