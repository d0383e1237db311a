// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDecimator.h
 * @brief The state of one DecimateDisplay call (private), shared by its
 * set-up and output (penumbraDisplayDecimation.cxx) and its collapse checks
 * and collapses (penumbraDecimationCollapse.cxx).
 */
#ifndef penumbraDecimator_h
#define penumbraDecimator_h

#include "penumbraDisplayDecimation.h"
#include "penumbraReconstruction.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace penumbra
{
namespace detail
{

/**
 * A collapse is refused when a resulting triangle would hold more removed
 * points than this: the check of a collapse reads every removed point of
 * the triangles it changes, and without a bound a region of constant value
 * (an unlit face) would merge into a few triangles holding all its points,
 * each later check reading all of them. It caps the merging at about this
 * many points per triangle. The edge midpoints add about one and a half test
 * points per input triangle, so with them the cap is twice as high.
 */
constexpr std::size_t MaximumRemovedPerTriangle = 32;
constexpr std::size_t MaximumTestedPerTriangle = 64;
/// Smallest area of a resulting triangle, relative to its longest edge squared.
constexpr double MinimumShape = 1e-8;
/// Barycentric slack of the point location (relative).
constexpr double LocationSlack = 1e-9;
/// A point this far inside a triangle of a fan (barycentric) is in no other.
constexpr double InsideMargin = 1e-9;

struct Candidate
{
  double Cost;
  int From;
  int To;
  int Version;
  bool operator<(const Candidate& other) const { return this->Cost > other.Cost; } // min-heap
};

inline std::uint64_t EdgeKey(int a, int b)
{
  const std::uint32_t lo = static_cast<std::uint32_t>(std::min(a, b));
  const std::uint32_t hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

/// Merges the triangles of a display mesh by half-edge collapses (see DecimateDisplay).
class Decimator
{
public:
  /// The tolerances, features, stars and test points of `mesh`, decimated in place by Run.
  Decimator(ResampledMesh& mesh, const DecimationOptions& options);

  /// Collapse the cheapest allowed edges until none is within tolerance, then compact.
  DecimationStatistics Run();

private:
  // Test points past the mesh's points (ids from Points on) are edge
  // midpoints, held by the triangles like removed points.
  double U(int p) const
  {
    return p < this->Points ? this->Mesh.Points[2 * static_cast<std::size_t>(p)]
                            : this->Midpoints[2 * static_cast<std::size_t>(p - this->Points)];
  }

  double V(int p) const
  {
    return p < this->Points ? this->Mesh.Points[2 * static_cast<std::size_t>(p) + 1]
                            : this->Midpoints[2 * static_cast<std::size_t>(p - this->Points) + 1];
  }

  double Value(int p, int c) const
  {
    return p < this->Points
      ? this->Mesh.Values[static_cast<std::size_t>(p) * this->Channels + c]
      : this->MidpointValues[static_cast<std::size_t>(p - this->Points) * this->Channels + c];
  }

  /// The midpoint of every edge that is no feature (`edges`: the sorted keys
  /// of all triangles' edges, with repeats; `features`: sorted, unique),
  /// held by the first triangle of that edge. Along features the display is
  /// one-dimensional and its points suffice.
  void AddEdgeMidpoints(const std::vector<std::uint64_t>& edges,
    const std::vector<std::uint64_t>& features);

  double Area(int a, int b, int c) const
  {
    return 0.5 * ((this->U(b) - this->U(a)) * (this->V(c) - this->V(a)) -
      (this->V(b) - this->V(a)) * (this->U(c) - this->U(a)));
  }

  /// Whether the triangle is counter-clockwise with an area above
  /// MinimumShape times its longest edge squared.
  bool HasShape(const std::array<int, 3>& tri) const;

  /// Triangle t of u's star once u has moved into v: false when it goes (it
  /// has v), else its corners in `tri`.
  bool Moved(int t, int u, int v, std::array<int, 3>& tri) const;

  /// Barycentric coordinates of point p in triangle (a, b, c).
  void Barycentric(int p, int a, int b, int c, double w[3]) const;

  /// The other vertices of x's triangles, without repetition.
  void Neighbours(int x, std::vector<int>& out) const;

  /// The targets u may move into: any neighbour if it lies on no feature;
  /// along a straight run of features, its two neighbours there; none for
  /// corners, junctions and the ends of lines, nor when one of u's
  /// triangles has no shape (a star with a degenerate triangle, as where the
  /// two sides of a discontinuity meet, does not cover its region once:
  /// moving u could fold the mesh unseen).
  void Targets(int u, std::vector<int>& out) const;

  /// The cost of moving u into v: the largest error relative to the
  /// tolerance over u and the points its triangles hold, or a value above 1
  /// when the collapse is not allowed; without `all`, the queue's estimate:
  /// the error at u alone (the link condition is not checked).
  double Cost(int u, int v, bool all);

  /// The new triangle (u's star with u moved to v) holding p, or -1; the
  /// triangle `hint` (or -1) is tried first.
  int Locate(int p, int u, int v, double w[3], int hint) const;

  /// Locate in the checked collapse's new triangles (Fan): the same result
  /// as Locate, sooner. The fan covers its region once (Cost checked the
  /// link condition and the orientations), so a point well inside one of
  /// its triangles lies in no other.
  int LocateInFan(int p, double w[3], int hint) const;

  /// The tolerance at test point p, channel c.
  double PointTolerance(int p, int c) const;

  /// |display - value| of p after moving u into v, relative to the
  /// tolerance (`hint`: the triangle holding p now, or -1); `home` gets the
  /// triangle holding p then (-1 if none).
  double PointCost(int p, int u, int v, int hint, int& home) const;

  /// Queue u's cheapest allowed collapse, if any (a new version of u's entry).
  void Push(int u);

  /// Move u into v: its triangles with v go, the others take v, and the
  /// removed points they held move to the new triangles holding them.
  void Collapse(int u, int v);

  /// Write the kept points and live triangles back, in their old order.
  void Compact();

  /// The lines that met at removed joints become one polyline each, from
  /// one kept end to the other, held by the lowest-numbered of them.
  void JoinLines(std::vector<std::vector<int>>& polylines) const;

  ResampledMesh& Mesh;
  const int Channels;
  const int Points; ///< points of the mesh; test points past them are edge midpoints
  const std::size_t Cap;
  std::vector<double> Relative, Absolute; ///< per channel: the two parts of the tolerance
  const double LocalFraction;
  std::vector<double> Midpoints;      ///< (u, v) per test point (given, then edge midpoints)
  std::vector<double> MidpointValues; ///< Channels per test point
  std::vector<int> LineEnds;          ///< per line: its first and last point (or -1)
  std::vector<char> Joint;            ///< per point: two lines of a group meet there alone
  std::vector<std::pair<int, int>> Homes; ///< the last full check's (point, triangle)
  /// A triangle of the checked collapse's star after the move: its id, its
  /// corners and its area.
  struct FanTriangle
  {
    int Triangle;
    std::array<int, 3> Corners;
    double Area;
  };
  std::vector<FanTriangle> Fan;
  std::array<int, 2> HomesOf = { { -1, -1 } }; ///< the collapse Homes belongs to
  std::vector<double> Tolerance;
  std::vector<std::array<int, 3>> Triangles;
  std::vector<char> Alive;
  std::vector<std::vector<int>> Removed; ///< per triangle: removed points inside it
  std::vector<std::vector<int>> Stars;   ///< per point: its live triangles
  std::vector<std::vector<int>> Features; ///< per point: its neighbours along features
  std::vector<char> Gone;
  std::vector<char> Pinned; ///< per point: the end of a line, not a joint
  std::vector<int> Version;
  std::vector<char> Queued; ///< per point: whether it has an entry in Queue
  std::priority_queue<Candidate> Queue;
  std::vector<int> Scratch0, Scratch1;
};

} // namespace detail
} // namespace penumbra

#endif
