// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraEnergyBookkeeping.h"

#include "penumbraEscapeRays.h"
#include "penumbraMath.h"
#include "penumbraSampleSet.h"
#include "penumbraScene.h"

#include <vector>

namespace penumbra
{

namespace
{

RGB Difference(const RGB& a, const RGB& b)
{
  return { a.R - b.R, a.G - b.G, a.B - b.B };
}

} // namespace

void EnergyBookkeeping::Ensure(
  const Scene& scene, const SampleSet& samples, const EscapeRays& escape)
{
  if (!this->Valid)
  {
    this->Energy = this->InitialEnergy(scene, samples, &escape);
    this->Reference =
      this->Emitted.Mean() > 0.0 ? this->Emitted.Mean() : this->Energy.InitialUnshot.Mean();
    this->Valid = true;
  }
}

ShootingEnergy EnergyBookkeeping::Get(const Scene& scene, const SampleSet& samples) const
{
  return this->Valid ? this->Energy : this->InitialEnergy(scene, samples, nullptr);
}

double EnergyBookkeeping::ReferencePower(const SampleSet& samples) const
{
  if (this->Valid)
  {
    return this->Reference;
  }
  const double emitted = this->Emitted.Mean();
  return emitted > 0.0 ? emitted : samples.TotalUnshotPower().Mean();
}

ShootingEnergy EnergyBookkeeping::InitialEnergy(
  const Scene& scene, const SampleSet& samples, const EscapeRays* escape) const
{
  ShootingEnergy e;
  e.Emitted = this->Emitted;
  for (std::size_t i = 0; i < samples.Surfaces.size(); ++i)
  {
    const SurfaceSamples& s = samples.Surfaces[i];
    if (s.Triangles.empty())
    {
      continue;
    }
    e.InitialUnshot += samples.UnshotPower[i];
    // Reflected radiance received so far (direct light): Total - L^e.
    const Surface& surface = scene.Surfaces[i];
    const RGB power = samples.ReflectedPower(static_cast<int>(i), surface.Emission);
    // The light it received: its values carry the tracked reflectance, so
    // black surfaces' absorption is known too.
    const RGB tracked = TrackedReflectance(surface.Reflectance);
    for (int c = 0; c < 3; ++c)
    {
      e.PriorAbsorbed[c] += (1.0 - surface.Reflectance[c]) / tracked[c] * power[c];
    }
  }
  // Where each emitter's light went besides the receivers, by its rays.
  RGB known;
  for (std::size_t i = 0; i < scene.Surfaces.size(); ++i)
  {
    const Surface& surface = scene.Surfaces[i];
    const RGB power = surface.Emission * (Pi * ComputePolygonGeometry(surface.Vertices).Area);
    if (power.IsZero())
    {
      continue;
    }
    if (escape && !samples.Surfaces[i].Triangles.empty())
    {
      e.PriorEscaped += power * escape->UniformEscapedFraction(static_cast<int>(i));
      e.PriorAbsorbed += power * escape->UniformBackFraction(static_cast<int>(i));
      known += power;
    }
  }
  // Emitters whose rays are unknown: what is not accounted for escaped.
  const RGB rest = Difference(Difference(Difference(e.Emitted, e.InitialUnshot), e.PriorAbsorbed),
    e.PriorEscaped);
  if (known.IsZero() || !escape)
  {
    e.PriorEscaped += rest;
  }
  else
  {
    e.PriorResidual = rest;
  }
  e.Unshot = e.InitialUnshot;
  return e;
}

void EnergyBookkeeping::AddReceived(ShotRecord& record, const RGB& incident, const RGB& rho)
{
  record.Incident += incident;
  record.Absorbed += RGB(1.0 - rho.R, 1.0 - rho.G, 1.0 - rho.B) * incident;
}

void EnergyBookkeeping::CloseShot(ShotRecord& record, const SampleSet& samples)
{
  record.Absorbed += record.Backs;
  record.Residual = Difference(
    Difference(Difference(record.Power, record.Incident), record.Backs), record.Escaped);
  this->Energy.ShotAbsorbed += record.Absorbed;
  this->Energy.ShotEscaped += record.Escaped;
  this->Energy.ShotResidual += record.Residual;
  this->Energy.Unshot = samples.TotalUnshotPower();
  record.UnshotAfter = this->Energy.Unshot.Mean();
}

void EnergyBookkeeping::CloseTail(const RGB& absorbed, const RGB& escaped, const SampleSet& samples)
{
  this->Energy.ShotAbsorbed += absorbed;
  this->Energy.ShotEscaped += escaped;
  this->Energy.Unshot = samples.TotalUnshotPower();
}

} // namespace penumbra
