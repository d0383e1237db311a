// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraProgressiveShooter.h
 * @brief Progressive refinement with radiance functions (Lischinski, Tampieri
 * and Greenberg 1991, section 3): every surface keeps a total and an unshot
 * radiance FUNCTION; the surface with the most unshot power shoots it, as the
 * non-uniform source it is, to every surface that can see it.
 *
 * Each taking-part surface has a fixed sample mesh (SurfaceSamples) with the
 * total and unshot radiance at its points; every shot is evaluated at every
 * existing sample of every receiver and added there. Run repeats: pick the
 * surface with the largest unshot power (ties: lowest id), shoot it by the
 * exact method (exact visibility, closed-form integrals of its linear
 * radiance) if its power is at least ExactPowerFraction of the reference
 * power, else by the fast one (a hierarchy of its pieces, one multipole
 * expansion and about one occlusion ray per node used); weak shots may be
 * grouped or, with ReuseTransport, become Jacobi sweeps of every surface
 * through a recorded transport. It stops when the unshot power is at most
 * UnshotFraction of the reference power and of each lit surface's own
 * reflected power (estimated), after MaximumShots shots, when
 * nothing is left to shoot, or when the callback asks. Energy is booked so
 * that Emitted = Absorbed + Unshot + Escaped (ShootingEnergy). Each shot is
 * one parallel loop through the caller's ParallelFor, bit-identical for any
 * number of threads.
 *
 * Documentation/design/transport.md explains the methods, their measured
 * errors and costs, and which file of Filters/Transport holds which part.
 */
#ifndef penumbraProgressiveShooter_h
#define penumbraProgressiveShooter_h

#include "penumbraTransportModule.h" // for export macro
#include "penumbraParallel.h"        // for ParallelFor
#include "penumbraPreparedScene.h"
#include "penumbraScene.h"
#include "penumbraShootingEnergy.h"  // for ShotMethod, ShotRecord, ShootingEnergy
#include "penumbraSurfaceSamples.h"  // for SurfaceSamples
#include "penumbraVector.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace penumbra
{

/// Settings of ProgressiveShooter; defaults in brackets. "The design page"
/// is Documentation/design/transport.md.
struct ProgressiveShooterSettings
{
  /// Stop when the total unshot power (mean of RGB) is at most this fraction
  /// of the reference power (emitted, or initial unshot if nothing emits)
  /// and could add at most this fraction of its own reflected power to any
  /// lit surface (a disc estimate; the design page, "Stopping").
  /// [1e-3], in [0, 1]; 0 runs until MaximumShots or no unshot power is left.
  double UnshotFraction = 1e-3;
  /// Largest number of shots of one Run. [10000], >= 0
  int MaximumShots = 10000;
  /// Shots whose power (mean of RGB) is at least this fraction of the
  /// reference power use ShotMethod::Exact, weaker ones ShotMethod::Fast.
  /// An exact shot costs about the shooter's triangles times the receiving
  /// points, the fast one about its hierarchy's cut: at 0.05 the Cornell box
  /// takes 70 s instead of 4.4 s (0.42% against 0.51% RMS against the path-
  /// traced reference), at 0.2 a room of 100 boxes over 845 s instead of
  /// 55 s. Where the fast method's visibility per node would blur the
  /// shadows a strong secondary shooter casts, its shot evaluates those
  /// receivers exactly whatever this setting ("Secondary shadows" in the
  /// design page): a floor lit only by a half-lit panel over a baffle is
  /// 0.30% RMS off at 1 (Benchmarks/secondary_shadow.py).
  /// [1], in [0, inf]: 0 = every shot exact, 1 = only shots as strong as
  /// all the emission, infinity = every shot fast.
  double ExactPowerFraction = 1.0;
  /// Fast method: a node of the shooter's hierarchy is used whole (one
  /// multipole expansion) when its radius is below this times its distance
  /// from the sample. Smaller is more accurate and slower (the number of
  /// nodes used grows about as 1 / OpeningAngle^2); see "The fast shot"
  /// in Documentation/design/transport.md for measured figures. [0.3], in (0, 2]
  double OpeningAngle = 0.3;
  /// Fast method: shots weaker than this fraction f of the reference power
  /// are computed coarser, their error mattering less: a shot of power S
  /// uses the opening angle OpeningAngle * min(2, sqrt(f * reference / S)).
  /// (The error of a fast shot grows about linearly with the opening angle
  /// where visibility dominates it, as its cube where the truncation of the
  /// expansion does, while its cost falls as its square; hence the cap.)
  /// On the Cornell box 0.003 takes a third less time for the same error,
  /// and the furnace stays within 7e-5. [0.003], in [0, 1]; 0 = off
  double CoarseShotFraction = 0.003;
  /// Run: a fast shot also shoots, in the same pass, every other surface
  /// with the same front normal whose unshot power also calls for the fast
  /// method, over one hierarchy of all their pieces (a far cluster of them
  /// costs one expansion and one ray). Surfaces with the same normal never
  /// light each other, so nothing is lost; the shot's error is that of the
  /// fast method. [true]
  bool GroupWeakShots = true;
  /// Run, with GroupWeakShots: the group also takes the weak surfaces
  /// facing other ways whose unshot power is at least a tenth of the
  /// shooter's (see "Group shots" in the design page). The members' unshot
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
  /// design page): the cut of one hierarchy over every surface and its
  /// visibility at every receiving point are kept, and a sweep only
  /// re-weights them with the current unshot radiance, without rays.
  /// Replaces GroupWeakShots, GroupAcrossOrientations and
  /// CoarseShotFraction for those shots. Costs memory: about 4 bytes per
  /// node and 32 per near piece used at each point. [true]
  bool ReuseTransport = true;
  /// Fast method: receiving points are evaluated in clusters of at most
  /// this many points facing the same way (see "Receiver clusters" in the
  /// design page): a node of the shooter's hierarchy far from the whole
  /// cluster is tested by one ray from the cluster, not one per point.
  /// 0 or 1 evaluates every point on its own. [16], in [0, 4096]
  int ReceiverClusterSize = 16;
  /// Fast method: shooter triangles whose longest edge exceeds this
  /// fraction of the shooter's diameter are split in four, recursively,
  /// before the hierarchy is built: it bounds the size of the leaves, hence
  /// how finely visibility is refined away from the sample. [0.1], in (0, 1]
  double LeafSize = 0.1;
  /// Distance, relative to the surface's diameter, by which boundary samples
  /// are moved inside the surface before evaluation (see "Boundary
  /// samples" in the design page).
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
  /// Reflected power (RGB watts) added by summing the tail of the sweeps
  /// in closed form at the end (0 when it was not summed): see
  /// "Convergence" in Documentation/design/transport.md.
  RGB TailPower;
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
  /// Shoot in a prepared scene, sharing its occluder set and Embree scene.
  explicit ProgressiveShooter(const std::shared_ptr<const PreparedScene>& scene);
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
   * itself, or for a boundary sample the point moved inside (see
   * BoundaryOffset). Use these to compute the initial direct light consistently.
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
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace penumbra

#endif
