// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraShooterRadiance.h
 * @brief The (unshot) radiance of a shooting surface as a function over its
 * surface: a constant RGB value, or a piecewise-linear function given by a
 * triangle mesh in the shooter's plane with RGB values at its points.
 *
 * The progressive shooter (paper section 3) shoots the radiance a surface has
 * received but not yet distributed. After the first shot that radiance is not
 * uniform: it follows the shadows cast on the shooter. Lischinski, Tampieri and
 * Greenberg (section 5, Fig. 7 and 8) show that treating it as a constant
 * misplaces the light it sends out; both evaluators of the core therefore take
 * a ShooterRadiance and integrate it as the function it is.
 *
 * A mesh need not be conforming: a value discontinuity is modelled by two
 * triangles that do not share points. The function is zero off the mesh, so
 * the mesh should cover the shooter polygon exactly (a mesh larger than the
 * shooter is harmless to the exact evaluator, which integrates over the
 * visible part of the shooter only).
 */
#ifndef penumbraShooterRadiance_h
#define penumbraShooterRadiance_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraVector.h"

#include <array>
#include <vector>

namespace penumbra
{

/**
 * A linear RGB function of position in a plane:
 * L_c(p) = Value_c + Dot(Gradient[c], p - Origin) for channel c. The gradients
 * lie in the plane, so L is also defined (constant along the plane's normal)
 * at points off the plane.
 */
struct LinearRadiance
{
  Vec3 Origin;
  RGB Value;
  Vec3 Gradient[3];

  /// Value at p (any point in space; see above).
  RGB Evaluate(const Vec3& p) const
  {
    const Vec3 d = p - this->Origin;
    return { this->Value.R + Dot(this->Gradient[0], d), this->Value.G + Dot(this->Gradient[1], d),
      this->Value.B + Dot(this->Gradient[2], d) };
  }

  /// Whether every gradient is exactly zero (the function is constant).
  bool IsConstant() const
  {
    for (const Vec3& g : this->Gradient)
    {
      if (g.X != 0.0 || g.Y != 0.0 || g.Z != 0.0)
      {
        return false;
      }
    }
    return true;
  }

  /// The constant function `value`.
  static LinearRadiance MakeConstant(const RGB& value)
  {
    LinearRadiance f;
    f.Value = value;
    return f;
  }

  /**
   * The linear function interpolating `values` at the three points of a
   * triangle; its gradients lie in the triangle's plane. A degenerate
   * triangle gives the constant function values[0].
   */
  PENUMBRAVISIBILITY_EXPORT static LinearRadiance FromTriangle(const Vec3 points[3], const RGB values[3]);
};

/// One triangle of a piecewise-linear radiance: its points and their values.
struct RadianceTriangle
{
  Vec3 Points[3];
  RGB Values[3];
};

/**
 * The unshot radiance of a shooter, W sr^-1 m^-2 per channel: constant, or
 * piecewise linear over a triangle mesh lying in the shooter's plane.
 * Immutable after construction; every query is const and thread-safe.
 */
class PENUMBRAVISIBILITY_EXPORT ShooterRadiance
{
public:
  /// The constant zero radiance.
  ShooterRadiance() = default;

  /// The constant radiance `value` over the whole shooter.
  explicit ShooterRadiance(const RGB& value);

  /**
   * A piecewise-linear radiance: `triangles` index `points`, `values[i]` is
   * the radiance at points[i]. The triangles must lie in one plane (within
   * 1e-6 of the mesh's diameter); their orientation does not matter. Throws
   * InputError naming the offending point or triangle for: sizes that do not
   * match, no triangle, an index out of range, non-finite coordinates or
   * values, or points off the plane. Degenerate triangles (area below 1e-12
   * of the squared diameter) carry nothing and are dropped
   * (GetNumberOfDroppedTriangles()); a mesh with no other triangle throws.
   * Values may be negative (a linear function is integrated exactly
   * whatever its sign).
   */
  ShooterRadiance(std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles,
    std::vector<RGB> values);

  /// Whether the radiance is one constant value (no mesh).
  bool IsConstant() const { return this->Triangles.empty(); }

  /// The constant value (meaningful when IsConstant()).
  const RGB& GetConstantValue() const { return this->Constant; }

  /// Degenerate triangles the constructor dropped.
  int GetNumberOfDroppedTriangles() const { return this->DroppedTriangles; }

  /// Number of mesh triangles (0 for a constant radiance).
  int GetNumberOfTriangles() const { return static_cast<int>(this->Triangles.size()); }

  /// Triangle `i` in [0, GetNumberOfTriangles()), with its point values.
  RadianceTriangle GetTriangle(int i) const;

  /// The linear function of triangle `i` (as LinearRadiance::FromTriangle).
  const LinearRadiance& GetTriangleFunction(int i) const { return this->Functions[i]; }

  /// Area of triangle `i`.
  double GetTriangleArea(int i) const { return this->Areas[i]; }

  /// Mesh points, triangles and point values as given to the constructor.
  const std::vector<Vec3>& GetPoints() const { return this->Points; }
  const std::vector<std::array<int, 3>>& GetTriangles() const { return this->Triangles; }
  const std::vector<RGB>& GetValues() const { return this->Values; }

  /// Unit normal of the mesh's plane (zero vector for a constant radiance).
  const Vec3& GetPlaneNormal() const { return this->Normal; }

  /**
   * The index of a triangle containing the orthogonal projection of p onto
   * the mesh's plane, or -1 if there is none within 1e-9 of the mesh's
   * diameter (always -1 for a constant radiance). On a shared edge either
   * neighbour may be returned. Uses a uniform grid: O(1) expected.
   */
  int FindTriangle(const Vec3& p) const;

  /**
   * Radiance at p: the constant value, or the linear interpolation in the
   * triangle FindTriangle(p) returns, or zero off the mesh.
   */
  RGB Evaluate(const Vec3& p) const;

  /**
   * Integral of the radiance over the shooter, W sr^-1 (times pi: the
   * shooter's unshot power in watts). A constant radiance needs the
   * shooter's area `shooterArea` (>= 0); for a mesh the integral is exact
   * (area times the mean of the three point values, summed over triangles)
   * and `shooterArea` is ignored.
   */
  RGB Integrate(double shooterArea) const;

  /**
   * Set `ids` to the triangles (each once, in an order fixed by the grid)
   * whose bounding rectangle in the mesh's plane overlaps that of the
   * polygon `vertices` (projected onto the plane): a superset of the
   * triangles the polygon overlaps. Empty for a constant radiance. Uses the
   * uniform grid.
   */
  void FindTriangles(const Vec3* vertices, int count, std::vector<int>& ids) const;

private:
  void BuildGrid();
  void CellRange(double u0, double v0, double u1, double v1, int range[4]) const;

  RGB Constant;
  std::vector<Vec3> Points;
  std::vector<std::array<int, 3>> Triangles;
  int DroppedTriangles = 0;
  std::vector<RGB> Values;
  std::vector<LinearRadiance> Functions;
  std::vector<double> Areas;
  // Plane frame and grid of triangle ids (CSR layout).
  Vec3 Normal;
  Vec3 AxisU;
  Vec3 AxisV;
  double Tolerance = 0.0;
  double GridMin[2] = { 0.0, 0.0 };
  double GridMax[2] = { 0.0, 0.0 }; ///< of the triangles' bounding boxes
  double CellSize[2] = { 1.0, 1.0 };
  int GridSize[2] = { 0, 0 };
  std::vector<int> CellStarts;
  std::vector<int> CellItems;
  /// Per triangle: its rectangle in the plane (u0, v0, u1, v1) and the first
  /// grid cell (i, j) it is listed in, so that a query reports it once
  /// without sorting (from the first cell of the query's range it is in).
  std::vector<std::array<double, 4>> Boxes;
  std::vector<std::array<int, 2>> FirstCells;
};

} // namespace penumbra

#endif
