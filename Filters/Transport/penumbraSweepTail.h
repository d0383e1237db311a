// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSweepTail.h
 * @brief The light the remaining sweeps would still bring, summed in
 * closed form (private): once successive Jacobi sweeps scale the unshot
 * radiance by one ratio lambda everywhere (the slowest mode of the
 * transport dominates), every later sweep would add lambda times the
 * previous one, so the rest of the series is lambda / (1 - lambda) times
 * the unshot radiance (Documentation/design/transport.md, "Convergence").
 */
#ifndef penumbraSweepTail_h
#define penumbraSweepTail_h

#include "penumbraShootingEnergy.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

class EnergyBookkeeping;
struct SampleSet;

/// Watches the sweeps of a run and sums their tail when it is predictable.
class SweepTail
{
public:
  /// A shot that was not a sweep: forget what was seen.
  void Reset() { this->Previous.clear(); this->Ready = false; }

  /**
   * After sweep `record`: compare the unshot radiance with that after the
   * previous sweep. Ready() once two successive sweeps have been seen and
   * the ratio lambda (per channel, the sweep's unshot power after over
   * before) is in (0, 1).
   */
  void Observe(const SampleSet& samples, const ShotRecord& record);

  bool IsReady() const { return this->Ready; }

  /**
   * The error (mean of RGB, watts) the tail's sum would leave: the part of
   * the unshot radiance that the last sweep did not scale by lambda
   * (sum over samples of |u - lambda u_previous|, by area), times
   * 1 / (1 - lambda) for the sweeps it would take.
   */
  double RemainingError() const { return this->Error; }

  /// The ratio of the last two sweeps, per channel.
  const RGB& Ratio() const { return this->Lambda; }

  /**
   * Add the tail: Total += lambda / (1 - lambda) Unshot at every sample,
   * Unshot := 0, and book the unshot power as the last sweep split it
   * (absorbed and escaped in its proportions). Returns the power added to
   * the solution's reflected light (RGB watts: lambda / (1 - lambda) times
   * the unshot power).
   */
  RGB Apply(SampleSet& samples, EnergyBookkeeping& energy) const;

private:
  std::vector<std::vector<RGB>> Previous; ///< unshot radiance after the previous sweep
  RGB PreviousPower;
  RGB Lambda;
  RGB AbsorbedShare; ///< the last sweep's absorbed / shot power
  RGB EscapedShare;  ///< the last sweep's escaped / shot power
  double Error = 0.0;
  bool Ready = false;
};

} // namespace penumbra

#endif
