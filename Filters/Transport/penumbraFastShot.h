// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraFastShot.h
 * @brief The fast method of a shot at one point (private): the shooter's
 * hierarchy cut where its nodes look small, one multipole expansion per
 * node used, visibility by occlusion rays refined where it varies, and near
 * leaves split and integrated in closed form (Documentation/design/
 * transport.md, "The fast shot").
 */
#ifndef penumbraFastShot_h
#define penumbraFastShot_h

#include "penumbraShot.h"
#include "penumbraSurfaceSamples.h"
#include "penumbraVector.h"
#include "penumbraVisibilityQueue.h"

#include <array>
#include <vector>

namespace penumbra
{

class RayCaster;
struct TransportUnit;

/// Deepest split of a near leaf by the fast method (pieces 1/2^NearDepth of the leaf).
constexpr int NearDepth = 10;

/// A piece of a near leaf being refined.
struct Piece
{
  Vec3 Points[3];
  RGB Values[3];
  int Depth;
};

/// Scratch memory of the fast method, one per chunk of a shot's parallel loop.
struct FastWorkspace
{
  std::vector<int> Near;      ///< near leaves of the current sample
  std::vector<Piece> Pieces;  ///< refinement stack of a near leaf
  std::vector<RGB> Weights;   ///< irradiance of each near piece, if visible
  std::vector<int> TargetLeaves; ///< near pieces: the leaf each target lies on
  std::vector<int> Stack;
  std::vector<int> Current; ///< nodes whose visibility is tested in this round
  std::vector<int> Next;
  VisibilityQueue Rays;     ///< the rays of the current round
  std::vector<int> Roots;   ///< nodes each point handles on its own (a receiver cluster's rest)
  std::vector<int> Visible; ///< receiver cluster: visible nodes far from every point
  std::vector<unsigned char> Flags; ///< receiver cluster: per target, the origins that see it
  PointBatch Batch; ///< receiver cluster: its points, the visible far nodes summed at each
};

/**
 * The fast method's hierarchy of surface `j` alone (front normal `normal`):
 * the `kept` triangles of `points` (s's points projected onto its plane)
 * with s's unshot radiance, split until no longer than `size`, moments
 * about hierarchy.Origin (set by the caller).
 */
void PrepareFastShooter(const SurfaceSamples& s, const std::vector<Vec3>& points,
  const std::vector<std::array<int, 3>>& kept, double size, int j, const Vec3& normal,
  ShooterHierarchy& hierarchy);

/**
 * The fast method at x (unit normal n, on surface `receiver`), rays from
 * `origin`, over the subtrees of the shot's hierarchy rooted at `roots`
 * (the root alone for the whole shooter). Unclamped (see NonNegative).
 * Adds the rays traced to `rays`. With `record`, the visible nodes and near
 * pieces are appended to it (penumbraRecordedTransport.h) instead of
 * summed, and the result is 0.
 */
RGB EvaluateFast(const Shot& shot, const Vec3& x, const Vec3& origin, const Vec3& n, int receiver,
  const std::vector<int>& roots, const RayCaster& caster, FastWorkspace& ws, long long& rays,
  TransportUnit* record = nullptr);

} // namespace penumbra

#endif
