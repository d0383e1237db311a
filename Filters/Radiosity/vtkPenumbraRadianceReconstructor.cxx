// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraRadianceReconstructor.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include "penumbraReconstruction.h"
#include "penumbraScene.h"
#include "penumbraSliverRepair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>
#include <unordered_map>

vtkStandardNewMacro(vtkPenumbraRadianceReconstructor);

vtkPenumbraRadianceReconstructor::vtkPenumbraRadianceReconstructor()
{
  const penumbra::ReconstructionOptions interpolant;
  const penumbra::ResampleOptions display;
  this->Mode = interpolant.Mode == penumbra::ReconstructionMode::Linear ? LINEAR : CLOUGH_TOCHER;
  this->EnforceNonNegativity = interpolant.EnforceNonNegativity;
  this->DisplayTolerance = display.DisplayTolerance;
  this->CompactTolerance = display.CompactTolerance;
  this->CompactIndirectTolerance = display.CompactIndirectTolerance;
  this->SubdivisionLevel = display.SubdivisionLevel;
  this->TargetEdgeLength = display.TargetEdgeLength;
  this->ComputeErrorEstimate = display.ComputeErrorEstimate;
}

namespace
{
/// The cells of one surface, by kind (input cell ids and point ids).
struct SurfaceCells
{
  std::vector<std::array<vtkIdType, 3>> Triangles;
  std::vector<std::array<vtkIdType, 2>> Lines;
  std::vector<int> LineOrders;
  std::vector<int> LineSources;
  /// Largest residual of adaptive sampling per triangle (empty if unknown).
  std::vector<std::array<double, 3>> Residuals;
};

/// One surface's reconstructed output, in its own point numbering.
struct SurfaceOutput
{
  std::vector<penumbra::Vec3> Points;
  std::vector<double> Radiance;
  std::vector<double> Error;
  std::vector<int> Triangles;
  std::vector<std::vector<int>> Lines;
  std::vector<int> LineOrders;
  std::vector<int> LineSources;
  int RepairedSlivers = 0; ///< see penumbra::RepairSlivers
};

penumbra::Vec3 GetPoint(vtkPoints* points, vtkIdType id)
{
  double p[3];
  points->GetPoint(id, p);
  return { p[0], p[1], p[2] };
}

/// A frame in a surface's plane.
struct SurfaceFrame
{
  penumbra::Vec3 Origin;
  penumbra::Vec3 AxisU;
  penumbra::Vec3 AxisV;
};

/// The frame of the triangles' plane: normal from their area vectors, U
/// along the first edge not parallel to it.
SurfaceFrame FrameOfTriangles(const SurfaceCells& cells, vtkPoints* points)
{
  penumbra::Vec3 normal;
  for (const auto& t : cells.Triangles)
  {
    const penumbra::Vec3 a = GetPoint(points, t[0]);
    normal += penumbra::Cross(GetPoint(points, t[1]) - a, GetPoint(points, t[2]) - a);
  }
  normal = penumbra::Normalized(normal);
  SurfaceFrame frame;
  frame.Origin = GetPoint(points, cells.Triangles[0][0]);
  for (const auto& t : cells.Triangles)
  {
    const penumbra::Vec3 edge = GetPoint(points, t[1]) - GetPoint(points, t[0]);
    frame.AxisU = penumbra::Normalized(edge - normal * penumbra::Dot(edge, normal));
    if (penumbra::SquaredLength(frame.AxisU) > 0.5)
    {
      break;
    }
  }
  frame.AxisV = penumbra::Cross(normal, frame.AxisU);
  return frame;
}

/// Reconstruct one surface; throws penumbra::InputError.
void ReconstructSurface(const SurfaceCells& cells, vtkPoints* points, vtkDataArray* radiance,
  const penumbra::ReconstructionOptions& options, const penumbra::ResampleOptions& resample,
  SurfaceOutput& out)
{
  const SurfaceFrame frame = FrameOfTriangles(cells, points);
  const penumbra::Vec3& origin = frame.Origin;
  const penumbra::Vec3& axisU = frame.AxisU;
  const penumbra::Vec3& axisV = frame.AxisV;

  penumbra::SampleMesh mesh;
  mesh.NumberOfChannels = 3;
  std::unordered_map<vtkIdType, int> local;
  std::vector<vtkIdType> global;
  auto localId = [&](vtkIdType id) {
    auto found = local.find(id);
    if (found != local.end())
    {
      return found->second;
    }
    const penumbra::Vec3 d = GetPoint(points, id) - origin;
    double value[3];
    radiance->GetTuple(id, value);
    const int k = mesh.AddPoint(penumbra::Dot(d, axisU), penumbra::Dot(d, axisV), value);
    local.emplace(id, k);
    global.push_back(id);
    return k;
  };
  for (const auto& t : cells.Triangles)
  {
    mesh.AddTriangle(localId(t[0]), localId(t[1]), localId(t[2]));
  }
  std::vector<std::size_t> keptLines;
  for (std::size_t k = 0; k < cells.Lines.size(); ++k)
  {
    auto a = local.find(cells.Lines[k][0]);
    auto b = local.find(cells.Lines[k][1]);
    if (a != local.end() && b != local.end() && cells.LineOrders[k] >= -1 &&
      cells.LineOrders[k] <= 2)
    {
      mesh.AddConstrainedEdge(a->second, b->second, cells.LineOrders[k]);
      mesh.EdgeLabels.push_back(cells.LineSources[k]);
      keptLines.push_back(k);
    }
  }

  // The projection into this frame can turn a sampler's slivers clockwise.
  const penumbra::SliverRepairResult repair = penumbra::RepairSlivers(mesh);
  out.RepairedSlivers = repair.GetNumberOfRepairs();
  std::vector<std::size_t> lineOfEdge(repair.EdgeOrigin.size());
  for (std::size_t e = 0; e < lineOfEdge.size(); ++e)
  {
    lineOfEdge[e] = keptLines[static_cast<std::size_t>(repair.EdgeOrigin[e])];
  }
  keptLines = std::move(lineOfEdge);

  penumbra::Reconstruction reconstruction;
  reconstruction.Build(mesh, options);

  penumbra::ErrorProbes probes;
  for (std::size_t t = 0; t < cells.Residuals.size(); ++t)
  {
    const int repaired = repair.TriangleMap[t];
    if (cells.Residuals[t][0] >= 0.0 && repaired >= 0) // negative: the triangle was not probed
    {
      probes.Add(repaired, cells.Residuals[t].data(), 3);
    }
  }

  penumbra::ResampledMesh result;
  reconstruction.Resample(resample, result, probes.Triangles.empty() ? nullptr : &probes);
  const int n = result.GetNumberOfPoints();
  out.Points.resize(static_cast<std::size_t>(n));
  for (int p = 0; p < n; ++p)
  {
    const int source = result.SourcePoint[p];
    out.Points[p] = source >= 0
      ? GetPoint(points, global[source])
      : origin + axisU * result.Points[2 * p] + axisV * result.Points[2 * p + 1];
  }
  out.Radiance = std::move(result.Values);
  out.Error = std::move(result.ErrorEstimate);
  out.Triangles = std::move(result.Triangles);
  for (std::size_t k = 0; k < keptLines.size(); ++k)
  {
    const int first = result.LineOffsets[k], last = result.LineOffsets[k + 1];
    if (last - first >= 2)
    {
      out.Lines.emplace_back(result.LinePoints.begin() + first, result.LinePoints.begin() + last);
      out.LineOrders.push_back(cells.LineOrders[keptLines[k]]);
      out.LineSources.push_back(cells.LineSources[keptLines[k]]);
    }
  }
}
/// Sort the cells by surface (cell ids run over verts, lines, polys, strips).
/// Returns the error for cells that cannot be reconstructed, empty if none.
std::string SortCellsBySurface(vtkPolyData* input, vtkDataArray* surfaceIds,
  vtkDataArray* orders, vtkDataArray* sources, vtkDataArray* residuals,
  std::map<int, SurfaceCells>& surfaces)
{
  std::string error;
  penumbra::ForEachCell(
    input, [&](vtkIdType cellId, int kind, vtkIdType npts, const vtkIdType* pts) {
      if (kind == 3)
      {
        error = "triangle strips are not supported; triangulate the sample mesh first";
        return false;
      }
      SurfaceCells& cells = surfaces[static_cast<int>(surfaceIds->GetComponent(cellId, 0))];
      if (kind == 0)
      {
        return true; // vertex cells carry nothing to reconstruct
      }
      if (kind == 1)
      {
        for (vtkIdType k = 0; k + 1 < npts; ++k)
        {
          cells.Lines.push_back({ pts[k], pts[k + 1] });
          cells.LineOrders.push_back(orders ? static_cast<int>(orders->GetComponent(cellId, 0)) : 2);
          cells.LineSources.push_back(
            sources ? static_cast<int>(sources->GetComponent(cellId, 0)) : -1);
        }
        return true;
      }
      if (npts != 3)
      {
        error = "cell " + std::to_string(cellId) + " is a polygon with " + std::to_string(npts) +
          " points; the sample mesh must be triangles";
        return false;
      }
      cells.Triangles.push_back({ pts[0], pts[1], pts[2] });
      if (residuals)
      {
        std::array<double, 3> r;
        residuals->GetTuple(cellId, r.data());
        cells.Residuals.push_back(r);
      }
      return true;
    });
  return error;
}

/// Reconstruct the surfaces in parallel. Returns the first error
/// ("surface <id>: ..."), empty if none.
std::string ReconstructSurfaces(const std::vector<int>& ids,
  const std::vector<const SurfaceCells*>& work, vtkPoints* points, vtkDataArray* radiance,
  const penumbra::ReconstructionOptions& options, const penumbra::ResampleOptions& resample,
  std::vector<SurfaceOutput>& results)
{
  std::string error;
  std::mutex errorMutex;
  vtkSMPTools::For(0, static_cast<vtkIdType>(work.size()), [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType s = first; s < last; ++s)
    {
      try
      {
        ReconstructSurface(*work[s], points, radiance, options, resample, results[s]);
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> lock(errorMutex);
        if (error.empty())
        {
          error = "surface " + std::to_string(ids[s]) + ": " + e.what();
        }
      }
    }
  });
  return error;
}

/// The surfaces' reconstructions, in surface order, as the output polydata.
/// With the surfaces' materials, the values (L^e + rho_t E / pi, see
/// BlackTrackingReflectance) become Radiance and Irradiance; without them the
/// values are written as Radiance.
void AssembleOutput(const std::vector<int>& ids, const std::vector<SurfaceOutput>& results,
  bool computeErrorEstimate, const penumbra::SurfaceMaterials* materials, vtkPolyData* output)
{
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> outLines, outPolys;
  vtkNew<vtkDoubleArray> outRadiance, outError, outIrradiance;
  outRadiance->SetName("Radiance");
  outRadiance->SetNumberOfComponents(3);
  outIrradiance->SetName("Irradiance");
  outIrradiance->SetNumberOfComponents(3);
  outError->SetName("RadianceErrorEstimate");
  outError->SetNumberOfComponents(3);
  std::vector<int> lineSurface, lineOrder, lineSource, polySurface;
  for (std::size_t s = 0; s < results.size(); ++s)
  {
    const SurfaceOutput& r = results[s];
    const vtkIdType offset = outPoints->GetNumberOfPoints();
    penumbra::RGB emission, share(1.0, 1.0, 1.0), toIrradiance;
    if (materials)
    {
      const penumbra::RGB& rho = materials->Reflectance[ids[s]];
      const penumbra::RGB tracked = penumbra::TrackedReflectance(rho);
      emission = materials->Emission[ids[s]];
      share = penumbra::ReflectedShare(rho);
      toIrradiance = penumbra::RGB(M_PI / tracked.R, M_PI / tracked.G, M_PI / tracked.B);
    }
    for (std::size_t p = 0; p < r.Points.size(); ++p)
    {
      outPoints->InsertNextPoint(r.Points[p].X, r.Points[p].Y, r.Points[p].Z);
      const double* value = &r.Radiance[3 * p];
      if (materials)
      {
        double radiance[3], irradiance[3];
        for (int c = 0; c < 3; ++c)
        {
          radiance[c] = share[c] > 0.0 ? value[c] : emission[c];
          irradiance[c] = toIrradiance[c] * std::max(0.0, value[c] - emission[c]);
        }
        outRadiance->InsertNextTuple(radiance);
        outIrradiance->InsertNextTuple(irradiance);
      }
      else
      {
        outRadiance->InsertNextTuple(value);
      }
      if (computeErrorEstimate)
      {
        const double* error = &r.Error[3 * p];
        // The estimate of a black channel is its irradiance's, scaled by rho_t.
        outError->InsertNextTuple3(share[0] * error[0], share[1] * error[1], share[2] * error[2]);
      }
    }
    for (std::size_t t = 0; t + 2 < r.Triangles.size(); t += 3)
    {
      const vtkIdType tri[3] = { offset + r.Triangles[t], offset + r.Triangles[t + 1],
        offset + r.Triangles[t + 2] };
      outPolys->InsertNextCell(3, tri);
      polySurface.push_back(ids[s]);
    }
    for (std::size_t k = 0; k < r.Lines.size(); ++k)
    {
      outLines->InsertNextCell(static_cast<vtkIdType>(r.Lines[k].size()));
      for (int p : r.Lines[k])
      {
        outLines->InsertCellPoint(offset + p);
      }
      lineSurface.push_back(ids[s]);
      lineOrder.push_back(r.LineOrders[k]);
      lineSource.push_back(r.LineSources[k]);
    }
  }
  output->SetPoints(outPoints);
  output->SetLines(outLines);
  output->SetPolys(outPolys);
  output->GetPointData()->AddArray(outRadiance);
  output->GetPointData()->SetActiveScalars("Radiance");
  if (materials)
  {
    output->GetPointData()->AddArray(outIrradiance);
  }
  if (computeErrorEstimate)
  {
    output->GetPointData()->AddArray(outError);
  }
  penumbra::AddMeshCellArrays(output, lineSurface, lineOrder, lineSource, polySurface);
}
}

int vtkPenumbraRadianceReconstructor::Execute(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  if (!input || input->GetNumberOfPolys() == 0)
  {
    return 1;
  }
  vtkDataArray* radiance = input->GetPointData()->GetArray("Radiance");
  vtkDataArray* surfaceIds = input->GetCellData()->GetArray("SurfaceId");
  vtkDataArray* orders = input->GetCellData()->GetArray("DiscontinuityOrder");
  vtkDataArray* sources = input->GetCellData()->GetArray("SourceId");
  vtkDataArray* residuals = input->GetCellData()->GetArray("SamplingResidual");
  if (residuals && residuals->GetNumberOfComponents() != 3)
  {
    residuals = nullptr;
  }
  if (!radiance || radiance->GetNumberOfComponents() != 3)
  {
    vtkErrorMacro(<< "the input needs a 3-component point array 'Radiance' "
                     "(run vtkPenumbraRadianceEvaluator first)");
    return 0;
  }
  if (!surfaceIds)
  {
    vtkErrorMacro(<< "the input needs a cell array 'SurfaceId'");
    return 0;
  }

  std::map<int, SurfaceCells> surfaces;
  std::string error = SortCellsBySurface(input, surfaceIds, orders, sources, residuals, surfaces);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }

  penumbra::ReconstructionOptions options;
  options.Mode = this->Mode == LINEAR ? penumbra::ReconstructionMode::Linear
                                      : penumbra::ReconstructionMode::CloughTocher;
  options.EnforceNonNegativity = this->EnforceNonNegativity;
  penumbra::ResampleOptions resample;
  resample.DisplayTolerance = this->DisplayTolerance;
  resample.CompactTolerance = this->CompactTolerance;
  resample.CompactIndirectTolerance = this->CompactIndirectTolerance;
  // The indirect part applies where the interreflections were shot on the
  // coarse level (a positive IndirectSpacing), whose blur is the error it
  // stands for.
  vtkDataArray* indirect = input->GetFieldData()->GetArray("MeanIndirectRadiance");
  vtkDataArray* spacing = input->GetFieldData()->GetArray("IndirectSpacing");
  if (indirect && spacing && spacing->GetNumberOfTuples() == 1 && spacing->GetComponent(0, 0) > 0.0)
  {
    if (indirect->GetNumberOfComponents() == 3 && indirect->GetNumberOfTuples() == 1)
    {
      for (int c = 0; c < 3; ++c)
      {
        resample.IndirectRadiance.push_back(std::max(0.0, indirect->GetComponent(0, c)));
      }
    }
  }
  resample.SubdivisionLevel = this->SubdivisionLevel;
  resample.TargetEdgeLength = this->TargetEdgeLength;
  resample.ComputeErrorEstimate = this->ComputeErrorEstimate;

  std::vector<int> ids;
  std::vector<const SurfaceCells*> work;
  for (const auto& entry : surfaces)
  {
    if (!entry.second.Triangles.empty())
    {
      ids.push_back(entry.first);
      work.push_back(&entry.second);
    }
  }
  std::vector<SurfaceOutput> results(work.size());
  this->UpdateProgress(0.0);
  error =
    ReconstructSurfaces(ids, work, input->GetPoints(), radiance, options, resample, results);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  int slivers = 0, sliverSurfaces = 0, firstSliverSurface = -1;
  for (std::size_t s = 0; s < results.size(); ++s)
  {
    if (results[s].RepairedSlivers > 0)
    {
      slivers += results[s].RepairedSlivers;
      if (sliverSurfaces++ == 0)
      {
        firstSliverSurface = ids[s];
      }
    }
  }
  if (slivers > 0)
  {
    std::ostringstream message;
    message << "repaired " << slivers
            << " sample triangle(s) with zero or negative area in their surface's plane "
            << "(slivers within rounding of an edge) on " << sliverSurfaces
            << " surface(s), the first surface " << firstSliverSurface;
    this->Warn(message.str());
  }
  penumbra::SurfaceMaterials materials;
  const bool known = penumbra::GetSurfaceMaterials(input->GetFieldData(), materials) &&
    (ids.empty() || ids.back() < static_cast<int>(materials.Reflectance.size()));
  AssembleOutput(ids, results, this->ComputeErrorEstimate, known ? &materials : nullptr, output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPenumbraRadianceReconstructor::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << (this->Mode == LINEAR ? "LINEAR" : "CLOUGH_TOCHER") << "\n";
  os << indent << "DisplayTolerance: " << this->DisplayTolerance << "\n";
  os << indent << "CompactTolerance: " << this->CompactTolerance << "\n";
  os << indent << "CompactIndirectTolerance: " << this->CompactIndirectTolerance << "\n";
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "TargetEdgeLength: " << this->TargetEdgeLength << "\n";
  os << indent << "EnforceNonNegativity: " << (this->EnforceNonNegativity ? "On" : "Off") << "\n";
  os << indent << "ComputeErrorEstimate: " << (this->ComputeErrorEstimate ? "On" : "Off") << "\n";
}
