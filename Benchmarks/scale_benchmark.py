#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scale benchmark: the default solve of generated interiors of N polygons,
and its error against a path-traced reference.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Benchmarks/scale_benchmark.py [--scene furnished_room|box_room] \\
        [--sizes 1000 5000 20000] [--threads 2] \\
        [--runs 3] [--indirect-samples N] [--no-reuse] [--unshot-fraction F] \\
        [--compact-tolerance T] [--dense]

The scenes: `furnished_room` (default; penumbra.generators.furnished_room:
office bays with desks on legs, chairs, bookcases 1 cm from a wall full of
books, partitions, lights hung 5 mm below the ceiling) or `box_room` (a room
full of boxes). Where Benchmarks/reference holds a probe reference of the
scene (`SCENE_POLYGONS_seedSEED.npz`, made by reference/mitsuba_probes.py),
the solution is read at its probe points (the displayed, piecewise-linear
radiance) and a second table gives, per probe group (floor, table tops, walls,
ceiling), the RMS and largest error relative to the group's reference mean,
with the reference's own noise removed in quadrature, and for the leak
groups (the wall behind bookcases, the ceiling behind lights, the floor next
to legs) the mean radiance of solution and reference relative to the mean
of the surface around them.

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
CompactTolerance; --dense asks for the dense display (CompactTolerance and
CompactIndirectTolerance 0).
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


#: Leak groups of the probe references and the group of the surface around them.
LEAK_HOSTS = {"gap": "wall", "behind_light": "ceiling", "contact": "floor"}


def reference_path(scene_name, polygons, seed):
    return os.path.join(HERE, "reference", "%s_%d_seed%d.npz" % (scene_name, polygons, seed))


def probe_errors(result, scene, reference):
    """Errors of `result` at the probes of `reference` (an npz of
    reference/mitsuba_probes.py), by group (see probes.group_errors), plus
    for the leak groups the means relative to their host group's mean."""
    import numpy as np
    sys.path.insert(0, os.path.join(HERE, "reference"))
    from mitsuba_cornell import polygons_from_polydata, scene_digest
    from probes import group_errors, radiance_at

    polygons, reflectance, emission = polygons_from_polydata(scene)
    if scene_digest(polygons, reflectance, emission) != str(reference["scene_sha256"]):
        raise RuntimeError("the reference was rendered for another scene: regenerate it")
    valid = reference["valid"]
    groups = reference["groups"][valid]
    values = radiance_at(result, reference["points"][valid], reference["cells"][valid])
    truth, noise = reference["radiance"][valid], reference["stderr"][valid]
    errors = group_errors(values, truth, noise, groups)
    for leak, host in LEAK_HOSTS.items():
        if leak in errors and host in errors:
            pick = groups == leak
            errors[leak]["solution_over_host"] = float(np.nanmean(values[pick]) /
                                                       errors[host]["mean"])
            errors[leak]["reference_over_host"] = float(np.mean(truth[pick]) /
                                                        errors[host]["mean"])
    return errors


def run_child(scene_name, polygons, threads, seed, settings):
    """One solve, in this process; prints one JSON line."""
    sys.path.insert(0, HERE)
    import numpy as np
    import penumbra
    from penumbra import generators
    from speed_accuracy import peak_memory_mb

    scene = getattr(generators, scene_name)(polygons, seed=seed)
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
    errors = None
    if os.path.exists(reference_path(scene_name, polygons, seed)):
        errors = probe_errors(result, scene,
                              np.load(reference_path(scene_name, polygons, seed)))
    print(json.dumps({"errors": errors,
        "polygons": scene.GetNumberOfCells(), "seconds": seconds, "peak_mb": peak_memory_mb(),
        "stages": stages, "output_points": result.GetNumberOfPoints(),
        "output_triangles": result.GetNumberOfPolys(), "vtp_mb": vtp_mb,
        "indirect_samples": int(field.GetArray("IndirectSamples").GetValue(0)),
        "shots": int(field.GetArray("Shots").GetValue(0)),
        "unshot": field.GetArray("UnshotFraction").GetValue(0),
        "separate": int(field.GetArray("IndirectSeparatePoints").GetValue(0))
        if field.GetArray("IndirectSeparatePoints") else 0,
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


#: Probe groups whose error is compared with a target (relative RMS, after removing noise).
ERROR_TARGETS = {"floor": 0.02, "table": 0.02, "wall": 0.02, "ceiling": 0.03}


def print_errors(rows):
    """The probe-error table of the rows that have a reference."""
    rows = [r for r in rows if r.get("errors")]
    if not rows:
        return
    print()
    print("Error at the reference's probes: RMS (noise removed) / largest, relative to the "
          "group's mean (target RMS); leaks: mean of solution / reference relative to the "
          "surface around them")
    names = [g for g in ERROR_TARGETS if g in rows[0]["errors"]]
    leaks = [g for g in LEAK_HOSTS if g in rows[0]["errors"]]
    print("| polygons | " + " | ".join("%s (<= %.0f%%)" % (g, 100 * ERROR_TARGETS[g])
                                       for g in names) +
          "".join(" | %s" % g for g in leaks) + " | reference noise (RMS) |")
    print("|" + " --- |" * (2 + len(names) + len(leaks)))
    for r in rows:
        e = r["errors"]
        cells = ["%.2f%% / %.1f%%%s" % (100 * e[g]["rms_denoised"], 100 * e[g]["max"],
                                        " (%d missing)" % e[g]["missing"] if e[g]["missing"]
                                        else "") for g in names]
        cells += ["%.2f%% / %.2f%%" % (100 * e[g]["solution_over_host"],
                                       100 * e[g]["reference_over_host"]) for g in leaks]
        noise = max(e[g]["noise"] for g in names)
        print("| %d | %s | %.2f%% |" % (r["polygons"], " | ".join(cells), 100 * noise))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=("furnished_room", "box_room"),
                        default="furnished_room")
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 5000, 20000])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int,
                        help="the generator's seed (default: 0 for furnished_room, whose "
                        "references are made with it, 1 for box_room)")
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
                        help="CompactTolerance (default: the solver's)")
    parser.add_argument("--dense", action="store_true",
                        help="the dense display (CompactTolerance and CompactIndirectTolerance 0)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="any other setting of penumbra.solve by its snake_case name, "
                             "e.g. --set jump_threshold=1e-3 (repeatable)")
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.seed is None:
        args.seed = 0 if args.scene == "furnished_room" else 1
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
        if args.dense:
            settings["compact_tolerance"] = 0.0
            settings["compact_indirect_tolerance"] = 0.0
        for assignment in args.set:
            name, _, value = assignment.partition("=")
            settings[name.strip()] = float(value)
        run_child(args.scene, args.child, args.threads, args.seed, settings)
        return 0

    rows = []
    print("| polygons | time (s, range) | peak memory (MB) | mesher / evaluator / shooter / "
          "reconstructor (s) | output points | output triangles | .vtp (MB) | points shot on "
          "(of them on their own) | shots | unshot left | escaped | residual |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for size in args.sizes:
        command = [sys.executable, os.path.abspath(__file__), "--child", str(size),
                   "--scene", args.scene,
                   "--threads", str(args.threads), "--seed", str(args.seed)]
        if args.indirect_samples is not None:
            command += ["--indirect-samples", str(args.indirect_samples)]
        if args.no_reuse:
            command.append("--no-reuse")
        if args.unshot_fraction is not None:
            command += ["--unshot-fraction", repr(args.unshot_fraction)]
        if args.compact_tolerance is not None:
            command += ["--compact-tolerance", repr(args.compact_tolerance)]
        if args.dense:
            command.append("--dense")
        for assignment in args.set:
            command += ["--set", assignment]
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
        print("| %d | %.1f%s | %.0f | %s | %d | %d | %.1f | %d (%d) | %d | %.4f | %.2e | %.2e |" % (
            row["polygons"], row["seconds"], spread, row["peak_mb"], stage, row["output_points"],
            row["output_triangles"], row["vtp_mb"], row["indirect_samples"], row["separate"],
            row["shots"],
            row["unshot"], row["escaped"], row["residual"]), flush=True)
    if not rows:
        return 1
    print_errors(rows)
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
    with_errors = [r for r in rows if r.get("errors")]
    figure, axes = plt.subplots(1, 2 if with_errors else 1,
                                figsize=(11 if with_errors else 6, 4.5), squeeze=False)
    axis = axes[0][0]
    axis.loglog(polygons, [r["seconds"] for r in rows], "o-",
                label="time, s (slope %.2f)" % time_exponent)
    axis.loglog(polygons, [r["peak_mb"] for r in rows], "s--",
                label="peak memory, MB (slope %.2f)" % memory_exponent)
    axis.axhline(TARGET_SECONDS, color="C0", lw=0.8, ls=":")
    axis.set_xlabel("polygons (%s)" % args.scene)
    label = "default solve" if args.indirect_samples is None and not args.no_reuse else \
        "indirect samples %s%s" % (args.indirect_samples or "default",
                                   ", transport not reused" if args.no_reuse else "")
    axis.set_title("%s, %d threads%s%s%s" % (
        label, args.threads,
        "" if args.unshot_fraction is None else ", unshot %g" % args.unshot_fraction,
        "" if args.compact_tolerance is None else ", compact %g" % args.compact_tolerance,
        ", dense display" if args.dense else "")
        + "".join(", " + assignment for assignment in args.set)
        + (", median of %d" % args.runs if args.runs > 1 else ""))
    axis.legend()
    axis.grid(True, which="both", alpha=0.3)
    if with_errors:
        panel = axes[0][1]
        sizes = [r["polygons"] for r in with_errors]
        for k, group in enumerate(g for g in ERROR_TARGETS if g in with_errors[0]["errors"]):
            panel.loglog(sizes, [100 * r["errors"][group]["rms_denoised"] for r in with_errors],
                         "o-", color="C%d" % k, label=group)
            panel.axhline(100 * ERROR_TARGETS[group], color="C%d" % k, lw=0.8, ls=":")
        panel.set_xlabel("polygons (%s)" % args.scene)
        panel.set_ylabel("RMS error at the probes, % of the mean")
        panel.set_title("against the path-traced reference")
        panel.legend()
        panel.grid(True, which="both", alpha=0.3)
    path = os.path.join(args.out, "scale.png")
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    print("wrote %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
