// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraIndirectSampling.h
 * @brief Where the progressive shooter evaluates each surface's shots: its
 * fine samples, or on large inputs its coarse IndirectLevel.
 */
#ifndef penumbraIndirectSampling_h
#define penumbraIndirectSampling_h

#include "penumbraTransportModule.h" // for export macro
#include "penumbraIndirectLevel.h"
#include "penumbraProgressiveShooter.h"
#include "penumbraScene.h"
#include "penumbraSurfaceSamples.h"

#include <cstddef>
#include <memory>
#include <unordered_map>

namespace penumbra
{

class RayCaster;

/**
 * The choice, per surface, between the fine samples and the coarse level
 * for shooting, and the way back to the fine samples afterwards.
 */
class PENUMBRATRANSPORT_EXPORT IndirectSampling
{
public:
  /**
   * Give each surface's samples (`samples`: fine samples by surface id) to
   * `shooter`. With `maximumIndirectSamples` > 0, the lattice spacing is
   * IndirectSpacing's for that budget, and a surface whose IndirectLevel at
   * that spacing has fewer points than its fine samples is shot on the level
   * (its fine samples are kept here), with its interpolation kept from
   * crossing occluders by rays through `caster` (IndirectLevel::
   * SeparateOccluded, in parallel through `loop`); every other surface's
   * samples are moved to the shooter. Throws what IndirectLevel throws.
   */
  void Assign(const Scene& scene, std::unordered_map<int, SurfaceSamples>& samples,
    std::size_t maximumIndirectSamples, const RayCaster& caster, const ParallelFor& loop,
    ProgressiveShooter& shooter);

  /// After shooting: add what the shots brought to each coarse level to its fine samples.
  void Prolong(const ProgressiveShooter& shooter);

  /// The fine samples of `surface` after shooting (and Prolong).
  const SurfaceSamples& GetSamples(int surface, const ProgressiveShooter& shooter) const;

  /// The coarse level's spacing; 0 when no surface is shot on it.
  double GetSpacing() const;

  /// Number of fine points of the coarse surfaces evaluated on their own (see Assign).
  std::size_t GetNumberOfSeparatePoints() const { return this->SeparatePoints; }

private:
  /// A surface shot on the coarse level: the level and its values before shooting.
  struct CoarseSurface
  {
    std::shared_ptr<IndirectLevel> Level;
    SurfaceSamples Before;
  };
  std::unordered_map<int, CoarseSurface> Coarse;
  std::unordered_map<int, SurfaceSamples> Fine;
  double Spacing = 0.0;
  std::size_t SeparatePoints = 0;
};

} // namespace penumbra

#endif
