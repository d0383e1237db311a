#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scale benchmark: the default solve of generated rooms full of
boxes (penumbra.generators.box_room) of N polygons.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Benchmarks/scale_benchmark.py [--sizes 1000 5000 20000] [--threads 2] \\
        [--runs 3] [--indirect-samples N] [--no-reuse] [--unshot-fraction F] \\
        [--compact-tolerance T]

Each size runs in its own process (so peak memory is that solve's alone):
penumbra.solve(scene) with the solver's defaults, i.e. direct light plus
interreflections until UnshotFraction of the emitted power is left unshot
(--unshot-fraction sets it). Prints a
Markdown table (polygons, wall time, peak resident memory, stage times,
output triangles and the size of the .vtp the command line writes,
points shot on, shots, the escaped and residual power as fractions of the
emitted: a box room is closed, so escaped should be 0)
and the least-squares growth exponents of time and memory against the
number of polygons, and draws a log-log chart into --out. With --runs R
each size is solved R times (one process each) and the table gives the
medians, with the range of the wall times
(default build/benchmarks). Targets: 20,000 polygons in under
5 minutes and 4 GB on 2 cores. --indirect-samples sets the solver's
MaximumIndirectSamples; --no-reuse turns its ReuseTransport off (weak
shots one orientation at a time, each tracing its rays); --compact-tolerance sets
CompactTolerance (0: the dense display).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TARGET_SECONDS, TARGET_MB = 300.0, 4096.0


def run_child(polygons, threads, seed, settings):
    """One solve, in this process; prints one JSON line."""
    sys.path.insert(0, HERE)
    import penumbra
    from penumbra.generators import box_room
    from speed_accuracy import peak_memory_mb

    scene = box_room(polygons, seed=seed)
    # Stage times from the progress callback: when each stage first reports.
    starts = {}

    def progress(stage, fraction):
        starts.setdefault(stage, time.perf_counter())

    start = time.perf_counter()
    result = penumbra.solve(scene, threads=threads, progress=progress, **settings)
    end = time.perf_counter()
    seconds = end - start
    ordered = sorted(starts.items(), key=lambda item: item[1]) + [("end", end)]
    stages = {name: ordered[k + 1][1] - begin for k, (name, begin) in enumerate(ordered[:-1])}
    field = result.GetFieldData()
    from penumbra.export import write_vtp
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "result.vtp")
        write_vtp(result, path)
        vtp_mb = os.path.getsize(path) / 1e6
    print(json.dumps({
        "polygons": scene.GetNumberOfCells(), "seconds": seconds, "peak_mb": peak_memory_mb(),
        "stages": stages, "output_points": result.GetNumberOfPoints(),
        "output_triangles": result.GetNumberOfPolys(), "vtp_mb": vtp_mb,
        "indirect_samples": int(field.GetArray("IndirectSamples").GetValue(0)),
        "shots": int(field.GetArray("Shots").GetValue(0)),
        "unshot": field.GetArray("UnshotFraction").GetValue(0),
        "escaped": power_fraction(field, "EscapedPower"),
        "residual": power_fraction(field, "ResidualPower")}))


def power_fraction(field, name):
    """A power field as a fraction of the emitted power (channel means)."""
    emitted = field.GetArray("EmittedPower")
    value = field.GetArray(name)
    total = sum(emitted.GetComponent(0, c) for c in range(3))
    return sum(value.GetComponent(0, c) for c in range(3)) / total if total > 0 else 0.0


def fit(xs, ys):
    import numpy as np
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0]) if len(xs) > 1 else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 5000, 20000])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--runs", type=int, default=1,
                        help="solves per size; the table gives medians (default 1)")
    parser.add_argument("--timeout", type=float, default=3600.0,
                        help="seconds allowed per size before it is reported as not finished")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build", "benchmarks"))
    parser.add_argument("--indirect-samples", type=int,
                        help="MaximumIndirectSamples (default: the solver's)")
    parser.add_argument("--no-reuse", action="store_true",
                        help="ReuseTransport off (default: the solver's, on)")
    parser.add_argument("--unshot-fraction", type=float,
                        help="UnshotFraction (default: the solver's)")
    parser.add_argument("--compact-tolerance", type=float,
                        help="CompactTolerance (default: the solver's; 0: the dense display)")
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child is not None:
        settings = {}
        if args.indirect_samples is not None:
            settings["maximum_indirect_samples"] = args.indirect_samples
        if args.no_reuse:
            settings["reuse_transport"] = False
        if args.unshot_fraction is not None:
            settings["unshot_fraction"] = args.unshot_fraction
        if args.compact_tolerance is not None:
            settings["compact_tolerance"] = args.compact_tolerance
        run_child(args.child, args.threads, args.seed, settings)
        return 0

    rows = []
    print("| polygons | time (s, range) | peak memory (MB) | mesher / evaluator / shooter / "
          "reconstructor (s) | output points | output triangles | .vtp (MB) | points shot on | "
          "shots | unshot left | escaped | residual |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for size in args.sizes:
        command = [sys.executable, os.path.abspath(__file__), "--child", str(size),
                   "--threads", str(args.threads), "--seed", str(args.seed)]
        if args.indirect_samples is not None:
            command += ["--indirect-samples", str(args.indirect_samples)]
        if args.no_reuse:
            command.append("--no-reuse")
        if args.unshot_fraction is not None:
            command += ["--unshot-fraction", repr(args.unshot_fraction)]
        if args.compact_tolerance is not None:
            command += ["--compact-tolerance", repr(args.compact_tolerance)]
        runs = []
        for _ in range(max(1, args.runs)):
            try:
                done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                      universal_newlines=True, timeout=args.timeout)
            except subprocess.TimeoutExpired:
                print("| %d | > %.0f (stopped) | | | | | | | | | | |" % (size, args.timeout),
                      flush=True)
                break
            if done.returncode != 0:
                print("| %d | failed: %s | | | | | | | | | | |" % (
                    size, (done.stderr.strip().splitlines() or ["?"])[-1]), flush=True)
                break
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
        if len(runs) < max(1, args.runs):
            continue
        # Medians over the runs (the scene and the output are the same each time).
        row = dict(runs[0])
        row["seconds"] = statistics.median(r["seconds"] for r in runs)
        row["peak_mb"] = statistics.median(r["peak_mb"] for r in runs)
        row["stages"] = {name: statistics.median(r["stages"].get(name, 0.0) for r in runs)
                         for name in ("mesher", "evaluator", "shooter", "reconstructor")}
        rows.append(row)
        stage = " / ".join("%.1f" % row["stages"][name] for name in
                           ("mesher", "evaluator", "shooter", "reconstructor"))
        spread = "" if len(runs) == 1 else " (%.1f-%.1f)" % (
            min(r["seconds"] for r in runs), max(r["seconds"] for r in runs))
        print("| %d | %.1f%s | %.0f | %s | %d | %d | %.1f | %d | %d | %.4f | %.2e | %.2e |" % (
            row["polygons"], row["seconds"], spread, row["peak_mb"], stage, row["output_points"],
            row["output_triangles"], row["vtp_mb"], row["indirect_samples"], row["shots"],
            row["unshot"], row["escaped"], row["residual"]), flush=True)
    if not rows:
        return 1
    polygons = [r["polygons"] for r in rows]
    time_exponent = fit(polygons, [r["seconds"] for r in rows])
    memory_exponent = fit(polygons, [r["peak_mb"] for r in rows])
    print("growth: time ~ polygons^%.2f, peak memory ~ polygons^%.2f" % (time_exponent,
                                                                          memory_exponent))
    largest = max(rows, key=lambda r: r["polygons"])
    print("largest (%d polygons): %.0f s (target < %.0f s), %.0f MB (target < %.0f MB)"
          % (largest["polygons"], largest["seconds"], TARGET_SECONDS, largest["peak_mb"],
             TARGET_MB))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(args.out, exist_ok=True)
    figure, axis = plt.subplots(figsize=(6, 4.5))
    axis.loglog(polygons, [r["seconds"] for r in rows], "o-",
                label="time, s (slope %.2f)" % time_exponent)
    axis.loglog(polygons, [r["peak_mb"] for r in rows], "s--",
                label="peak memory, MB (slope %.2f)" % memory_exponent)
    axis.axhline(TARGET_SECONDS, color="C0", lw=0.8, ls=":")
    axis.set_xlabel("polygons (box rooms)")
    label = "default solve" if args.indirect_samples is None and not args.no_reuse else \
        "indirect samples %s%s" % (args.indirect_samples or "default",
                                   ", transport not reused" if args.no_reuse else "")
    axis.set_title("%s, %d threads%s%s" % (
        label, args.threads,
        "" if args.unshot_fraction is None else ", unshot %g" % args.unshot_fraction,
        "" if args.compact_tolerance is None else ", compact %g" % args.compact_tolerance)
        + (", median of %d" % args.runs if args.runs > 1 else ""))
    axis.legend()
    axis.grid(True, which="both", alpha=0.3)
    path = os.path.join(args.out, "scale.png")
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    print("wrote %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
