// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraSamplingReceiver.h
 * @brief Working state of one receiver in the adaptive sampler: its plane
 * frame, its refinable triangulation with the per-point tables, the radiance
 * samples of its vertices (one per side on order-0 lines and the outline),
 * and the conversions from the input mesh and to the result. Private to
 * Penumbra::Meshing.
 *
 * Design notes: Documentation/design/sampling.md
 */
#ifndef penumbraSamplingReceiver_h
#define penumbraSamplingReceiver_h

#include "penumbraAdaptiveSampler.h"
#include "penumbraMath.h"
#include "penumbraPlaneFrame.h"
#include "penumbraReceiverTriangulation.h"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{
namespace detail
{

/// Channel k (0 R, 1 G, 2 B) of c.
double Channel(const RGB& c, int k);

/// The receiver's plane frame.
struct Frame : PlaneFrame
{
  double LargestCoordinate = 0.0; // largest |coordinate| of the mesh's points
};

/// Throws InputError for settings out of range.
void CheckSettings(const AdaptiveSamplingSettings& s);

/// Validate the mesh and compute its frame: normal from the triangles'
/// summed cross products (their front), first axis along the longest outline
/// piece (else the first triangle edge), origin at the bounding-box centre.
Frame MakeFrame(const ReceiverMesh& mesh);

/// A radiance sample of a vertex: on an order-0 line, one per side, with the
/// direction (unit, in the plane) toward which it was taken.
struct SideSample
{
  double Du = 0.0, Dv = 0.0;
  bool Sided = false;
  RGB Value;
};

/// Working state of one receiver.
struct Receiver
{
  Frame F;
  double Diameter = 0.0;
  double SideOffset = 1e-9;
  std::vector<Vec3> Vertex3; // per vertex id (input ones exact)
  std::vector<std::vector<SideSample>> Samples; // per vertex id
  std::vector<double> FeatureSize; // per vertex id: see DiscontinuityLineLengths
  std::unique_ptr<RefinableTriangulation> Tri;
  RefinableSnapshot Snap;
  std::vector<int> CornerStart, Corners; // per point: (triangle * 3 + corner) list
  std::vector<char> PointSided;
  std::vector<RGB> Values; // per point
  std::size_t Irregularities = 0;

  P2 Vertex(int id) const { return this->Snap.Vertices[id]; }
  P2 PointUV(int p) const { return this->Snap.Vertices[this->Snap.PointVertex[p]]; }

  /// 3D position of a vertex (input vertices exact, others from the frame).
  Vec3 Position3(int vertex) const;
  /// Extract the current mesh and its per-point tables.
  void Refresh();
  /// Does direction d lie in the corner of one of point p's triangles?
  bool InSector(int p, double du, double dv) const;
  /// Offset of a point into triangle t (on its side): the unit direction
  /// toward t's centroid and the distance to move.
  void SideDirection(int t, const P2& at, double& du, double& dv, double& distance) const;
  /// Side sample direction of point p when its triangles form a fan with two
  /// free edges (a point of the outline or of an order-0 line): the bisector
  /// of the fan, so that a line crossing the boundary there at right angles
  /// (e.g. where a shooter's plane crosses the receiver's outline) keeps the
  /// point; returns false for a closed fan.
  bool FanBisector(int p, double& du, double& dv, double& distance) const;
  /// Side sample direction of point p: toward the centroid of its triangle
  /// with the largest angle at p (strictly inside the sector).
  int WidestTriangle(int p) const;
};

/// Build the working state from vertices (2D and 3D), segments and seeds.
void Prepare(Receiver& rec, const std::vector<P2>& vertices, const std::vector<Vec3>& vertex3,
  const std::vector<RefinableSegment>& segments, const std::vector<P2>& seeds);

/// The input mesh's vertices (compact ids in order of first use), segments
/// and triangle centroids in the frame.
void Decompose(const ReceiverMesh& mesh, const Frame& f, std::vector<P2>& vertices,
  std::vector<Vec3>& vertex3, std::vector<int>& vertexOfPoint,
  std::vector<RefinableSegment>& segments, std::vector<P2>& seeds);

/// Give every point of the current snapshot its value, evaluating the points
/// that have none (new vertices from irregular input, the initial mesh).
void AssignValues(Receiver& rec, const RadianceBatchFunction& evaluate,
  AdaptiveSamplingStatistics& stats);

/// The current samples as a SampleMesh (same point and triangle ids).
SampleMesh MakeSampleMesh(const Receiver& rec);

/// Area-weighted mean of the linear interpolant of the current values.
RGB MeanRadiance(const Receiver& rec);

/// Fill the result from the final state.
void Finish(const Receiver& rec, int receiverId, AdaptiveSamplingResult& result);

} // namespace detail
} // namespace penumbra

#endif
