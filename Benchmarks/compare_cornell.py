#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Penumbra's Cornell box against the Mitsuba 3 path-traced reference.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/compare_cornell.py [--runs 3]
        [--method discontinuity|standard] [--element-size S] [--quality draft|normal|high]
        [--dense] [--set NAME=VALUE ...]

Solves the built-in Cornell box with penumbra.solve() (median wall time of
--runs runs), averages the displayed radiance (linear over the output
triangles, as the data contract defines it) over each reference pixel's
1 cm footprint (k x k points per pixel), and prints, per sensor (floor, back
wall), the RMS, 99th percentile and maximum of |Penumbra - Mitsuba| relative
to the sensor's mean reference radiance, over the valid (unmasked) pixels.
Reference: Benchmarks/reference/cornell_reference.npz (see its README).
Also draws the signed relative difference per pixel of each sensor into
--out/cornell_error_map.png (default out: build/benchmarks). --set passes a
setting of vtkPenumbraSolver to penumbra.solve by its snake_case name (e.g.
--set maximum_sample_spacing=0.015625), after --quality's.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkIdList
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkGenericCell, vtkPolyData, vtkStaticCellLocator

import penumbra
from penumbra.settings import parse

HERE = os.path.dirname(os.path.abspath(__file__))


def surface_mesh(result, surface_id):
    """The output triangles of one surface, as a polydata sharing the points."""
    lines = result.GetNumberOfLines()
    ids = vtk_to_numpy(result.GetCellData().GetArray("SurfaceId"))[lines:]
    polys = vtk_to_numpy(result.GetPolys().GetData()).reshape(-1, 4)[ids == surface_id]
    cells = vtkCellArray()
    for tri in polys:
        cells.InsertNextCell(3)
        for p in tri[1:]:
            cells.InsertCellPoint(int(p))
    mesh = vtkPolyData()
    mesh.SetPoints(result.GetPoints())
    mesh.SetPolys(cells)
    return mesh


def pixel_averages(result, surface_id, reference, name, k=4):
    mesh = surface_mesh(result, surface_id)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(mesh)
    locator.BuildLocator()
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
    origin, u, v = (reference[name + "_" + key] for key in ("origin", "u", "v"))
    normal = reference[name + "_normal"]
    size = float(reference[name + "_pixel_size"])
    rows, cols = reference[name + "_shape"]
    mask = reference[name + "_mask"]
    out = np.full((rows, cols, 3), np.nan)
    cell = vtkGenericCell()
    pcoords = [0.0, 0.0, 0.0]
    weights = [0.0] * 8
    offsets = (np.arange(k) + 0.5) / k
    for i in range(rows):
        for j in range(cols):
            if not mask[i, j]:
                continue
            values = []
            for a in offsets:
                for b in offsets:
                    x = origin + (j + a) * size * u + (i + b) * size * v + 1e-9 * normal
                    cell_id = locator.FindCell(list(x), 1e-9, cell, pcoords, weights)
                    if cell_id < 0:
                        continue
                    ids = [cell.GetPointId(n) for n in range(3)]
                    values.append(sum(weights[n] * radiance[ids[n]] for n in range(3)))
            if values:
                out[i, j] = np.mean(values, axis=0)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--method", choices=("discontinuity", "standard"), default="discontinuity")
    parser.add_argument("--element-size", type=float, default=None,
                        help="--method standard: initial element size relative to the scene")
    parser.add_argument("--quality", choices=("draft", "normal", "high"), default=None,
                        help="a preset of `penumbra solve --quality` (discontinuity method)")
    parser.add_argument("--dense", action="store_true",
                        help="the dense display (CompactTolerance and CompactIndirectTolerance 0)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a setting of penumbra.solve by its snake_case name, e.g. "
                        "sampling_tolerance=0.001 (repeatable)")
    parser.add_argument("--reference", default=os.path.join(HERE, "reference", "cornell_reference.npz"))
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build", "benchmarks"))
    args = parser.parse_args()
    reference = np.load(args.reference, allow_pickle=True)
    times = []
    for _ in range(args.runs):
        start = time.perf_counter()
        settings = {} if args.element_size is None else {"element_size": args.element_size}
        if args.dense:
            settings.update(compact_tolerance=0.0, compact_indirect_tolerance=0.0)
        settings.update(parse("vtkPenumbraSolver", text) for text in args.set)
        result = penumbra.solve("cornell", threads=args.threads, method=args.method,
                                quality=args.quality, **settings)
        times.append(time.perf_counter() - start)
    print("solve time: median %.2f s over %d runs (min %.2f, max %.2f), %d threads"
          % (statistics.median(times), len(times), min(times), max(times), args.threads))
    field = result.GetFieldData()
    if field.GetArray("Shots") is not None:
        print("shots %d, unshot fraction %.2e" % (field.GetArray("Shots").GetValue(0),
                                                  field.GetArray("UnshotFraction").GetValue(0)))
    print("| sensor | pixels | RMS / mean | p99 / mean | max / mean | mean Penumbra / mean Mitsuba |")
    print("| --- | --- | --- | --- | --- | --- |")
    maps = {}
    for name in reference["sensors"].item().split(","):
        cell_id = int(reference[name + "_cell_id"])
        ours = pixel_averages(result, cell_id, reference, name)
        theirs = reference[name + "_radiance"].astype(float)
        valid = reference[name + "_mask"] & np.all(np.isfinite(ours), axis=2)
        difference = np.abs(ours[valid] - theirs[valid])
        mean = theirs[valid].mean(axis=0)
        relative = difference / mean
        maps[name] = np.where(valid, (ours[..., 0] - theirs[..., 0]) / mean[0], np.nan)
        print("| %s | %d | %s | %s | %s | %s |" % (
            name, valid.sum(),
            " ".join("%.2f%%" % (100 * np.sqrt(np.mean(relative[:, c] ** 2))) for c in range(3)),
            " ".join("%.2f%%" % (100 * np.percentile(relative[:, c], 99)) for c in range(3)),
            " ".join("%.1f%%" % (100 * relative[:, c].max()) for c in range(3)),
            " ".join("%.4f" % (ours[valid][:, c].mean() / mean[c]) for c in range(3))))
    draw_error_maps(maps, os.path.join(args.out, "cornell_error_map.png"))
    return 0


def draw_error_maps(maps, path):
    """Signed relative difference (Penumbra - Mitsuba) / mean, red channel."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(os.path.dirname(path), exist_ok=True)
    figure, axes = plt.subplots(1, len(maps), figsize=(5.5 * len(maps), 4.6))
    for axis, (name, values) in zip(np.atleast_1d(axes), maps.items()):
        image = axis.imshow(values, cmap="RdBu", vmin=-0.05, vmax=0.05, origin="lower")
        axis.set_title("%s: (Penumbra - Mitsuba) / mean" % name)
        axis.set_xlabel("pixel (1 cm)")
        figure.colorbar(image, ax=axis, fraction=0.046)
    figure.tight_layout()
    figure.savefig(path, dpi=80)
    plt.close(figure)
    print("wrote %s" % path)


if __name__ == "__main__":
    sys.exit(main())
