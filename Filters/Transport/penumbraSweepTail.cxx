// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraSweepTail.h"

#include "penumbraEnergyBookkeeping.h"
#include "penumbraMath.h"
#include "penumbraSampleSet.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{

namespace
{

/// The unshot vectors kept: the last three differences, enough to sum the
/// first three modes of the transport (the Cornell box's remaining error
/// after three sweeps: about 10 times below the geometric tail's).
constexpr int MaximumVectors = 4;
/// A difference whose part not spanned by the earlier ones is below this
/// fraction of its norm adds nothing the fit can trust: it is dropped.
constexpr double DependentFraction = 1e-6;

/// Every sample's unshot radiance, surfaces one after the other.
std::vector<RGB> Flatten(const SampleSet& samples)
{
  std::vector<RGB> all;
  for (const SurfaceSamples& s : samples.Surfaces)
  {
    all.insert(all.end(), s.Unshot.begin(), s.Unshot.end());
  }
  return all;
}

/// Every sample's lumped weight (a third of its triangles' area), in the order of Flatten.
std::vector<double> FlatWeights(const SampleSet& samples)
{
  std::vector<double> all;
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    const std::vector<double>& w = samples.LumpedWeights[i];
    all.insert(all.end(), w.begin(), w.end());
    all.resize(all.size() + samples.Surfaces[i].Unshot.size() - w.size(), 0.0);
  }
  return all;
}

} // namespace

void SweepTail::Reset()
{
  this->Vectors.clear();
  this->Coefficients.clear();
  this->Ready = false;
}

void SweepTail::Before(const SampleSet& samples)
{
  if (this->Vectors.empty())
  {
    this->Vectors.push_back(Flatten(samples));
    this->LastPower = samples.TotalUnshotPower();
  }
}

double SweepTail::Fit(const std::vector<double>& weights, int count, RGB* coefficients) const
{
  const int n = static_cast<int>(this->Vectors.size());
  const int first = n - 1 - count;
  const std::vector<RGB>& target = this->Vectors[first];
  const std::size_t size = target.size();
  double error = 0.0;
  for (int c = 0; c < 3; ++c)
  {
    // Modified Gram-Schmidt on the differences D_j = u_{first+j} - u_{first+j+1}
    // in the weighted inner product; R is upper triangular.
    std::vector<std::vector<double>> q(count, std::vector<double>(size));
    double r[MaximumVectors][MaximumVectors] = {};
    std::vector<char> kept(count, 0);
    for (int j = 0; j < count; ++j)
    {
      const std::vector<RGB>& a = this->Vectors[first + j];
      const std::vector<RGB>& b = this->Vectors[first + j + 1];
      for (std::size_t k = 0; k < size; ++k)
      {
        q[j][k] = a[k][c] - b[k][c];
      }
      double original = 0.0;
      for (std::size_t k = 0; k < size; ++k)
      {
        original += weights[k] * q[j][k] * q[j][k];
      }
      for (int i = 0; i < j; ++i)
      {
        if (!kept[i])
        {
          continue;
        }
        double dot = 0.0;
        for (std::size_t k = 0; k < size; ++k)
        {
          dot += weights[k] * q[i][k] * q[j][k];
        }
        r[i][j] = dot;
        for (std::size_t k = 0; k < size; ++k)
        {
          q[j][k] -= dot * q[i][k];
        }
      }
      double norm = 0.0;
      for (std::size_t k = 0; k < size; ++k)
      {
        norm += weights[k] * q[j][k] * q[j][k];
      }
      if (norm > DependentFraction * DependentFraction * original && norm > 0.0)
      {
        norm = std::sqrt(norm);
        r[j][j] = norm;
        for (std::size_t k = 0; k < size; ++k)
        {
          q[j][k] /= norm;
        }
        kept[j] = 1;
      }
    }
    // c = R^-1 Q^T target, over the kept columns.
    double projection[MaximumVectors] = {};
    for (int j = 0; j < count; ++j)
    {
      if (kept[j])
      {
        for (std::size_t k = 0; k < size; ++k)
        {
          projection[j] += weights[k] * q[j][k] * target[k][c];
        }
      }
    }
    double solution[MaximumVectors] = {};
    for (int j = count - 1; j >= 0; --j)
    {
      if (!kept[j])
      {
        continue;
      }
      double sum = projection[j];
      for (int i = j + 1; i < count; ++i)
      {
        sum -= r[j][i] * solution[i];
      }
      solution[j] = sum / r[j][j];
    }
    // The residual target - sum_j c_j D_j, by area.
    double residual = 0.0;
    for (std::size_t k = 0; k < size; ++k)
    {
      double value = target[k][c];
      for (int j = 0; j < count; ++j)
      {
        value -= solution[j] *
          (this->Vectors[first + j][k][c] - this->Vectors[first + j + 1][k][c]);
      }
      residual += weights[k] * std::abs(value);
    }
    for (int j = 0; j < count; ++j)
    {
      coefficients[j][c] = solution[j];
      if (!std::isfinite(solution[j]))
      {
        return HUGE_VAL;
      }
    }
    // Each channel is its own series (its own reflectances): its residual
    // spreads over the sweeps its own ratio takes.
    error += Pi * residual / (3.0 * (1.0 - this->Lambda[c]));
  }
  return error;
}

void SweepTail::Observe(const SampleSet& samples, const ShotRecord& record)
{
  const RGB power = samples.TotalUnshotPower();
  this->Ready = false;
  const bool seen = !this->Vectors.empty();
  if (seen)
  {
    const RGB before = this->LastPower;
    bool usable = true;
    for (int c = 0; c < 3; ++c)
    {
      this->Lambda[c] = before[c] > 0.0 ? power[c] / before[c] : 0.0;
      usable = usable && (before[c] <= 0.0 || (this->Lambda[c] > 0.0 && this->Lambda[c] < 1.0));
      this->AbsorbedShare[c] = record.Power[c] > 0.0 ? record.Absorbed[c] / record.Power[c] : 0.0;
      this->EscapedShare[c] = record.Power[c] > 0.0 ? record.Escaped[c] / record.Power[c] : 0.0;
    }
    if (static_cast<int>(this->Vectors.size()) == MaximumVectors)
    {
      this->Vectors.erase(this->Vectors.begin());
    }
    this->Vectors.push_back(Flatten(samples));
    this->LastPower = power;
    double slowest = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      slowest = std::max(slowest, this->Lambda[c]);
    }
    this->Error = HUGE_VAL;
    if (usable && slowest < 1.0)
    {
      // The number of differences whose fit leaves the least error.
      const std::vector<double> weights = FlatWeights(samples);
      const int available = static_cast<int>(this->Vectors.size()) - 1;
      for (int count = 1; count <= available; ++count)
      {
        RGB coefficients[MaximumVectors];
        const double error = this->Fit(weights, count, coefficients);
        if (error < this->Error)
        {
          this->Error = error;
          this->Coefficients.assign(coefficients, coefficients + count);
          this->First = static_cast<int>(this->Vectors.size()) - 1 - count;
        }
      }
    }
    // One sweep says too little: from the light before it (sharp direct
    // light) to the first bounce the distribution changes most, and a fit
    // to that one step can look closer than it is on a weakly lit surface
    // (the half-lit panel's floor came out 0.16% dark).
    this->Ready = this->Error < HUGE_VAL && this->Vectors.size() >= 3;
  }
  else
  {
    this->Vectors.push_back(Flatten(samples));
    this->LastPower = power;
  }
}

RGB SweepTail::Apply(SampleSet& samples, EnergyBookkeeping& energy) const
{
  RGB absorbed, escaped;
  const RGB unshot = samples.TotalUnshotPower();
  for (int c = 0; c < 3; ++c)
  {
    // Every later sweep splits what it shoots as the last one did, so the
    // unshot power ends up absorbed and escaped in those proportions.
    const double spent = this->AbsorbedShare[c] + this->EscapedShare[c];
    absorbed[c] = spent > 0.0 ? unshot[c] * this->AbsorbedShare[c] / spent : unshot[c];
    escaped[c] = unshot[c] - absorbed[c];
  }
  // The rest of the series: sum_j (c_j - 1) u_{First+j} - u_m, where the
  // sweeps have added u_{First+1} .. u_m already and z = sum_j c_j u_{First+j}
  // stands for sum_{k >= First} u_k.
  const int count = static_cast<int>(this->Coefficients.size());
  const std::vector<RGB>& last = this->Vectors.back();
  RGB added;
  std::size_t index = 0;
  for (int i = 0; i < samples.GetNumberOfSurfaces(); ++i)
  {
    SurfaceSamples& s = samples.Surfaces[i];
    const std::vector<double>& weights = samples.LumpedWeights[i];
    for (std::size_t k = 0; k < s.Unshot.size(); ++k, ++index)
    {
      RGB rest = last[index] * -1.0;
      for (int j = 0; j < count; ++j)
      {
        const RGB& v = this->Vectors[this->First + j][index];
        for (int c = 0; c < 3; ++c)
        {
          rest[c] += (this->Coefficients[j][c] - 1.0) * v[c];
        }
      }
      for (int c = 0; c < 3; ++c)
      {
        rest[c] = std::max(0.0, rest[c]); // the true rest is never negative
      }
      s.Total[k] += rest;
      if (k < weights.size())
      {
        added += rest * (Pi * weights[k]);
      }
      s.Unshot[k] = RGB();
    }
    samples.UnshotPower[i] = RGB();
  }
  energy.CloseTail(absorbed, escaped, samples);
  return added;
}

} // namespace penumbra
