// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraStandardRadiosity.h"

#include "penumbraFormFactor.h"
#include "penumbraMath.h"
#include "penumbraParallel.h"
#include "penumbraRayCastEvaluator.h"
#include "penumbraStandardRadiosityInternals.h"
#include "penumbraTimer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>

namespace penumbra
{

using baseline::Element;
using baseline::PastShot;
using baseline::Patch;
using baseline::Vertex;

namespace
{
RGB Difference(const RGB& a, const RGB& b)
{
  return RGB(a.R - b.R, a.G - b.G, a.B - b.B);
}

std::uint64_t EdgeKey(int a, int b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

}

void StandardRadiositySettings::Validate() const
{
  auto fail = [](const std::string& what) { throw InputError(what); };
  if (!(this->PatchSize > 0.0 && this->PatchSize <= 1.0))
  {
    fail("PatchSize must be in (0, 1], got " + std::to_string(this->PatchSize));
  }
  if (!(this->ElementSize > 0.0 && this->ElementSize <= 1.0))
  {
    fail("ElementSize must be in (0, 1], got " + std::to_string(this->ElementSize));
  }
  if (this->ShooterSamples < 1 || this->ShooterSamples > 32)
  {
    fail("ShooterSamples must be in [1, 32], got " + std::to_string(this->ShooterSamples));
  }
  if (!(this->SubdivisionThreshold > 0.0))
  {
    fail("SubdivisionThreshold must be positive, got " + std::to_string(this->SubdivisionThreshold));
  }
  if (this->MaximumSubdivisionDepth < 0 || this->MaximumSubdivisionDepth > 12)
  {
    fail("MaximumSubdivisionDepth must be in [0, 12], got " +
      std::to_string(this->MaximumSubdivisionDepth));
  }
  if (!(this->UnshotFraction >= 0.0 && this->UnshotFraction <= 1.0))
  {
    fail("UnshotFraction must be in [0, 1], got " + std::to_string(this->UnshotFraction));
  }
  if (this->MaximumShots < 0)
  {
    fail("MaximumShots must be >= 0, got " + std::to_string(this->MaximumShots));
  }
}

/**
 * A vertex on its surface's outline lies in the plane of a neighbouring
 * surface that meets it there (a wall on the floor's edge), which it would
 * then not see at all, although the limit from inside sees half a
 * hemisphere of it. It is evaluated as that limit: moved inside along the
 * sum of the inward normals of the outline edges through it, by 1e-4 of the
 * scene's size (far above Embree's single-precision resolution, far below
 * any element). Other vertices are evaluated where they are.
 */
Vec3 StandardRadiosity::Internals::InwardPoint(const Vec3& p, int surface) const
{
  const std::vector<Vec3>& v = this->SceneCopy.Surfaces[surface].Vertices;
  const Vec3& normal = this->Geometry[surface].Normal;
  const double size = this->SceneCopy.Size();
  Vec3 inward;
  for (std::size_t q = 0; q < v.size(); ++q)
  {
    const Vec3& a = v[q];
    const Vec3 edge = v[(q + 1) % v.size()] - a;
    const double t = std::min(1.0, std::max(0.0, Dot(p - a, edge) / SquaredLength(edge)));
    if (Length(a + edge * t - p) <= 1e-9 * size)
    {
      inward += Normalized(Cross(normal, edge)); // counter-clockwise: inside is on the left
    }
  }
  return SquaredLength(inward) > 0.0 ? p + Normalized(inward) * (1e-4 * size) : p;
}

void StandardRadiosity::Internals::Reset()
{
  this->Vertices.clear();
  this->Elements.clear();
  this->Patches.clear();
  this->Midpoints.clear();
  this->History.clear();
  this->SubdividedElements = 0;
  this->Rays = 0;
  this->Energy = ShootingEnergy();
}

double StandardRadiosity::Internals::FormFactor(
  const Vec3& x, const Vec3& n, int receiver, int patchId, long long& rays) const
{
  const Patch& patch = this->Patches[patchId];
  if (receiver == patch.Surface)
  {
    return 0.0; // a planar surface does not see itself
  }
  const Vec3& m = this->Geometry[patch.Surface].Normal;
  if (!(Dot(m, x - patch.Corners[0]) > 0.0))
  {
    return 0.0; // x is behind the patch, which emits from its front only
  }
  thread_local std::vector<Vec3> targets;
  thread_local std::vector<double> weights;
  thread_local std::vector<unsigned char> occluded;
  targets.clear();
  weights.clear();
  double weightSum = 0.0;
  for (const Vec3& y : patch.Samples)
  {
    const Vec3 d = y - x;
    const double r2 = SquaredLength(d);
    const double r = std::sqrt(r2);
    const double cx = Dot(n, d) / r;
    const double cy = -Dot(m, d) / r;
    if (!(cx > 0.0 && cy > 0.0))
    {
      continue;
    }
    const double w = cx * cy * patch.SampleArea / (Pi * r2 + patch.SampleArea);
    targets.push_back(y);
    weights.push_back(w);
    weightSum += w;
  }
  const bool analytic = this->Settings.FormFactor == FormFactorMode::AnalyticVisibility;
  double unoccluded = 0.0;
  if (analytic)
  {
    Vec3 clipped[8];
    const int count = ClipPolygonToHalfSpace(patch.Corners.data(), 3, n, Dot(n, x), clipped);
    unoccluded = count >= 3 ? PointPolygonFormFactor(x, n, clipped, count) : 0.0;
    if (!(unoccluded > 0.0))
    {
      return 0.0;
    }
    if (targets.empty())
    {
      // Only a sliver of the patch, without samples, is in front of x: one
      // ray to that sliver's vertex average decides its visibility.
      Vec3 centre;
      for (int q = 0; q < count; ++q)
      {
        centre += clipped[q];
      }
      targets.push_back(centre / count);
      weights.push_back(1.0);
      weightSum = 1.0;
    }
  }
  if (targets.empty())
  {
    return 0.0;
  }
  occluded.resize(targets.size());
  this->Caster->TraceFrom(x, targets.data(), static_cast<int>(targets.size()), occluded.data(),
    receiver, patch.Surface);
  rays += static_cast<long long>(targets.size());
  double visible = 0.0;
  for (std::size_t q = 0; q < targets.size(); ++q)
  {
    if (!occluded[q])
    {
      visible += weights[q];
    }
  }
  return analytic ? unoccluded * (visible / weightSum) : visible;
}

RGB StandardRadiosity::Internals::TotalUnshotPower() const
{
  RGB total;
  for (const Patch& p : this->Patches)
  {
    total += p.UnshotPower;
  }
  return total;
}

int StandardRadiosity::Internals::SelectPatch() const
{
  int best = -1;
  double bestPower = 0.0;
  for (int p = 0; p < static_cast<int>(this->Patches.size()); ++p)
  {
    const double power = this->Patches[p].UnshotPower.Mean();
    if (power > bestPower)
    {
      best = p;
      bestPower = power;
    }
  }
  return best;
}

ShotRecord StandardRadiosity::Internals::Shoot(int patchId)
{
  const auto start = std::chrono::steady_clock::now();
  Patch& patch = this->Patches[patchId];
  ShotRecord record;
  record.Shooter = patch.Surface;
  record.Power = patch.UnshotPower;
  const RGB radiance = patch.UnshotPower * (1.0 / (Pi * patch.Area));

  // Receivers: surfaces partly in front of the patch with the patch partly
  // in front of them.
  const int surfaces = static_cast<int>(this->SceneCopy.Surfaces.size());
  std::vector<char> receives(surfaces, 0);
  const PolygonGeometry& shooter = this->Geometry[patch.Surface];
  for (int s = 0; s < surfaces; ++s)
  {
    const PolygonGeometry& g = this->Geometry[s];
    if (s == patch.Surface || !(g.Area > 0.0))
    {
      continue;
    }
    bool patchInFront = false;
    for (const Vec3& c : patch.Corners)
    {
      patchInFront = patchInFront || Dot(g.Normal, c) > g.Offset;
    }
    bool receiverInFront = false;
    for (const Vec3& v : this->SceneCopy.Surfaces[s].Vertices)
    {
      receiverInFront = receiverInFront || Dot(shooter.Normal, v) > shooter.Offset;
    }
    receives[s] = patchInFront && receiverInFront;
    record.Receivers += receives[s];
  }

  const std::size_t count = this->Vertices.size();
  std::vector<double> factors(count, 0.0);
  std::vector<long long> rays(count, 0);
  RunParallel(this->Loop, count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
    {
      const Vertex& vertex = this->Vertices[v];
      if (receives[vertex.Surface])
      {
        factors[v] = this->FormFactor(vertex.Evaluation, this->Geometry[vertex.Surface].Normal,
          vertex.Surface, patchId, rays[v]);
      }
    }
  });
  for (std::size_t v = 0; v < count; ++v)
  {
    Vertex& vertex = this->Vertices[v];
    if (receives[vertex.Surface])
    {
      ++record.Samples;
      record.Rays += rays[v];
      const RGB incident = radiance * factors[v];
      vertex.IncidentOverPi += incident;
      vertex.Total += this->SceneCopy.Surfaces[vertex.Surface].Reflectance * incident;
    }
  }
  this->Rays += record.Rays;
  for (Element& e : this->Elements)
  {
    const int surface = this->Patches[e.Patch].Surface;
    if (!e.Leaf || !receives[surface])
    {
      continue;
    }
    const double f = (factors[e.Corners[0]] + factors[e.Corners[1]] + factors[e.Corners[2]]) / 3.0;
    if (!(f > 0.0))
    {
      continue;
    }
    const RGB& rho = this->SceneCopy.Surfaces[surface].Reflectance;
    const RGB incident = radiance * (Pi * f * e.Area);
    record.Incident += incident;
    record.Absorbed += RGB(1.0 - rho.R, 1.0 - rho.G, 1.0 - rho.B) * incident;
    const RGB reflected = rho * radiance * f;
    e.Unshot += reflected;
    this->Patches[e.Patch].UnshotPower += reflected * (Pi * e.Area);
  }
  for (int e : patch.Elements)
  {
    this->Elements[e].Unshot = RGB();
  }
  patch.UnshotPower = RGB();
  this->History.push_back({ patchId, radiance });

  record.Escaped = Difference(record.Power, record.Incident);
  this->Energy.ShotAbsorbed += record.Absorbed;
  this->Energy.ShotEscaped += record.Escaped;
  this->Subdivide(receives);
  this->Energy.Unshot = this->TotalUnshotPower();
  record.UnshotAfter = this->Energy.Unshot.Mean();
  record.Seconds = Seconds(start);
  return record;
}

void StandardRadiosity::Internals::CollectHanging(int a, int b, std::vector<int>& out) const
{
  const auto found = this->Midpoints.find(EdgeKey(a, b));
  if (found == this->Midpoints.end())
  {
    return;
  }
  this->CollectHanging(a, found->second, out);
  out.push_back(found->second);
  this->CollectHanging(found->second, b, out);
}

bool StandardRadiosity::Internals::NeedsSplit(const Element& e, std::vector<int>& ring) const
{
  ring.clear();
  for (int q = 0; q < 3; ++q)
  {
    ring.push_back(e.Corners[q]);
    this->CollectHanging(e.Corners[q], e.Corners[(q + 1) % 3], ring);
  }
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (int v : ring)
  {
    const double value = this->Vertices[v].Total.Mean();
    low = std::min(low, value);
    high = std::max(high, value);
  }
  // Relative to the element's brightest vertex, but never below the scene's
  // reference radiance: differences in dark regions do not matter as much.
  return high - low > this->Settings.SubdivisionThreshold * std::max(high, this->ReferenceRadiance);
}

int StandardRadiosity::Internals::Midpoint(int a, int b, std::vector<int>& created)
{
  const auto inserted = this->Midpoints.emplace(EdgeKey(a, b), static_cast<int>(this->Vertices.size()));
  if (inserted.second)
  {
    Vertex vertex;
    vertex.Position = (this->Vertices[a].Position + this->Vertices[b].Position) * 0.5;
    vertex.Surface = this->Vertices[a].Surface;
    vertex.Evaluation = this->InwardPoint(vertex.Position, vertex.Surface);
    this->Vertices.push_back(vertex);
    created.push_back(inserted.first->second);
  }
  return inserted.first->second;
}

void StandardRadiosity::Internals::Subdivide(const std::vector<char>& changed)
{
  if (this->Settings.MaximumSubdivisionDepth == 0 ||
    !std::isfinite(this->Settings.SubdivisionThreshold))
  {
    return;
  }
  std::vector<int> ring;
  std::vector<int> split;
  std::vector<int> created;
  while (true)
  {
    split.clear();
    for (int e = 0; e < static_cast<int>(this->Elements.size()); ++e)
    {
      // Only the surfaces the shot changed can have new differences.
      const Element& element = this->Elements[e];
      if (element.Leaf && element.Depth < this->Settings.MaximumSubdivisionDepth &&
        changed[this->Vertices[element.Corners[0]].Surface] &&
        this->NeedsSplit(element, ring))
      {
        split.push_back(e);
      }
    }
    if (split.empty())
    {
      return;
    }
    created.clear();
    for (int e : split)
    {
      const Element parent = this->Elements[e];
      const std::array<int, 3>& c = parent.Corners;
      const int ab = this->Midpoint(c[0], c[1], created);
      const int bc = this->Midpoint(c[1], c[2], created);
      const int ca = this->Midpoint(c[2], c[0], created);
      const std::array<std::array<int, 3>, 4> children = {
        { { c[0], ab, ca }, { ab, c[1], bc }, { ca, bc, c[2] }, { ab, bc, ca } }
      };
      this->Elements[e].Leaf = false;
      for (const auto& corners : children)
      {
        Element child;
        child.Corners = corners;
        child.Patch = parent.Patch;
        child.Depth = parent.Depth + 1;
        child.Area = parent.Area / 4.0; // midpoint split: four congruent quarters
        child.Unshot = parent.Unshot;   // constant: the patch's power is unchanged
        this->Patches[parent.Patch].Elements.push_back(static_cast<int>(this->Elements.size()));
        this->Elements.push_back(child);
      }
    }
    this->SubdividedElements += static_cast<int>(split.size());
    // New vertices gather every past shot, as if they had existed from the start.
    std::vector<long long> rays(created.size(), 0);
    RunParallel(this->Loop, created.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t q = begin; q < end; ++q)
      {
        Vertex& vertex = this->Vertices[created[q]];
        const Surface& s = this->SceneCopy.Surfaces[vertex.Surface];
        const Vec3& n = this->Geometry[vertex.Surface].Normal;
        RGB incident;
        for (const PastShot& shot : this->History)
        {
          const double f = this->FormFactor(vertex.Evaluation, n, vertex.Surface, shot.Patch, rays[q]);
          incident += shot.Radiance * f;
        }
        vertex.IncidentOverPi = incident;
        vertex.Total = s.Emission + s.Reflectance * incident;
      }
    });
    for (long long r : rays)
    {
      this->Rays += r;
    }
  }
}

StandardRadiosity::StandardRadiosity(const Scene& scene)
  : Internal(new Internals)
{
  ValidateScene(scene);
  this->Internal->SceneCopy = scene;
  for (const Surface& s : scene.Surfaces)
  {
    this->Internal->Geometry.push_back(ComputePolygonGeometry(s.Vertices));
  }
  this->Internal->Caster.reset(new RayCaster(scene));
}

StandardRadiosity::~StandardRadiosity() = default;

void StandardRadiosity::SetSettings(const StandardRadiositySettings& settings)
{
  settings.Validate();
  this->Internal->Settings = settings;
}

const StandardRadiositySettings& StandardRadiosity::GetSettings() const
{
  return this->Internal->Settings;
}

void StandardRadiosity::SetParallelFor(ParallelFor parallelFor)
{
  this->Internal->Loop = std::move(parallelFor);
}

StandardRadiositySummary StandardRadiosity::Run(const ShotCallback& callback)
{
  Internals& I = *this->Internal;
  const auto start = std::chrono::steady_clock::now();
  I.Reset();
  I.BuildMesh();
  StandardRadiositySummary summary;
  I.Energy.Emitted = I.SceneCopy.EmittedPower();
  I.Energy.InitialUnshot = I.TotalUnshotPower();
  // Rounding only: the elements' areas sum to the polygons' areas.
  I.Energy.PriorEscaped = Difference(I.Energy.Emitted, I.Energy.InitialUnshot);
  I.Energy.Unshot = I.Energy.InitialUnshot;
  const double emitted = I.Energy.Emitted.Mean();
  const double initial = I.Energy.InitialUnshot.Mean();
  const double target = I.Settings.UnshotFraction * emitted;
  while (!ShootingDone(
    I.TotalUnshotPower().Mean(), target, summary.Shots, I.Settings.MaximumShots, summary.Reason))
  {
    const int patch = I.SelectPatch();
    if (patch < 0)
    {
      summary.Reason = StopReason::NothingToShoot;
      break;
    }
    const ShotRecord record = I.Shoot(patch);
    ++summary.Shots;
    if (callback &&
      !callback(record,
        ShootingProgress(record.UnshotAfter, initial, target, summary.Shots, I.Settings.MaximumShots)))
    {
      summary.Reason = StopReason::Aborted;
      break;
    }
  }
  I.Energy.Unshot = I.TotalUnshotPower();
  summary.UnshotFraction = emitted > 0.0 ? I.Energy.Unshot.Mean() / emitted : 0.0;
  summary.Patches = static_cast<int>(I.Patches.size());
  summary.Elements = static_cast<int>(
    std::count_if(I.Elements.begin(), I.Elements.end(), [](const Element& e) { return e.Leaf; }));
  summary.Vertices = static_cast<int>(I.Vertices.size());
  summary.SubdividedElements = I.SubdividedElements;
  summary.Rays = I.Rays;
  summary.Energy = I.Energy;
  summary.Seconds = Seconds(start);
  return summary;
}

StandardRadiosityMesh StandardRadiosity::GetMesh() const
{
  const Internals& I = *this->Internal;
  StandardRadiosityMesh mesh;
  for (const Vertex& v : I.Vertices)
  {
    mesh.Points.push_back(v.Position);
    mesh.Radiance.push_back(v.Total);
    mesh.Irradiance.push_back(v.IncidentOverPi * Pi);
  }
  std::vector<int> ring;
  for (const Element& e : I.Elements)
  {
    if (!e.Leaf)
    {
      continue;
    }
    const int surface = I.Patches[e.Patch].Surface;
    ring.clear();
    for (int q = 0; q < 3; ++q)
    {
      ring.push_back(e.Corners[q]);
      I.CollectHanging(e.Corners[q], e.Corners[(q + 1) % 3], ring);
    }
    if (ring.size() == 3)
    {
      mesh.Triangles.push_back(e.Corners);
      mesh.TriangleSurface.push_back(surface);
      continue;
    }
    // T-vertices: fan from the centroid, valued as the element's linear
    // interpolant there, so the display has no cracks.
    const int centre = static_cast<int>(mesh.Points.size());
    Vec3 position;
    RGB value, incident;
    for (int q = 0; q < 3; ++q)
    {
      position += I.Vertices[e.Corners[q]].Position;
      value += I.Vertices[e.Corners[q]].Total;
      incident += I.Vertices[e.Corners[q]].IncidentOverPi;
    }
    mesh.Points.push_back(position / 3.0);
    mesh.Radiance.push_back(value * (1.0 / 3.0));
    mesh.Irradiance.push_back(incident * (Pi / 3.0));
    for (std::size_t q = 0; q < ring.size(); ++q)
    {
      mesh.Triangles.push_back({ centre, ring[q], ring[(q + 1) % ring.size()] });
      mesh.TriangleSurface.push_back(surface);
    }
  }
  // Outline: directed edges whose reverse no triangle of the surface uses
  // (surfaces have separate vertices, so edges never pair across surfaces).
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& t : mesh.Triangles)
  {
    for (int q = 0; q < 3; ++q)
    {
      ++uses[EdgeKey(t[q], t[(q + 1) % 3])];
    }
  }
  for (std::size_t t = 0; t < mesh.Triangles.size(); ++t)
  {
    const auto& tri = mesh.Triangles[t];
    for (int q = 0; q < 3; ++q)
    {
      if (uses[EdgeKey(tri[q], tri[(q + 1) % 3])] == 1)
      {
        mesh.BoundaryEdges.push_back({ tri[q], tri[(q + 1) % 3] });
        mesh.BoundaryEdgeSurface.push_back(mesh.TriangleSurface[t]);
      }
    }
  }
  return mesh;
}

namespace
{
void CheckPatchId(int patchId, int count)
{
  if (patchId < 0 || patchId >= count)
  {
    throw InputError(
      "patch " + std::to_string(patchId) + " out of range (" + std::to_string(count) + " patches)");
  }
}
}

double StandardRadiosity::FormFactor(const Vec3& x, const Vec3& n, int receiverId, int patchId) const
{
  CheckPatchId(patchId, this->GetNumberOfPatches());
  long long rays = 0;
  return this->Internal->FormFactor(x, n, receiverId, patchId, rays);
}

int StandardRadiosity::GetNumberOfPatches() const
{
  return static_cast<int>(this->Internal->Patches.size());
}

std::array<Vec3, 3> StandardRadiosity::GetPatch(int patchId) const
{
  CheckPatchId(patchId, this->GetNumberOfPatches());
  return this->Internal->Patches[patchId].Corners;
}

} // namespace penumbra
