// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraEscapeRays.h
 * @brief Where a shooter's light goes besides its receivers (private): a
 * fixed set of cosine-distributed rays from each surface, counting those
 * that meet no surface or a surface without samples (they escape) and
 * keeping those that meet a surface's back (absorbed there: the back of a
 * one-sided surface is black). A surface none of whose rays escapes is
 * closed in: all it shoots reaches a receiver or a back
 * (Documentation/design/transport.md, "Energy").
 */
#ifndef penumbraEscapeRays_h
#define penumbraEscapeRays_h

#include "penumbraParallel.h"
#include "penumbraVector.h"

#include <vector>

namespace penumbra
{

class RayCaster;
struct SampleSet;

/// The escaping rays of every surface, traced once for the current samples.
class EscapeRays
{
public:
  /// Forget every surface's rays (the samples changed).
  void Invalidate() { this->Surfaces.clear(); }

  /**
   * Trace the rays of the surfaces in `surfaces` that have none yet: each
   * gets RaysPerSurface(total surfaces) rays from points spread by area over
   * its triangles (a Halton sequence), cosine-distributed about its normal.
   */
  void Ensure(const SampleSet& samples, const std::vector<int>& surfaces, const RayCaster& caster,
    const ParallelFor& loop);

  /// Whether none of the rays of surface `surface` escapes (Ensure first).
  bool IsClosed(int surface) const;

  /// The rays of surface `surface` that escape (Ensure first).
  int GetEscapingRays(int surface) const;

  /**
   * The fraction of the unshot power of surface `surface` (per channel)
   * that meets the backs of surfaces: its unshot radiance at the origins of
   * the rays that do, over its mean, over the rays traced. 0 when no ray
   * does. Ensure first.
   */
  RGB BackFraction(const SampleSet& samples, int surface) const;

  /// The same for the rays that escape (0 for a closed surface).
  RGB EscapedFraction(const SampleSet& samples, int surface) const;

  /// Of a uniformly radiating surface `surface` (an emitter's emission):
  /// the fraction of its rays that escape, and that meet backs.
  double UniformEscapedFraction(int surface) const;
  double UniformBackFraction(int surface) const;

  /// Rays traced per surface for a scene of `surfaces` surfaces: 16384,
  /// fewer (at least 256) when that would exceed 2^24 rays in all.
  static int RaysPerSurface(int surfaces);

private:
  /// Where a kept ray starts.
  struct Origin
  {
    int Triangle;
    float A, B; ///< barycentric coordinates of corners 1 and 2
  };
  struct SurfaceRays
  {
    bool Traced = false;
    int Rays = 0;
    std::vector<Origin> Escaping;
    std::vector<Origin> Backs;
  };
  /// The unshot power fraction carried by the rays from `origins`.
  RGB Fraction(const SampleSet& samples, int surface, const std::vector<Origin>& origins) const;
  std::vector<SurfaceRays> Surfaces;
};

} // namespace penumbra

#endif
