#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Print a hash of the solved outputs of the built-in scenes.

A restructuring of the code that must not change its results is checked by
running this before and after and comparing the lines:

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
        Testing/Scripts/output_hash.py [--direct-only] [--scenes cornell blind]

Each line gives the scene, the number of output points and triangles, and a
SHA-256 of the point coordinates (rounded to 1e-9 of the largest coordinate)
and of Radiance (rounded to 1e-9 of the largest value), with the solve time.
Settings not given keep the solver's defaults.
"""
import argparse
import hashlib
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy


def rounded(values):
    """Round to 1e-9 of the largest magnitude (+0.0 for -0.0)."""
    scale = float(np.max(np.abs(values))) if values.size else 0.0
    if scale == 0.0:
        return np.zeros_like(values)
    return np.round(values / scale, 9) + 0.0


def output_hash(result):
    points = vtk_to_numpy(result.GetPoints().GetData()).astype(np.float64)
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance")).astype(np.float64)
    polys = vtk_to_numpy(result.GetPolys().GetConnectivityArray()).astype(np.int64)
    digest = hashlib.sha256()
    for part in (rounded(points), rounded(radiance), polys):
        digest.update(np.ascontiguousarray(part).tobytes())
    return points.shape[0], result.GetPolys().GetNumberOfCells(), digest.hexdigest()[:16]


def main(argv=None):
    import penumbra

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="*", default=[name for name, _ in penumbra.scenes()])
    parser.add_argument("--direct-only", action="store_true", help="no interreflections")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args(argv)
    for name in args.scenes:
        start = time.perf_counter()
        result = penumbra.solve(name, threads=args.threads, indirect=not args.direct_only)
        elapsed = time.perf_counter() - start
        points, triangles, digest = output_hash(result)
        print("%-10s %9d points %9d triangles  %s  (%.1f s)"
              % (name, points, triangles, digest, elapsed), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
