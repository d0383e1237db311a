#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""CIE 171:2006 validation cases that Penumbra can build: 5.3 and 5.8.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/cie171.py
        [--runs 3] [--out build/benchmarks]

5.3: a 1 m^2 Lambertian source in the ceiling of a black 4 x 4 x 3 m room
(penumbra.generators.black_room): the illuminance (Irradiance) at every output point of
the floor and of a wall, with the defaults, with SamplingTolerance 1e-3 and 2e-4 and
with quality "high", and at sensors on a 0.25 m grid of a work plane 0.8 m above the
floor, against Lambert's exact polygon formula. Errors are the largest |computed -
exact| relative to the surface's mean exact value (its area mean, by the midpoint rule
on a 200 x 200 grid).

5.8: the closed cube (penumbra.generators.closed_cube), reflectance 0 to 0.95:
the six faces' area-mean illuminance against flux balance,
Phi / (S_T (1 - rho)).

Prints a Markdown table (median time of --runs) and writes
--out/cie171.csv and the chart --out/cie171.png.
"""
import argparse
import csv
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def timed(runs, function):
    times, result = [], None
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return result, statistics.median(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build", "benchmarks"))
    args = parser.parse_args(argv)
    import penumbra
    import penumbra.sensors
    from penumbra.generators import black_room, closed_cube

    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "Testing", "Python"))
    from test_conservation import face_means
    from test_irradiance import LUMINANCE, SOURCE, lambert_irradiance, point_array, surface_points

    rows = []
    scene = black_room(luminance=LUMINANCE)
    # The floor (y = 0) and the wall x = 0 of the 4 x 4 x 3 m room.
    surfaces = ((0, "floor", (0, 1, 0), lambda a, b: (4 * a, 0.0, 4 * b)),
                (1, "wall", (1, 0, 0), lambda a, b: (0.0, 3 * a, 4 * b)))
    midpoints = (np.arange(200) + 0.5) / 200
    area_means = {name: np.mean([lambert_irradiance(np.array(at(a, b)), np.array(normal, float),
                                                    SOURCE, LUMINANCE)
                                 for a in midpoints for b in midpoints])
                  for _, name, normal, at in surfaces}
    for label, settings in (("defaults", {}),
                            ("SamplingTolerance 1e-3", {"sampling_tolerance": 1e-3}),
                            ("SamplingTolerance 2e-4", {"sampling_tolerance": 2e-4}),
                            ("quality high", {"quality": "high"})):
        result, seconds = timed(args.runs, lambda: penumbra.solve(scene, threads=2, **settings))
        for surface, name, normal, _ in surfaces:
            points, ids = surface_points(result, surface)
            exact = np.array([lambert_irradiance(p, np.array(normal, float), SOURCE, LUMINANCE)
                              for p in points])
            error = np.abs(point_array(result, "Irradiance")[ids, 0] - exact).max() / area_means[name]
            rows.append(("5.3", "%s, %s" % (name, label), len(ids), error, seconds))
    grid = np.arange(0.125, 4.0, 0.25)
    positions = np.array([(x, 0.8, z) for x in grid for z in grid])
    normals = np.tile((0.0, 1.0, 0.0), (len(positions), 1))
    values, seconds = timed(args.runs, lambda: penumbra.sensors.evaluate(
        None, scene, positions, normals))
    exact = np.array([lambert_irradiance(p, n, SOURCE, LUMINANCE) for p, n in zip(positions, normals)])
    rows.append(("5.3", "work plane 0.8 m, sensors", len(positions),
                 np.abs(values[:, 0] - exact).max() / exact.mean(), seconds))

    side, emitter_side, emission = 4.0, 0.02, 1000.0
    flux = np.pi * emission * 6.0 * emitter_side ** 2
    total_area = 6.0 * (side ** 2 + emitter_side ** 2)
    for rho in (0.0, 0.2, 0.5, 0.8, 0.9, 0.95):
        result, seconds = timed(args.runs, lambda: penumbra.solve(closed_cube(rho), threads=2))
        means = face_means(result, range(6), "Irradiance")[:, 0]
        expected = flux / (total_area * (1.0 - rho))
        rows.append(("5.8", "reflectance %.2f, 6 faces' mean" % rho, 6,
                     np.abs(means / expected - 1.0).max(), seconds))

    print("| case | what | points | largest error | time (s) |")
    print("| --- | --- | --- | --- | --- |")
    for case, what, count, error, seconds in rows:
        print("| %s | %s | %d | %.3f%% | %.2f |" % (case, what, count, 100 * error, seconds))
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "cie171.csv")
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(("case", "what", "points", "largest_error", "seconds"))
        writer.writerows(rows)
    print("wrote", path)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    fig, axes = plt.subplots(figsize=(9, 4.2))
    labels = ["%s %s" % (r[0], r[1]) for r in rows]
    axes.barh(range(len(rows)), [max(100 * r[3], 1e-6) for r in rows], color="tab:blue")
    axes.axvline(0.1, color="grey", linestyle="--", label="0.1%")
    axes.set_xscale("log")
    axes.set_yticks(range(len(rows)))
    axes.set_yticklabels(labels, fontsize=8)
    axes.invert_yaxis()
    axes.set_xlabel("largest error relative to the surface's mean (%)")
    axes.set_title("CIE 171:2006 cases 5.3 and 5.8: Penumbra's illuminance against exact values")
    axes.legend()
    fig.tight_layout()
    chart = os.path.join(args.out, "cie171.png")
    fig.savefig(chart, dpi=90)
    print("wrote", chart)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
