// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraVisibilityQueue.h"

#include "penumbraRayCastEvaluator.h"

namespace penumbra
{

void VisibilityQueue::Trace(const RayCaster& caster, const Vec3& origin, int receiver)
{
  this->Occluded.resize(this->Targets.size());
  caster.TraceFrom(origin, this->Targets.data(), this->TargetSurfaces.data(),
    static_cast<int>(this->Targets.size()), this->Occluded.data(), receiver);
}

} // namespace penumbra
