// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file vtkPenumbraAdaptiveSampling.h
 * @brief Private: the adaptive-sampling path of vtkPenumbraRadianceEvaluator,
 * from the sample triangles to the refined mesh. Not installed, not wrapped.
 */
#ifndef vtkPenumbraAdaptiveSampling_h
#define vtkPenumbraAdaptiveSampling_h

#include "penumbraAdaptiveSampler.h"
#include "penumbraDiscontinuityMesher.h"
#include "penumbraVector.h"

#include <functional>
#include <map>
#include <string>

class vtkPenumbraRadianceEvaluator;
class vtkPolyData;

namespace penumbra
{
/**
 * What the adaptive sampling gave each surface, kept for the next execution
 * (vtkPenumbraRadianceEvaluator::SetReuseUnchangedSurfaces): a surface whose
 * input mesh and budget are the same again, in the same Context (the
 * settings, scene and shooters), takes its Result instead of being sampled.
 */
struct SampledSurfaceCache
{
  struct Entry
  {
    ReceiverMesh Input;
    int Budget = 0;
    AdaptiveSamplingResult Result;
  };
  std::string Context;
  std::map<int, Entry> Surfaces;

  /// The entry of surface `surface`, or null.
  const Entry* Find(int surface) const
  {
    const auto found = this->Surfaces.find(surface);
    return found != this->Surfaces.end() ? &found->second : nullptr;
  }
};

/**
 * Refine each surface's mesh of `samples` (vtkPenumbraDiscontinuityMesher's
 * output) with penumbra::SampleReceiver, the scene's budget shared among the
 * surfaces by area, and write the refined meshes to `output` (see
 * vtkPenumbraRadianceEvaluator's class description). `evaluatePoint` gives
 * the radiance at a point of a surface and must be thread-safe;
 * `sceneDiagonal` scales MaximumSampleSpacing. Reports progress and honours
 * abort through `self`. With `cache`, surfaces found unchanged in it are
 * reused and every surface's result is kept in it (`context` names
 * everything else the results depend on; another context empties it);
 * `reused` receives how many were reused. Returns false after an error
 * (reported on `self`).
 */
bool SampleAdaptively(vtkPenumbraRadianceEvaluator* self, vtkPolyData* samples,
  vtkPolyData* output, double sceneDiagonal,
  const std::function<RGB(int, const Vec3&)>& evaluatePoint,
  SampledSurfaceCache* cache = nullptr, const std::string& context = std::string(),
  int* reused = nullptr);
}

#endif
