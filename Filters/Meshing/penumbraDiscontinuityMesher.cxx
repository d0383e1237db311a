// SPDX-License-Identifier: GPL-3.0-or-later
// The discontinuity mesher's driver: scene preparation, validation of the
// settings, shooter selection, and per receiver the boundaries (outline,
// contacts, shadows of each shooter, jump threshold), their merging and the
// triangulation (in penumbraReceiverTriangulation.cxx, the CGAL unit).
#include "penumbraDiscontinuityMesher.h"

#include "penumbraConstraintMerging.h"
#include "penumbraContacts.h"
#include "penumbraExactEvaluator.h"
#include "penumbraCovers.h"
#include "penumbraJumpThreshold.h"
#include "penumbraMath.h"
#include "penumbraMeshingTolerances.h"
#include "penumbraOccluderSet.h"
#include "penumbraReceiverFrame.h"
#include "penumbraReceiverTriangulation.h"
#include "penumbraSceneTopology.h"
#include "penumbraShortEdges.h"
#include "penumbraTimer.h"
#include "penumbraVisualEvents.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace penumbra
{

namespace
{

constexpr double kMaxMinimumAngle = 20.6;

} // namespace

//------------------------------------------------------------------------------
DiscontinuityMeshStatistics& DiscontinuityMeshStatistics::operator+=(
  const DiscontinuityMeshStatistics& o)
{
  this->Receivers += o.Receivers;
  this->Pairs += o.Pairs;
  this->CandidateOccluders += o.CandidateOccluders;
  this->Wedges += o.Wedges;
  this->SegmentsGenerated += o.SegmentsGenerated;
  this->SegmentsKept += o.SegmentsKept;
  this->ContactSegments += o.ContactSegments;
  this->CoverSegments += o.CoverSegments;
  this->Constraints += o.Constraints;
  this->ConstraintFailures += o.ConstraintFailures;
  this->Points += o.Points;
  this->Triangles += o.Triangles;
  this->DroppedDegenerate += o.DroppedDegenerate;
  this->MergedTriangles += o.MergedTriangles;
  this->RemovedArea += o.RemovedArea;
  this->BoundarySeconds += o.BoundarySeconds;
  this->TriangulationSeconds += o.TriangulationSeconds;
  return *this;
}

struct DiscontinuityMesher::Internals
{
  std::shared_ptr<const PreparedScene> Prepared; // shared with the solve's other stages
  const Scene& ValidScene;
  const OccluderSet& Occluders;
  const ExactEvaluator Evaluator; ///< visible light, for the jump threshold's reference
  detail::SceneTopology Topology;
  /// (surface, emitted power) of every surface with positive power, and their
  /// total: computed once, as every receiver selects its shooters.
  std::vector<std::pair<int, double>> EmitterPower;
  double TotalPower = 0.0;

  explicit Internals(std::shared_ptr<const PreparedScene> scene);

  void Check(int receiverId, const DiscontinuityMeshSettings& settings) const;
  std::vector<int> Select(const DiscontinuityMeshSettings& settings) const;
  std::vector<detail::Segment2> Boundaries(int receiverId,
    const DiscontinuityMeshSettings& settings, const detail::ReceiverFrame& frame,
    DiscontinuityMeshStatistics& stats) const;
  std::vector<detail::Constraint2D> Constraints(int receiverId,
    const DiscontinuityMeshSettings& settings, const detail::ReceiverFrame& frame,
    DiscontinuityMeshStatistics& stats) const;
};

DiscontinuityMesher::Internals::Internals(std::shared_ptr<const PreparedScene> prepared)
  : Prepared(std::move(prepared))
  , ValidScene(Prepared->GetScene())
  , Occluders(*Prepared->GetOccluders())
  , Evaluator(Prepared)
{
  const Scene& scene = this->ValidScene;
  this->Topology.Build(scene);
  const std::size_t count = scene.Surfaces.size();
  for (std::size_t k = 0; k < count; ++k)
  {
    const double power =
      scene.Surfaces[k].Emission.Mean() * Pi * this->Topology.Polygons[k].Area;
    this->TotalPower += power;
    if (power > 0.0)
    {
      this->EmitterPower.emplace_back(static_cast<int>(k), power);
    }
  }
}

void DiscontinuityMesher::Internals::Check(
  int receiverId, const DiscontinuityMeshSettings& settings) const
{
  if (receiverId < 0 || receiverId >= static_cast<int>(this->Topology.Polygons.size()))
  {
    std::ostringstream os;
    os << "receiver id " << receiverId << " is out of range [0, "
       << this->Topology.Polygons.size() << ")";
    throw InputError(os.str());
  }
  if (!(settings.MinimumAngle >= 0.0 && settings.MinimumAngle <= kMaxMinimumAngle))
  {
    std::ostringstream os;
    os << "MinimumAngle " << settings.MinimumAngle << " is outside [0, " << kMaxMinimumAngle
       << "] degrees";
    throw InputError(os.str());
  }
  if (!(settings.JumpThreshold >= 0.0 && settings.JumpThreshold <= 1.0))
  {
    std::ostringstream os;
    os << "JumpThreshold " << settings.JumpThreshold << " is outside [0, 1]";
    throw InputError(os.str());
  }
  if (!(settings.ContactTolerance >= 0.0 && settings.ContactTolerance <= 1e-2))
  {
    std::ostringstream os;
    os << "ContactTolerance " << settings.ContactTolerance << " is outside [0, 0.01]";
    throw InputError(os.str());
  }
  if (!(settings.ShooterPowerFraction >= 0.0 && settings.ShooterPowerFraction <= 1.0))
  {
    std::ostringstream os;
    os << "ShooterPowerFraction " << settings.ShooterPowerFraction << " is outside [0, 1]";
    throw InputError(os.str());
  }
}

namespace
{
/// Whether shooter s traces its boundaries on the receiver (ShooterReceivers).
bool MeshesOn(const DiscontinuityMeshSettings& settings, int s, int receiverId)
{
  if (settings.ShooterReceivers.empty())
  {
    return true;
  }
  for (std::size_t k = 0; k < settings.Shooters.size(); ++k)
  {
    const std::vector<int>& receivers = settings.ShooterReceivers[k];
    if (settings.Shooters[k] == s &&
      (receivers.empty() ||
        std::find(receivers.begin(), receivers.end(), receiverId) != receivers.end()))
    {
      return true;
    }
  }
  return false;
}
} // namespace

std::vector<int> DiscontinuityMesher::Internals::Select(
  const DiscontinuityMeshSettings& settings) const
{
  const int count = static_cast<int>(this->Topology.Polygons.size());
  std::vector<int> shooters;
  if (!settings.ShooterRadiance.empty() &&
    settings.ShooterRadiance.size() != settings.Shooters.size())
  {
    std::ostringstream os;
    os << "ShooterRadiance has " << settings.ShooterRadiance.size() << " entries but Shooters has "
       << settings.Shooters.size();
    throw InputError(os.str());
  }
  if (!settings.ShooterReceivers.empty() &&
    settings.ShooterReceivers.size() != settings.Shooters.size())
  {
    std::ostringstream os;
    os << "ShooterReceivers has " << settings.ShooterReceivers.size()
       << " entries but Shooters has " << settings.Shooters.size();
    throw InputError(os.str());
  }
  for (const std::vector<int>& receivers : settings.ShooterReceivers)
  {
    for (const int id : receivers)
    {
      if (id < 0 || id >= count)
      {
        std::ostringstream os;
        os << "ShooterReceivers: receiver id " << id << " is out of range [0, " << count << ")";
        throw InputError(os.str());
      }
    }
  }
  if (!settings.Shooters.empty())
  {
    for (int id : settings.Shooters)
    {
      if (id < 0 || id >= count)
      {
        std::ostringstream os;
        os << "shooter id " << id << " is out of range [0, " << count << ")";
        throw InputError(os.str());
      }
      shooters.push_back(id);
    }
  }
  else
  {
    for (const std::pair<int, double>& emitter : this->EmitterPower)
    {
      if (emitter.second >= settings.ShooterPowerFraction * this->TotalPower)
      {
        shooters.push_back(emitter.first);
      }
    }
  }
  std::sort(shooters.begin(), shooters.end());
  shooters.erase(std::unique(shooters.begin(), shooters.end()), shooters.end());
  return shooters;
}

std::vector<detail::Segment2> DiscontinuityMesher::Internals::Boundaries(int receiverId,
  const DiscontinuityMeshSettings& settings, const detail::ReceiverFrame& frame,
  DiscontinuityMeshStatistics& stats) const
{
  std::vector<detail::Segment2> segments;
  // The outline first (order -1).
  const std::size_t n = frame.Outline.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    detail::Segment2 s;
    s.A = frame.Outline[i];
    s.B = frame.Outline[(i + 1) % n];
    s.Order = -1;
    s.Outline = true;
    segments.push_back(s);
  }
  if (settings.Contacts)
  {
    detail::AddContacts(
      this->Topology, this->Occluders, receiverId, settings, frame, segments, stats);
    detail::AddCovers(
      this->Topology, this->Occluders, receiverId, settings, frame, segments, stats);
  }
  std::vector<int> shooters = this->Select(settings);
  shooters.erase(std::remove_if(shooters.begin(), shooters.end(),
                   [&](int s) { return !MeshesOn(settings, s, receiverId); }),
    shooters.end());
  const std::size_t firstShadow = segments.size();
  // The jump threshold's reference: the largest direct radiance the receiver
  // gets with visibility (sum over shooters, at a few points). Shadows whose
  // jump cannot reach JumpThreshold times it are not even traced (see
  // ShadowEvents::Faint).
  const double minimumJump =
    detail::MinimumJump(
      this->Topology, this->ValidScene, this->Evaluator, receiverId, shooters, settings);
  const detail::PolygonData& receiver = this->Topology.Polygons[receiverId];
  double receiverRadius = 0.0;
  for (const Vec3& v : receiver.V)
  {
    receiverRadius = std::max(receiverRadius, Length(v - receiver.Centroid));
  }
  for (int s : shooters)
  {
    // A shooter whose whole light on the receiver stays below the minimum
    // jump casts no boundary worth tracing (the margin keeps rounding from
    // dropping one at the threshold).
    const bool faint = minimumJump >= 0.0 && settings.CullWedges &&
      detail::JumpRadiance(this->ValidScene, settings, s) *
          detail::FormFactorBound(this->Topology.Polygons[s], receiver, receiverRadius, true) *
          (1.0 + 1e-9) <
        minimumJump;
    if (s != receiverId && !faint)
    {
      detail::ShadowEvents(this->Topology, this->Occluders, this->ValidScene, settings, frame,
        receiverId, s, minimumJump, segments, stats)
        .Run();
    }
  }
  detail::DropFaintShadows(this->Topology, this->ValidScene, receiverId, settings, frame,
    minimumJump, firstShadow, segments);
  for (std::size_t k = firstShadow; k < segments.size(); ++k)
  {
    if (segments[k].SourceId >= 0)
    {
      ++stats.SegmentsKept;
    }
  }
  return segments;
}

std::vector<detail::Constraint2D> DiscontinuityMesher::Internals::Constraints(int receiverId,
  const DiscontinuityMeshSettings& settings, const detail::ReceiverFrame& frame,
  DiscontinuityMeshStatistics& stats) const
{
  std::vector<detail::Segment2> segments = this->Boundaries(receiverId, settings, frame, stats);
  const double size = this->Topology.Size;
  std::vector<detail::Constraint2D> constraints =
    detail::MergeSegments(std::move(segments), detail::kSnap * size, detail::kMinPiece * size);
  stats.Constraints += constraints.size();
  return constraints;
}

//------------------------------------------------------------------------------
DiscontinuityMesher::DiscontinuityMesher(const Scene& scene)
  : DiscontinuityMesher(std::make_shared<const PreparedScene>(scene)) // validates it
{
}

DiscontinuityMesher::DiscontinuityMesher(const std::shared_ptr<const PreparedScene>& scene)
  : Internal(new Internals(scene))
{
}

DiscontinuityMesher::~DiscontinuityMesher() = default;
DiscontinuityMesher::DiscontinuityMesher(DiscontinuityMesher&&) noexcept = default;
DiscontinuityMesher& DiscontinuityMesher::operator=(DiscontinuityMesher&&) noexcept = default;

int DiscontinuityMesher::GetNumberOfSurfaces() const
{
  return static_cast<int>(this->Internal->Topology.Polygons.size());
}

std::vector<int> DiscontinuityMesher::SelectShooters(
  const DiscontinuityMeshSettings& settings) const
{
  return this->Internal->Select(settings);
}

std::vector<DiscontinuitySegment> DiscontinuityMesher::ComputeBoundaries(int receiverId,
  const DiscontinuityMeshSettings& settings, DiscontinuityMeshStatistics* statistics) const
{
  const auto start = std::chrono::steady_clock::now();
  this->Internal->Check(receiverId, settings);
  DiscontinuityMeshStatistics stats;
  stats.Receivers = 1;
  const detail::ReceiverFrame frame =
    detail::MakeFrame(this->Internal->Topology.Polygons[receiverId]);
  const std::vector<detail::Constraint2D> constraints =
    this->Internal->Constraints(receiverId, settings, frame, stats);
  std::vector<DiscontinuitySegment> out;
  out.reserve(constraints.size());
  for (const detail::Constraint2D& c : constraints)
  {
    DiscontinuitySegment s;
    s.A = frame.To3D({ c.A[0], c.A[1] });
    s.B = frame.To3D({ c.B[0], c.B[1] });
    s.Order = c.Order;
    s.SourceId = c.SourceId;
    s.ReceiverId = receiverId;
    out.push_back(s);
  }
  stats.BoundarySeconds = Seconds(start);
  if (statistics)
  {
    *statistics += stats;
  }
  return out;
}

ReceiverMesh DiscontinuityMesher::MeshReceiver(int receiverId,
  const DiscontinuityMeshSettings& settings, DiscontinuityMeshStatistics* statistics) const
{
  const auto start = std::chrono::steady_clock::now();
  this->Internal->Check(receiverId, settings);
  DiscontinuityMeshStatistics stats;
  stats.Receivers = 1;
  const detail::ReceiverFrame frame =
    detail::MakeFrame(this->Internal->Topology.Polygons[receiverId]);
  detail::TriangulationInput input;
  input.ReceiverId = receiverId;
  input.Constraints = this->Internal->Constraints(receiverId, settings, frame, stats);
  input.Origin = frame.Origin;
  input.AxisU = frame.U;
  input.AxisV = frame.V;
  input.MinimumAngle = settings.MinimumAngle;
  const detail::PolygonData& rec = this->Internal->Topology.Polygons[receiverId];
  for (std::size_t i = 0; i < rec.V.size(); ++i)
  {
    input.Known2D.push_back(frame.Outline[i]);
    input.Known3D.push_back(rec.V[i]);
  }
  stats.BoundarySeconds = Seconds(start);
  const auto triangulationStart = std::chrono::steady_clock::now();
  detail::TriangulationOutput result = detail::TriangulateReceiver(input);
  stats.TriangulationSeconds = Seconds(triangulationStart);
  stats.ConstraintFailures += result.Failures;
  stats.DroppedDegenerate += result.DroppedDegenerate;
  if (!(settings.MinimumAngle > 0.0))
  {
    // Refinement makes its small triangles on purpose, around sharp angles
    // between constraints; without it, such edges are rounding errors.
    const detail::MergeCounts merged = detail::MergeShortEdges(
      result.Mesh, rec.N, detail::kMinPiece * this->Internal->Topology.Size, rec.V);
    stats.MergedTriangles += merged.Collapsed;
    stats.DroppedDegenerate += merged.Inverted;
  }
  stats.RemovedArea += result.RemovedArea;
  stats.Points += result.Mesh.Points.size();
  stats.Triangles += result.Mesh.Triangles.size();
  if (statistics)
  {
    *statistics += stats;
  }
  return std::move(result.Mesh);
}

} // namespace penumbra