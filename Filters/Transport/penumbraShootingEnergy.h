// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShootingEnergy.h
 * @brief What a shot did and the energy bookkeeping of a run of shots:
 * Emitted = Absorbed + Unshot + Escaped + Residual per channel, by construction
 * (Documentation/design/transport.md, "Energy"). Shared by the progressive
 * shooter and the standard radiosity baseline; penumbraEnergyBookkeeping.h
 * computes them.
 */
#ifndef penumbraShootingEnergy_h
#define penumbraShootingEnergy_h

#include "penumbraVector.h"

namespace penumbra
{

/// How a shot's irradiance was computed.
enum class ShotMethod
{
  Exact = 0, ///< exact visibility + closed-form linear-source integrals
  Fast = 1   ///< hierarchy of the shooter + one occlusion ray per node used
};

/// What one shot did. Powers are RGB, in watts (scene units squared times
/// W m^-2).
struct ShotRecord
{
  int Shooter = -1;                     ///< surface id of the shooter
  ShotMethod Method = ShotMethod::Exact; ///< how E was computed
  RGB Power;          ///< shot power: pi * integral of the shooter's unshot radiance
  RGB Incident;       ///< power incident on the receivers' sample meshes
  RGB Absorbed;       ///< absorbed: sum of (1 - rho_i) * incident_i, plus Backs
  /// Power that met the backs of surfaces (black, so absorbed), estimated by
  /// rays (penumbraEscapeRays.h).
  RGB Backs;
  /// What left the scene, estimated by rays: 0 when none of the shooters'
  /// escape rays escapes.
  RGB Escaped;
  /// Power - Incident - Backs - Escaped: what the receivers' quadrature of
  /// the computed irradiance missed (positive) or found in excess
  /// (negative), the discretisation's imbalance, plus in an open scene the
  /// noise of the rays' estimates.
  RGB Residual;
  /// Factor applied to the computed irradiance so that the receivers got
  /// Power - Backs, when none of the shooters' light can leave the scene
  /// and the correction is small (1 otherwise).
  RGB Scale = RGB(1.0, 1.0, 1.0);
  /// Factor applied instead to the Uniform receivers (one value per
  /// surface), which then take the whole imbalance (1 when there are none).
  RGB CoarseScale = RGB(1.0, 1.0, 1.0);
  int GroupSize = 1;  ///< surfaces shot together (GroupWeakShots); Shooter is the strongest
  int Receivers = 0;  ///< receivers that exchange light with the shooter
  /// Of which evaluated exactly for their secondary shadows (a fast shot).
  int ExactReceivers = 0;
  long long Samples = 0;      ///< samples evaluated
  long long Rays = 0;         ///< occlusion rays (fast method)
  double Seconds = 0.0;       ///< wall-clock time of the shot
  double UnshotAfter = 0.0;   ///< total unshot power (mean of RGB) after the shot
};

/**
 * Energy bookkeeping of a run, per channel, in watts. The identity
 * Emitted = Absorbed() + Unshot + Escaped() + Residual() holds up to
 * rounding by construction (see Documentation/design/transport.md,
 * "Energy"). Escaped is light that left the scene; Residual is the
 * discretisation's imbalance, where the samples' quadrature finds less (or
 * more) light than was sent.
 */
struct ShootingEnergy
{
  RGB Emitted;        ///< pi * sum of L^e * area over ALL surfaces (Scene::EmittedPower)
  RGB InitialUnshot;  ///< unshot power of the samples before the first shot
  RGB PriorAbsorbed;  ///< absorbed by the direct pass, inferred from the reflected radiance
  RGB PriorEscaped;   ///< left the scene in the direct pass
  /// Emitted - InitialUnshot - PriorAbsorbed - PriorEscaped
  RGB PriorResidual;
  RGB ShotAbsorbed;   ///< absorbed during the shots
  RGB ShotEscaped;    ///< escaped during the shots
  RGB ShotResidual;   ///< the shots' Residual (ShotRecord)
  RGB Unshot;         ///< unshot power left

  /// PriorAbsorbed + ShotAbsorbed.
  RGB Absorbed() const { return this->PriorAbsorbed + this->ShotAbsorbed; }
  /// PriorEscaped + ShotEscaped.
  RGB Escaped() const { return this->PriorEscaped + this->ShotEscaped; }
  /// PriorResidual + ShotResidual.
  RGB Residual() const { return this->PriorResidual + this->ShotResidual; }
};

} // namespace penumbra

#endif
