#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Where the direct light's time goes, scene by scene, and what it buys.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/direct_profile.py
        [--runs 3] [--scenes NAMES] [--set Setting=value ...] [--out build/benchmarks]

Solves each scene's direct light (the pipeline's stages, default settings,
2 threads, each stage updated and timed in turn) --runs times and reports
the median of each stage's time (the mesher; the evaluator: the adaptive
sampler and the exact evaluator together; the reconstructor: the cubic and
the display) and their sum, the samples the sampler kept, the radiance evaluations it
made (Evaluations) and their ratio (evaluations per kept sample: the probes
that found the interpolant good enough are the rest), the output's points,
and the error of the displayed floor radiance against the exact evaluator at
4,000 random floor points (RMS and largest, relative to their mean) and, for
scenes with a small feature, at 4,000 random points of a band around it
(largest, relative to the same mean): the 2 mm strip of floor centred on the
box's lit edge (contact, floating: under the floating box the light ramps
down within 0.4 mm), the slit's light, a 4 mm strip along one slat's
penumbra (1.5 mm wide), the floor under the light against the wall.

Scenes: the library's strip, occluder, seven and blind, and built here
(a 2 x 2 m floor, surface 0, under a 0.4 x 0.4 m light 1.5 m up unless
said): a 0.5 m box standing on the floor (contact), the same box 1 mm
above it (floating), a plate 0.5 m up with a 0.5 mm slit (slit), a small
distant light (a 5 cm square 20 m up and aside, like the sun) through
slats (sun slats), forty 1 cm squares 0.3 m up (tiny occluders), and a
light against a wall (wall light).

--set changes a setting of every stage that has it (vtkPenumbraRadianceEvaluator's
MinimumFeatureSize, the reconstructor's SubdivisionLevel, ...), for comparing
values on all the scenes at once.

Prints a Markdown table and writes --out/direct_profile.csv and the chart
--out/direct_profile.png (time per stage, stacked, per scene).
"""
import argparse
import csv
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
FLOOR_SIZE = 1.0  # half the floor's side
GREY = (0.5, 0.5, 0.5)
BLACK = (0.0, 0.0, 0.0)


def quad(a, b, c, d, reflectance=GREY, emission=BLACK):
    return {"vertices": [a, b, c, d], "reflectance": reflectance, "emission": emission}


def floor():
    w = FLOOR_SIZE
    return quad((-w, 0, w), (w, 0, w), (w, 0, -w), (-w, 0, -w))


def light(cx=0.6, cz=0.0, half=0.2, height=1.5, radiance=10.0):
    """A square light facing down."""
    return quad((cx - half, height, cz - half), (cx + half, height, cz - half),
                (cx + half, height, cz + half), (cx - half, height, cz + half),
                reflectance=BLACK, emission=(radiance,) * 3)


def box(half, bottom, top):
    """An axis-aligned box's six faces, facing out."""
    s, lo, hi = half, bottom, top
    return [quad((-s, hi, -s), (-s, hi, s), (s, hi, s), (s, hi, -s)),
            quad((-s, lo, -s), (s, lo, -s), (s, lo, s), (-s, lo, s)),
            quad((-s, lo, s), (s, lo, s), (s, hi, s), (-s, hi, s)),
            quad((-s, lo, -s), (-s, hi, -s), (s, hi, -s), (s, lo, -s)),
            quad((s, lo, -s), (s, hi, -s), (s, hi, s), (s, lo, s)),
            quad((-s, lo, -s), (-s, lo, s), (-s, hi, s), (-s, hi, -s))]


def plate(x0, x1, z0, z1, y):
    """A horizontal rectangle facing up."""
    return quad((x0, y, z0), (x0, y, z1), (x1, y, z1), (x1, y, z0), reflectance=BLACK)


def built_scene(name):
    """(polygons, band): the scene's polygons and the (x0, x1, z0, z1) band
    around its small feature, or None."""
    if name == "contact":
        return [floor()] + box(0.25, 0.0, 0.5) + [light()], (0.249, 0.251, -0.25, 0.25)
    if name == "floating":
        return [floor()] + box(0.25, 0.001, 0.501) + [light()], (0.249, 0.251, -0.25, 0.25)
    if name == "slit":
        gap = 0.00025
        return ([floor(), plate(-1.2, -gap, -1.2, 1.2, 0.5), plate(gap, 1.2, -1.2, 1.2, 0.5),
                 light(cx=0.0)], (-0.15, 0.15, -0.5, 0.5))
    if name == "sun slats":
        slats = [plate(-0.9, 0.9, z - 0.02, z + 0.02, 0.6) for z in np.arange(-0.8, 0.81, 0.1)]
        sun = light(cx=-6.0, half=0.025, height=20.0, radiance=2e5)
        return [floor()] + slats + [sun], (-0.8, 0.8, -0.0845, -0.0805)
    if name == "tiny occluders":
        rng = np.random.default_rng(5)
        squares = [plate(x - 0.005, x + 0.005, z - 0.005, z + 0.005, 0.3)
                   for x, z in rng.uniform(-0.6, 0.6, size=(40, 2))]
        return [floor()] + squares + [light(cx=0.0)], None
    if name == "wall light":
        w = FLOOR_SIZE
        wall = quad((-w, 0, -w), (-w, 2, -w), (-w, 2, w), (-w, 0, w))
        return [floor(), wall, light(cx=-w + 0.2, height=1.0)], (-1.0, -0.7, -0.5, 0.5)
    raise KeyError(name)


LIBRARY = ("strip", "occluder", "seven", "blind")
BUILT = ("contact", "floating", "slit", "sun slats", "tiny occluders", "wall light")


def load(name):
    import penumbra
    from penumbra.generators import scene_from_polygons

    if name in LIBRARY:
        return penumbra.load_scene(name), None
    polygons, band = built_scene(name)
    return scene_from_polygons(polygons), band


def band_points(band, count, seed=11):
    x0, x1, z0, z1 = band
    rng = np.random.default_rng(seed)
    points = np.zeros((count, 3))
    points[:, 0] = rng.uniform(x0, x1, count)
    points[:, 2] = rng.uniform(z0, z1, count)
    return points


def apply_settings(stages, settings):
    """Set each Name=value on every stage that has a SetName (the value read
    as that filter's setting: its type and range)."""
    from penumbra.settings import parse

    for text in settings:
        name = text.partition("=")[0].strip()
        targets = [stage for stage in stages.values() if hasattr(stage, "Set" + name)]
        if not targets:
            raise SystemExit("--set %s: no stage has a setting %s" % (text, name))
        for stage in targets:
            getattr(stage, "Set" + name)(parse(stage.GetClassName(), text)[1])


def staged_solve(scene, settings=()):
    """The direct light through the pipeline's stages, each updated and timed
    in turn (2 threads); returns (result, seconds per stage, kept samples,
    evaluations)."""
    from vtkmodules.vtkCommonCore import vtkSMPTools
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    from penumbra.pipeline import build_pipeline

    vtkSMPTools.Initialize(2)
    source = vtkTrivialProducer()
    source.SetOutput(scene)
    stages = build_pipeline(source.GetOutputPort(), indirect=False)
    apply_settings(stages, settings)
    seconds = {}
    for stage in ("mesher", "evaluator", "reconstructor"):
        start = time.perf_counter()
        stages[stage].Update()
        seconds[stage] = time.perf_counter() - start
    sampled = stages["evaluator"].GetOutput()
    evaluations = sampled.GetFieldData().GetArray("Evaluations").GetValue(0)
    return stages["reconstructor"].GetOutput(), seconds, sampled.GetNumberOfPoints(), evaluations


def profile(name, runs, settings=()):
    sys.path.insert(0, HERE)
    from speed_accuracy import displayed_radiance, exact_radiance, floor_points

    scene, band = load(name)
    stages = {"mesher": [], "evaluator": [], "reconstructor": []}
    for _ in range(runs):
        result, seconds, samples, evaluations = staged_solve(scene, settings)
        for stage in stages:
            stages[stage].append(seconds[stage])
    points = floor_points(scene, 4000)
    exact = exact_radiance(scene, points)
    shown = displayed_radiance(result, points)
    mean = exact.mean()
    error = np.abs(shown - exact) / mean
    row = {"scene": name, "solve": sum(statistics.median(v) for v in stages.values()),
           "mesher": statistics.median(stages["mesher"]),
           "evaluator": statistics.median(stages["evaluator"]),
           "reconstructor": statistics.median(stages["reconstructor"]),
           "samples": samples, "evaluations": evaluations,
           "per_sample": evaluations / samples if samples > 0 else float("nan"),
           "output_points": result.GetNumberOfPoints(),
           "rms": float(np.sqrt(np.nanmean(error ** 2))), "max": float(np.nanmax(error)),
           "band_max": float("nan")}
    if band is not None:
        near = band_points(band, 4000)
        row["band_max"] = float(np.nanmax(np.abs(displayed_radiance(result, near)
                                                 - exact_radiance(scene, near)) / mean))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--scenes", default=",".join(LIBRARY + BUILT))
    parser.add_argument("--set", nargs="*", default=[], metavar="Setting=value")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build", "benchmarks"))
    args = parser.parse_args(argv)
    rows = [profile(name, args.runs, args.set) for name in args.scenes.split(",")]
    print("| scene | solve (s) | mesher | evaluator | reconstructor | samples | evaluations "
          "| per sample | output points | RMS | largest | largest near the feature |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        band = "-" if np.isnan(r["band_max"]) else "%.3g%%" % (100 * r["band_max"])
        print("| %s | %.3f | %.3f | %.3f | %.3f | %d | %d | %.2f | %d | %.3g%% | %.3g%% | %s |"
              % (r["scene"], r["solve"], r["mesher"], r["evaluator"], r["reconstructor"],
                 r["samples"], r["evaluations"], r["per_sample"], r["output_points"],
                 100 * r["rms"], 100 * r["max"], band))
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "direct_profile.csv")
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(figsize=(9, 4.2))
    names = [r["scene"] for r in rows]
    left = np.zeros(len(rows))
    for stage, colour in (("mesher", "tab:green"), ("evaluator", "tab:blue"),
                          ("reconstructor", "tab:orange")):
        values = np.array([r[stage] for r in rows])
        axes.barh(names, values, left=left, color=colour, label=stage)
        left += values
    axes.invert_yaxis()
    axes.set_xlabel("seconds (median of %d, 2 threads)" % args.runs)
    axes.set_title("Direct light: time per stage, "
                   + (", ".join(args.set) if args.set else "default settings"))
    axes.legend()
    fig.tight_layout()
    chart = os.path.join(args.out, "direct_profile.png")
    fig.savefig(chart, dpi=90)
    print("wrote", chart)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
