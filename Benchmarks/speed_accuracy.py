#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Speed against accuracy: the direct-light scenes and the Cornell box.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/speed_accuracy.py \\
        [--scenes strip,occluder,seven,blind,cornell] [--methods LABELS|all] [--points 4000]
        [--threads 2] [--out DIR] [--mitsuba-python build/_deps/mitsuba-venv/bin/python]
        [--no-radiance] [--replot DIR/speed_accuracy.csv]

For each scene and each method it runs one solve in a fresh process (so
that the peak memory is that run's) and measures the wall time of the
solve, the peak resident memory of the process (VTK and Python included,
about 65 MB of it; Mitsuba's python about 145 MB; for Radiance, plus the
largest peak of its oconv and rtrace processes), the number of samples
(discontinuity meshing: radiance evaluations; standard radiosity:
vertices; path tracer: light samples or camera samples; Radiance: points
given to rtrace, repeats included) and the error of
the displayed floor radiance (linear over the output triangles, as the
data contract defines it) against exact values at independent random
points of the floor (vtkPenumbraRadianceEvaluator, exact method, at the points
themselves): RMS, 99th percentile and maximum of |error| relative to the
mean exact radiance (first channel; these scenes' lights are grey).

In these scenes the floor's radiance is exactly the direct light: the
lights do not reflect, and the occluders face up, away from the floor.
The Cornell box is solved with its interreflections and measured against
the Mitsuba 3 reference of compare_cornell.py (floor and back wall pixels,
all channels), with fewer methods (CORNELL_METHODS).

Method families (one curve each on the charts):

- discontinuity meshing, exact evaluation + cubic reconstruction, at
  sampling tolerances 0.05, 0.02, 0.008, 0.002 (the default) and 0.0005
  (vtkPenumbraRadianceEvaluator's SamplingTolerance), and at 0.05 with samples
  up to 1/8 of the scene's diagonal apart (d=1/8; MaximumSampleSpacing,
  default 1/32); on the Cornell box at 0.02 and 0.002 and at four coarser
  settings aimed at 1% RMS (tolerance 0.05, longer sample spacing d,
  shooting stopped at a larger unshot fraction u, weak shots coarser c:
  see METHODS). Without a spacing limit (d=0: not run by default, ask for
  "exact + cubic d=0" and the like with --methods) the sampling stops
  sooner but is less accurate for its time at every tolerance tried
  (measured: seven occluders 0.12% RMS in 1.3 s against 0.052% in 1.0 s
  with the limit; at tolerance 0.05 the blind's floor is 2.6% off in
  0.22 s, above the path tracer's curve there);
- the same with linear reconstruction, at tolerances 0.02 and 0.002;
- the same with ray-cast evaluation (cubic reconstruction), at ray-cast
  tolerances 0.01 and 0.001, direct-light scenes only. Ray casting's
  visibility estimate is stepwise, so in penumbrae the adaptive sampling
  may never meet its tolerance and runs to its sample budget (at the
  default tolerance and budget it took 318 s and 868,000 samples on
  "occluder"): these runs use tolerance 0.02 and at most 20,000 samples
  per surface, which keeps them to 2 to 10 s; at ray-cast tolerance 0.01
  the noisier estimate keeps the sampling refining (up to 3.3 times the
  samples of 0.001) and it ends less accurate;
- standard radiosity at five mesh densities, with a finer subdivision
  threshold, without subdivision, with smaller shooting patches, and with
  Wallace et al.'s disc form factors as published;
- the Mitsuba 3 path tracer, in the Mitsuba venv's python
  (--mitsuba-python; left out when there is none). On the direct-light
  scenes, at 1 to 16,384 samples per point: the scene (the penumbra
  scene's polygons as triangles, diffuse Reflectance, one-sided area
  lights of radiance Emission) is loaded and the floor's radiance is
  estimated at the very points of the error measure with Mitsuba's own
  light sampling and shadow rays (next_event): the next-event estimate a
  path tracer makes at its first bounce, at 4,000 points only, without
  camera rays or further bounces -- the best case for it. Its mean
  converges to the exact values (measured: RMS falls by 4 for 16 times
  the samples, down to 0.2% at 16,384, where its mean over the floor is
  within 0.03% of the exact one). On the
  Cornell box, at 16 to 4,096 samples per pixel, it renders the
  reference's own sensors (floor and back wall, 1 cm pixels;
  Benchmarks/reference/mitsuba_cornell.py's scene and settings, other
  seeds); its error is that of its pixels against the reference's, which
  has 0.17% noise of its own. Its time covers loading the scene, compiling
  the kernels (Dr.Jit caches them on disk, so after a first run this is
  mostly a cache load: 0.01 to 0.04 s at 1 to 16 samples) and sampling,
  not importing Mitsuba (as the other methods' times do not cover
  importing VTK).

- Radiance 6 (`rtrace -I`, from PyPI's pyradiance: the venv of
  Benchmarks/reference/setup_radiance.sh, made on first use; --no-radiance
  leaves it out). The scene is converted to Radiance primitives
  (Benchmarks/radiance_scene.py: polygons in Penumbra's vertex order,
  `plastic` of the Reflectance, `light` of radiance Emission, or `illum`
  with a `plastic` for a light that also reflects), compiled by `oconv`,
  and `rtrace -I` gives the irradiance at the very points of the error
  measure with the surface's normal, in --threads processes (`-n`),
  points given in binary (-fdd); radiance = reflectance * irradiance / pi
  per channel. The points lie on the surface: rtrace -I takes them as the
  surface point and its rays do not hit the surface they leave. Its time
  covers writing the primitives, `oconv`, `rtrace` and averaging. Before
  any timing, radiance_check compares its direct light at its finest
  settings with the exact values (measured: on "strip", no shadow, mean
  ratio 1.00016, RMS 0.058%, largest 0.21%; on the Cornell box's sensors,
  direct light only, mean ratios 1.0011 floor and 1.0003 back wall, RMS
  0.82% and 0.28% from the partitioned light), and stops if the
  conversion's sides or units are wrong.
  Direct-light scenes: `-ab 0` (these floors get direct light only; and
  Radiance's plastic reflects on both sides, so the occluders' undersides
  would light the floor), every source sample tested (`-dt 0 -dc 1`),
  source subdivision `-ds` 0.5 to 0.01 without jitter, where its error
  stops falling below 0.05 to 0.02 (the light is cut into a bounded number
  of partitions), 0.05 and 0.01 with jitter `-dj 0.7`, then `-ds 0.02 -dj
  1` with each point given 4, 16 and 64 times and the independent
  jittered estimates averaged (x4, x16, x64): the only way past its
  partitions, its error falls as one over the root of the repeats.
  Cornell box: interreflections at 2 x 2 points per valid pixel of the
  reference's sensors, averaged, as the other methods' pixels (the pixel
  centres alone would add 0.44% RMS on the floor, measured on Penumbra's
  own solution). With the ambient cache as users run it (`-ab` 2 to 8,
  `-ad` 256 to 1024, `-as` half of it, `-aa` 0.2 to 0.1, `-ar` 32 to 256,
  an ambient file fresh per run shared by the processes) and without it
  (`-aa 0`, `-ab` 8 and 12, `-ad 32`, Russian roulette below weight 1/ad
  (`-lw 3e-2`), jittered sources, the points repeated 1 to 64 times).
  The light must be subdivided (`-ds` 0.05 or 0.02): at the default 0.2
  this 13 x 10.5 cm light 55 cm away is one sample, its shadows are hard,
  and the error stays at 7 to 8% RMS however many bounces and divisions.
  Radiance stays about 0.5 to 1% below the reference in its mean (0.2%
  for Penumbra's solution), with or without the cache, which bounds it
  near 1% RMS.

After the runs it prints the speed-accuracy goals checked against the measured
rows (claims): on each scene, at each exact + cubic run's time, the RMS
of the standard, path-tracer and Radiance curves (their lower envelopes,
interpolated log-log, only where their runs cover that time) and the
ratio to the run's (Penumbra's accuracy ratio at equal time), and the
smallest ratio over the overlap; on the Cornell box, also the time each
family takes to reach 1% RMS
(interpolated log-log) and the ratios. The paper's Figs. 5 and 6 are
Benchmarks/paper_figures.py.

Writes DIR/speed_accuracy.md (the table, then the claims),
DIR/speed_accuracy.csv and one log-log chart of RMS error against time
per scene, DIR/speed_accuracy_SCENE.png, each family's runs marked and
its lower envelope drawn (DIR defaults to the current folder). --replot
redoes these from a CSV without running anything.
"""
import argparse
import csv
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = ("strip", "occluder", "seven", "blind", "cornell")
CORNELL_REFERENCE = os.path.join(HERE, "reference", "cornell_reference.npz")
# (family, label, settings) -- settings are interpreted by run_one.
# Standard radiosity: the visibility sampling of the light (s x s rays per
# patch triangle) must be refined with the mesh, or finer meshes only show
# the s^2 steps of the penumbrae more sharply.
CUBIC = "discontinuity (exact + cubic)"
LINEAR = "discontinuity (exact + linear)"
RAY_CAST = "discontinuity (ray cast + cubic)"
RADIANCE = "Radiance (rtrace -I)"
# Discontinuity meshing's sampling tolerance (vtkPenumbraRadianceEvaluator's
# SamplingTolerance, relative to each surface's mean radiance; default 0.002):
# the knob that trades its accuracy for time.
CUBIC_TOLERANCES = (0.05, 0.02, 0.008, 0.002, 0.0005)
LINEAR_TOLERANCES = (0.02, 0.002)


def tolerance_label(base, tolerance):
    return base if tolerance == 0.002 else "%s tol=%g" % (base, tolerance)


METHODS = tuple(
    (CUBIC, tolerance_label("exact + cubic", t), {"tolerance": t}) for t in CUBIC_TOLERANCES
) + tuple(
    (LINEAR, tolerance_label("exact + linear", t), {"tolerance": t, "reconstruction": "linear"})
    for t in LINEAR_TOLERANCES
) + (
    # Ray-cast evaluation, bounded (see the module docstring): a looser sampling
    # tolerance and a budget of 20,000 samples per surface.
    (RAY_CAST, "ray cast + cubic tol=0.02 rt=0.01",
     {"evaluation": "ray_cast", "ray_cast_tolerance": 0.01, "tolerance": 0.02,
      "max_samples": 20000}),
    (RAY_CAST, "ray cast + cubic tol=0.02 rt=0.001",
     {"evaluation": "ray_cast", "ray_cast_tolerance": 0.001, "tolerance": 0.02,
      "max_samples": 20000}),
    # Direct light: the fastest setting, samples 8 times as far apart as
    # vtkPenumbraRadianceEvaluator's MaximumSampleSpacing allows by default (1/32 of
    # the scene's diagonal). With no spacing limit at all (d=0, not run by
    # default) the adaptive sampling stops sooner but is less accurate for its
    # time at every tolerance (measured: see the module docstring).
    (CUBIC, "exact + cubic tol=0.05 d=1/8", {"tolerance": 0.05, "spacing": 1.0 / 8}),
    (CUBIC, "exact + cubic tol=0.05 d=0", {"tolerance": 0.05, "spacing": 0.0}),
    (CUBIC, "exact + cubic tol=0.02 d=0", {"tolerance": 0.02, "spacing": 0.0}),
    (CUBIC, "exact + cubic d=0", {"tolerance": 0.002, "spacing": 0.0}),
    # Cornell box: coarser settings aimed at 1% RMS: a looser sampling
    # tolerance, a longer sample spacing (d, vtkPenumbraRadianceEvaluator's
    # MaximumSampleSpacing, default 1/32), shooting stopped at a larger
    # unshot fraction (u, vtkPenumbraProgressiveShooter's UnshotFraction, default
    # 0.001) and weak shots computed coarser (c, its CoarseShotFraction,
    # default 0.003).
    (CUBIC, "exact + cubic tol=0.05 d=1/8 u=0.001 c=0.03",
     {"tolerance": 0.05, "spacing": 1.0 / 8, "unshot": 0.001, "coarse": 0.03}),
    (CUBIC, "exact + cubic tol=0.05 d=1/16 u=0.001 c=0.03",
     {"tolerance": 0.05, "spacing": 1.0 / 16, "unshot": 0.001, "coarse": 0.03}),
    (CUBIC, "exact + cubic tol=0.05 d=1/24 u=0.002 c=0.03",
     {"tolerance": 0.05, "spacing": 1.0 / 24, "unshot": 0.002, "coarse": 0.03}),
    (CUBIC, "exact + cubic tol=0.05 u=0.002 c=0.03",
     {"tolerance": 0.05, "unshot": 0.002, "coarse": 0.03}),
    ("standard", "standard h=0.1 s=2", {"element_size": 0.1, "shooter_samples": 2}),
    ("standard", "standard h=0.05 s=4", {"element_size": 0.05, "shooter_samples": 4}),
    ("standard", "standard h=0.025 s=8", {"element_size": 0.025, "shooter_samples": 8}),
    ("standard", "standard h=0.0125 s=16", {"element_size": 0.0125, "shooter_samples": 16}),
    ("standard", "standard h=0.00625 s=16", {"element_size": 0.00625, "shooter_samples": 16}),
    ("standard", "standard h=0.025 s=8 t=0.05",
     {"element_size": 0.025, "shooter_samples": 8, "subdivision_threshold": 0.05}),
    ("standard", "standard h=0.025 s=8 no subdivision",
     {"element_size": 0.025, "shooter_samples": 8, "maximum_subdivision_depth": 0}),
    ("standard", "standard h=0.05 s=4 t=0.1",
     {"element_size": 0.05, "shooter_samples": 4, "subdivision_threshold": 0.1}),
    ("standard", "standard h=0.05 s=4 p=0.2",
     {"element_size": 0.05, "shooter_samples": 4, "patch_size": 0.2}),
    ("standard", "standard disc h=0.025 s=8",
     {"element_size": 0.025, "shooter_samples": 8, "form_factor": "disc"}),
) + tuple(("path tracing", "Mitsuba %d spp" % spp, {"spp": spp})
          for spp in (1, 4, 16, 64, 256, 1024, 4096, 16384)
) + tuple((RADIANCE, "Radiance -ds %g%s" % (ds, " -dj 0.7" if jitter else ""),
           {"rtrace": ["-ab", "0", "-dt", "0", "-dc", "1", "-ds", "%g" % ds]
            + (["-dj", "0.7"] if jitter else [])})
          for ds, jitter in ((0.5, False), (0.2, False), (0.1, False), (0.05, False),
                             (0.02, False), (0.01, False), (0.05, True), (0.01, True))
) + tuple((RADIANCE, "Radiance -ds 0.02 -dj 1 x%d" % repeats,
           # Past its finest source subdivision Radiance gets closer only by
           # averaging independent jittered estimates (-u+, the default): the
           # points given `repeats` times each.
           {"rtrace": ["-ab", "0", "-dt", "0", "-dc", "1", "-ds", "0.02", "-dj", "1"],
            "repeats": repeats})
          for repeats in (4, 16, 64)
) + tuple((RADIANCE, "Radiance " + options + (" x%d" % repeats if repeats > 1 else ""),
           {"rtrace": options.split(), "repeats": repeats, "cornell": True})
          for options, repeats in (
              # The ambient cache as users run it (-aa, -ar; -lw stays at its
              # default 1e-4 with Russian roulette) ...
              ("-ab 2 -ad 256 -as 128 -aa 0.2 -ar 32 -ds 0.05", 1),
              ("-ab 4 -ad 512 -as 256 -aa 0.15 -ar 64 -ds 0.05", 1),
              ("-ab 8 -ad 1024 -as 512 -aa 0.1 -ar 128 -ds 0.05", 1),
              ("-ab 8 -ad 1024 -as 512 -aa 0.1 -ar 256 -ds 0.02 -dt 0 -dc 1", 1),
              # ... and without it: Monte Carlo at every point, Russian
              # roulette below weight 1/ad, jittered sources; more accuracy
              # by repeating the points (raising -ad costs more: measured
              # -ad 128 took about 15 times the time of -ad 32 for half the error).
              ("-ab 8 -ad 32 -aa 0 -lw 3e-2 -ds 0.05 -dj 1", 1),
              ("-ab 8 -ad 32 -aa 0 -lw 3e-2 -ds 0.05 -dj 1", 4),
              ("-ab 12 -ad 32 -aa 0 -lw 3e-2 -ds 0.02 -dj 1 -dt 0 -dc 1", 16),
              ("-ab 12 -ad 32 -aa 0 -lw 3e-2 -ds 0.02 -dj 1 -dt 0 -dc 1", 64)))
FAMILIES = (CUBIC, LINEAR, RAY_CAST, "standard", "path tracing", RADIANCE)
CORNELL_ONLY = [label for _, label, settings in METHODS
                if {"unshot", "coarse", "cornell"} & set(settings)]
ON_REQUEST = ["exact + cubic tol=0.05 d=0", "exact + cubic tol=0.02 d=0", "exact + cubic d=0"]
# Path tracer sample counts: on the direct-light scenes (the next-event
# estimate at the floor points, see next_event) and on the Cornell box (the
# reference's sensors rendered by the path tracer).
DIRECT_SPP = (1, 4, 16, 64, 256, 1024, 4096, 16384)
CORNELL_SPP = (16, 64, 256, 1024, 4096)
DEFAULT_METHODS = [label for family, label, settings in METHODS
                   if label not in CORNELL_ONLY + ON_REQUEST
                   and (family != "path tracing" or settings["spp"] in DIRECT_SPP)]
# The Cornell box (with interreflections) costs far more per sample: the
# finer standard meshes, the tightest tolerance and ray casting would take
# minutes each.
CORNELL_METHODS = ["exact + cubic tol=0.02", "exact + cubic",
                   "exact + linear"] + CORNELL_ONLY + [
    "standard h=0.1 s=2", "standard h=0.05 s=4", "standard h=0.05 s=4 t=0.1",
    "standard h=0.05 s=4 p=0.2"] + ["Mitsuba %d spp" % spp for spp in CORNELL_SPP]
# The Mitsuba venv made by Benchmarks/reference/setup_mitsuba.sh.
MITSUBA_PYTHON = os.path.join(os.path.dirname(HERE), "build", "_deps", "mitsuba-venv", "bin",
                              "python")
FLOOR = 0  # the floor is surface 0 of every scene measured here


def floor_points(scene, count, seed=7):
    """`count` random points strictly inside the floor (an axis-aligned
    rectangle at y = 0 in these scenes), reproducibly."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    corners = vtk_to_numpy(scene.GetCell(FLOOR).GetPoints().GetData())
    low, high = corners.min(axis=0), corners.max(axis=0)
    margin = 1e-3 * (high - low)
    rng = np.random.default_rng(seed)
    points = rng.uniform(low + margin, high - margin, size=(count, 3))
    points[:, 1] = corners[0, 1]
    return points


def exact_radiance(scene, points, surface=FLOOR, all_channels=False):
    """Exact direct radiance at `points` on the surface (the floor unless
    told; vtkPenumbraRadianceEvaluator): the first channel, or all."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    import penumbra
    from penumbra.pipeline import point_samples

    data = point_samples(points, surface)
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputData(0, data)
    evaluator.SetSceneData(scene)
    radiance = vtk_to_numpy(penumbra.run_filter(evaluator).GetPointData().GetArray("Radiance"))
    return radiance if all_channels else radiance[:, 0]


def displayed_radiance(result, points):
    """The result's radiance at `points` on the floor, linear over its triangles."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkGenericCell, vtkStaticCellLocator

    sys.path.insert(0, HERE)
    from compare_cornell import surface_mesh

    mesh = surface_mesh(result, FLOOR)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(mesh)
    locator.BuildLocator()
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))[:, 0]
    cell = vtkGenericCell()
    pcoords = [0.0, 0.0, 0.0]
    weights = [0.0] * 8
    out = np.full(len(points), np.nan)
    for k, p in enumerate(points):
        if locator.FindCell(list(p), 1e-9, cell, pcoords, weights) >= 0:
            out[k] = sum(weights[n] * radiance[cell.GetPointId(n)] for n in range(3))
    return out


def solve(scene_data, family, settings, threads, indirect):
    """One solve; returns (result, number of radiance samples)."""
    from vtkmodules.vtkCommonCore import vtkSMPTools
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    import penumbra
    from penumbra.pipeline import build_pipeline

    vtkSMPTools.Initialize(threads)
    if family == "standard":
        result = penumbra.solve(scene_data, method="standard", **settings)
        return result, int(result.GetFieldData().GetArray("Vertices").GetValue(0))
    source = vtkTrivialProducer()
    source.SetOutput(scene_data)
    stages = build_pipeline(source.GetOutputPort(), indirect=indirect,
                            unshot_fraction=settings.get("unshot"))
    evaluator = stages["evaluator"]
    if settings.get("evaluation") == "ray_cast":
        evaluator.SetMethod(penumbra.vtkPenumbraRadianceEvaluator.RAY_CAST)
        evaluator.SetRayCastTolerance(settings.get("ray_cast_tolerance",
                                                   evaluator.GetRayCastTolerance()))
    for key, setter in (("tolerance", evaluator.SetSamplingTolerance),
                        ("max_samples", evaluator.SetMaximumSamplesPerSurface),
                        ("spacing", evaluator.SetMaximumSampleSpacing)):
        if key in settings:
            setter(settings[key])
    if "coarse" in settings and indirect:
        stages["shooter"].SetCoarseShotFraction(settings["coarse"])
    if settings.get("reconstruction") == "linear":
        stages["reconstructor"].SetModeToLinear()
    result = penumbra.run_filter(stages["reconstructor"])
    evaluations = evaluator.GetOutput().GetFieldData().GetArray("Evaluations")
    return result, int(evaluations.GetValue(0)) if evaluations is not None else -1


def peak_memory_mb():
    """This process's peak resident memory. Not getrusage's ru_maxrss: Linux
    carries it over from the parent through fork and exec, so every child
    would report at least the parent's size."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0  # kB -> MB
    return float("nan")


def children_peak_memory_mb():
    """The largest peak resident memory of this process's finished children
    (Radiance's oconv and rtrace processes)."""
    import resource

    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0  # kB -> MB


def direct_errors(result, reference_path):
    """|displayed - exact| / mean exact at the reference's floor points."""
    reference = np.load(reference_path)
    shown = displayed_radiance(result, reference["points"])
    exact = reference["exact"]
    valid = np.isfinite(shown)
    return np.abs(shown[valid] - exact[valid]) / exact[valid].mean()


def cornell_errors(result):
    """|displayed - Mitsuba| / mean Mitsuba over the floor's and back wall's
    reference pixels (compare_cornell.py's pixel averages, 2 x 2 points per
    pixel), all three channels."""
    sys.path.insert(0, HERE)
    from compare_cornell import pixel_averages

    reference = np.load(CORNELL_REFERENCE, allow_pickle=True)
    return reference_errors({
        name: pixel_averages(result, int(reference[name + "_cell_id"]), reference, name, k=2)
        for name in reference["sensors"].item().split(",")})


def reference_errors(images):
    """|image - Mitsuba reference| / mean reference over the valid pixels of
    each sensor of `images` (name -> (H, W, 3) pixel averages), all three
    channels, concatenated."""
    reference = np.load(CORNELL_REFERENCE, allow_pickle=True)
    relative = []
    for name, ours in images.items():
        theirs = reference[name + "_radiance"].astype(float)
        valid = reference[name + "_mask"] & np.all(np.isfinite(ours), axis=2)
        relative.append((np.abs(ours[valid] - theirs[valid]) / theirs[valid].mean(axis=0)).ravel())
    return np.concatenate(relative)


def load_mitsuba_scene(polygons, reflectance, emission, sensors, settings, threads):
    """Mitsuba 3 (the reference's variant, `threads` threads) loads the scene
    of mitsuba_cornell.build_scene_dict with `sensors`. Returns (the mitsuba
    and drjit modules, the scene, the perf_counter time before loading)."""
    import mitsuba_cornell

    mitsuba_cornell.configure_llvm()
    import drjit
    import mitsuba

    mitsuba.set_variant(str(np.load(CORNELL_REFERENCE, allow_pickle=True)["variant"]))
    drjit.set_thread_count(threads)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="penumbra-mitsuba-") as folder:
        scene = mitsuba.load_dict(mitsuba_cornell.build_scene_dict(
            mitsuba, polygons, reflectance, emission, sensors, settings, folder))
    return mitsuba, drjit, scene, start


def path_trace(spp, threads):
    """Mitsuba 3 renders the reference's sensors (mitsuba_cornell.py's scene,
    sensors and settings) at `spp` samples per pixel, with seeds the
    reference did not use. Runs in the Mitsuba venv's python. Returns
    ({sensor: (H, W, 3) image}, seconds: scene loading, kernel compilation
    and rendering, total camera samples)."""
    sys.path.insert(0, os.path.join(HERE, "reference"))
    import mitsuba_cornell

    reference = np.load(CORNELL_REFERENCE, allow_pickle=True)
    names = reference["sensors"].item().split(",")
    settings = mitsuba_cornell.argument_parser().parse_args(
        ["--spp-per-pass", str(spp), "--passes", "1", "--batches", "1",
         "--threads", str(threads), "--sensors", ",".join(names)])
    polygons, reflectance, emission = mitsuba_cornell.load_penumbra_polygons(
        "cornell", settings.penumbra_pythonpath)
    sensors = mitsuba_cornell.make_sensors(polygons, names, settings.pixel, settings.height,
                                           settings.near_clip)
    for sensor in sensors:
        if not np.array_equal(sensor["mask"], reference[sensor["name"] + "_mask"]):
            raise RuntimeError("%s: the sensor differs from the reference's" % sensor["name"])
    mitsuba, _, scene, start = load_mitsuba_scene(polygons, reflectance, emission, sensors,
                                                  settings, threads)
    images = {}
    for k, sensor in enumerate(sensors):
        # The reference used seeds 1 to spp_total / spp_per_pass; these are far above.
        mean = mitsuba_cornell.render_sensor(mitsuba, scene, k, sensor, settings,
                                             10 ** 6 + 1000 * k)[0]
        images[sensor["name"]] = mean
    seconds = time.perf_counter() - start
    samples = spp * sum(int(np.prod(sensor["shape"])) for sensor in sensors)
    return images, seconds, samples


def next_event(scene_name, points, spp, threads, seed=10 ** 6):
    """Mitsuba 3's estimate of the floor's direct radiance at `points`: the
    scene (triangles fanned from the penumbra scene's polygons, diffuse
    Reflectance, one-sided area lights of radiance Emission, built by
    mitsuba_cornell.build_scene_dict as for the Cornell box) is loaded and,
    at every point (a SurfaceInteraction3f with the floor's normal), `spp`
    light samples are
    drawn by the scene's own emitter sampling with a shadow ray each
    (scene.sample_emitter_direction, test_visibility=True): radiance =
    reflectance / pi * mean(weight * cos), the next-event estimate a path
    tracer makes at its first bounce, vectorised over points x spp with
    Dr.Jit (at most 2^20 lanes a pass). Runs in the Mitsuba venv's python.
    Returns (radiance at the points (first channel), seconds: scene loading,
    kernel compilation or cache loading and sampling, shadow rays)."""
    sys.path.insert(0, os.path.join(HERE, "reference"))
    import mitsuba_cornell

    settings = mitsuba_cornell.argument_parser().parse_args([])
    polygons, reflectance, emission = mitsuba_cornell.load_penumbra_polygons(
        scene_name, settings.penumbra_pythonpath)
    normal = [float(x) for x in mitsuba_cornell.polygon_normal(polygons[FLOOR])]
    # The Cornell reference's kind of scene, without sensors (its integrator is not used).
    mitsuba, drjit, scene, start = load_mitsuba_scene(polygons, reflectance, emission, [],
                                                      settings, threads)
    sampler = mitsuba.load_dict({"type": "independent"})
    count = len(points)
    per_pass = max(1, min(spp, (1 << 20) // count))
    total = np.zeros(count)
    done = 0
    while done < spp:
        passes = min(per_pass, spp - done)
        lanes = np.tile(points, (passes, 1))  # lane = sample * count + point
        interaction = drjit.zeros(mitsuba.SurfaceInteraction3f, passes * count)
        interaction.p = mitsuba.Point3f(lanes[:, 0], lanes[:, 1], lanes[:, 2])
        interaction.n = mitsuba.Normal3f(*normal)
        interaction.sh_frame = mitsuba.Frame3f(interaction.n)
        sampler.seed(seed + done, passes * count)
        direction, weight = scene.sample_emitter_direction(interaction, sampler.next_2d(), True)
        cosine = drjit.maximum(drjit.dot(direction.d, interaction.n), 0.0)
        total += np.array(weight.x * cosine).reshape(passes, count).sum(axis=0)
        done += passes
    radiance = reflectance[FLOOR, 0] / np.pi * total / spp
    return radiance, time.perf_counter() - start, spp * count


def radiance_run(scene, rays, settings, threads):
    """Radiance's irradiance at `rays` (n x 6: point, normal): the scene
    converted to Radiance primitives and compiled (Benchmarks/
    radiance_scene.py), then `rtrace -I` with settings["rtrace"] in `threads`
    processes (-n), each point given settings["repeats"] times and the
    estimates averaged, with an ambient file fresh for the run when the
    ambient cache is on (-aa above 0, or not given: its default is 0.1, but
    only -ab above 0 uses it). The points lie on the surfaces: rtrace -I
    takes them as the surface point itself and its rays do not hit the
    surface they leave (1e-6 to 1e-5 off changed nothing measurable).
    Returns (n x 3 irradiance, seconds: conversion, octree, tracing and
    averaging, rays traced from the points)."""
    from radiance_scene import installed_bin, make_octree, rtrace_irradiance

    binaries = installed_bin()
    options = list(settings["rtrace"])
    repeats = settings.get("repeats", 1)
    cached = "-aa" not in options or float(options[options.index("-aa") + 1]) > 0.0
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        octree = make_octree(binaries, scene, folder)
        if cached:
            options += ["-af", os.path.join(folder, "scene.amb")]
        irradiance, _ = rtrace_irradiance(binaries, octree, np.repeat(rays, repeats, axis=0),
                                          options, processes=threads)
        irradiance = irradiance.reshape(len(rays), repeats, 3).mean(axis=1)
        seconds = time.perf_counter() - start
    return irradiance, seconds, len(rays) * repeats


def radiance_direct(scene_name, points, settings, threads):
    """Radiance's floor radiance at `points` (first channel), with the
    floor's normal: radiance = floor reflectance * irradiance / pi. Returns
    (radiance, seconds, rays; see radiance_run)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    import penumbra

    scene = penumbra.load_scene(scene_name)
    reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))[FLOOR, 0]
    sys.path.insert(0, os.path.join(HERE, "reference"))
    from mitsuba_cornell import polygon_normal

    corners = scene.GetCell(FLOOR).GetPoints()
    normal = polygon_normal([np.array(corners.GetPoint(k))
                             for k in range(corners.GetNumberOfPoints())])
    rays = np.hstack([points, np.tile(normal, (len(points), 1))])
    irradiance, seconds, samples = radiance_run(scene, rays, settings, threads)
    return reflectance * irradiance[:, 0] / np.pi, seconds, samples


def cornell_points(reference, k=2):
    """The points at which the other methods' Cornell pixels are averaged
    (compare_cornell.pixel_averages: k x k per valid pixel, 1e-6 in front of
    the surface): (sensor name, rows, columns, (k * k * pixels) x 6 rays:
    point and sensor normal, the k * k points of a pixel `pixels` apart)."""
    offsets = (np.arange(k) + 0.5) / k
    for name in reference["sensors"].item().split(","):
        origin, u, v, normal = (reference[name + "_" + key]
                                for key in ("origin", "u", "v", "normal"))
        size = float(reference[name + "_pixel_size"])
        rows, cols = np.nonzero(reference[name + "_mask"])
        points = np.vstack([origin + (cols[:, None] + a) * size * u
                            + (rows[:, None] + b) * size * v + 1e-6 * normal
                            for b in offsets for a in offsets])
        yield name, rows, cols, np.hstack([points, np.tile(normal, (len(points), 1))])


def radiance_cornell(settings, threads):
    """Radiance's Cornell box at the reference's sensors: the irradiance at
    2 x 2 points per valid pixel (cornell_points, as the other methods'
    pixels are measured: the pixel centres alone would put Penumbra's own
    solution 0.44% RMS further from the reference on the floor, from the
    curvature of the radiance in penumbrae and contact shadows), averaged;
    radiance = reflectance * irradiance / pi per channel. Returns (sensor
    name -> (H, W, 3) image, seconds, rays; see radiance_run)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    import penumbra

    reference = np.load(CORNELL_REFERENCE, allow_pickle=True)
    scene = penumbra.load_scene("cornell")
    reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))
    sensors = list(cornell_points(reference))
    irradiance, seconds, samples = radiance_run(
        scene, np.vstack([rays for *_, rays in sensors]), settings, threads)
    images, first = {}, 0
    for name, rows, cols, rays in sensors:
        image = np.full(tuple(reference[name + "_shape"]) + (3,), np.nan)
        rho = reflectance[int(reference[name + "_cell_id"])]
        mean = irradiance[first:first + len(rays)].reshape(-1, len(rows), 3).mean(axis=0)
        image[rows, cols] = rho * mean / np.pi
        first += len(rays)
        images[name] = image
    return images, seconds, samples


def radiance_check(scenes, points):
    """Front sides and units of the conversion against exact values, before
    any timing: Radiance's direct light (-ab 0) at its finest source
    subdivision, with every source tested, against Penumbra's exact radiance
    (vtkPenumbraRadianceEvaluator). On "strip" (the whole light seen from
    every floor point: no shadow) at the error points; on the Cornell box
    (when measured) at the centres of the reference's valid pixels, per
    channel, which checks the light's front side and the sensors' normals.
    A wrong side or unit is an error of order one; Radiance's partitions of
    the light leave a fraction of a percent. Prints the figures; raises if
    the mean is off by more than 0.2% on "strip" or 0.5% on the Cornell
    box, or any "strip" point by more than 1%."""
    import penumbra

    settings = {"rtrace": ["-ab", "0", "-ds", "0.02", "-dt", "0", "-dc", "1"]}
    strip = penumbra.load_scene("strip")
    floor = floor_points(strip, points)
    exact = exact_radiance(strip, floor)
    radiance = radiance_direct("strip", floor, settings, 1)[0]
    relative = (radiance - exact) / exact.mean()
    checks = [("strip floor", radiance.mean() / exact.mean(), np.sqrt(np.mean(relative ** 2)),
               np.abs(relative).max(), 0.002, 0.01)]
    if "cornell" in scenes:
        from vtkmodules.util.numpy_support import vtk_to_numpy

        reference = np.load(CORNELL_REFERENCE, allow_pickle=True)
        scene = penumbra.load_scene("cornell")
        reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))
        for name, _, _, rays in cornell_points(reference, k=1):
            cell_id = int(reference[name + "_cell_id"])
            exact = exact_radiance(scene, rays[:, :3], cell_id, all_channels=True)
            radiance = (reflectance[cell_id] * radiance_run(scene, rays, settings, 1)[0] / np.pi)
            relative = (radiance - exact) / exact.mean(axis=0)
            ratio = radiance.mean(axis=0) / exact.mean(axis=0)
            checks.append(("Cornell %s (direct)" % name, ratio[np.argmax(np.abs(ratio - 1))],
                           np.sqrt(np.mean(relative ** 2)), np.abs(relative).max(), 0.005, None))
    print("Radiance against exact direct light (rtrace -I %s):" % " ".join(settings["rtrace"]))
    for name, ratio, rms, largest, mean_limit, largest_limit in checks:
        print("  %-24s mean ratio %.5f, RMS %.3f%%, largest %.3f%%"
              % (name, ratio, 100 * rms, 100 * largest), flush=True)
        if abs(ratio - 1) > mean_limit or (largest_limit and largest > largest_limit):
            raise RuntimeError("Radiance's %s is off: its conversion (front sides or units) "
                               "is wrong" % name)


def run_one(args):
    """Child process: one (scene, method) run; prints one JSON line."""
    family, label, settings = METHODS[args.one]
    cornell = args.scene == "cornell"
    if family == "path tracing" and cornell:
        images, seconds, samples = path_trace(settings["spp"], args.threads)
        memory = peak_memory_mb()
        relative = reference_errors(images)
    elif family == RADIANCE and cornell:
        images, seconds, samples = radiance_cornell(settings, args.threads)
        memory = peak_memory_mb() + children_peak_memory_mb()
        relative = reference_errors(images)
    elif family == RADIANCE:
        reference = np.load(args.reference)
        radiance, seconds, samples = radiance_direct(args.scene, reference["points"], settings,
                                                     args.threads)
        memory = peak_memory_mb() + children_peak_memory_mb()
        relative = np.abs(radiance - reference["exact"]) / reference["exact"].mean()
    elif family == "path tracing":
        reference = np.load(args.reference)
        radiance, seconds, samples = next_event(args.scene, reference["points"],
                                                settings["spp"], args.threads)
        memory = peak_memory_mb()
        relative = np.abs(radiance - reference["exact"]) / reference["exact"].mean()
    else:
        import penumbra

        scene_data = penumbra.load_scene(args.scene)
        start = time.perf_counter()
        result, samples = solve(scene_data, family, settings, args.threads, indirect=cornell)
        seconds = time.perf_counter() - start
        memory = peak_memory_mb()
        relative = cornell_errors(result) if cornell else direct_errors(result, args.reference)
    print(json.dumps({
        "scene": args.scene, "family": family, "method": label, "seconds": seconds,
        "memory_mb": memory, "samples": samples, "points": int(len(relative)),
        "rms": float(np.sqrt(np.mean(relative ** 2))),
        "p99": float(np.percentile(relative, 99)), "max": float(relative.max())}))
    return 0


MARKERS = {CUBIC: "o", LINEAR: "D", RAY_CAST: "v", "standard": "s", "path tracing": "^",
           RADIANCE: "P"}
COLORS = {family: "C%d" % k for k, family in enumerate(FAMILIES)}  # the same on every chart


def front(rows, scene, family):
    """The family's runs on `scene` as (seconds, rms, label), sorted by time,
    and its curve: the lower envelope (the runs no faster run beats), held
    level to the time of its slowest run (by then the family has reached
    that error)."""
    points = sorted((r["seconds"], r["rms"], r["method"]) for r in rows
                    if r["scene"] == scene and r["family"] == family)
    curve = [p for k, p in enumerate(points) if all(q[1] > p[1] for q in points[:k])]
    if curve and points[-1][0] > curve[-1][0]:
        curve.append((points[-1][0], curve[-1][1], points[-1][2]))
    return points, curve


def short_label(label):
    for prefix in ("Mitsuba ", "standard ", "exact + cubic", "exact + linear",
                   "ray cast + cubic", "Radiance "):
        if label.startswith(prefix):
            return label[len(prefix):].strip() or "default"
    return label


def chart(rows, scene, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 5))
    for family in FAMILIES:
        points, curve = front(rows, scene, family)
        if not points:
            continue
        line, = axes.plot([p[0] for p in curve], [p[1] for p in curve], label=family,
                          color=COLORS[family])
        axes.scatter([p[0] for p in points], [p[1] for p in points], marker=MARKERS[family],
                     color=line.get_color(), s=14)
        for x, y, label in points:
            axes.annotate(short_label(label), (x, y), fontsize=5, xytext=(3, 3),
                          textcoords="offset points", color=line.get_color())
    if scene == "cornell":
        axes.axhline(0.01, color="grey", linestyle=":", linewidth=0.8)
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("wall time (s, %s)" % "2 threads")
    axes.set_ylabel("RMS error / mean (%s)" % ("floor and back wall vs Mitsuba"
                                                if scene == "cornell" else "floor"))
    axes.set_title("%s: error against time" % scene)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def interpolate(curve, seconds):
    """RMS of a family's curve at `seconds`, linear in log-log between its
    runs; None where the curve does not cover that time."""
    if not curve or not curve[0][0] <= seconds <= curve[-1][0]:
        return None
    for (t0, e0, _), (t1, e1, _) in zip(curve, curve[1:]):
        if t0 <= seconds <= t1:
            if t1 == t0:
                return min(e0, e1)
            w = np.log(seconds / t0) / np.log(t1 / t0)
            return float(np.exp((1 - w) * np.log(e0) + w * np.log(e1)))
    return curve[0][1]


def time_to(curve, target):
    """(seconds, exact) when a family's curve first reaches `target` RMS,
    interpolated log-log between its runs; exact is False when its fastest
    run is already below (the time is then an upper bound); None if never."""
    for k, (t1, e1, _) in enumerate(curve):
        if e1 <= target:
            if k == 0:
                return t1, False
            t0, e0 = curve[k - 1][:2]
            w = np.log(target / e0) / np.log(e1 / e0)
            return float(np.exp((1 - w) * np.log(t0) + w * np.log(t1))), True
    return None


def hardware_summary():
    """The processor, its core count, the memory and the system, for dated tables."""
    model = "unknown processor"
    try:
        with open("/proc/cpuinfo") as stream:
            model = next(line.split(":", 1)[1].strip() for line in stream
                         if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    return "%s, %d cores, %.0f GB, %s" % (model, os.cpu_count() or 0, memory,
                                          platform.platform(terse=True))


def claims(rows):
    """The speed-accuracy goals checked on the measured rows; returns Markdown lines.
    Every scene: at each exact + cubic run's time, the standard, path-tracer
    and Radiance curves' RMS (interpolated, only where they cover that time)
    and their ratio to the run's (Penumbra's accuracy ratio at equal time);
    the smallest ratio over the overlap (goal, on the direct-light scenes:
    above 1 everywhere, at least 10 against standard radiosity and
    Radiance, 100 against the path tracer). Cornell box: the time each
    family takes to reach 1% RMS (goal: discontinuity meshing 10 times
    faster than any other)."""
    lines = []
    others = ("standard", "path tracing", RADIANCE)
    scenes = [s for s in SCENES if any(r["scene"] == s for r in rows)]
    direct = scenes  # the equal-time ratios, on the Cornell box too
    if direct:
        lines += ["| scene | exact + cubic run | time (s) | RMS | standard RMS then | ratio "
                  "| path tracer RMS then | ratio | Radiance RMS then | ratio |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        summary = []
        for scene in direct:
            runs = front(rows, scene, CUBIC)[0]
            curves = {f: front(rows, scene, f)[1] for f in others}
            worst = {f: None for f in others}
            for seconds, rms, label in runs:
                cells = []
                for family in others:
                    theirs = interpolate(curves[family], seconds)
                    if theirs is None:
                        cells += ["-", "-"]
                        continue
                    ratio = theirs / rms
                    worst[family] = ratio if worst[family] is None else min(worst[family], ratio)
                    cells += ["%.3g%%" % (100 * theirs), "%.3g" % ratio]
                lines.append("| %s | %s | %.2f | %.3g%% | %s |" % (
                    scene, label, seconds, 100 * rms, " | ".join(cells)))
            summary.append((scene, worst))
        lines += ["", "| scene | smallest ratio to standard (goal >= 10) "
                  "| smallest ratio to path tracer (goal >= 100) "
                  "| smallest ratio to Radiance (goal >= 10) | below all everywhere |",
                  "| --- | --- | --- | --- | --- |"]
        for scene, worst in summary:
            values = [worst[f] for f in others]
            lines.append("| %s | %s | %s | %s | %s |" % (
                scene, *("%.3g" % v if v is not None else "no overlap" for v in values),
                "no overlap" if all(v is None for v in values)
                else "yes" if all(v is None or v > 1 for v in values) else "no"))
    if "cornell" in scenes:
        times = {}
        lines += ["", "| Cornell box family | time to 1% RMS (s) | best run |",
                  "| --- | --- | --- |"]
        for family in FAMILIES:
            points, curve = front(rows, "cornell", family)
            if not points:
                continue
            reached = time_to(curve, 0.01)
            times[family] = reached
            best = min(points, key=lambda p: p[1])
            lines.append("| %s | %s | %s: %.3g%% at %.1f s |" % (
                family, "not reached" if reached is None else
                ("%.1f" if reached[1] else "<= %.1f") % reached[0],
                best[2], 100 * best[1], best[0]))
        ours = times.get(CUBIC)
        if ours is not None:
            lines.append("")
            for family in others:
                if family not in times:
                    continue
                theirs = times[family]
                if theirs is None:
                    longest = max(p[0] for p in front(rows, "cornell", family)[0])
                    lines.append("- %s does not reach 1%% RMS in its longest run (%.1f s): "
                                 "exact + cubic is at least %.1f times faster (goal: 10)"
                                 % (family, longest, longest / ours[0]))
                else:
                    lines.append("- exact + cubic reaches 1%% RMS %s%.1f times faster than %s "
                                 "(goal: 10)" % ("" if ours[1] else "at least ",
                                                 theirs[0] / ours[0], family))
    return lines


FIELDS = ["scene", "family", "method", "seconds", "memory_mb", "samples", "points", "rms",
          "p99", "max"]


def write_outputs(rows, out):
    """The CSV, the Markdown table with the claims below it, the claims on
    standard output."""
    with open(os.path.join(out, "speed_accuracy.csv"), "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    lines = claims(rows)
    print("\n".join(["", "Goals:", ""] + lines))
    with open(os.path.join(out, "speed_accuracy.md"), "w") as stream:
        stream.write("# Speed against accuracy\n\nMeasured %s on %s by `Benchmarks/"
                     "speed_accuracy.py`.\n\n" % (datetime.date.today().isoformat(),
                                                    hardware_summary()))
        stream.write("| scene | method | time (s) | peak memory (MB) | samples | RMS | p99 | max |\n")
        stream.write("| --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for r in rows:
            stream.write("| %s | %s | %.2f | %.0f | %d | %.3g%% | %.3g%% | %.3g%% |\n"
                         % (r["scene"], r["method"], r["seconds"], r["memory_mb"], r["samples"],
                            100 * r["rms"], 100 * r["p99"], 100 * r["max"]))
        stream.write("\n## Goals\n\n%s\n" % "\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--methods", default=None,
                        help="comma-separated method labels, or 'all' (default: all but "
                             "the ray-cast evaluation)")
    parser.add_argument("--points", type=int, default=4000)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", default=".")
    parser.add_argument("--mitsuba-python", default=MITSUBA_PYTHON,
                        help="python of the Mitsuba 3 venv (Benchmarks/reference/setup_mitsuba.sh; "
                             "default %(default)s); the path tracer is left out without it")
    parser.add_argument("--no-radiance", action="store_true",
                        help="leave Radiance out (otherwise its venv is made on first use: "
                             "Benchmarks/reference/setup_radiance.sh)")
    parser.add_argument("--replot", metavar="CSV",
                        help="no runs: redo the charts, tables and claims from a CSV "
                             "this script wrote")
    parser.add_argument("--one", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--scene", help=argparse.SUPPRESS)
    parser.add_argument("--reference", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one is not None:
        return run_one(args)
    os.makedirs(args.out, exist_ok=True)
    if args.replot:
        with open(args.replot, newline="") as stream:
            rows = [{k: (v if k in ("scene", "family", "method") else float(v))
                     for k, v in row.items()} for row in csv.DictReader(stream)]
        for scene in SCENES:
            if any(r["scene"] == scene for r in rows):
                chart(rows, scene, os.path.join(args.out, "speed_accuracy_%s.png" % scene))
        write_outputs(rows, args.out)
        return 0

    import penumbra
    from radiance_scene import radiance_bin

    wanted = ([label for _, label, _ in METHODS] if args.methods == "all"
              else args.methods.split(",") if args.methods else None)

    def chosen(scene, family, label):
        if family == RADIANCE and args.no_radiance:
            return False
        if wanted is None:
            return label in (CORNELL_METHODS if scene == "cornell" else DEFAULT_METHODS)
        return label in wanted

    scenes = args.scenes.split(",")
    if any(chosen(scene, family, label) for scene in scenes for family, label, _ in METHODS
           if family == RADIANCE):
        radiance_bin()  # makes the Radiance venv the first time
        radiance_check(scenes, args.points)
    rows = []
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for scene in scenes:
            reference = os.path.join(folder, scene + ".npz")
            if scene != "cornell":
                scene_data = penumbra.load_scene(scene)
                points = floor_points(scene_data, args.points)
                np.savez(reference, points=points, exact=exact_radiance(scene_data, points))
            for index, (family, label, _) in enumerate(METHODS):
                if not chosen(scene, family, label):
                    continue
                python = sys.executable
                if family == "path tracing":
                    if not os.access(args.mitsuba_python, os.X_OK):
                        print("%-9s %-40s left out: no Mitsuba venv at %s"
                              % (scene, label, args.mitsuba_python), flush=True)
                        continue
                    python = args.mitsuba_python
                child = subprocess.run(
                    [python, os.path.abspath(__file__), "--one", str(index),
                     "--scene", scene, "--reference", reference, "--threads", str(args.threads)],
                    stdout=subprocess.PIPE, universal_newlines=True, check=True)
                row = json.loads(child.stdout.strip().splitlines()[-1])
                rows.append(row)
                print("%-9s %-40s %7.2f s %6.0f MB %8d samples  RMS %.3g%%  p99 %.3g%%  max %.3g%%"
                      % (scene, label, row["seconds"], row["memory_mb"], row["samples"],
                         100 * row["rms"], 100 * row["p99"], 100 * row["max"]), flush=True)
            chart(rows, scene, os.path.join(args.out, "speed_accuracy_%s.png" % scene))
    write_outputs(rows, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
