// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraPreparedScene.h"

#include "penumbraOccluderSet.h"
#include "penumbraRayCaster.h"

namespace penumbra
{

PreparedScene::PreparedScene(const Scene& scene)
  : SceneCopy(scene)
{
  ValidateScene(this->SceneCopy);
  this->Occluders = std::make_shared<const OccluderSet>(this->SceneCopy);
}

PreparedScene::~PreparedScene() = default;

const std::shared_ptr<const RayCaster>& PreparedScene::GetRayCaster() const
{
  std::call_once(this->CasterBuilt,
    [this] { this->Caster = std::make_shared<const RayCaster>(this->SceneCopy); });
  return this->Caster;
}

} // namespace penumbra
