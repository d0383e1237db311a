// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraProgressiveShooter.h
 * @brief Progressive refinement with radiance functions (Lischinski, Tampieri
 * and Greenberg 1991, section 3): every surface keeps a total and an unshot
 * radiance FUNCTION; the surface with the most unshot power shoots it, as the
 * non-uniform source it is, to every surface that can see it.
 *
 * Representation. Each taking-part surface i has a sample mesh (points in
 * its plane, triangles) and, per point, the RGB total radiance L_i and unshot
 * radiance dL_i. Both are the piecewise-linear functions interpolating those
 * values over the mesh (a point duplicated across an order-0 line is just a
 * separate point, so the functions may jump there). The unshot power of i is
 * pi * integral of dL_i over its triangles, exact for the linear interpolant;
 * shooters are ranked by the mean of its three channels (RGB::Mean).
 *
 * How contributions of shooters with different samples are added (the
 * paper's open problem; design.md section 5). Every shot is evaluated at
 * every existing sample of every receiver and added to that sample's total
 * and unshot values: the sample mesh of a receiver is fixed for the whole
 * run (the caller builds it beforehand, e.g. by the discontinuity mesher and
 * adaptive sampler run against its primary sources) and no sample is
 * inserted while shooting. The shot history is therefore implicit in the
 * per-sample sums; a contribution is never interpolated from another
 * shot's samples, but a secondary shooter's shadows are only as sharp as
 * the receiver's existing samples allow.
 *
 * The loop. Initially (as left by the direct-light evaluation) Total is
 * L^e + the direct light and Unshot is what remains to shoot: the reflected
 * direct light for surfaces whose emission was already shot, plus the
 * emission for emitters not yet shot. Then, until the stopping rule holds:
 * 1. j = the surface with the largest unshot power (ties: lowest id);
 * 2. for every receiver i != j with samples that can exchange light with j
 *    (the shaft between them is not empty), at every sample x of i (unit
 *    normal n_i, reflectance rho_i):
 *      E_j(x) = integral over the part of j visible from x of
 *               dL_j(y) cos(theta_x) cos(theta_y) / r^2 dA_y,
 *      Total_i(x) += rho_i / pi E_j(x),  Unshot_i(x) += rho_i / pi E_j(x);
 * 3. Unshot_j := 0 at all of j's samples.
 * It stops when the total unshot power (mean of RGB) is at most
 * UnshotFraction times the reference power (the scene's emitted power, or
 * the initial unshot power if nothing emits), after MaximumShots shots, when
 * no surface has positive unshot power, or when the caller's callback asks.
 *
 * Two ways to compute E_j, chosen per shot by the shot's power:
 * - Exact (power >= ExactPowerFraction * reference): the part of j visible
 *   from x is found exactly (convex pieces; occluders culled once per pair by
 *   the shaft, then per point by the pyramid), each piece is clipped by
 *   every triangle of j's mesh that carries unshot radiance, and each
 *   intersection is integrated in closed form for the linear radiance of its
 *   triangle (VisibleShooterIrradiance of penumbraLinearSource.h; Lambert's
 *   formula when the unshot radiance is the same at every sample of the
 *   shooter, e.g. an emitter not shot yet). Error: rounding (1e-14 against
 *   quadrature). Cost: about 5 us per (sample, shooter triangle) pair, the
 *   closed form's cost, plus the visibility; so it grows as samples times
 *   shooter triangles.
 * - Fast (weaker shots): a hierarchy (k-d tree) over j's triangles, those
 *   longer than LeafSize * j's diameter split first, stores per node the
 *   moments of dL_j up to second order about its power-weighted centroid c.
 *   From x the tree is cut where a node's radius R < OpeningAngle * |c - x|;
 *   such a node contributes the second-order multipole expansion of the
 *   integral of dL_j k (k = cos cos / r^2) about c, times its visibility.
 *   (The paper's Eq. 6 weight pi A / (pi r^2 + A) of Wallace et al. was
 *   tried first: it biases each node by about -A / (pi r^2), -1.6 % to
 *   -4.4 % measured at OpeningAngle 0.3; the expansion errs by 0.04 %.)
 *   Visibility: one Embree occlusion ray to the centroid of each child of a
 *   node used (one to a leaf's centroid); when the two children disagree a
 *   shadow edge may cross the node, and the children are handled the same
 *   way instead, recursively (rays traced in rounds of packets). Leaves
 *   still looking large from x are split in four while x is within a
 *   piece's radius of it (at most 10 levels), each piece with its own ray,
 *   integrated in closed form over its part in front of x (the ray aimed at
 *   that part) or by the expansion: so contacts (a receiver touching the
 *   shooter's plane) keep their near-field light. Cost per sample: about
 *   log(shooter triangles) / OpeningAngle^2 nodes and twice as many rays,
 *   nearly independent of the shooter's mesh and of the occluders. Error:
 *   all-or-nothing visibility per node, so the penumbrae of secondary
 *   shooters are resolved to the size of the nodes used. Measured on the
 *   Cornell box with 4x4 meshes (TestProgressiveShooter), all shots fast,
 *   indirect radiance against all shots exact: RMS 1.2 % at OpeningAngle
 *   0.3, 0.7 % at 0.2, 0.4 % at 0.1, for 1.0x, 1.8x and 5x the time; with
 *   the default ExactPowerFraction (5 strongest of 70 shots exact) 0.7 %.
 *   A shot with 8x8 meshes (800 samples, 128 shooter triangles): exact
 *   0.48 s, fast 0.10 s on 2 threads; the gap grows with the meshes.
 *
 * Group shots (GroupWeakShots). The fast method over the pieces of many
 * shooters at once. With GroupAcrossOrientations their normals m differ,
 * and the kernel k = (n.d)(-m.d)/|d|^4 is linear in m: a node whose leaves face different
 * ways stores the moments of L m_i for each axis i and sums the three
 * one-normal expansions. That holds only where x is in front of every
 * leaf's plane; each node keeps a cone (axis, half-angle) of its normals,
 * and is culled when x is behind all its planes, opened when x may be
 * behind some (tested from the cone and the node's bounding sphere). The
 * hierarchy splits by normal first while a node's cone is wider than 0.5
 * rad, then by space, so that clusters face one way. Members receive from
 * each other (never from their own plane). Leaves are split to LeafSize as
 * in a single shot while the group has at most 250,000 of them, else they
 * are the sample triangles themselves. Measured on the Cornell box with
 * 4x4 meshes, all shots fast (TestProgressiveShooter): across
 * orientations 10 shots, RMS 1.05 % against all shots exact; same-normal
 * groups only 57 shots, 1.28 %; single shots 70, 1.20 %.
 *
 * Receiver clusters (ReceiverClusterSize). Fast shots evaluate the
 * receiving points in clusters: the points of each plane (coplanar
 * surfaces together) are split at the median of their longest extent until
 * a cluster has at most ReceiverClusterSize points and is at most
 * sqrt(ReceiverClusterSize) point spacings wide. For each cluster (centre
 * x_c, radius rho) the hierarchy is cut once: a node in front of the whole
 * cluster with radius R < OpeningAngle * (|c - x_c| - rho) is far from
 * every point; its visibility is tested by rays from four of the cluster's
 * points (the one nearest x_c, then each the farthest from those before),
 * refined through the children as above. Where the four agree they decide
 * for every point, and the node's expansion is evaluated at each point with
 * its own position; where they disagree (a shadow edge crosses the
 * cluster) the node goes to the points. Nodes a point at x_c would open are
 * opened for the cluster; the rest go to the points, each evaluating them
 * as a single point would. Measured: Cornell box 10x10 meshes, all fast,
 * against every point on its own: RMS 0.6 %, largest 9 % of the mean
 * indirect radiance (TestProgressiveShooter); 4x4 meshes against all
 * exact: RMS 1.16 % (1.28 % without); box_room(100) on 30,000 points,
 * across orientations: shooter 74 s instead of 94 s. Clusters of points
 * with one normal but on different planes (a box's top and the floor
 * around it) were tried: 2.5 % RMS, 130 % largest, as the four rays can
 * all start on one of the planes.
 *
 * Recorded transport (ReuseTransport). A fast shot traces about a thousand
 * rays per receiving point, and a room needs tens of weak shots, each
 * tracing them again. What a fast shot does at a point depends on the
 * geometry (which nodes it cuts, which of them it sees, which near pieces
 * it integrates) and, linearly, on the unshot radiance (the nodes'
 * moments, the pieces' corner values). So once the strongest unshot power
 * calls for the fast method, every surface shoots at once (a Jacobi sweep,
 * members receiving from each other) through one hierarchy over all
 * triangles, recorded on the first sweep: its leaves carry the barycentric
 * coordinates of their triangle's corners as the three channels (so every
 * centroid is an area centroid, and a near piece's irradiance is the
 * weights of its triangle's three corners), every receiver cluster is
 * evaluated as above, and the nodes and near weights it would sum are
 * stored instead. Each sweep then recomputes the leaves' and nodes'
 * moments from the current unshot radiance (about the recorded centroids)
 * and sums the stored terms, without a ray. The hierarchy is the group
 * shot's, with every triangle that has an area (not only those with unshot
 * radiance), its centroids weighted by the unshot power of the first
 * sweep; the record is dropped when samples or the opening angle, leaf
 * size or cluster size change. Measured (TestProgressiveShooter, Cornell
 * box 4x4 meshes, all fast, against all shots exact): 9 sweeps, RMS 0.99 %
 * in 0.24 s, where single and grouped shots take 57 shots, 1.14 %, 0.51 s.
 * box_room(300) on 30,000 points: 11 sweeps, 37 s of shooting (the first
 * 17.6 s, then about 2.2 s each) instead of 198 s for 25 grouped shots.
 *
 * Boundary samples. A sample on the boundary of its mesh (an incident edge
 * used by one triangle: the surface's outline, and both copies of a point on
 * an order-0 line) is evaluated at the point moved toward the centroid of its
 * incident triangle with the largest angle there (on a tie, the mean of the
 * tied centroids, so that mirror-symmetric meshes give mirror-symmetric
 * points), by BoundaryOffset times the surface's diameter (at most half the
 * way), i.e. as the limit from inside the surface. Without it a point on an
 * edge shared with a perpendicular wall would lie in the wall's plane and
 * receive nothing from it, while the limit from inside receives half a
 * hemisphere's worth; at a corner the limit depends on the direction, hence
 * the symmetric rule. The fast method's rays for these samples start
 * RayOriginOffset times the diameter inside, in the same direction (Embree's
 * single precision cannot resolve 1e-7), and near pieces are not refined
 * below 4 times that distance.
 *
 * Energy. Every shot records its power S (pi * integral of dL_j), the power
 * incident on the receivers Phi = sum_i integral of E_i dA (integral of the
 * linear interpolant of E at the samples), the absorbed part
 * sum_i (1 - rho_i) integral of E_i dA, and the escaped part S - Phi: light
 * that left the scene (an open scene), hit the back of a surface (which
 * occludes but neither reflects nor, in this bookkeeping, absorbs), reached
 * surfaces without samples, or was lost (or gained) by the interpolation of
 * E on the receivers' meshes (a mesh that ignores a contact shadow spreads
 * the shooter's radiance under the occluder, where it lights the
 * occluder's back faces). Before the first shot, Emitted - InitialUnshot
 * was consumed by the direct pass; its absorbed part is inferred from the
 * reflected direct radiance as (1 - rho_i) / rho_i * pi * integral of
 * (Total_i - L^e_i) per channel with rho_i > 0, the rest counts as escaped
 * (including what black receivers absorbed then). So, per channel and up to
 * rounding,
 *   Emitted = Absorbed + Unshot + Escaped
 * by construction (ShootingEnergy). In a closed scene with exact transport
 * and a constant field (the furnace) Escaped is ~0 (measured 1e-9 of
 * Emitted); in general it measures the discretisation loss.
 *
 * Sample points that are in no triangle (e.g. error probes) receive every
 * shot like the others but carry no power (they shoot nothing).
 * Surfaces without samples neither shoot nor receive (they still occlude);
 * light reaching them counts as escaped.
 *
 * Threads and determinism. Each shot is one parallel loop over the samples
 * of the receivers, run through a caller-supplied ParallelFor (serial by
 * default; the VTK filter passes vtkSMPTools::For). Every sample is computed
 * independently from const data and written to its own slot, and all sums
 * (powers, energy) are formed afterwards in a fixed order, so the results are
 * bit-identical for any number of threads.
 */
#ifndef penumbraProgressiveShooter_h
#define penumbraProgressiveShooter_h

#include "penumbraTransportModule.h" // for export macro
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace penumbra
{

/**
 * Runs body(b, e) over disjoint sub-ranges [b, e) covering [begin, end),
 * possibly concurrently, and returns when all are done (the contract of
 * vtkSMPTools::For). An empty function means serial: body(begin, end).
 */
using ParallelFor = std::function<void(
  std::size_t begin, std::size_t end, const std::function<void(std::size_t, std::size_t)>& body)>;

/**
 * The sample mesh of one surface and its radiance functions. Points lie in
 * the surface's plane (within 1e-6 of its diameter); triangles index Points
 * (orientation free); Total and Unshot hold one RGB value per point, in
 * W sr^-1 m^-2. The triangles should cover the surface once.
 */
struct SurfaceSamples
{
  std::vector<Vec3> Points;
  std::vector<std::array<int, 3>> Triangles;
  std::vector<RGB> Total;  ///< total radiance at each point
  std::vector<RGB> Unshot; ///< unshot radiance at each point
  /// Receive one irradiance for the whole surface, evaluated at one point
  /// (the centroid of the triangles, or of the largest if that lies
  /// outside) and added at every point: for surfaces smaller than the
  /// resolution wanted (the coarse level's small polygons), at a fraction
  /// of the cost. It still shoots its linear unshot radiance. [false]
  bool Uniform = false;
};

/// How a shot's irradiance was computed.
enum class ShotMethod
{
  Exact = 0, ///< exact visibility + closed-form linear-source integrals
  Fast = 1   ///< hierarchy of the shooter + one occlusion ray per node used
};

/// Settings of ProgressiveShooter; defaults in brackets.
struct ProgressiveShooterSettings
{
  /// Stop when the total unshot power (mean of RGB) is at most this fraction
  /// of the reference power (emitted, or initial unshot if nothing emits).
  /// [1e-3], in [0, 1]; 0 runs until MaximumShots or no unshot power is left.
  double UnshotFraction = 1e-3;
  /// Largest number of shots of one Run. [10000], >= 0
  int MaximumShots = 10000;
  /// Shots whose power (mean of RGB) is at least this fraction of the
  /// reference power use ShotMethod::Exact, weaker ones ShotMethod::Fast.
  /// [0.05], in [0, inf]: 0 = every shot exact, infinity = every shot fast.
  double ExactPowerFraction = 0.05;
  /// Fast method: a node of the shooter's hierarchy is used whole (one
  /// multipole expansion) when its radius is below this times its distance
  /// from the sample. Smaller is more accurate and slower (the number of
  /// nodes used grows about as 1 / OpeningAngle^2); see the file comment
  /// for measured figures. [0.3], in (0, 2]
  double OpeningAngle = 0.3;
  /// Fast method: shots weaker than this fraction f of the reference power
  /// are computed coarser, their error mattering less: a shot of power S
  /// uses the opening angle OpeningAngle * min(2, sqrt(f * reference / S)).
  /// (The error of a fast shot grows about linearly with the opening angle
  /// where visibility dominates it, as its cube where the truncation of the
  /// expansion does, while its cost falls as its square; hence the cap.)
  /// [0 = off], in [0, 1]
  double CoarseShotFraction = 0.0;
  /// Run: a fast shot also shoots, in the same pass, every other surface
  /// with the same front normal whose unshot power also calls for the fast
  /// method, over one hierarchy of all their pieces (a far cluster of them
  /// costs one expansion and one ray). Surfaces with the same normal never
  /// light each other, so nothing is lost; the shot's error is that of the
  /// fast method. [true]
  bool GroupWeakShots = true;
  /// Run, with GroupWeakShots: the group also takes the weak surfaces
  /// facing other ways whose unshot power is at least a tenth of the
  /// shooter's (see "Group shots" in the file comment). The members' unshot
  /// radiance is shot at once and what they send each other becomes their
  /// new unshot radiance: a Jacobi sweep of the surfaces that matter now.
  /// It takes far fewer shots (Cornell box, all fast: 10 instead of 57) but
  /// a sweep costs about as much as shooting each member alone, and
  /// Southwell's order skips the surfaces that matter little: measured
  /// slower on a 32-polygon room (55 s against 21 s). [false]
  bool GroupAcrossOrientations = false;
  /// Run: once the strongest unshot power calls for the fast method, every
  /// later shot is a Jacobi sweep of all surfaces at once through a
  /// transport recorded on the first one (see "Recorded transport" in the
  /// file comment): the cut of one hierarchy over every surface and its
  /// visibility at every receiving point are kept, and a sweep only
  /// re-weights them with the current unshot radiance, without rays.
  /// Replaces GroupWeakShots, GroupAcrossOrientations and
  /// CoarseShotFraction for those shots. Costs memory: about 4 bytes per
  /// node and 32 per near piece used at each point. [false here;
  /// vtkProgressiveShooter and vtkPenumbraSolver turn it on]
  bool ReuseTransport = false;
  /// Fast method: receiving points are evaluated in clusters of at most
  /// this many points facing the same way (see "Receiver clusters" in the
  /// file comment): a node of the shooter's hierarchy far from the whole
  /// cluster is tested by one ray from the cluster, not one per point.
  /// 0 or 1 evaluates every point on its own. [16], in [0, 4096]
  int ReceiverClusterSize = 16;
  /// Fast method: shooter triangles whose longest edge exceeds this
  /// fraction of the shooter's diameter are split in four, recursively,
  /// before the hierarchy is built: it bounds the size of the leaves, hence
  /// how finely visibility is refined away from the sample. [0.1], in (0, 1]
  double LeafSize = 0.1;
  /// Distance, relative to the surface's diameter, by which boundary samples
  /// are moved inside the surface before evaluation (see the file comment).
  /// [1e-7], in [0, 1e-2]; 0 evaluates them where they are.
  double BoundaryOffset = 1e-7;
  /// Fast method: distance, relative to the surface's diameter, by which the
  /// visibility rays of boundary samples start inside the surface. Embree
  /// works in single precision, so a ray starting 1e-7 from a neighbouring
  /// wall may or may not hit it; starting farther in avoids that at the cost
  /// of sampling visibility slightly off the sample. [1e-4], in [0, 1e-2]
  double RayOriginOffset = 1e-4;

  /// Throws InputError naming the first setting out of its range.
  PENUMBRATRANSPORT_EXPORT void Validate() const;
};

/// What one shot did. Powers are RGB, in watts (scene units squared times
/// W m^-2).
struct ShotRecord
{
  int Shooter = -1;                     ///< surface id of the shooter
  ShotMethod Method = ShotMethod::Exact; ///< how E was computed
  RGB Power;          ///< shot power: pi * integral of the shooter's unshot radiance
  RGB Incident;       ///< power incident on the receivers' sample meshes
  RGB Absorbed;       ///< part of Incident absorbed: sum of (1 - rho_i) * incident_i
  RGB Escaped;        ///< Power - Incident: left the scene or lost to discretisation
  int GroupSize = 1;  ///< surfaces shot together (GroupWeakShots); Shooter is the strongest
  int Receivers = 0;  ///< receivers that exchange light with the shooter
  long long Samples = 0;      ///< samples evaluated
  long long Rays = 0;         ///< occlusion rays (fast method)
  double Seconds = 0.0;       ///< wall-clock time of the shot
  double UnshotAfter = 0.0;   ///< total unshot power (mean of RGB) after the shot
};

/**
 * Energy bookkeeping of a run, per channel, in watts. The identity
 * Emitted = Absorbed() + Unshot + Escaped() holds up to rounding by
 * construction (see the file comment).
 */
struct ShootingEnergy
{
  RGB Emitted;        ///< pi * sum of L^e * area over ALL surfaces (Scene::EmittedPower)
  RGB InitialUnshot;  ///< unshot power of the samples before the first shot
  RGB PriorAbsorbed;  ///< absorbed by the direct pass, inferred from the reflected radiance
  RGB PriorEscaped;   ///< Emitted - InitialUnshot - PriorAbsorbed
  RGB ShotAbsorbed;   ///< absorbed during the shots
  RGB ShotEscaped;    ///< escaped or lost during the shots
  RGB Unshot;         ///< unshot power left

  /// PriorAbsorbed + ShotAbsorbed.
  RGB Absorbed() const { return this->PriorAbsorbed + this->ShotAbsorbed; }
  /// PriorEscaped + ShotEscaped.
  RGB Escaped() const { return this->PriorEscaped + this->ShotEscaped; }
};

/// Why Run stopped.
enum class StopReason
{
  Converged = 0,      ///< unshot power at most UnshotFraction of the reference
  NothingToShoot = 1, ///< no surface has positive unshot power
  MaximumShots = 2,   ///< MaximumShots reached
  Aborted = 3         ///< the callback asked to stop
};

/// Result of Run.
struct ShootingSummary
{
  StopReason Reason = StopReason::Converged;
  int Shots = 0;                 ///< shots of this run
  int ExactShots = 0;            ///< of which exact
  int FastShots = 0;             ///< of which fast
  double ReferencePower = 0.0;   ///< power the fractions refer to (mean of RGB)
  double UnshotFraction = 0.0;   ///< unshot power left / reference power
  double Seconds = 0.0;          ///< wall-clock time of the run
  double ExactSeconds = 0.0;     ///< of which in exact shots
  double FastSeconds = 0.0;      ///< of which in fast shots
  ShootingEnergy Energy;         ///< bookkeeping after the run
  std::vector<ShotRecord> History; ///< one record per shot of this run
};

/**
 * Called after every shot with its record and the progress in [0, 1]
 * (log-scale: log(unshot / initial) / log(target / initial), or shots /
 * MaximumShots when UnshotFraction is 0). Return true to continue, false to
 * stop the run (e.g. `return !filter->GetAbortExecute();`).
 */
using ShotCallback = std::function<bool(const ShotRecord& shot, double progress)>;

/**
 * Called during a long shot (the first sweep through a recorded transport,
 * which traces every ray the later sweeps reuse) with the fraction of that
 * shot done, in [0, 1], increasing; from the thread that called Run or
 * Shoot, between parallel loops, never from a worker.
 */
using ShotProgressCallback = std::function<void(double fraction)>;

/**
 * The stopping rule of the shooting loops, checked before each shot: true
 * (and `reason` set) when the unshot power is at most `target`
 * (StopReason::Converged) or `shots` has reached `maximumShots`
 * (StopReason::MaximumShots).
 */
PENUMBRATRANSPORT_EXPORT bool ShootingDone(
  double unshot, double target, int shots, int maximumShots, StopReason& reason);

/**
 * The progress passed to a ShotCallback (see there), in [0, 1], after
 * `shots` shots that left `unshotAfter` of an `initial` unshot power.
 */
PENUMBRATRANSPORT_EXPORT double ShootingProgress(
  double unshotAfter, double initial, double target, int shots, int maximumShots);

/**
 * The progressive-refinement loop of paper section 3 over per-surface sample
 * meshes. Construct once per scene, give each taking-part surface its
 * samples, then Run (or Shoot step by step). Not thread-safe itself: the
 * parallelism is inside each shot, through SetParallelFor.
 */
class PENUMBRATRANSPORT_EXPORT ProgressiveShooter
{
public:
  /// Prepare `scene` (geometry and materials are copied; the scene may be discarded).
  explicit ProgressiveShooter(const Scene& scene);
  ~ProgressiveShooter();
  ProgressiveShooter(const ProgressiveShooter&) = delete;
  ProgressiveShooter& operator=(const ProgressiveShooter&) = delete;

  /// Number of surfaces of the scene.
  int GetNumberOfSurfaces() const;

  /// Replace the settings. Throws InputError (via Validate) for a setting out of range.
  void SetSettings(const ProgressiveShooterSettings& settings);
  const ProgressiveShooterSettings& GetSettings() const;

  /// The parallel loop used by every shot (empty = serial, the default).
  void SetParallelFor(ParallelFor parallelFor);

  /// Progress inside long shots (see ShotProgressCallback; empty = none, the default).
  void SetShotProgressCallback(ShotProgressCallback callback);

  /**
   * Give surface `surfaceId` its sample mesh and radiance values (moved in;
   * an empty mesh removes the surface from the solution). Throws InputError
   * naming the surface and the offending point or triangle for: an id out
   * of range, a degenerate scene polygon, sizes that do not match, an index
   * out of range, non-finite coordinates or values, or a point off the
   * surface's plane by more than 1e-6 of its diameter. Degenerate triangles
   * are allowed (they carry no power). Resets the energy bookkeeping.
   */
  void SetSurfaceSamples(int surfaceId, SurfaceSamples samples);

  /// The current samples and values of surface `surfaceId` (empty if none).
  const SurfaceSamples& GetSurfaceSamples(int surfaceId) const;

  /**
   * Where sample `point` of surface `surfaceId` is evaluated: the point
   * itself, or for a boundary sample the point moved inside (see the file
   * comment). Use these to compute the initial direct light consistently.
   * A Uniform surface with triangles has one evaluation point for all.
   */
  const std::vector<Vec3>& GetEvaluationPoints(int surfaceId) const;

  /// Unshot power pi * integral of Unshot of surface `surfaceId`, RGB watts.
  RGB GetUnshotPower(int surfaceId) const;

  /// Sum of GetUnshotPower over all surfaces.
  RGB GetTotalUnshotPower() const;

  /// The surface with the largest positive unshot power (mean of RGB; ties:
  /// lowest id), or -1 if none.
  int SelectShooter() const;

  /**
   * One shot from `shooterId` with `method` (steps 2 and 3 of the loop),
   * whatever its power. Returns its record (also appended to the history of
   * the energy bookkeeping). Throws InputError for an id out of range.
   */
  ShotRecord Shoot(int shooterId, ShotMethod method);

  /// The method the settings choose for a shot of `power` (mean of RGB) watts.
  ShotMethod ChooseMethod(double power) const;

  /**
   * Shoot until the stopping rule holds (see the file comment). `callback`
   * (optional) is called after each shot and may stop the run.
   */
  ShootingSummary Run(const ShotCallback& callback = ShotCallback());

  /// Energy bookkeeping since the samples were last set (see ShootingEnergy).
  ShootingEnergy GetEnergy() const;

  /**
   * Reference power of the stopping rule and of ExactPowerFraction (mean of
   * RGB): the scene's emitted power, or the initial unshot power of the
   * samples if the scene emits nothing.
   */
  double GetReferencePower() const;

  /**
   * Irradiance (W m^-2, RGB) at `points` (count of them, unit normal
   * `normal`, lying on receiver `receiverId` or -1 for free points) due to
   * surface `shooterId` emitting its CURRENT unshot radiance, by `method`.
   * Nothing is modified. The building block of Shoot, exposed for tests and
   * for callers that add samples later; the points are used as given (no
   * boundary offsets: the fast method's rays start at the points). Serial.
   */
  std::vector<RGB> ComputeIrradiance(int shooterId, ShotMethod method, const Vec3* points,
    std::size_t count, const Vec3& normal, int receiverId) const;

private:
  struct Internal;
  std::unique_ptr<Internal> P;
};

} // namespace penumbra

#endif
