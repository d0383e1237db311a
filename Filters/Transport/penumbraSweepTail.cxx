// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSweepTail.h"

#include "penumbraEnergyBookkeeping.h"
#include "penumbraMath.h"
#include "penumbraSampleSet.h"

#include <cmath>

namespace penumbra
{

void SweepTail::Observe(const SampleSet& samples, const ShotRecord& record)
{
  const RGB power = samples.TotalUnshotPower();
  const bool seen = !this->Previous.empty();
  this->Ready = false;
  if (seen)
  {
    bool usable = true;
    for (int c = 0; c < 3; ++c)
    {
      const double before = this->PreviousPower[c];
      this->Lambda[c] = before > 0.0 ? power[c] / before : 0.0;
      usable = usable && (before <= 0.0 || (this->Lambda[c] > 0.0 && this->Lambda[c] < 1.0));
      this->AbsorbedShare[c] = record.Power[c] > 0.0 ? record.Absorbed[c] / record.Power[c] : 0.0;
      this->EscapedShare[c] = record.Power[c] > 0.0 ? record.Escaped[c] / record.Power[c] : 0.0;
    }
    // Mismatch of the last sweep with a pure scaling, by area (the
    // lumped weights: never negative).
    RGB mismatch;
    double slowest = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      slowest = std::max(slowest, this->Lambda[c]);
    }
    for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
    {
      const SurfaceSamples& s = samples.Surfaces[i];
      const std::vector<RGB>& before = this->Previous[i];
      for (std::size_t t = 0; t < s.Triangles.size(); ++t)
      {
        const double third = samples.Areas[i][t] / 3.0 * Pi;
        for (const int k : s.Triangles[t])
        {
          for (int c = 0; c < 3; ++c)
          {
            mismatch[c] += third * std::abs(s.Unshot[k][c] - this->Lambda[c] * before[k][c]);
          }
        }
      }
    }
    this->Error = usable && slowest < 1.0 ? mismatch.Mean() / (1.0 - slowest) : HUGE_VAL;
    this->Ready = usable && slowest < 1.0;
  }
  this->Previous.resize(samples.Surfaces.size());
  for (std::size_t i = 0; i < samples.Surfaces.size(); ++i)
  {
    this->Previous[i] = samples.Surfaces[i].Unshot;
  }
  this->PreviousPower = power;
}

RGB SweepTail::Apply(SampleSet& samples, EnergyBookkeeping& energy) const
{
  RGB factor;
  RGB absorbed, escaped;
  const RGB unshot = samples.TotalUnshotPower();
  for (int c = 0; c < 3; ++c)
  {
    const double lambda = this->Lambda[c];
    factor[c] = lambda > 0.0 && lambda < 1.0 ? lambda / (1.0 - lambda) : 0.0;
    // Every later sweep splits what it shoots as the last one did, so the
    // unshot power ends up absorbed and escaped in those proportions.
    const double spent = this->AbsorbedShare[c] + this->EscapedShare[c];
    absorbed[c] = spent > 0.0 ? unshot[c] * this->AbsorbedShare[c] / spent : unshot[c];
    escaped[c] = unshot[c] - absorbed[c];
  }
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    SurfaceSamples& s = samples.Surfaces[i];
    for (std::size_t k = 0; k < s.Unshot.size(); ++k)
    {
      s.Total[k] += factor * s.Unshot[k];
      s.Unshot[k] = RGB();
    }
    samples.UnshotPower[i] = RGB();
  }
  energy.CloseTail(absorbed, escaped, samples);
  return factor * unshot;
}

} // namespace penumbra
