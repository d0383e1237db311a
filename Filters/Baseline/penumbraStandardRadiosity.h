// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraStandardRadiosity.h
 * @brief Standard radiosity, the baseline the paper beat: a uniform mesh of
 * constant-radiosity elements, progressive refinement (Cohen, Chen, Wallace
 * and Greenberg 1988) with vertex-to-patch form factors by ray casting
 * (Wallace, Elmquist and Haines 1989), adaptive subdivision where the
 * radiosity of neighbouring vertices differs by more than a threshold
 * (Cohen, Greenberg, Immel and Brock 1986), Gouraud display.
 *
 * Mesh. Each surface is triangulated (the ear triangles of RayCaster), each
 * triangle cut uniformly into m x m patches (m from PatchSize, one m per
 * surface so that shared edges match), each patch into k x k elements (k
 * from ElementSize). Patches shoot, elements receive (Cohen et al. 1986's
 * substructuring): a patch's unshot power is the sum of its elements'.
 * Elements are triangles split 1 -> 4 at their edge midpoints by the
 * adaptive subdivision; a midpoint shared with an unsplit neighbour is a
 * T-vertex, which the display triangulation includes (no cracks).
 *
 * Radiosity (here radiance L = B / pi, W sr^-1 m^-2) is computed at the mesh
 * vertices; an element's radiance is the mean of its three corners' (the
 * constant value it shoots and absorbs with); the display interpolates the
 * vertex values linearly over the elements.
 *
 * A shot. j = the patch with the largest unshot power (mean of RGB; ties:
 * lowest id) shoots its unshot radiance dL_j (power / (pi A_j), constant).
 * Every vertex x (unit normal n) of every other surface receives
 *   L(x) += rho dL_j F(x, j),
 * every element e: Unshot_e += rho dL_j mean of F over its corners; then
 * j's elements' unshot radiance is zeroed. F(x, j), the form factor from
 * the differential area at x to patch j, comes from s x s sample points
 * y_k (the centroids of a uniform s x s subdivision of j, s =
 * ShooterSamples), each with the disc weight of Wallace et al.
 *   w_k = cos(theta_x) cos(theta_y) A_k / (pi r_k^2 + A_k)
 * and an Embree occlusion ray V_k:
 * - FormFactorMode::Disc (Wallace et al. as published): F = sum V_k w_k.
 *   The disc approximation errs where x is closer to j than j's size, and
 *   misses the near field altogether: a vertex at the foot of a wall gets
 *   almost nothing from the wall, whose light comes from within a few
 *   vertex-to-wall distances (the furnace test: -57 % on the box's edges).
 * - FormFactorMode::AnalyticVisibility (default, "reasonably tuned"): F =
 *   F_0 * sum V_k w_k / sum w_k, where F_0 is the unoccluded form factor in
 *   closed form (Lambert's formula, penumbraFormFactor.h) of j clipped to
 *   x's front half-space. Exact when j is wholly visible or hidden; the
 *   visibility is a weighted fraction of s x s rays otherwise.
 *
 * Adaptive subdivision. After each shot, a leaf element shallower than
 * MaximumSubdivisionDepth is split when the largest difference of vertex
 * radiance (mean of RGB) among its corners and T-vertices exceeds
 * SubdivisionThreshold times the larger of its brightest vertex's radiance
 * and the reference radiance (the emitted power spread over all surfaces:
 * P_e / (pi A), mean of RGB; it keeps dark regions from being refined for
 * differences nobody sees); the children are checked again, until nothing
 * splits. A new vertex then gathers all
 * past shots (each patch with the dL it shot: the shot history), so its
 * value is what it would have been had it existed from the start; the
 * children inherit their parent's unshot radiance (power is conserved).
 * What the parent received before the split was measured at its corners
 * only, a real error of the method: in the furnace, where transient
 * differences of the shooting order trigger splits, it leaves 1 % (no
 * subdivision: 3e-7; TestStandardRadiosity).
 *
 * Vertices on a surface's outline (in the plane of a wall that meets the
 * floor there, say) are evaluated 1e-4 of the scene's size inside the
 * surface, as the limit from inside; otherwise they would not see the wall.
 *
 * Energy, per channel: Emitted = Absorbed + Escaped + Unshot by
 * construction, where a shot's incident power is sum_e A_e pi dL_j
 * mean(F) over the receiving elements, absorbed (1 - rho) of it, and the
 * rest of the shot's power escaped (left an open scene, or the form
 * factors' discretisation error: ~0 in a closed box with the analytic mode).
 *
 * Accuracy and cost (measured; TestStandardRadiosity, speed_accuracy.py).
 * Unoccluded direct light on a floor, displayed error at independent points
 * (RMS / mean) for element sizes 0.2, 0.1, 0.05, 0.025: 1.9 %, 0.70 %,
 * 0.18 %, 0.049 % (second order, as linear interpolation). With occluders
 * the penumbrae are sampled by the s x s rays and the elements: the
 * default settings give 2.7 % on the paper's Fig. 3 floor and 43 % on the
 * venetian blind; element size 0.025 and s = 8 give 1.9 % and 12 %, and
 * with a threshold of 0.05 besides 1.4 % and 2 % (2.6 to 3.6 times slower
 * than that mesh with the default threshold). Cornell box with the
 * defaults: 619 shots, 11,000 vertices, 12-20 s on 2 cores, 3.6 % RMS on
 * the floor and 3.4 % on the back wall against the Mitsuba reference; the
 * coarse shooting patches dominate that error: PatchSize 0.2 gives 1.7 %
 * and 1.2 % in about 6 times the time.
 *
 * Threads: each shot's vertices, and each round's new vertices, are a
 * parallel loop through the caller's ParallelFor; each vertex is computed
 * independently and all sums are formed serially in a fixed order, so the
 * results do not depend on the thread count.
 */
#ifndef penumbraStandardRadiosity_h
#define penumbraStandardRadiosity_h

#include "penumbraBaselineModule.h" // for export macro
#include "penumbraProgressiveShooter.h" // for ParallelFor, ShotRecord, ShootingEnergy, StopReason
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <array>
#include <memory>
#include <vector>

namespace penumbra
{

/// How StandardRadiosity computes a vertex-to-patch form factor.
enum class FormFactorMode
{
  AnalyticVisibility = 0, ///< closed-form unoccluded F times the ray-cast visible fraction
  Disc = 1                ///< sum of Wallace et al.'s disc terms of the visible samples
};

/// Settings of StandardRadiosity; defaults in brackets.
struct StandardRadiositySettings
{
  /// Longest patch edge (shooters), relative to the scene's size
  /// (Scene::Size). Smaller patches shoot more faithfully but need more
  /// shots. [0.5], in (0, 1]
  double PatchSize = 0.5;
  /// Longest element edge of the initial mesh (receivers), relative to the
  /// scene's size; no larger than PatchSize in effect. [0.05], in (0, 1]
  double ElementSize = 0.05;
  /// Visibility samples per patch edge: s x s occlusion rays from each
  /// vertex to each shooting patch. [4], in [1, 32]
  int ShooterSamples = 4;
  /// The form factor (see the file comment). [AnalyticVisibility]
  FormFactorMode FormFactor = FormFactorMode::AnalyticVisibility;
  /// Split an element when its vertices' radiances differ by more than this
  /// times the larger of its brightest vertex's radiance and the reference
  /// radiance (see the file comment). [0.2], in (0, inf]; inf never splits.
  double SubdivisionThreshold = 0.2;
  /// Deepest adaptive subdivision (each level quarters an element). [3], in [0, 12]
  int MaximumSubdivisionDepth = 3;
  /// Stop when the unshot power (mean of RGB) is at most this fraction of
  /// the emitted power. [1e-3], in [0, 1]
  double UnshotFraction = 1e-3;
  /// Largest number of shots. [10000], >= 0
  int MaximumShots = 10000;

  /// Throws InputError naming the first setting out of its range.
  PENUMBRABASELINE_EXPORT void Validate() const;
};

/// Result of StandardRadiosity::Run.
struct StandardRadiositySummary
{
  StopReason Reason = StopReason::Converged;
  int Shots = 0;                ///< shots of the run
  double UnshotFraction = 0.0;  ///< unshot power left / emitted power (mean of RGB)
  double Seconds = 0.0;         ///< wall-clock time of Run (meshing included)
  int Patches = 0;              ///< shooting patches
  int Elements = 0;             ///< leaf elements at the end
  int Vertices = 0;             ///< radiance vertices at the end
  int SubdividedElements = 0;   ///< elements split by the adaptive subdivision
  long long Rays = 0;           ///< occlusion rays traced
  ShootingEnergy Energy;        ///< Prior* fields are 0: nothing precedes the shots
};

/**
 * The display mesh: triangles covering every surface (T-vertices included:
 * an element with T-vertices is fanned from its centroid, whose radiance is
 * the mean of its corners'), radiance per point, and the surfaces' outline
 * edges.
 */
struct StandardRadiosityMesh
{
  std::vector<Vec3> Points;
  std::vector<RGB> Radiance;                  ///< per point, W sr^-1 m^-2
  std::vector<RGB> Irradiance;                ///< per point, W m^-2
  std::vector<std::array<int, 3>> Triangles;  ///< counter-clockwise about the front normal
  std::vector<int> TriangleSurface;           ///< scene surface of each triangle
  std::vector<std::array<int, 2>> BoundaryEdges; ///< outline edges of the surfaces
  std::vector<int> BoundaryEdgeSurface;
};

/**
 * Standard progressive radiosity over a scene. Construct, set the settings
 * and the parallel loop, Run, then read the mesh. Not thread-safe itself.
 */
class PENUMBRABASELINE_EXPORT StandardRadiosity
{
public:
  /// Prepare `scene` (copied). Throws InputError if it is not valid (ValidateScene).
  explicit StandardRadiosity(const Scene& scene);
  ~StandardRadiosity();
  StandardRadiosity(const StandardRadiosity&) = delete;
  StandardRadiosity& operator=(const StandardRadiosity&) = delete;

  /// Throws InputError (via Validate) for a setting out of range.
  void SetSettings(const StandardRadiositySettings& settings);
  const StandardRadiositySettings& GetSettings() const;

  /// The parallel loop of each shot (empty = serial, the default).
  void SetParallelFor(ParallelFor parallelFor);

  /**
   * Mesh the scene and shoot until the stopping rule holds. `callback`
   * (optional) is called after each shot with its record and the progress
   * in [0, 1] (log scale of the unshot power) and may stop the run.
   * Each call starts afresh.
   */
  StandardRadiositySummary Run(const ShotCallback& callback = ShotCallback());

  /// The result of the last Run (empty before).
  StandardRadiosityMesh GetMesh() const;

  /**
   * Form factor from the point x (unit normal n) on surface `receiverId`
   * (or -1) to patch `patchId` of the last Run, as the shots use it.
   * For tests. Throws InputError for a patch id out of range.
   */
  double FormFactor(const Vec3& x, const Vec3& n, int receiverId, int patchId) const;

  /// Number of patches of the last Run.
  int GetNumberOfPatches() const;
  /// The corners of a patch of the last Run (counter-clockwise about the
  /// front normal). Throws InputError for a patch id out of range.
  std::array<Vec3, 3> GetPatch(int patchId) const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace penumbra

#endif
