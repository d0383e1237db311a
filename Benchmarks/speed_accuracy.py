#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Speed against accuracy: the direct-light scenes and the Cornell box (issue 7).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/speed_accuracy.py \\
        [--scenes strip,occluder,seven,blind,cornell] [--methods LABELS|all] [--points 4000]
        [--threads 2] [--out DIR] [--mitsuba-python build/_deps/mitsuba-venv/bin/python]

For each scene and each method it runs one solve in a fresh process (so
that the peak memory is that run's) and measures the wall time of the
solve, the peak resident memory of the process (VTK and Python included,
about 100 MB of it), the number of radiance samples (discontinuity
meshing: evaluations; standard radiosity: vertices) and the error of the
displayed floor radiance (linear over the output triangles, as the data
contract defines it) against exact values at independent random points of
the floor (vtkRadianceEvaluator, exact method, at the points themselves):
RMS, 99th percentile and maximum of |error| relative to the mean exact
radiance (first channel; these scenes' lights are grey).

In these scenes the floor's radiance is exactly the direct light: the
lights do not reflect, and the occluders face up, away from the floor.
The Cornell box is solved with its interreflections and measured against
the Mitsuba 3 reference of compare_cornell.py (floor and back wall pixels,
all channels), with fewer methods (CORNELL_METHODS).

Methods: discontinuity meshing with exact evaluation and cubic
reconstruction, with linear reconstruction (and with ray-cast evaluation
on request, see DEFAULT_METHODS); standard radiosity at five mesh
densities, with a finer subdivision threshold, without subdivision, with
smaller shooting patches, and with Wallace et al.'s disc form factors as
published; on the Cornell box also the Mitsuba 3 path tracer at 16 to
16,384 samples per pixel, rendering the reference's own sensors (floor
and back wall, 1 cm pixels; Benchmarks/reference/mitsuba_cornell.py's
scene and settings, other seeds) in the Mitsuba venv's python
(--mitsuba-python; left out when there is none). Its time covers loading
the scene, compiling the kernels and rendering; its samples are camera
samples (pixels x spp); its error is that of its pixels against the
reference's, which has 0.17% noise of its own. The paper's Figs. 5 and 6
are Benchmarks/paper_figures.py.

Writes DIR/speed_accuracy.md, DIR/speed_accuracy.csv and one log-log chart
of RMS error against time per scene, DIR/speed_accuracy_SCENE.png
(DIR defaults to the current folder).
"""
import argparse
import csv
import json
import os
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
METHODS = (
    ("discontinuity", "exact + cubic", {}),
    ("discontinuity", "ray cast + cubic", {"evaluation": "ray_cast"}),
    ("discontinuity", "exact + linear", {"reconstruction": "linear"}),
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
          for spp in (16, 64, 256, 1024, 4096, 16384))
# The path tracer renders the Cornell box only (the reference's sensors).
PATH_TRACED_SCENES = ("cornell",)
# Ray-cast evaluation is left out unless asked for (--methods all): with the
# adaptive sampling it took 318 s and 868,000 samples on "occluder" (exact:
# 0.65 s, 3,344 samples); the sampling does not settle on its estimates.
DEFAULT_METHODS = [label for _, label, _ in METHODS if label != "ray cast + cubic"]
# The Cornell box (with interreflections) costs far more per sample: the
# finer standard meshes would take minutes each.
CORNELL_METHODS = ["exact + cubic", "exact + linear", "standard h=0.1 s=2",
                   "standard h=0.05 s=4", "standard h=0.05 s=4 t=0.1",
                   "standard h=0.05 s=4 p=0.2"] + [
    label for family, label, _ in METHODS if family == "path tracing"]
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


def exact_radiance(scene, points):
    """Exact direct radiance at `points` on the floor (vtkRadianceEvaluator)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    import penumbra
    from penumbra.pipeline import point_samples

    data = point_samples(points, FLOOR)
    evaluator = penumbra.vtkRadianceEvaluator()
    evaluator.SetInputData(0, data)
    evaluator.SetSceneData(scene)
    return vtk_to_numpy(penumbra.run_filter(evaluator).GetPointData().GetArray("Radiance"))[:, 0]


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
    stages = build_pipeline(source.GetOutputPort(), indirect=indirect)
    if settings.get("evaluation") == "ray_cast":
        stages["evaluator"].SetMethod(penumbra.vtkRadianceEvaluator.RAY_CAST)
    if settings.get("reconstruction") == "linear":
        stages["reconstructor"].SetModeToLinear()
    result = penumbra.run_filter(stages["reconstructor"])
    evaluations = stages["evaluator"].GetOutput().GetFieldData().GetArray("Evaluations")
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
    mitsuba_cornell.configure_llvm()
    import drjit
    import mitsuba

    mitsuba.set_variant(str(reference["variant"]))
    drjit.set_thread_count(threads)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="penumbra-mitsuba-") as folder:
        scene = mitsuba.load_dict(mitsuba_cornell.build_scene_dict(
            mitsuba, polygons, reflectance, emission, sensors, settings, folder))
    images = {}
    for k, sensor in enumerate(sensors):
        # The reference used seeds 1 to spp_total / spp_per_pass; these are far above.
        mean = mitsuba_cornell.render_sensor(mitsuba, scene, k, sensor, settings,
                                             10 ** 6 + 1000 * k)[0]
        images[sensor["name"]] = mean
    seconds = time.perf_counter() - start
    samples = spp * sum(int(np.prod(sensor["shape"])) for sensor in sensors)
    return images, seconds, samples


def run_one(args):
    """Child process: one (scene, method) run; prints one JSON line."""
    family, label, settings = METHODS[args.one]
    cornell = args.scene == "cornell"
    if family == "path tracing":
        images, seconds, samples = path_trace(settings["spp"], args.threads)
        memory = peak_memory_mb()
        relative = reference_errors(images)
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


def chart(rows, scene, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(6, 4.5))
    for family, marker in (("discontinuity", "o"), ("standard", "s"), ("path tracing", "^")):
        points = sorted((r["seconds"], r["rms"], r["method"]) for r in rows
                        if r["scene"] == scene and r["family"] == family)
        if not points:
            continue
        # The family's curve is its lower envelope: the runs no faster run beats.
        front = [p for k, p in enumerate(points) if all(q[1] > p[1] for q in points[:k])]
        line, = axes.plot([p[0] for p in front], [p[1] for p in front], label=family)
        axes.scatter([p[0] for p in points], [p[1] for p in points], marker=marker,
                     color=line.get_color())
        for x, y, label in points:
            axes.annotate(label, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("wall time (s, %s)" % "2 threads")
    axes.set_ylabel("RMS error / mean (%s)" % ("floor and back wall vs Mitsuba"
                                                if scene == "cornell" else "floor"))
    axes.set_title("%s: error against time" % scene)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


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
    parser.add_argument("--one", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--scene", help=argparse.SUPPRESS)
    parser.add_argument("--reference", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one is not None:
        return run_one(args)

    import penumbra

    if args.methods == "all":
        wanted = [label for _, label, _ in METHODS]
    else:
        wanted = args.methods.split(",") if args.methods else DEFAULT_METHODS
    rows = []
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for scene in args.scenes.split(","):
            reference = os.path.join(folder, scene + ".npz")
            if scene != "cornell":
                scene_data = penumbra.load_scene(scene)
                points = floor_points(scene_data, args.points)
                np.savez(reference, points=points, exact=exact_radiance(scene_data, points))
            for index, (family, label, _) in enumerate(METHODS):
                if label not in wanted or (scene == "cornell" and args.methods is None
                                           and label not in CORNELL_METHODS):
                    continue
                python = sys.executable
                if family == "path tracing":
                    if scene not in PATH_TRACED_SCENES:
                        continue
                    if not os.access(args.mitsuba_python, os.X_OK):
                        print("%-9s %-18s left out: no Mitsuba venv at %s"
                              % (scene, label, args.mitsuba_python), flush=True)
                        continue
                    python = args.mitsuba_python
                child = subprocess.run(
                    [python, os.path.abspath(__file__), "--one", str(index),
                     "--scene", scene, "--reference", reference, "--threads", str(args.threads)],
                    stdout=subprocess.PIPE, universal_newlines=True, check=True)
                row = json.loads(child.stdout.strip().splitlines()[-1])
                rows.append(row)
                print("%-9s %-18s %7.2f s %6.0f MB %8d samples  RMS %.3g%%  p99 %.3g%%  max %.3g%%"
                      % (scene, label, row["seconds"], row["memory_mb"], row["samples"],
                         100 * row["rms"], 100 * row["p99"], 100 * row["max"]), flush=True)
            chart(rows, scene, os.path.join(args.out, "speed_accuracy_%s.png" % scene))
    fields = ["scene", "family", "method", "seconds", "memory_mb", "samples", "points", "rms",
              "p99", "max"]
    with open(os.path.join(args.out, "speed_accuracy.csv"), "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(args.out, "speed_accuracy.md"), "w") as stream:
        stream.write("| scene | method | time (s) | peak memory (MB) | samples | RMS | p99 | max |\n")
        stream.write("| --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for r in rows:
            stream.write("| %s | %s | %.2f | %.0f | %d | %.3g%% | %.3g%% | %.3g%% |\n"
                         % (r["scene"], r["method"], r["seconds"], r["memory_mb"], r["samples"],
                            100 * r["rms"], 100 * r["p99"], 100 * r["max"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
