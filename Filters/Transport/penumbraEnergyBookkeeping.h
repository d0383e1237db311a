// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraEnergyBookkeeping.h
 * @brief How the progressive shooter keeps its ShootingEnergy
 * (penumbraShootingEnergy.h) and the ShotRecord powers (private): the
 * state before the first shot, inferred from the samples, and each shot's
 * incident, absorbed and escaped power (Documentation/design/transport.md,
 * "Energy").
 */
#ifndef penumbraEnergyBookkeeping_h
#define penumbraEnergyBookkeeping_h

#include "penumbraShootingEnergy.h"
#include "penumbraVector.h"

namespace penumbra
{

class EscapeRays;
struct SampleSet;
struct Scene;

/// The energy bookkeeping since the samples were last set.
class EnergyBookkeeping
{
public:
  /// `emitted`: the scene's emitted power (Scene::EmittedPower).
  explicit EnergyBookkeeping(const RGB& emitted)
    : Emitted(emitted)
  {
  }

  /// The samples changed: start again from InitialEnergy at the next Ensure.
  void Invalidate() { this->Valid = false; }
  bool IsValid() const { return this->Valid; }

  /// Start the bookkeeping (and fix the reference power) if not started;
  /// `escape` has the rays of every emitter with samples.
  void Ensure(const Scene& scene, const SampleSet& samples, const EscapeRays& escape);

  /// The bookkeeping so far (valid), or what it would start from.
  ShootingEnergy Get(const Scene& scene, const SampleSet& samples) const;
  const ShootingEnergy& Current() const { return this->Energy; }

  /**
   * The reference power of the stopping rule (mean of RGB): the emitted
   * power, or the initial unshot power if nothing emits (fixed by Ensure;
   * before it, the current unshot power).
   */
  double ReferencePower(const SampleSet& samples) const;
  /// The reference power fixed by the last Ensure that started the bookkeeping.
  double FixedReferencePower() const { return this->Reference; }

  /**
   * The state before the first shot: the direct pass's absorbed part
   * inferred from the reflected radiance (plus what met surfaces' backs),
   * its escaped part from the emitters' rays, the rest of what it consumed
   * as residual. Without `escape` (or for an emitter without samples) what
   * is not inferred counts as escaped.
   */
  ShootingEnergy InitialEnergy(
    const Scene& scene, const SampleSet& samples, const EscapeRays* escape) const;

  /// A receiver of reflectance `rho` got `incident` watts from the shot.
  static void AddReceived(ShotRecord& record, const RGB& incident, const RGB& rho);

  /// Close the shot's record: its residual, the bookkeeping's shot sums,
  /// and the unshot power left (after the receivers' updates).
  void CloseShot(ShotRecord& record, const SampleSet& samples);

  /// The sum of the sweeps' tail (penumbraSweepTail.h) spent the unshot
  /// power as `absorbed` and `escaped`.
  void CloseTail(const RGB& absorbed, const RGB& escaped, const SampleSet& samples);

private:
  RGB Emitted;
  bool Valid = false;
  ShootingEnergy Energy;
  double Reference = 0.0;
};

} // namespace penumbra

#endif
