// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSweepTail.h
 * @brief The light the remaining sweeps would still bring, summed in
 * closed form (private). Successive Jacobi sweeps through the recorded
 * transport apply one linear operator A to the unshot radiance,
 * u_{k+1} = A u_k, and the solution still lacks the rest of the series,
 * sum_{k > m} u_k = A (I - A)^-1 u_m. From the last few unshot vectors the
 * tail finds the combination z = sum_j c_j u_{m-p+j} (j < p) that best
 * solves (I - A) z = u_{m-p} (a minimal residual, GMRES-like step in the
 * Krylov space the sweeps have built: the differences u_k - u_{k+1} are
 * (I - A) u_k), and adds z minus what the sweeps have already added. With
 * one vector this is the geometric tail lambda / (1 - lambda) u_m of a
 * single dominant mode; with three, the next modes are summed too, so
 * fewer sweeps reach the same remaining error
 * (Documentation/design/transport.md, "Convergence").
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
  void Reset();

  /// Before a sweep: the unshot radiance it starts from, if no sweep has
  /// been seen since the last Reset (the first vector of the series).
  void Before(const SampleSet& samples);

  /**
   * After sweep `record`: keep its unshot radiance and fit the tail to the
   * vectors kept. Ready() once two sweeps have been seen and the ratio
   * lambda (per channel, the sweep's unshot power after over before) is
   * in (0, 1).
   */
  void Observe(const SampleSet& samples, const ShotRecord& record);

  bool IsReady() const { return this->Ready; }

  /**
   * The error (mean of RGB, watts) the tail's sum would leave: the
   * residual of the fit (pi times its integral of |r| over the surfaces,
   * the light not accounted for), times 1 / (1 - lambda) for the sweeps
   * that would spread it, per channel.
   */
  double RemainingError() const { return this->Error; }

  /// The ratio of the last two sweeps' unshot power, per channel.
  const RGB& Ratio() const { return this->Lambda; }

  /**
   * Add the tail: Total += the fitted rest of the series at every sample
   * (never negative), Unshot := 0, and book the unshot power as the last
   * sweep split it (absorbed and escaped in its proportions). Returns the
   * power added to the solution's reflected light (RGB watts).
   */
  RGB Apply(SampleSet& samples, EnergyBookkeeping& energy) const;

private:
  /// Fit the coefficients to the last `count` differences (per channel),
  /// by area (`weights`: every sample's lumped weight, in vector order);
  /// returns the remaining error of that fit, HUGE_VAL if it fails.
  double Fit(const std::vector<double>& weights, int count, RGB* coefficients) const;

  /// Unshot radiance of every sample, surfaces one after the other: the
  /// series' vectors seen, oldest first (at most MaximumVectors).
  std::vector<std::vector<RGB>> Vectors;
  RGB LastPower; ///< the unshot power of the last vector
  RGB Lambda;
  RGB AbsorbedShare; ///< the last sweep's absorbed / shot power
  RGB EscapedShare;  ///< the last sweep's escaped / shot power
  /// The fit: coefficients c_j of the vectors Vectors[first + j], per channel.
  std::vector<RGB> Coefficients;
  int First = 0;
  double Error = 0.0;
  bool Ready = false;
};

} // namespace penumbra

#endif
