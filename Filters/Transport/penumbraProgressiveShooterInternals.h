// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraProgressiveShooterInternals.h
 * @brief The state of a ProgressiveShooter (private), shared by the files
 * that implement it: the loop (penumbraProgressiveShooter.cxx) and the
 * secondary shadows' exact receivers (penumbraSecondaryShadows.cxx).
 */
#ifndef penumbraProgressiveShooterInternals_h
#define penumbraProgressiveShooterInternals_h

#include "penumbraEnergyBookkeeping.h"
#include "penumbraEscapeRays.h"
#include "penumbraExactEvaluator.h"
#include "penumbraPreparedScene.h"
#include "penumbraProgressiveShooter.h"
#include "penumbraRayCaster.h"
#include "penumbraReceiverClusters.h"
#include "penumbraRecordedTransport.h"
#include "penumbraSampleSet.h"
#include "penumbraShot.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{

struct ProgressiveShooter::Internals
{
  explicit Internals(const Scene& scene)
    : Exact(scene)
    , SceneCopy(scene)
    , Samples(Exact.GetOccluders(), scene.Surfaces.size())
    , Energy(scene.EmittedPower())
  {
  }
  /// Shares the prepared scene's occluder set and Embree scene.
  explicit Internals(const std::shared_ptr<const PreparedScene>& scene)
    : Exact(scene)
    , SceneCopy(scene->GetScene())
    , Prepared(scene)
    , Samples(Exact.GetOccluders(), SceneCopy.Surfaces.size())
    , Energy(SceneCopy.EmittedPower())
  {
  }

  /// A receiver of a shot, its shaft candidates, and its first work item
  /// (its evaluation points are items [First, First + their number)).
  struct Receiver
  {
    int Id;
    std::size_t First;
    std::vector<int> Candidates;
  };

  const RayCaster& Caster()
  {
    if (!this->Rays)
    {
      this->Rays = this->Prepared ? this->Prepared->GetRayCaster()
                                  : std::make_shared<const RayCaster>(this->SceneCopy);
    }
    return *this->Rays;
  }
  void EnsureClusters()
  {
    if (!this->Clusters.Valid)
    {
      this->Clusters.Build(this->Samples, this->Settings.ReceiverClusterSize);
    }
  }

  ShotRecord ShootSurfaces(const std::vector<int>& members, ShotMethod method, double reference,
    bool sweep = false, const std::vector<int>& exactSurfaces = std::vector<int>());
  std::vector<Receiver> FindReceivers(const Shot& shot, const std::vector<char>& isMember,
    bool sweep, std::size_t& items) const;
  std::vector<long long> FirstItems(const std::vector<Receiver>& receivers) const;
  long long SweepIrradiance(const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance);
  long long ClusterIrradiance(
    const Shot& shot, const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance);
  long long PointIrradiance(
    const Shot& shot, const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance);
  std::vector<RGB> PilotIrradiance(
    const Shot& shot, const Receiver& receiver, const std::vector<int>& points);
  void Receive(const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance,
    bool closed, ShotRecord& record);
  void RecordTransport();
  void EnsureEnergy();
  std::vector<int> SecondaryShadowSurfaces(int shooter);
  bool FastShadowsSuffice(const Receiver& receiver, const Shot& fast, const Shot& exact);
  void ExactReceivers(const std::vector<Receiver>& receivers, const std::vector<int>& which,
    int shooter, std::vector<RGB>& irradiance);
  bool SomeSurfaceUnsettled(double reference) const;

  ExactEvaluator Exact;
  Scene SceneCopy;
  std::shared_ptr<const PreparedScene> Prepared; // null when built from a Scene
  std::shared_ptr<const RayCaster> Rays;
  ProgressiveShooterSettings Settings;
  ParallelFor Loop;
  ShotProgressCallback ShotProgress;
  SampleSet Samples;
  ReceiverClusters Clusters;
  std::unique_ptr<RecordedTransport> Recorded; ///< null until the first sweep, and when invalidated
  EscapeRays Escape;
  EnergyBookkeeping Energy;
};

} // namespace penumbra

#endif
