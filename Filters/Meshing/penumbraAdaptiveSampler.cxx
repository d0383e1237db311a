// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraAdaptiveSampler.cxx
 * @brief The public entry points of the adaptive sampler: SampleReceiver
 * (argument checks and timing around ReceiverSampler) and the uniform
 * baseline SampleReceiverUniform.
 */
#include "penumbraAdaptiveSampler.h"

#include "penumbraMath.h"
#include "penumbraReceiverSampler.h"
#include "penumbraReceiverTriangulation.h"
#include "penumbraSamplingReceiver.h"
#include "penumbraScene.h" // InputError
#include "penumbraTimer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace penumbra
{

using detail::AssignValues;
using detail::CheckSettings;
using detail::Decompose;
using detail::Finish;
using detail::Frame;
using detail::MakeFrame;
using detail::MeanRadiance;
using detail::Prepare;
using detail::Receiver;

namespace
{

/// Splits every segment longer than `spacing` into equal pieces no longer
/// than it (new points appended, on the segment; pieces keep its labels).
void SubdivideSegments(double spacing, std::vector<P2>& vertices, std::vector<Vec3>& vertex3,
  std::vector<detail::RefinableSegment>& segments)
{
  std::vector<detail::RefinableSegment> pieces;
  for (const detail::RefinableSegment& s : segments)
  {
    const P2 a = vertices[s.A], b = vertices[s.B];
    const Vec3 a3 = vertex3[s.A], b3 = vertex3[s.B];
    const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
    const int count = std::max(1, static_cast<int>(std::ceil(length / spacing - 1e-9)));
    int previous = s.A;
    for (int k = 1; k <= count; ++k)
    {
      int next = s.B;
      if (k < count)
      {
        const double t = static_cast<double>(k) / count;
        next = static_cast<int>(vertices.size());
        vertices.push_back({ a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]) });
        vertex3.push_back(a3 + t * (b3 - a3));
      }
      detail::RefinableSegment piece = s;
      piece.A = previous;
      piece.B = next;
      pieces.push_back(piece);
      previous = next;
    }
  }
  segments.swap(pieces);
}

} // namespace

//------------------------------------------------------------------------------
AdaptiveSamplingResult SampleReceiver(const ReceiverMesh& mesh,
  const RadianceBatchFunction& evaluate, const AdaptiveSamplingSettings& settings)
{
  const auto start = std::chrono::steady_clock::now();
  CheckSettings(settings);
  if (!evaluate)
  {
    throw InputError("adaptive sampling: no evaluation function");
  }
  AdaptiveSamplingResult result;
  detail::ReceiverSampler sampler(mesh, evaluate, settings, result);
  sampler.Run();
  result.Statistics.Seconds = Seconds(start);
  return result;
}

//------------------------------------------------------------------------------
AdaptiveSamplingResult SampleReceiverUniform(const ReceiverMesh& mesh, int numberOfSamples,
  const RadianceBatchFunction& evaluate, const AdaptiveSamplingSettings& settings)
{
  const auto start = std::chrono::steady_clock::now();
  CheckSettings(settings);
  if (!evaluate)
  {
    throw InputError("adaptive sampling: no evaluation function");
  }
  if (numberOfSamples < 3)
  {
    throw InputError("uniform sampling: numberOfSamples must be >= 3");
  }
  AdaptiveSamplingResult result;
  AdaptiveSamplingStatistics& stats = result.Statistics;
  const Frame frame = MakeFrame(mesh);
  std::vector<P2> vertices, seeds;
  std::vector<Vec3> vertex3;
  std::vector<int> vertexOfPoint;
  std::vector<detail::RefinableSegment> segments;
  Decompose(mesh, frame, vertices, vertex3, vertexOfPoint, segments, seeds);

  // The full mesh once, for its boundary (edges with one kept side) and area.
  Receiver full;
  full.F = frame;
  Prepare(full, vertices, vertex3, segments, seeds);
  full.Refresh();
  std::vector<int> boundaryId(full.Snap.Vertices.size(), -1);
  std::vector<P2> boundaryVertices;
  std::vector<Vec3> boundary3;
  std::vector<detail::RefinableSegment> boundarySegments;
  auto idOf = [&](int v) {
    if (boundaryId[v] < 0)
    {
      boundaryId[v] = static_cast<int>(boundaryVertices.size());
      boundaryVertices.push_back(full.Snap.Vertices[v]);
      boundary3.push_back(full.Position3(v));
    }
    return boundaryId[v];
  };
  for (const auto& s : full.Snap.Segments)
  {
    if ((s.LeftA >= 0) != (s.RightA >= 0))
    {
      detail::RefinableSegment b;
      b.A = idOf(s.VertexA);
      b.B = idOf(s.VertexB);
      b.Order = s.Order;
      b.SourceId = s.SourceId;
      boundarySegments.push_back(b);
    }
  }
  double area = 0.0, lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
  for (const auto& t : full.Snap.Triangles)
  {
    const P2 a = full.PointUV(t[0]), b = full.PointUV(t[1]), c = full.PointUV(t[2]);
    area += 0.5 * Cross2(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]);
    for (const P2& q : { a, b, c })
    {
      for (int k = 0; k < 2; ++k)
      {
        lo[k] = std::min(lo[k], q[k]);
        hi[k] = std::max(hi[k], q[k]);
      }
    }
  }
  if (boundaryVertices.size() < 3)
  {
    throw InputError("uniform sampling: the receiver mesh has no boundary");
  }

  // Boundary points at about the grid's spacing: the outline usually comes
  // with its corners only, and long thin triangles joining them to the grid
  // would interpolate the radiance linearly along a whole edge (6% off along
  // a floor's edge in test_adversarial.py's light-plane case; a strip
  // narrower than the grid would get no interior point, only its corners).
  double perimeter = 0.0;
  for (const auto& s : boundarySegments)
  {
    const P2 a = boundaryVertices[s.A], b = boundaryVertices[s.B];
    perimeter += std::hypot(b[0] - a[0], b[1] - a[1]);
  }
  SubdivideSegments(std::max(std::sqrt(area / numberOfSamples), 2.0 * perimeter / numberOfSamples),
    boundaryVertices, boundary3, boundarySegments);

  // Grid of cell centres, spacing adjusted to the requested count.
  Receiver rec;
  rec.F = frame;
  rec.SideOffset = settings.SideOffset;
  const int interior = std::max(1, numberOfSamples - static_cast<int>(boundaryVertices.size()));
  double h = std::sqrt(area / interior);
  for (int attempt = 0; attempt < 8; ++attempt)
  {
    Prepare(rec, boundaryVertices, boundary3, boundarySegments, seeds);
    int hint = 0;
    for (int j = 0; lo[1] + (j + 0.5) * h < hi[1]; ++j)
    {
      // Alternate the direction of the rows so consecutive points are close.
      const int columns = static_cast<int>(std::ceil((hi[0] - lo[0]) / h - 0.5));
      for (int i = 0; i < columns; ++i)
      {
        const int ii = j % 2 ? columns - 1 - i : i;
        const int id = rec.Tri->InsertInFace(lo[0] + (ii + 0.5) * h, lo[1] + (j + 0.5) * h, hint);
        hint = id >= 0 ? id : hint;
      }
    }
    rec.Refresh();
    const int count = static_cast<int>(rec.Snap.PointVertex.size());
    if (std::abs(count - numberOfSamples) <= std::max(1, numberOfSamples / 100) ||
      count - static_cast<int>(boundaryVertices.size()) <= 0)
    {
      break;
    }
    h *= std::sqrt(
      static_cast<double>(count - static_cast<int>(boundaryVertices.size())) / interior);
  }
  AssignValues(rec, evaluate, stats);
  stats.InitialSamples = static_cast<int>(rec.Snap.PointVertex.size());
  result.ReferenceRadiance = MeanRadiance(rec);
  Finish(rec, mesh.ReceiverId, result);
  stats.Seconds = Seconds(start);
  return result;
}

} // namespace penumbra
