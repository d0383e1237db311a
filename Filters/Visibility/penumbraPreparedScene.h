// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraPreparedScene.h
 * @brief A scene validated once, with its occluder set (the BVH of every
 * visibility query) and its Embree scene built once, shared by the stages of
 * one solve.
 */
#ifndef penumbraPreparedScene_h
#define penumbraPreparedScene_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraScene.h"

#include <memory>
#include <mutex>

namespace penumbra
{

class OccluderSet;
class RayCaster;

/**
 * A validated scene and the structures every stage builds from it. The
 * stages' core classes (DiscontinuityMesher, ExactEvaluator,
 * ProgressiveShooter) take it instead of a Scene to share them; built from a
 * Scene, each builds its own. Immutable after construction (the ray caster
 * is built on first use, once, from any thread).
 */
class PENUMBRAVISIBILITY_EXPORT PreparedScene
{
public:
  /// Validate `scene` (throws InputError naming the first offending cell),
  /// copy it and build its occluder set.
  explicit PreparedScene(const Scene& scene);
  ~PreparedScene();
  PreparedScene(const PreparedScene&) = delete;
  PreparedScene& operator=(const PreparedScene&) = delete;

  const Scene& GetScene() const { return this->SceneCopy; }
  const std::shared_ptr<const OccluderSet>& GetOccluders() const { return this->Occluders; }
  /// The Embree scene, built on the first call.
  const std::shared_ptr<const RayCaster>& GetRayCaster() const;

private:
  Scene SceneCopy;
  std::shared_ptr<const OccluderSet> Occluders;
  mutable std::once_flag CasterBuilt;
  mutable std::shared_ptr<const RayCaster> Caster;
};

} // namespace penumbra

#endif
