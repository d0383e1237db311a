// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file vtkPenumbraAdaptiveSampling.h
 * @brief Private: the adaptive-sampling path of vtkPenumbraRadianceEvaluator,
 * from the sample triangles to the refined mesh. Not installed, not wrapped.
 */
#ifndef vtkPenumbraAdaptiveSampling_h
#define vtkPenumbraAdaptiveSampling_h

#include "penumbraVector.h"

#include <functional>

class vtkPenumbraRadianceEvaluator;
class vtkPolyData;

namespace penumbra
{
/**
 * Refine each surface's mesh of `samples` (vtkPenumbraDiscontinuityMesher's
 * output) with penumbra::SampleReceiver, the scene's budget shared among the
 * surfaces by area, and write the refined meshes to `output` (see
 * vtkPenumbraRadianceEvaluator's class description). `evaluatePoint` gives
 * the radiance at a point of a surface and must be thread-safe;
 * `sceneDiagonal` scales MaximumSampleSpacing. Reports progress and honours
 * abort through `self`. Returns false after an error (reported on `self`).
 */
bool SampleAdaptively(vtkPenumbraRadianceEvaluator* self, vtkPolyData* samples,
  vtkPolyData* output, double sceneDiagonal,
  const std::function<RGB(int, const Vec3&)>& evaluatePoint);
}

#endif
