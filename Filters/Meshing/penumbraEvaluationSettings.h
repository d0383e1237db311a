// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraEvaluationSettings.h
 * @brief The settings of the evaluation stage (vtkPenumbraRadianceEvaluator):
 * how radiance is computed at the samples and how receivers are sampled.
 * The member initialisers are the only place their defaults are written.
 */
#ifndef penumbraEvaluationSettings_h
#define penumbraEvaluationSettings_h

#include "penumbraAdaptiveSampler.h"  // for AdaptiveSamplingSettings
#include "penumbraRayCastEvaluator.h" // for RayCastSettings

namespace penumbra
{

/// How contributed radiance is computed at a sample.
enum class EvaluationMethod
{
  Exact = 0,  ///< visible part of the shooter + closed-form integral
  RayCast = 1 ///< adaptive subdivision of the shooter with occlusion rays (paper Eq. 6)
};

/// Settings of the evaluation stage; defaults in brackets.
struct EvaluationSettings
{
  /// [Exact]
  EvaluationMethod Method = EvaluationMethod::Exact;
  /// Used by EvaluationMethod::RayCast.
  RayCastSettings RayCast;
  /// The output radiance includes the receiver's own emission. [true]
  bool IncludeEmission = true;
  /// Refine triangle meshes adaptively (off: evaluate the given points). [true]
  bool AdaptiveSampling = true;
  /// Adaptive sampling of each receiver (SamplingTolerance,
  /// MaximumSamplesPerSurface, MinimumFeatureSize, ...). Its MaximumEdgeLength
  /// is set per scene from MaximumSampleSpacing.
  AdaptiveSamplingSettings Sampling;
  /// Sample budget of the whole scene, shared among the receivers in
  /// proportion to their area, each getting at least an equal share (so
  /// slivers and small parts keep what they need, and the total stays below
  /// twice the budget). [500000], >= 0; 0 = no scene budget. The Cornell box
  /// uses 13% of it; a 20,000-polygon room reaches it.
  long long MaximumSamples = 500000;
  /// Longest sample spacing, relative to the scene's bounding-box diagonal:
  /// room for light that arrives later (interreflections) where the direct
  /// light does not vary. [1/32], in [0, 1]; 0 = no limit.
  double MaximumSampleSpacing = 1.0 / 32.0;
};

} // namespace penumbra

#endif
