// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraAdaptiveSampling.h"

#include "vtkPenumbraRadianceEvaluator.h"
#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include "penumbraAdaptiveSampler.h"
#include "penumbraSampleBudget.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <unordered_map>

namespace penumbra
{
namespace
{
/// Per surface: the sample point ids in its mesh, and their numbers there.
using LocalIds = std::map<int, std::unordered_map<vtkIdType, int>>;

/// Each surface's triangles and points (mesher layout) from the sample
/// triangles; the segments of the line cells in `lines`, their cells in
/// `lineCells`. Returns the first polygon that is not a triangle, -1 if none.
vtkIdType CollectTriangles(vtkPolyData* samples, vtkDataArray* surfaceIds,
  std::map<int, ReceiverMesh>& meshes, LocalIds& localIds,
  std::vector<std::array<vtkIdType, 2>>& lines, std::vector<vtkIdType>& lineCells)
{
  std::map<int, std::map<std::array<double, 3>, int>> vertexIds;
  auto localId = [&](int surface, vtkIdType id) {
    auto& ids = localIds[surface];
    auto found = ids.find(id);
    if (found != ids.end())
    {
      return found->second;
    }
    ReceiverMesh& mesh = meshes[surface];
    double p[3];
    samples->GetPoint(id, p);
    auto& vertices = vertexIds[surface];
    const auto vertex = vertices.emplace(std::array<double, 3>{ p[0], p[1], p[2] },
      static_cast<int>(vertices.size()));
    mesh.Points.emplace_back(p[0], p[1], p[2]);
    mesh.PointVertex.push_back(vertex.first->second);
    const int k = static_cast<int>(mesh.Points.size()) - 1;
    ids.emplace(id, k);
    return k;
  };
  vtkIdType badCell = -1;
  ForEachCell(samples, [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
    if (kind == 1)
    {
      for (vtkIdType k = 0; k + 1 < npts; ++k)
      {
        lines.push_back({ pts[k], pts[k + 1] });
        lineCells.push_back(cellId);
      }
    }
    else if (kind == 2)
    {
      if (npts != 3)
      {
        badCell = cellId;
        return false;
      }
      const int surface = static_cast<int>(surfaceIds->GetComponent(cellId, 0));
      const int a = localId(surface, pts[0]), b = localId(surface, pts[1]),
                c = localId(surface, pts[2]);
      meshes[surface].ReceiverId = surface;
      meshes[surface].Triangles.push_back({ a, b, c });
    }
    return kind < 3; // strips: nothing to sample
  });
  return badCell;
}

/// The line segments whose ends are points of their surface's triangles, as
/// that surface's discontinuity segments.
void AttachSegments(const std::vector<std::array<vtkIdType, 2>>& lines,
  const std::vector<vtkIdType>& lineCells, vtkDataArray* surfaceIds, vtkDataArray* orders,
  vtkDataArray* sources, const LocalIds& localIds, std::map<int, ReceiverMesh>& meshes)
{
  for (std::size_t k = 0; k < lines.size(); ++k)
  {
    const int surface = static_cast<int>(surfaceIds->GetComponent(lineCells[k], 0));
    auto ids = localIds.find(surface);
    if (ids == localIds.end())
    {
      continue;
    }
    auto a = ids->second.find(lines[k][0]);
    auto b = ids->second.find(lines[k][1]);
    if (a == ids->second.end() || b == ids->second.end())
    {
      continue;
    }
    DiscontinuitySegment segment;
    ReceiverMesh& mesh = meshes[surface];
    segment.A = mesh.Points[a->second];
    segment.B = mesh.Points[b->second];
    segment.PointA = a->second;
    segment.PointB = b->second;
    segment.Order = orders ? static_cast<int>(orders->GetComponent(lineCells[k], 0)) : 2;
    segment.SourceId = sources ? static_cast<int>(sources->GetComponent(lineCells[k], 0)) : -1;
    segment.ReceiverId = surface;
    mesh.Segments.push_back(segment);
  }
}

bool SameVector(const Vec3& a, const Vec3& b)
{
  return a.X == b.X && a.Y == b.Y && a.Z == b.Z;
}

/// Whether two input meshes are the same to the bit (points, triangles, segments).
bool SameMesh(const ReceiverMesh& a, const ReceiverMesh& b)
{
  if (a.ReceiverId != b.ReceiverId || a.Points.size() != b.Points.size() ||
    a.PointVertex != b.PointVertex || a.Triangles != b.Triangles ||
    a.Segments.size() != b.Segments.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < a.Points.size(); ++k)
  {
    if (!SameVector(a.Points[k], b.Points[k]))
    {
      return false;
    }
  }
  for (std::size_t k = 0; k < a.Segments.size(); ++k)
  {
    const DiscontinuitySegment& p = a.Segments[k];
    const DiscontinuitySegment& q = b.Segments[k];
    if (!SameVector(p.A, q.A) || !SameVector(p.B, q.B) || p.Order != q.Order ||
      p.SourceId != q.SourceId || p.ReceiverId != q.ReceiverId || p.PointA != q.PointA ||
      p.PointB != q.PointB)
    {
      return false;
    }
  }
  return true;
}

/// Sample the receivers `which` (indices into receivers) within their
/// budgets; a receiver's input error goes to `errors`. Stops early on abort.
void SampleReceivers(vtkPenumbraRadianceEvaluator* self, const std::vector<std::size_t>& which,
  const std::vector<int>& surfaces, const std::vector<const ReceiverMesh*>& receivers,
  const std::vector<int>& budgets, const AdaptiveSamplingSettings& settings,
  const std::function<RGB(int, const Vec3&)>& evaluatePoint,
  std::vector<AdaptiveSamplingResult>& results, std::vector<std::string>& errors)
{
  // Receivers are sampled in parallel, largest initial mesh first (the
  // sampler's passes run on one thread per receiver; each receiver's batch
  // evaluations run in parallel too, nested). Results are assembled in
  // surface order afterwards, so the output does not depend on scheduling.
  std::vector<std::size_t> order = which;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return receivers[a]->Triangles.size() > receivers[b]->Triangles.size();
  });
  std::atomic<std::size_t> finished(0);
  const std::thread::id mainThread = std::this_thread::get_id();
  const vtkIdType numberOfReceivers = static_cast<vtkIdType>(order.size());
  vtkSMPTools::For(0, numberOfReceivers, 1, [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType k = first; k < last; ++k)
    {
      if (self->GetAbortExecute())
      {
        return;
      }
      const std::size_t w = order[k];
      const int surface = surfaces[w];
      try
      {
        const RadianceBatchFunction evaluate = [&](const Vec3* x, int count, RGB* values) {
          vtkSMPTools::For(0, count, [&](vtkIdType a, vtkIdType b) {
            for (vtkIdType i = a; i < b; ++i)
            {
              values[i] = evaluatePoint(surface, x[i]);
            }
          });
        };
        AdaptiveSamplingSettings receiverSettings = settings;
        receiverSettings.MaximumSamplesPerSurface = budgets[w];
        results[w] = SampleReceiver(*receivers[w], evaluate, receiverSettings);
      }
      catch (const InputError& e)
      {
        errors[w] = e.what();
      }
      const std::size_t done = ++finished;
      // Observers (Python ones included) are only called from the calling thread.
      if (std::this_thread::get_id() == mainThread)
      {
        self->UpdateProgress(static_cast<double>(done) / order.size());
      }
    }
  });
}

/// The refined meshes, in surface order, as the output polydata: points with
/// `Radiance` and `SurfaceId`, lines then triangles with the mesh cell arrays
/// and `SamplingResidual`, and the field array `Evaluations`.
void AssembleSampledMeshes(const std::vector<int>& surfaces,
  std::vector<AdaptiveSamplingResult>& results, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> outLines, outPolys;
  vtkNew<vtkDoubleArray> radiance, residual;
  radiance->SetName("Radiance");
  radiance->SetNumberOfComponents(3);
  residual->SetName("SamplingResidual");
  residual->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> pointSurface;
  pointSurface->SetName("SurfaceId");
  std::vector<int> lineSurface, lineOrder, lineSource, polySurface;
  std::vector<std::array<double, 3>> polyResidual;
  long long evaluations = 0;
  for (std::size_t w = 0; w < surfaces.size(); ++w)
  {
    const int surface = surfaces[w];
    AdaptiveSamplingResult result = std::move(results[w]);
    evaluations += result.Statistics.Evaluations;
    const vtkIdType offset = points->GetNumberOfPoints();
    for (std::size_t p = 0; p < result.Mesh.Points.size(); ++p)
    {
      const Vec3& x = result.Mesh.Points[p];
      points->InsertNextPoint(x.X, x.Y, x.Z);
      radiance->InsertNextTuple3(result.Values[p].R, result.Values[p].G, result.Values[p].B);
      pointSurface->InsertNextValue(surface);
    }
    // -1: not probed; the reconstructor then relies on its model alone there.
    std::vector<std::array<double, 3>> worst(result.Mesh.Triangles.size(), { -1.0, -1.0, -1.0 });
    for (std::size_t q = 0; q < result.Probes.Triangles.size(); ++q)
    {
      auto& largest = worst[static_cast<std::size_t>(result.Probes.Triangles[q])];
      for (int c = 0; c < 3; ++c)
      {
        largest[c] = std::max(largest[c], std::abs(result.Probes.Residuals[3 * q + c]));
      }
    }
    for (std::size_t t = 0; t < result.Mesh.Triangles.size(); ++t)
    {
      const auto& tri = result.Mesh.Triangles[t];
      const vtkIdType ids[3] = { offset + tri[0], offset + tri[1], offset + tri[2] };
      outPolys->InsertNextCell(3, ids);
      polySurface.push_back(surface);
      polyResidual.push_back(worst[t]);
    }
    for (const DiscontinuitySegment& segment : result.Mesh.Segments)
    {
      const vtkIdType ids[2] = { offset + segment.PointA, offset + segment.PointB };
      outLines->InsertNextCell(2, ids);
      lineSurface.push_back(surface);
      lineOrder.push_back(segment.Order);
      lineSource.push_back(segment.SourceId);
    }
  }

  output->Initialize();
  output->SetPoints(points);
  output->SetLines(outLines);
  output->SetPolys(outPolys);
  output->GetPointData()->AddArray(radiance);
  output->GetPointData()->SetActiveScalars("Radiance");
  output->GetPointData()->AddArray(pointSurface);
  AddMeshCellArrays(output, lineSurface, lineOrder, lineSource, polySurface);
  for (std::size_t k = 0; k < lineSurface.size(); ++k)
  {
    residual->InsertNextTuple3(0.0, 0.0, 0.0);
  }
  for (const auto& r : polyResidual)
  {
    residual->InsertNextTuple(r.data());
  }
  output->GetCellData()->AddArray(residual);
  vtkNew<vtkIdTypeArray> evaluationCount;
  evaluationCount->SetName("Evaluations");
  evaluationCount->InsertNextValue(static_cast<vtkIdType>(evaluations));
  output->GetFieldData()->AddArray(evaluationCount);
}
}

bool SampleAdaptively(vtkPenumbraRadianceEvaluator* self, vtkPolyData* samples,
  vtkPolyData* output, double sceneDiagonal,
  const std::function<RGB(int, const Vec3&)>& evaluatePoint, SampledSurfaceCache* cache,
  const std::string& context, int* reused)
{
  if (reused)
  {
    *reused = 0;
  }
  vtkDataArray* surfaceIds = samples->GetCellData()->GetArray("SurfaceId");
  vtkDataArray* orders = samples->GetCellData()->GetArray("DiscontinuityOrder");
  vtkDataArray* sources = samples->GetCellData()->GetArray("SourceId");
  if (!surfaceIds)
  {
    output->Initialize();
    vtkErrorWithObjectMacro(
      self, << "adaptive sampling needs the cell array 'SurfaceId' on the triangles");
    return false;
  }

  // Rebuild each surface's mesh (mesher layout) from the triangles and lines.
  std::map<int, ReceiverMesh> meshes;
  LocalIds localIds;
  std::vector<std::array<vtkIdType, 2>> lines;
  std::vector<vtkIdType> lineCells;
  const vtkIdType badCell =
    CollectTriangles(samples, surfaceIds, meshes, localIds, lines, lineCells);
  if (badCell >= 0)
  {
    output->Initialize();
    vtkErrorWithObjectMacro(self, << "cell " << badCell << " is not a triangle; adaptive sampling "
                  << "needs a triangle mesh (vtkPenumbraDiscontinuityMesher's output)");
    return false;
  }
  AttachSegments(lines, lineCells, surfaceIds, orders, sources, localIds, meshes);

  AdaptiveSamplingSettings settings;
  settings.SamplingTolerance = self->GetSamplingTolerance();
  settings.MaximumSamplesPerSurface = self->GetMaximumSamplesPerSurface();
  settings.MinimumFeatureSize = self->GetMinimumFeatureSize();
  settings.MaximumEdgeLength = self->GetMaximumSampleSpacing() * sceneDiagonal;

  std::vector<int> surfaces;
  std::vector<const ReceiverMesh*> receivers;
  for (const auto& entry : meshes)
  {
    surfaces.push_back(entry.first);
    receivers.push_back(&entry.second);
  }
  const std::vector<int> budgets =
    ShareSampleBudget(receivers, settings.MaximumSamplesPerSurface, self->GetMaximumSamples());
  std::vector<AdaptiveSamplingResult> results(receivers.size());
  std::vector<std::string> errors(receivers.size());
  // Surfaces sampled before with the same input, budget and context are
  // taken as they were; the rest are sampled, and kept for the next time.
  if (cache && cache->Context != context)
  {
    cache->Surfaces.clear();
    cache->Context = context;
  }
  std::vector<std::size_t> todo;
  for (std::size_t w = 0; w < receivers.size(); ++w)
  {
    const SampledSurfaceCache::Entry* kept = cache ? cache->Find(surfaces[w]) : nullptr;
    if (kept && kept->Budget == budgets[w] && SameMesh(kept->Input, *receivers[w]))
    {
      results[w] = kept->Result;
      if (reused)
      {
        ++*reused;
      }
    }
    else
    {
      todo.push_back(w);
    }
  }
  SampleReceivers(
    self, todo, surfaces, receivers, budgets, settings, evaluatePoint, results, errors);
  if (self->GetAbortExecute())
  {
    output->Initialize();
    return true;
  }
  for (std::size_t w = 0; w < receivers.size(); ++w)
  {
    if (!errors[w].empty())
    {
      output->Initialize();
      vtkErrorWithObjectMacro(self, << "surface " << surfaces[w] << ": " << errors[w]);
      return false;
    }
  }
  if (cache)
  {
    for (const std::size_t w : todo)
    {
      cache->Surfaces[surfaces[w]] = { *receivers[w], budgets[w], results[w] };
    }
  }
  // Where the budget stopped the refinement the tolerance is not met: the
  // user should know, and which settings to change.
  int capped = 0;
  int first = -1;
  for (std::size_t w = 0; w < receivers.size(); ++w)
  {
    if (results[w].Statistics.BudgetReached && capped++ == 0)
    {
      first = surfaces[w];
    }
  }
  if (capped > 0)
  {
    std::ostringstream message;
    message << capped << (capped == 1 ? " surface" : " surfaces") << " (the first: surface "
            << first << ") reached the sample budget before SamplingTolerance "
            << settings.SamplingTolerance << " was met there (MaximumSamples "
            << self->GetMaximumSamples() << " shared by area over the scene, at most "
            << "MaximumSamplesPerSurface " << settings.MaximumSamplesPerSurface
            << " each): raise them, or SamplingTolerance, for an even accuracy";
    self->Warn(message.str());
  }
  AssembleSampledMeshes(surfaces, results, output);
  return true;
}
}
