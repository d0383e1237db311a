// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraScreens.h
 * @brief Screens of a (shooter, receiver) pair: large convex polygons lying
 * between the two, which hide whole occluder features from the receiver
 * (the books on a shelf from the floor under it, the books in a bookcase
 * from the wall behind its back). A hidden feature is on no visible event
 * line, so its wedges need not be traced. Private (not installed).
 *
 * Design notes: Documentation/design/meshing.md
 */
#ifndef penumbraScreens_h
#define penumbraScreens_h

#include "penumbraSceneTopology.h"

#include <vector>

namespace penumbra
{
namespace detail
{

/**
 * The screens of one pair, and the test of a feature against them.
 *
 * A screen is a convex polygon whose plane has the whole shooter strictly
 * on one side and the whole receiver strictly on the other. Every event
 * line through a feature runs from a shooter point through the feature to
 * the receiver, so it crosses the screen's plane between the feature and
 * the receiver when the feature lies between the shooter and that plane.
 * For fixed shooter point the crossing moves projectively with the feature
 * point, and for a fixed feature point with the shooter point, so every
 * crossing lies in the convex hull of the crossings of the lines through a
 * shooter vertex and a feature end. When that hull is inside the screen,
 * every such line is blocked: exactly, not as an estimate.
 */
class ScreenSet
{
public:
  /// The screens among `candidates` (the pair's shaft candidates): the
  /// `maximum` largest convex polygons separating shooter and receiver by
  /// more than `tolerance`.
  void Build(const SceneTopology& topology, const std::vector<int>& candidates,
    const PolygonData& shooter, const PolygonData& receiver, double tolerance, int maximum);

  /// Whether one screen hides the feature (a vertex, count 1, or an edge,
  /// count 2) from the receiver for every line from the shooter.
  bool Hides(const Vec3* points, int count);

  int GetNumberOfScreens() const { return static_cast<int>(this->Screens.size()); }

private:
  struct Screen
  {
    Vec3 Normal;   ///< unit, towards the shooter
    double Offset; ///< plane: Dot(Normal, x) == Offset
    double NearestShooter; ///< smallest height of a shooter vertex over the plane
    std::vector<double> ShooterHeights;
    std::vector<Vec3> EdgeNormals; ///< in the plane, pointing inside
    std::vector<double> EdgeOffsets; ///< inside: Dot(EdgeNormals[k], x) >= EdgeOffsets[k]
  };
  bool Inside(const Screen& screen, const Vec3& x) const;
  bool HidesBehind(const Screen& screen, const Vec3* points, int count) const;

  std::vector<Screen> Screens;
  std::vector<Vec3> ShooterVertices;
  double Tolerance = 0.0;
  int Last = 0; ///< the screen that hid the last feature: neighbours often share it
};

} // namespace detail
} // namespace penumbra

#endif
