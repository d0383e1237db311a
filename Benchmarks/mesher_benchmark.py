#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark of vtkPenumbraDiscontinuityMesher on one thread.

For the built-in Cornell box, seven occluders and venetian blind, and for
generated rooms full of boxes (penumbra.generators.box_room, or with --scene
furnished_room the furnished interior) of 1,000 and 10,000 polygons (--sizes;
20,000 with --large), run the mesher with its defaults (every
light is a shooter) on ONE thread and time it: the median of 5 runs for scenes
under 1,000 polygons, of 3 runs otherwise (wall-clock time of the filter's
update; the process CPU time is reported too, as the machine may be shared).

Prints a Markdown table (scene, polygons, shooters, segments generated and
kept, contact segments, constraints, failed constraints, triangles, wedges
traced, time median/min/max, CPU time, time per segment), whether the Cornell
target (< 0.2 s) is met, and the growth exponents of the time with respect to
the number of segments generated, of polygons and of wedges (least-squares
slopes on log-log axes, over all scenes and over the generated rooms alone). Writes the table as
Markdown and CSV and a log-log chart (PNG) of time against segments into
--out (default: build/benchmarks of the source tree).

Run with the package on the path, e.g.::

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Benchmarks/mesher_benchmark.py --large
"""
import argparse
import csv
import os
import statistics
import sys
import time

import numpy as np

CORNELL_TARGET = 0.2  # seconds, light-only mesh on one core
BUILTIN = ("cornell", "seven", "blind")
FIELDS = ("SegmentsGenerated", "SegmentsKept", "ContactSegments", "Constraints",
          "ConstraintFailures", "Triangles", "Wedges")
COLUMNS = [("scene", "scene"), ("polygons", "polygons"), ("shooters", "shooters"),
           ("SegmentsGenerated", "segments generated"), ("SegmentsKept", "kept"),
           ("ContactSegments", "contact segments"), ("Constraints", "constraints"),
           ("ConstraintFailures", "failures"), ("Triangles", "triangles"), ("Wedges", "wedges"),
           ("runs", "runs"), ("median", "time median (s)"), ("min", "min (s)"),
           ("max", "max (s)"), ("cpu", "CPU median (s)"), ("us_per_segment", "µs / segment")]


def source_dir():
    return os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.join(source_dir(), "build", "benchmarks"),
                        help="output folder (default: %(default)s)")
    parser.add_argument("--sizes", type=int, nargs="*", default=[1000, 10000],
                        help="polygon counts of the generated rooms (default: 1000 10000)")
    parser.add_argument("--large", action="store_true", help="also a 20,000-polygon room")
    parser.add_argument("--seed", type=int, default=0, help="seed of the generated rooms")
    parser.add_argument("--scene", default="box_room", choices=("box_room", "furnished_room"),
                        help="generator of the rooms (default: %(default)s)")
    parser.add_argument("--threads", type=int, default=1,
                        help="vtkSMPTools threads (default 1: the one-core numbers)")
    parser.add_argument("--runs", type=int, default=0,
                        help="runs per scene (default: 5 under 1,000 polygons, else 3)")
    parser.add_argument("--jump-threshold", type=float, default=0.0,
                        help="the mesher's JumpThreshold (default 0, the mesher's default)")
    parser.add_argument("--no-builtin", action="store_true",
                        help="skip the built-in scenes (generated rooms only)")
    return parser.parse_args(argv)


def scenes(args):
    """(name, scene vtkPolyData, generated?) for every benchmarked scene."""
    import penumbra
    from penumbra import generators

    if not args.no_builtin:
        for name in BUILTIN:
            yield name, penumbra.load_scene(name), False
    sizes = list(args.sizes) + ([20000] if args.large and 20000 not in args.sizes else [])
    generator = getattr(generators, args.scene)
    for size in sizes:
        yield "%s(%d)" % (args.scene, size), generator(size, seed=args.seed), True


def shooter_count(scene):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    return int((emission.max(axis=1) > 0).sum())


def time_mesher(scene, runs, jump_threshold=0.0):
    """Run the mesher `runs` times; wall and CPU times and the last run's counts."""
    import penumbra

    wall, cpu, counts = [], [], None
    for _ in range(runs):
        mesher = penumbra.vtkPenumbraDiscontinuityMesher()
        mesher.SetInputData(scene)
        if jump_threshold:
            mesher.SetJumpThreshold(jump_threshold)
        start, start_cpu = time.perf_counter(), time.process_time()
        output = penumbra.run_filter(mesher)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
        field = output.GetFieldData()
        counts = {name: int(field.GetArray(name).GetValue(0)) for name in FIELDS}
        del output, mesher
    return wall, cpu, counts


def fit_slope(x, y):
    """Least-squares slope and intercept of log(y) against log(x)."""
    x, y = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept)


def fmt(value):
    if isinstance(value, float):
        return "%.4f" % value if value < 10 else "%.2f" % value
    return str(value)


def markdown(rows):
    lines = ["| " + " | ".join(title for _, title in COLUMNS) + " |",
             "|" + "|".join("---" if key == "scene" else "---:" for key, _ in COLUMNS) + "|"]
    for row in rows:
        lines.append("| " + " | ".join(fmt(row[key]) for key, _ in COLUMNS) + " |")
    return "\n".join(lines)


def exponents(rows):
    """Growth exponents (log-log slopes) of the median time, as printable lines and a dict."""
    result, lines = {}, []
    usable = [r for r in rows if r["SegmentsGenerated"] > 0 and r["median"] > 0]
    generated = [r for r in usable if r["generated"]]
    for label, subset in (("all scenes", usable), ("generated rooms", generated)):
        if len(subset) < 2:
            continue
        for key, name in (("SegmentsGenerated", "segments generated"), ("polygons", "polygons"),
                          ("Wedges", "wedges")):
            slope, _ = fit_slope([r[key] for r in subset], [r["median"] for r in subset])
            cpu_slope, _ = fit_slope([r[key] for r in subset], [r["cpu"] for r in subset])
            result[(label, key)] = slope
            lines.append("time ~ (%s)^%.2f over %s (%d points; CPU time: ^%.2f)"
                         % (name, slope, label, len(subset), cpu_slope))
    return result, lines


def chart(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    usable = [r for r in rows if r["SegmentsGenerated"] > 0 and r["median"] > 0]
    figure, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, key, label in ((axes[0], "SegmentsGenerated", "segments generated"),
                           (axes[1], "polygons", "polygons")):
        x = np.array([r[key] for r in usable], float)
        y = np.array([r["median"] for r in usable])
        low = y - np.array([r["min"] for r in usable])
        high = np.array([r["max"] for r in usable]) - y
        ax.errorbar(x, y, yerr=[low, high], fmt="o", capsize=3, label="median (min-max)")
        for r, xi, yi in zip(usable, x, y):
            ax.annotate(r["scene"], (xi, yi), textcoords="offset points", xytext=(5, -10),
                        fontsize=8)
        if len(usable) >= 2:
            slope, intercept = fit_slope(x, y)
            xs = np.geomspace(x.min(), x.max(), 50)
            ax.plot(xs, np.exp(intercept) * xs ** slope, "--",
                    label="fit: time ∝ %s$^{%.2f}$" % (label.split()[0], slope))
            # A linear reference through the largest scene.
            ax.plot(xs, y[np.argmax(x)] * xs / x.max(), ":", color="grey", label="slope 1")
        if key == "SegmentsGenerated":
            ax.axhline(CORNELL_TARGET, color="red", lw=0.8, label="Cornell target 0.2 s")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("mesher wall time, one thread (s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    axes[0].set_title("vtkPenumbraDiscontinuityMesher: time against segments")
    axes[1].set_title("time against polygons")
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    import penumbra  # noqa: F401  (after argparse: --help works without the package)
    from vtkmodules.vtkCommonCore import vtkSMPTools

    vtkSMPTools.Initialize(args.threads)
    os.makedirs(args.out, exist_ok=True)
    header = ("vtkSMPTools backend %s, %d thread(s); JumpThreshold %g; load average at start %s"
              % (vtkSMPTools.GetBackend(), vtkSMPTools.GetEstimatedNumberOfThreads(),
                 args.jump_threshold, " ".join("%.2f" % v for v in os.getloadavg())))
    print(header, flush=True)

    rows = []
    for name, scene, generated in scenes(args):
        polygons = scene.GetNumberOfCells()
        runs = args.runs or (5 if polygons < 1000 else 3)
        wall, cpu, counts = time_mesher(scene, runs, args.jump_threshold)
        row = dict(scene=name, polygons=polygons, shooters=shooter_count(scene), runs=runs,
                   generated=generated, median=statistics.median(wall), min=min(wall),
                   max=max(wall), cpu=statistics.median(cpu), **counts)
        row["us_per_segment"] = (1e6 * row["median"] / row["SegmentsGenerated"]
                                 if row["SegmentsGenerated"] else float("nan"))
        rows.append(row)
        print("  %-16s %6d polygons  %8d segments  %8d triangles  %.4f s (median of %d)"
              % (name, polygons, row["SegmentsGenerated"], row["Triangles"], row["median"], runs),
              flush=True)

    table = markdown(rows)
    print()
    print(table)
    print()
    summary = [header, "load average at end %s"
               % " ".join("%.2f" % v for v in os.getloadavg())]
    cornell = [r for r in rows if r["scene"] == "cornell"]
    if cornell:
        t = cornell[0]["median"]
        summary.append("Cornell target (light-only mesh < %.1f s on one core): %s (median %.4f s)"
                       % (CORNELL_TARGET, "MET" if t < CORNELL_TARGET else "NOT MET", t))
    failures = [r["scene"] for r in rows if r["ConstraintFailures"]]
    summary.append("constraint failures: %s" % (", ".join(failures) if failures else "none"))
    _, lines = exponents(rows)
    summary.extend(lines)
    print("\n".join(summary))

    base = os.path.join(args.out, "mesher_benchmark")
    with open(base + ".md", "w") as stream:
        stream.write(table + "\n\n" + "\n".join("- " + s for s in summary) + "\n")
    with open(base + ".csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        keys = [key for key, _ in COLUMNS]
        writer.writerow(keys)
        for row in rows:
            writer.writerow([row[key] for key in keys])
    chart(rows, base + ".png")
    print("\nwrote %s.md, %s.csv and %s.png" % (base, base, base))
    return 0


if __name__ == "__main__":
    sys.exit(main())
