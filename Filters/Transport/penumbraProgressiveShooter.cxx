// SPDX-License-Identifier: GPL-3.0-or-later
// The shooting loop: the public interface of ProgressiveShooter, the choice
// of shooters, methods and groups, and one shot from its preparation to the
// receivers' updates. The methods themselves are in the files named in
// Documentation/design/transport.md.
#include "penumbraProgressiveShooter.h"
#include "penumbraProgressiveShooterInternals.h"

#include "penumbraEnergyBookkeeping.h"
#include "penumbraEscapeRays.h"
#include "penumbraExactEvaluator.h"
#include "penumbraExactShot.h"
#include "penumbraFastShot.h"
#include "penumbraGroupShot.h"
#include "penumbraLinearSource.h"
#include "penumbraMath.h"
#include "penumbraOccluderSet.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraReceiverClusters.h"
#include "penumbraRecordedTransport.h"
#include "penumbraSampleSet.h"
#include "penumbraShadowRays.h"
#include "penumbraShot.h"
#include "penumbraSweepTail.h"
#include "penumbraTimer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

namespace penumbra
{

namespace
{

/// A shot's conservation scale (Receive) is applied only when it corrects
/// the computed irradiance by at most this fraction: meshes too coarse for
/// the light they receive err by more, and unevenly (up to 16% on 3 x 3
/// grids), where one factor for all receivers would move the error of some
/// onto the others; the imbalance then counts as residual.
constexpr double MaximumConservationCorrection = 0.02;
/// The Uniform receivers' share of a shot is corrected by at most this
/// fraction (see Receive); beyond, the imbalance is residual.
constexpr double MaximumCoarseCorrection = 0.5;

/// A fast shooter is shot alone for its secondary shadows (see
/// penumbraSecondaryShadows.cxx) only while it
/// holds at least this share of the unshot power: the few strong secondary
/// lights of a room (its lit floor and walls), not every surface in turn,
/// which in a scene of many surfaces would cost more single shots than
/// the sweeps through the recorded transport they precede.
constexpr double SingleShotShare = 0.05;
/// ... and at most this many single shots a run: each costs about what the
/// first sweep through the recorded transport does for all shooters.
constexpr int MaximumSingleShots = 8;

/// The strongest shooters whose unshot power SomeSurfaceUnsettled weighs
/// (the rest hold little of it once the global target is reached).
constexpr int SettlingShooters = 16;
/// Surfaces that reflect less than this fraction of the reference power are
/// not held to UnshotFraction of their own light.
constexpr double SettlingFloor = 1e-7;

/// Scratch memory of one chunk of a shot's parallel loop over points.
struct ShotWorkspace
{
  LinearSourceWorkspace Linear;
  FastWorkspace Fast;
};

/// The irradiance at x (normal n, on surface `receiver`) from `shot` by its
/// method; the fast method's rays start at `origin`.
RGB EvaluateShot(const Shot& shot, const ExactEvaluator& exact, const Vec3& x, const Vec3& origin,
  const Vec3& n, int receiver, const std::vector<int>* candidates, const RayCaster* caster,
  ShotWorkspace& ws, long long& rays)
{
  if (shot.Empty || shot.Behind(x))
  {
    return RGB();
  }
  if (shot.Method == ShotMethod::Exact)
  {
    return ExactIrradiance(shot, exact, x, n, receiver, candidates, ws.Linear);
  }
  ws.Fast.Roots.assign(1, 0);
  return NonNegative(
    EvaluateFast(shot, x, origin, n, receiver, ws.Fast.Roots, *caster, ws.Fast, rays));
}

} // namespace

/**
 * Shoot the members' unshot radiance (one surface, or a group) at every
 * receiver that can see them. With `sweep` (ReuseTransport) the members are
 * every surface with triangles and the irradiance comes from the recorded
 * transport (recorded on the first sweep). A fast single shot evaluates
 * the receivers `exactSurfaces` by the exact method instead, for their
 * secondary shadows (SecondaryShadowSurfaces).
 */
ShotRecord ProgressiveShooter::Internals::ShootSurfaces(const std::vector<int>& members,
  ShotMethod method, double reference, bool sweep, const std::vector<int>& exactSurfaces)
{
  const bool group = members.size() > 1;
  const int shooterId = members[0];
  const auto start = std::chrono::steady_clock::now();
  ShotRecord record;
  record.Shooter = shooterId;
  record.Method = method;
  record.GroupSize = static_cast<int>(members.size());
  std::vector<char> isMember(this->Samples.Surfaces.size(), 0);
  bool anyTriangles = false;
  for (int j : members)
  {
    this->Samples.MatchUnshotToPower(j);
    record.Power += this->Samples.UnshotPower[j];
    isMember[j] = 1;
    anyTriangles = anyTriangles || !this->Samples.Surfaces[j].Triangles.empty();
  }
  if (anyTriangles)
  {
    Shot shot;
    if (sweep)
    {
      shot.Empty = false; // the transport's hierarchy holds the members
    }
    else if (group)
    {
      PrepareGroupShot(
        this->Samples, members, this->Settings.OpeningAngle, this->Settings.LeafSize, shot);
    }
    else
    {
      PrepareShot(this->Samples, shooterId, method, this->Settings.OpeningAngle,
        this->Settings.LeafSize, shot);
    }
    const double coarse = this->Settings.CoarseShotFraction * reference;
    if (!sweep && record.Power.Mean() > 0.0 && record.Power.Mean() < coarse)
    {
      shot.OpeningAngle *= std::min(2.0, std::sqrt(coarse / record.Power.Mean()));
    }
    std::size_t items = 0;
    const std::vector<Receiver> receivers = this->FindReceivers(shot, isMember, sweep, items);
    record.Receivers = static_cast<int>(receivers.size());
    record.Samples = static_cast<long long>(items);
    std::vector<RGB> irradiance(items);
    // The receivers evaluated exactly (indices into receivers), and the rest.
    std::vector<int> exact;
    std::vector<Receiver> others;
    const bool secondary = items > 0 && !sweep && !group && method == ShotMethod::Fast;
    for (std::size_t r = 0; r < receivers.size(); ++r)
    {
      const bool chosen = secondary &&
        std::find(exactSurfaces.begin(), exactSurfaces.end(), receivers[r].Id) !=
          exactSurfaces.end();
      if (chosen)
      {
        exact.push_back(static_cast<int>(r));
      }
      else
      {
        others.push_back(receivers[r]);
      }
    }
    if (items > 0 && sweep)
    {
      record.Rays += this->SweepIrradiance(receivers, irradiance);
    }
    else if (items > 0 && method == ShotMethod::Fast && this->Settings.ReceiverClusterSize > 1)
    {
      record.Rays += this->ClusterIrradiance(shot, others, irradiance);
    }
    else if (items > 0)
    {
      record.Rays += this->PointIrradiance(shot, receivers, irradiance);
    }
    if (!exact.empty())
    {
      this->ExactReceivers(receivers, exact, shooterId, irradiance);
      record.ExactReceivers = static_cast<int>(exact.size());
    }
    // Members whose light cannot leave the scene deliver all their power to
    // the receivers and to the backs of surfaces, which absorb it: a closed
    // scene conserves energy exactly (see Receive).
    this->Escape.Ensure(this->Samples, members, this->Caster(), this->Loop);
    bool closed = true;
    for (int j : members)
    {
      if (!this->Samples.Surfaces[j].Triangles.empty())
      {
        closed = closed && this->Escape.IsClosed(j);
        record.Backs +=
          this->Samples.UnshotPower[j] * this->Escape.BackFraction(this->Samples, j);
        record.Escaped +=
          this->Samples.UnshotPower[j] * this->Escape.EscapedFraction(this->Samples, j);
      }
    }
    // The members' unshot radiance has been shot (before the updates: in a
    // group facing several ways members also receive).
    for (int j : members)
    {
      std::fill(
        this->Samples.Surfaces[j].Unshot.begin(), this->Samples.Surfaces[j].Unshot.end(), RGB());
      this->Samples.UnshotPower[j] = RGB();
    }
    this->Receive(receivers, irradiance, closed, record);
  }
  this->Energy.CloseShot(record, this->Samples);
  record.Seconds = Seconds(start);
  return record;
}

/// The receivers that can exchange light with the shot's members, with
/// their shaft candidates (exact single shots), and the work items in all.
std::vector<ProgressiveShooter::Internals::Receiver> ProgressiveShooter::Internals::FindReceivers(
  const Shot& shot, const std::vector<char>& isMember, bool sweep, std::size_t& items) const
{
  std::vector<Receiver> receivers;
  items = 0;
  if (shot.Empty)
  {
    return receivers;
  }
  const bool group = shot.Members.size() > 1;
  std::vector<int> candidates;
  for (int i = 0; i < this->Samples.GetNumberOfSurfaces(); ++i)
  {
    if ((isMember[i] && !shot.Mixed && !sweep) || this->Samples.EvaluationPoints[i].empty())
    {
      continue;
    }
    if (shot.Mixed || sweep)
    {
      // Members light each other; the hierarchy culls what is behind.
      candidates.clear();
    }
    else if (group)
    {
      if (!GroupMayReach(this->SceneCopy, this->Samples, shot, i))
      {
        continue;
      }
      candidates.clear();
    }
    else if (!this->Exact.ShaftCandidates(shot.Shooter, i, candidates))
    {
      continue;
    }
    receivers.push_back({ i, items, candidates });
    items += this->Samples.EvaluationPoints[i].size();
  }
  return receivers;
}

/// Per surface: the first work item of its points, or -1 if it receives nothing.
std::vector<long long> ProgressiveShooter::Internals::FirstItems(
  const std::vector<Receiver>& receivers) const
{
  std::vector<long long> firstItem(this->Samples.Surfaces.size(), -1);
  for (const Receiver& rec : receivers)
  {
    firstItem[rec.Id] = static_cast<long long>(rec.First);
  }
  return firstItem;
}

/// A sweep through the recorded transport (recorded first if need be);
/// returns the rays traced.
long long ProgressiveShooter::Internals::SweepIrradiance(
  const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance)
{
  long long rays = 0;
  if (!this->Recorded)
  {
    this->RecordTransport();
    rays += this->Recorded->Rays;
  }
  this->Recorded->Refresh(this->Samples, this->Loop);
  this->Recorded->Replay(
    this->Samples, this->Clusters, this->FirstItems(receivers), irradiance.data(), this->Loop);
  return rays;
}

/// Start the energy bookkeeping if not started, with the emitters' rays.
void ProgressiveShooter::Internals::EnsureEnergy()
{
  if (this->Energy.IsValid())
  {
    return;
  }
  std::vector<int> emitters;
  for (int i = 0; i < this->Samples.GetNumberOfSurfaces(); ++i)
  {
    if (!this->SceneCopy.Surfaces[i].Emission.IsZero())
    {
      emitters.push_back(i);
    }
  }
  if (!emitters.empty())
  {
    this->Escape.Ensure(this->Samples, emitters, this->Caster(), this->Loop);
  }
  this->Energy.Ensure(this->SceneCopy, this->Samples, this->Escape);
}

/// The transport of every surface to every receiver cluster, recorded once
/// for the current samples and settings.
void ProgressiveShooter::Internals::RecordTransport()
{
  std::unique_ptr<RecordedTransport> transport(new RecordedTransport);
  transport->Prepare(this->Samples, this->Settings.OpeningAngle, this->Settings.LeafSize);
  this->EnsureClusters();
  if (!transport->Sweep.Empty)
  {
    transport->Record(this->Samples, this->Clusters, this->Caster(), this->Loop,
      this->ShotProgress);
  }
  this->Recorded = std::move(transport);
}

/// The fast method by receiver clusters; returns the rays traced.
long long ProgressiveShooter::Internals::ClusterIrradiance(
  const Shot& shot, const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance)
{
  this->EnsureClusters();
  const std::vector<long long> firstItem = this->FirstItems(receivers);
  const RayCaster& caster = this->Caster();
  std::vector<long long> rays(this->Clusters.Clusters.size(), 0);
  RunParallel(this->Loop, this->Clusters.Clusters.size(), [&](std::size_t begin, std::size_t end) {
    FastWorkspace ws;
    for (std::size_t c = begin; c < end; ++c)
    {
      this->Clusters.Evaluate(shot, this->Clusters.Clusters[c], this->Samples, caster, firstItem,
        ws, irradiance.data(), rays[c]);
    }
  });
  long long sum = 0;
  for (const long long count : rays)
  {
    sum += count;
  }
  return sum;
}

/// The shot's method at every receiving point on its own; returns the rays traced.
long long ProgressiveShooter::Internals::PointIrradiance(
  const Shot& shot, const std::vector<Receiver>& receivers, std::vector<RGB>& irradiance)
{
  const bool fast = shot.Method == ShotMethod::Fast;
  const RayCaster* caster = fast ? &this->Caster() : nullptr;
  const std::size_t items = irradiance.size();
  std::vector<long long> rays(fast ? items : 0, 0); // per work item
  // Work item -> receiver by binary search on First.
  RunParallel(this->Loop, items, [&](std::size_t begin, std::size_t end) {
    ShotWorkspace ws;
    std::size_t r = static_cast<std::size_t>(
      std::upper_bound(receivers.begin(), receivers.end(), begin,
        [](std::size_t item, const Receiver& rec) { return item < rec.First; }) -
      receivers.begin() - 1);
    for (std::size_t item = begin; item < end; ++item)
    {
      while (r + 1 < receivers.size() && item >= receivers[r + 1].First)
      {
        ++r;
      }
      const Receiver& rec = receivers[r];
      const std::size_t k = item - rec.First;
      const Vec3& normal = this->Samples.Polygon(rec.Id).Normal;
      long long count = 0;
      irradiance[item] = EvaluateShot(shot, this->Exact, this->Samples.EvaluationPoints[rec.Id][k],
        this->Samples.RayOrigins[rec.Id][k], normal, rec.Id, &rec.Candidates, caster, ws, count);
      if (!rays.empty())
      {
        rays[item] = count;
      }
    }
  });
  long long sum = 0;
  for (const long long count : rays)
  {
    sum += count;
  }
  return sum;
}

/// The shot's method at the evaluation points `points` of one receiver.
std::vector<RGB> ProgressiveShooter::Internals::PilotIrradiance(
  const Shot& shot, const Receiver& receiver, const std::vector<int>& points)
{
  const bool fast = shot.Method == ShotMethod::Fast;
  const RayCaster* caster = fast ? &this->Caster() : nullptr;
  const Vec3& normal = this->Samples.Polygon(receiver.Id).Normal;
  std::vector<RGB> irradiance(points.size());
  RunParallel(this->Loop, points.size(), [&](std::size_t begin, std::size_t end) {
    ShotWorkspace ws;
    long long rays = 0;
    for (std::size_t k = begin; k < end; ++k)
    {
      const int p = points[k];
      irradiance[k] = EvaluateShot(shot, this->Exact, this->Samples.EvaluationPoints[receiver.Id][p],
        this->Samples.RayOrigins[receiver.Id][p], normal, receiver.Id, &receiver.Candidates, caster,
        ws, rays);
    }
  });
  return irradiance;
}

/**
 * The receivers' updates, in a fixed order. With `closed` (no light of the
 * shot can leave the scene) all the shot's power is received or absorbed
 * by the backs of surfaces (record.Backs, estimated by rays). A fast
 * shot's irradiance is then first scaled per channel so that the receivers
 * get Power - Backs: it corrects what the discretisation of the receivers
 * and shooters loses (by at most MaximumConservationCorrection;
 * not when a receiver is on a coarse level's lattice), or, when some
 * receivers are Uniform, whose one value errs more, what those receivers
 * lose or add (by at most MaximumCoarseCorrection; the others are left as
 * computed). An exact shot's irradiance is exact at the samples and its
 * power quadrature exact to third order: it is left as it is, so that a
 * run's result does not depend on the order of its shots.
 * Then Total and Unshot += rho / pi E at every sample, and the shot's
 * incident and absorbed power.
 */
void ProgressiveShooter::Internals::Receive(const std::vector<Receiver>& receivers,
  std::vector<RGB>& irradiance, bool closed, ShotRecord& record)
{
  std::vector<RGB> incident(receivers.size());
  std::vector<RGB> e;
  const auto values = [&](const Receiver& rec) -> std::vector<RGB>& {
    const std::size_t count = this->Samples.EvaluationPoints[rec.Id].size();
    e.assign(irradiance.begin() + static_cast<std::ptrdiff_t>(rec.First),
      irradiance.begin() + static_cast<std::ptrdiff_t>(rec.First + count));
    if (e.size() != this->Samples.Surfaces[rec.Id].Points.size())
    {
      e.assign(this->Samples.Surfaces[rec.Id].Points.size(), e[0]); // a uniform receiver
    }
    return e;
  };
  // A Uniform receiver (one value, at its centroid, for the whole surface)
  // errs by more than the fast method, and by more than
  // MaximumConservationCorrection (a small box face beside the floor that
  // lights it sees much more of it at its base than at its centre): when
  // there are such receivers they take the whole imbalance, the others
  // none. A receiver on a coarse level's lattice (LinearPower) integrates
  // accurate point values with a cruder quadrature: scaling them to its
  // total would spread the quadrature's error over them, so such a shot is
  // not scaled.
  std::vector<char> uniform(receivers.size(), 0);
  bool lattice = false;
  RGB computedResolved, computedUniform;
  for (std::size_t r = 0; r < receivers.size(); ++r)
  {
    const SurfaceSamples& s = this->Samples.Surfaces[receivers[r].Id];
    uniform[r] = s.Uniform ? 1 : 0;
    lattice = lattice || (s.LinearPower && !s.Uniform);
    incident[r] = this->Samples.Integral(receivers[r].Id, values(receivers[r]));
    (uniform[r] ? computedUniform : computedResolved) += incident[r];
  }
  const RGB computed = computedResolved + computedUniform;
  RGB scale(1.0, 1.0, 1.0);
  RGB coarseScale(1.0, 1.0, 1.0);
  for (int c = 0; c < 3; ++c)
  {
    const double delivered = record.Power[c] - record.Backs[c];
    if (!closed || record.Method != ShotMethod::Fast || !(delivered > 0.0))
    {
      continue;
    }
    if (computedUniform[c] > 0.0)
    {
      const double factor = (delivered - computedResolved[c]) / computedUniform[c];
      if (factor >= 1.0 - MaximumCoarseCorrection && factor <= 1.0 + MaximumCoarseCorrection)
      {
        coarseScale[c] = factor;
      }
    }
    else if (!lattice && computed[c] > 0.0 &&
      std::abs(delivered / computed[c] - 1.0) <= MaximumConservationCorrection)
    {
      scale[c] = delivered / computed[c];
    }
  }
  record.Scale = scale;
  record.CoarseScale = coarseScale;
  for (std::size_t r = 0; r < receivers.size(); ++r)
  {
    const Receiver& rec = receivers[r];
    SurfaceSamples& s = this->Samples.Surfaces[rec.Id];
    const RGB rho = this->SceneCopy.Surfaces[rec.Id].Reflectance;
    const RGB applied = uniform[r] ? coarseScale : scale;
    EnergyBookkeeping::AddReceived(record, incident[r] * applied, rho);
    // Black channels record their light in Total and reflect none of it.
    const RGB factor = TrackedReflectance(rho) * applied * (1.0 / Pi);
    const RGB share = ReflectedShare(rho);
    values(rec);
    for (std::size_t k = 0; k < e.size(); ++k)
    {
      const RGB dl = factor * e[k];
      s.Total[k] += dl;
      s.Unshot[k] += share * dl;
    }
    this->Samples.UpdateUnshotPower(rec.Id);
  }
}

/**
 * Whether the unshot power left could still add more than UnshotFraction of
 * its own reflected power to some lit surface (one reflecting at least
 * SettlingFloor of the reference power): the SettlingShooters strongest
 * shooters' unshot power times the disc estimate of their transfer. The
 * global target (UnshotFraction of the emitted power) stops too early for a
 * surface lit only by weak secondary light: the half-lit panel's floor,
 * which gets a small share of the emitted power, came out 0.26% dark.
 */
bool ProgressiveShooter::Internals::SomeSurfaceUnsettled(double reference) const
{
  const double fraction = this->Settings.UnshotFraction;
  const int count = this->Samples.GetNumberOfSurfaces();
  std::vector<std::pair<double, int>> shooters;
  for (int j = 0; j < count; ++j)
  {
    const double power = this->Samples.UnshotPower[j].Mean();
    if (power > 0.0)
    {
      shooters.emplace_back(power, j);
    }
  }
  const std::size_t kept = std::min<std::size_t>(shooters.size(), SettlingShooters);
  std::partial_sort(shooters.begin(), shooters.begin() + static_cast<std::ptrdiff_t>(kept),
    shooters.end(), [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
  for (int i = 0; i < count; ++i)
  {
    const double rho = this->SceneCopy.Surfaces[i].Reflectance.Mean();
    if (rho <= 0.0 || this->Samples.EvaluationPoints[i].empty())
    {
      continue;
    }
    const double reflected =
      this->Samples.ReflectedPower(i, this->SceneCopy.Surfaces[i].Emission).Mean();
    if (!(reflected >= SettlingFloor * reference))
    {
      continue;
    }
    double potential = 0.0;
    for (std::size_t k = 0; k < kept; ++k)
    {
      const int j = shooters[k].second;
      if (j != i)
      {
        potential += shooters[k].first *
          DiscTransferFraction(this->Samples.Polygon(j), this->Samples.Polygon(i));
      }
    }
    if (rho * potential > fraction * reflected)
    {
      return true;
    }
  }
  return false;
}

ProgressiveShooter::ProgressiveShooter(const std::shared_ptr<const PreparedScene>& scene)
  : Internal(new Internals(scene))
{
}

ProgressiveShooter::ProgressiveShooter(const Scene& scene)
  : Internal(new Internals(scene))
{
}

ProgressiveShooter::~ProgressiveShooter() = default;

int ProgressiveShooter::GetNumberOfSurfaces() const
{
  return this->Internal->Samples.GetNumberOfSurfaces();
}

void ProgressiveShooter::SetSettings(const ProgressiveShooterSettings& settings)
{
  Internals& I = *this->Internal;
  settings.Validate();
  const ProgressiveShooterSettings& old = I.Settings;
  const bool moved = settings.BoundaryOffset != old.BoundaryOffset ||
    settings.RayOriginOffset != old.RayOriginOffset;
  I.Clusters.Valid =
    I.Clusters.Valid && !moved && settings.ReceiverClusterSize == old.ReceiverClusterSize;
  if (!I.Clusters.Valid || settings.OpeningAngle != old.OpeningAngle ||
    settings.LeafSize != old.LeafSize)
  {
    I.Recorded.reset();
  }
  I.Settings = settings;
  if (moved)
  {
    for (int i = 0; i < this->GetNumberOfSurfaces(); ++i)
    {
      I.Samples.UpdateEvaluationPoints(i, settings.BoundaryOffset, settings.RayOriginOffset);
    }
  }
}

const ProgressiveShooterSettings& ProgressiveShooter::GetSettings() const
{
  return this->Internal->Settings;
}

void ProgressiveShooter::SetShotProgressCallback(ShotProgressCallback callback)
{
  this->Internal->ShotProgress = std::move(callback);
}

void ProgressiveShooter::SetParallelFor(ParallelFor parallelFor)
{
  this->Internal->Loop = std::move(parallelFor);
}

void ProgressiveShooter::SetSurfaceSamples(int surfaceId, SurfaceSamples samples)
{
  Internals& I = *this->Internal;
  if (surfaceId < 0 || surfaceId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: surface id " + std::to_string(surfaceId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  I.Samples.Validate(surfaceId, samples);
  I.Samples.Set(
    surfaceId, std::move(samples), I.Settings.BoundaryOffset, I.Settings.RayOriginOffset);
  I.Clusters.Valid = false;
  I.Recorded.reset();
  I.Escape.Invalidate();
  I.Energy.Invalidate();
}

const SurfaceSamples& ProgressiveShooter::GetSurfaceSamples(int surfaceId) const
{
  return this->Internal->Samples.Surfaces.at(static_cast<std::size_t>(surfaceId));
}

const std::vector<Vec3>& ProgressiveShooter::GetEvaluationPoints(int surfaceId) const
{
  return this->Internal->Samples.EvaluationPoints.at(static_cast<std::size_t>(surfaceId));
}

RGB ProgressiveShooter::GetUnshotPower(int surfaceId) const
{
  return this->Internal->Samples.UnshotPower.at(static_cast<std::size_t>(surfaceId));
}

RGB ProgressiveShooter::GetTotalUnshotPower() const
{
  return this->Internal->Samples.TotalUnshotPower();
}

int ProgressiveShooter::SelectShooter() const
{
  int best = -1;
  double bestPower = 0.0;
  for (int i = 0; i < this->GetNumberOfSurfaces(); ++i)
  {
    const double power = this->Internal->Samples.UnshotPower[i].Mean();
    if (power > bestPower)
    {
      best = i;
      bestPower = power;
    }
  }
  return best;
}

double ProgressiveShooter::GetReferencePower() const
{
  return this->Internal->Energy.ReferencePower(this->Internal->Samples);
}

ShotMethod ProgressiveShooter::ChooseMethod(double power) const
{
  const double fraction = this->Internal->Settings.ExactPowerFraction;
  if (std::isinf(fraction))
  {
    return ShotMethod::Fast;
  }
  return power >= fraction * this->GetReferencePower() ? ShotMethod::Exact : ShotMethod::Fast;
}

ShootingEnergy ProgressiveShooter::GetEnergy() const
{
  return this->Internal->Energy.Get(this->Internal->SceneCopy, this->Internal->Samples);
}

std::vector<RGB> ProgressiveShooter::ComputeIrradiance(int shooterId, ShotMethod method,
  const Vec3* points, std::size_t count, const Vec3& normal, int receiverId) const
{
  Internals& I = *this->Internal;
  if (shooterId < 0 || shooterId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: shooter id " + std::to_string(shooterId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  if (receiverId < -1 || receiverId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: receiver id " + std::to_string(receiverId) +
      " out of range [-1, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  std::vector<RGB> result(count);
  if (I.Samples.Surfaces[shooterId].Triangles.empty() || receiverId == shooterId)
  {
    return result;
  }
  Shot shot;
  PrepareShot(I.Samples, shooterId, method, I.Settings.OpeningAngle, I.Settings.LeafSize, shot);
  std::vector<int> candidates;
  const std::vector<int>* list = nullptr;
  if (receiverId >= 0 && method == ShotMethod::Exact)
  {
    if (!I.Exact.ShaftCandidates(shooterId, receiverId, candidates))
    {
      return result;
    }
    list = &candidates;
  }
  const RayCaster* caster = method == ShotMethod::Fast ? &I.Caster() : nullptr;
  ShotWorkspace ws;
  long long rays = 0;
  for (std::size_t k = 0; k < count; ++k)
  {
    result[k] =
      EvaluateShot(shot, I.Exact, points[k], points[k], normal, receiverId, list, caster, ws, rays);
  }
  return result;
}

ShotRecord ProgressiveShooter::Shoot(int shooterId, ShotMethod method)
{
  Internals& I = *this->Internal;
  if (shooterId < 0 || shooterId >= this->GetNumberOfSurfaces())
  {
    throw InputError("progressive shooter: shooter id " + std::to_string(shooterId) +
      " out of range [0, " + std::to_string(this->GetNumberOfSurfaces()) + ")");
  }
  I.EnsureEnergy();
  const std::vector<int> exactSurfaces =
    method == ShotMethod::Fast ? I.SecondaryShadowSurfaces(shooterId) : std::vector<int>();
  return I.ShootSurfaces({ shooterId }, method, this->GetReferencePower(), false, exactSurfaces);
}

bool ShootingDone(double unshot, double target, int shots, int maximumShots, StopReason& reason)
{
  if (unshot <= target)
  {
    reason = StopReason::Converged;
    return true;
  }
  if (shots >= maximumShots)
  {
    reason = StopReason::MaximumShots;
    return true;
  }
  return false;
}

double ShootingProgress(
  double unshotAfter, double initial, double target, int shots, int maximumShots)
{
  double progress;
  if (target > 0.0 && initial > target)
  {
    progress = std::log(std::max(unshotAfter, target) / initial) / std::log(target / initial);
  }
  else
  {
    progress = maximumShots > 0 ? static_cast<double>(shots) / maximumShots : 1.0;
  }
  return std::min(1.0, std::max(0.0, progress));
}

ShootingSummary ProgressiveShooter::Run(const ShotCallback& callback)
{
  Internals& I = *this->Internal;
  I.EnsureEnergy();
  const auto start = std::chrono::steady_clock::now();
  ShootingSummary summary;
  const double reference = I.Energy.FixedReferencePower();
  summary.ReferencePower = reference;
  const double initial = this->GetTotalUnshotPower().Mean();
  const double target = I.Settings.UnshotFraction * reference;
  const auto weak = [this](double power) { return this->ChooseMethod(power) == ShotMethod::Fast; };
  SweepTail tail;
  bool swept = false; // once sweeping, the strong secondary lights have been shot
  // On a coarse level the indirect light is blurred to its lattice anyway:
  // no receiver there is evaluated exactly (see SecondaryShadowReceivers).
  bool coarse = false;
  for (const SurfaceSamples& s : I.Samples.Surfaces)
  {
    coarse = coarse || s.LinearPower;
  }
  int singles = 0;
  // Past the global target, on while the light left matters to some surface
  // (within MaximumShots).
  const auto done = [&]() {
    const double unshot = this->GetTotalUnshotPower().Mean();
    return ShootingDone(unshot, target, summary.Shots, I.Settings.MaximumShots, summary.Reason) &&
      !(summary.Reason == StopReason::Converged && unshot > 0.0 &&
        summary.Shots < I.Settings.MaximumShots && I.SomeSurfaceUnsettled(reference));
  };
  while (!done())
  {
    const int j = this->SelectShooter();
    if (j < 0)
    {
      summary.Reason = StopReason::NothingToShoot;
      break;
    }
    const ShotMethod method = this->ChooseMethod(I.Samples.UnshotPower[j].Mean());
    std::vector<int> members(1, j);
    std::vector<int> exactSurfaces;
    bool sweep = method == ShotMethod::Fast && I.Settings.ReuseTransport;
    bool secondary = false;
    if (method == ShotMethod::Fast && !swept && !coarse && singles < MaximumSingleShots &&
      I.Samples.UnshotPower[j].Mean() >= SingleShotShare * this->GetTotalUnshotPower().Mean())
    {
      // A shooter whose light casts shadows that matter is shot on its own
      // first, its shadows evaluated exactly (see SecondaryShadowShare).
      exactSurfaces = I.SecondaryShadowSurfaces(j);
      secondary = !exactSurfaces.empty();
      sweep = sweep && !secondary;
      singles += secondary ? 1 : 0;
    }
    swept = swept || sweep;
    if (sweep)
    {
      // Every surface (j, the strongest, first): its unshot radiance shoots
      // through the transport, zero or not.
      for (int k = 0; k < this->GetNumberOfSurfaces(); ++k)
      {
        if (k != j && !I.Samples.Surfaces[k].Triangles.empty())
        {
          members.push_back(k);
        }
      }
    }
    else if (method == ShotMethod::Fast && I.Settings.GroupWeakShots && !secondary)
    {
      members = SelectGroup(I.Samples, j, I.Settings.GroupAcrossOrientations, weak);
    }
    if (sweep)
    {
      tail.Before(I.Samples);
    }
    ShotRecord record =
      I.ShootSurfaces(members, method, this->GetReferencePower(), sweep, exactSurfaces);
    ++summary.Shots;
    if (method == ShotMethod::Exact)
    {
      ++summary.ExactShots;
      summary.ExactSeconds += record.Seconds;
    }
    else
    {
      ++summary.FastShots;
      summary.FastSeconds += record.Seconds;
    }
    summary.History.push_back(record);
    if (sweep)
    {
      tail.Observe(I.Samples, record);
    }
    else
    {
      tail.Reset();
    }
    const bool sumTail = tail.IsReady() && tail.RemainingError() <= target;
    if (callback &&
      !callback(record,
        ShootingProgress(
          record.UnshotAfter, initial, target, summary.Shots, I.Settings.MaximumShots)))
    {
      summary.Reason = StopReason::Aborted;
      break;
    }
    if (sumTail)
    {
      summary.Reason = StopReason::Converged;
      break;
    }
  }
  // The rest of the sweeps in closed form, when they have settled to one
  // ratio closely enough to leave less error than stopping here does.
  if (summary.Reason == StopReason::Converged && tail.IsReady() &&
    tail.RemainingError() < std::max(target, this->GetTotalUnshotPower().Mean()))
  {
    summary.TailPower = tail.Apply(I.Samples, I.Energy);
  }
  summary.Energy = I.Energy.Current();
  summary.UnshotFraction = reference > 0.0 ? this->GetTotalUnshotPower().Mean() / reference : 0.0;
  summary.Seconds = Seconds(start);
  return summary;
}

} // namespace penumbra
