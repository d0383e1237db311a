#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""CIE 171:2006 test case 5.8: the closed cube, reflectance 0 to 0.95.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/closed_cube.py
        [--runs 3] [--reflectances 0 0.05 0.1 ...] [--out build/benchmarks]

Solves penumbra.generators.closed_cube(rho) with the defaults and prints, per
reflectance, the largest error of the six faces' mean displayed radiance
against the flux-balance value rho Phi / (pi S_T (1 - rho)), the escaped and
residual power relative to the emitted, the shots and the solve time (median
of --runs). Draws the largest error and the time against rho to
--out/closed_cube.png.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_REFLECTANCES = [0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--reflectances", type=float, nargs="+", default=DEFAULT_REFLECTANCES)
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build", "benchmarks"))
    args = parser.parse_args(argv)
    import penumbra
    from penumbra.generators import closed_cube, closed_cube_radiance

    sys.path.insert(0, os.path.join(os.path.dirname(HERE), "Testing", "Python"))
    from test_conservation import face_means, field

    rows = []
    print("| reflectance | largest face error | escaped / emitted | residual / emitted | shots "
          "| time (s) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for rho in args.reflectances:
        times = []
        for _ in range(args.runs):
            start = time.perf_counter()
            result = penumbra.solve(closed_cube(rho), threads=2)
            times.append(time.perf_counter() - start)
        means = face_means(result, range(6))
        expected = closed_cube_radiance(rho)
        error = np.abs(means / expected - 1).max() if rho > 0 else np.abs(means).max()
        emitted = field(result, "EmittedPower").mean()
        escaped = field(result, "EscapedPower").mean() / emitted
        residual = field(result, "ResidualPower").mean() / emitted
        shots = int(field(result, "Shots")[0])
        seconds = statistics.median(times)
        rows.append((rho, error, seconds))
        print("| %.2f | %s | %.1e | %.1e | %d | %.2f |"
              % (rho, "%.3f%%" % (100 * error) if rho > 0 else "0 (black)", escaped, residual,
                 shots, seconds))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    os.makedirs(args.out, exist_ok=True)
    lit = [r for r in rows if r[0] > 0]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    left.plot([r[0] for r in lit], [100 * r[1] for r in lit], "o-")
    left.axhline(0.1, color="grey", linestyle="--", label="0.1%")
    left.set_xlabel("reflectance")
    left.set_ylabel("largest face error (%)")
    left.legend()
    right.plot([r[0] for r in rows], [r[2] for r in rows], "o-")
    right.set_xlabel("reflectance")
    right.set_ylabel("solve time (s), 2 cores")
    fig.suptitle("CIE 171:2006 case 5.8, closed cube: Penumbra against flux balance")
    fig.tight_layout()
    path = os.path.join(args.out, "closed_cube.png")
    fig.savefig(path, dpi=90)
    print("wrote", path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
