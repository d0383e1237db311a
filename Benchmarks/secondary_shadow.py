#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Secondary shadows: the half-lit panel scene against an independent reference.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/secondary_shadow.py
        [--runs 3] [--probes 2000] [--out build/benchmarks]

Scene: penumbra.generators.half_lit_panel(). The floor receives no direct
light: all of it comes from the panel, through the baffle's shadow.

Reference, computed here from the geometry alone (numpy, no Penumbra code):
- the panel's direct irradiance by Lambert's polygon formula (exact; the
  part of the panel below the baffle is in its full shadow, the part above
  sees the whole light);
- the floor's first bounce at each probe by Gauss-Legendre quadrature over
  the panel's visible part: for a floor point and a panel column z the rays
  blocked by the baffle form one interval of panel heights (the crossing of
  the baffle's plane moves monotonically with the height), found in closed
  form, so every quadrature rule integrates a smooth function;
- the higher bounces (floor -> panel -> floor ...) by a Nystrom iteration on
  midpoint grids with ray-tested visibility: a few percent of the floor's
  light, resolved to about 1e-2 of themselves.
Prints the floor's RMS, 99th percentile and largest error relative to its
mean reference radiance, and the solve time (median of --runs), and draws
the floor's reference, Penumbra's floor and their difference to
--out/secondary_shadow.png.
"""
import argparse
import os
import statistics
import time

import numpy as np

RHO_FLOOR, RHO_PANEL, EMISSION = 0.5, 0.9, 50.0
LIGHT = np.array([(1.0, 2.0, 1.8), (1.0, 2.0, 2.2), (1.0, 2.4, 2.2), (1.0, 2.4, 1.8)])
BAFFLE_Y, BAFFLE_X, BAFFLE_Z = 1.5, (0.0, 1.0), (0.5, 3.5)
PANEL_Y, PANEL_Z = (0.5, 2.5), (1.0, 3.0)


def lambert(points, normal, polygon):
    """Irradiance at `points` (n, 3) with unit `normal` from `polygon` (k, 3)
    of unit radiance, seen whole (Lambert's formula)."""
    total = np.zeros(len(points))
    for k in range(len(polygon)):
        r1 = polygon[k] - points
        r2 = polygon[(k + 1) % len(polygon)] - points
        cross = np.cross(r1, r2)
        norm = np.linalg.norm(cross, axis=1)
        angle = np.arctan2(norm, np.einsum("ij,ij->i", r1, r2))
        total += angle * (cross @ normal) / norm
    return 0.5 * np.abs(total)


def panel_direct(y, z):
    """The panel's direct radiance at heights y, depths z (arrays)."""
    points = np.stack([np.zeros_like(y), y, z], axis=-1).reshape(-1, 3)
    lit = points[:, 1] > BAFFLE_Y
    e = np.zeros(len(points))
    e[lit] = EMISSION * lambert(points[lit], np.array([1.0, 0.0, 0.0]), LIGHT)
    return (RHO_PANEL / np.pi * e).reshape(np.shape(y))


def kernel(floor, panel):
    """cos cos / r^2 between floor points (n, 3, normal +y) and panel points
    (m, 3, normal +x): (n, m)."""
    d = panel[None, :, :] - floor[:, None, :]
    r2 = np.einsum("ijk,ijk->ij", d, d)
    return d[:, :, 1] * (-d[:, :, 0]) / (r2 * r2)


def blocked(floor, panel):
    """Whether the segments floor (n, 3) -> panel (m, 3) cross the baffle."""
    t = (BAFFLE_Y - floor[:, None, 1]) / (panel[None, :, 1] - floor[:, None, 1])
    x = floor[:, None, 0] + t * (panel[None, :, 0] - floor[:, None, 0])
    z = floor[:, None, 2] + t * (panel[None, :, 2] - floor[:, None, 2])
    return ((t > 0) & (t < 1) & (x >= BAFFLE_X[0]) & (x <= BAFFLE_X[1]) & (z >= BAFFLE_Z[0])
            & (z <= BAFFLE_Z[1]))


def blocked_heights(xf, zf, zp):
    """For floor point (xf, 0, zf) and panel columns zp (array): the interval
    of panel heights above the baffle (y in [1.5, 2.5]) whose rays cross the
    baffle, as arrays (low, high), empty where low >= high. The crossing is
    at t = 1.5 / y: x = xf (1 - t), z = zf + t (zp - zf), both monotone in t."""
    lo = np.full(len(zp), BAFFLE_Y / PANEL_Y[1])
    hi = np.ones(len(zp))
    if xf > BAFFLE_X[1]:  # x in [0, 1] <=> t >= 1 - 1 / xf (x >= 0 for t <= 1)
        lo = np.maximum(lo, 1.0 - BAFFLE_X[1] / xf)
    slope = zp - zf
    flat = slope == 0.0
    safe = np.where(flat, 1.0, slope)
    for bound, lower in ((BAFFLE_Z[0], True), (BAFFLE_Z[1], False)):
        edge = (bound - zf) / safe
        rising = (slope > 0) == lower  # inside for t beyond the edge
        lo = np.where(~flat & rising, np.maximum(lo, edge), lo)
        hi = np.where(~flat & ~rising, np.minimum(hi, edge), hi)
    outside = (zf < BAFFLE_Z[0]) | (zf > BAFFLE_Z[1])
    hi = np.where(flat & outside, lo, hi)
    empty = lo >= hi
    return np.where(empty, 0.0, BAFFLE_Y / hi), np.where(empty, 0.0, BAFFLE_Y / np.maximum(lo, 1e-300))


def first_bounce(probes, order=16, columns=32):
    """The floor's radiance at `probes` (n, 2: x, z) from the panel's direct light."""
    g, w = np.polynomial.legendre.leggauss(order)
    dz = (PANEL_Z[1] - PANEL_Z[0]) / columns
    zs = (PANEL_Z[0] + dz * (np.arange(columns)[:, None] + 0.5 * (g[None, :] + 1))).ravel()
    wz = np.tile(w * dz / 2, columns)
    out = np.zeros(len(probes))
    for n, (xf, zf) in enumerate(probes):
        floor = np.array([[xf, 0.0, zf]])
        b0, b1 = blocked_heights(xf, zf, zs)
        empty = b0 >= b1
        pieces = [(np.full(len(zs), BAFFLE_Y), np.where(empty, PANEL_Y[1], b0)),
                  (np.where(empty, PANEL_Y[1], b1), np.full(len(zs), PANEL_Y[1]))]
        total = 0.0
        for y0, y1 in pieces:
            span = np.maximum(y1 - y0, 0.0)
            ys = y0[:, None] + span[:, None] * 0.5 * (g[None, :] + 1)  # (columns, order)
            zz = np.broadcast_to(zs[:, None], ys.shape)
            panel = np.stack([np.zeros(ys.size), ys.ravel(), zz.ravel()], axis=1)
            values = (panel_direct(ys.ravel(), zz.ravel()) * kernel(floor, panel)[0]).reshape(ys.shape)
            total += np.sum(wz * span / 2 * (values @ w))
        out[n] = RHO_FLOOR / np.pi * total
    return out


def higher_bounces(probes, cells=80, iterations=6):
    """The floor's radiance at `probes` from the panel's indirect light (the
    floor lighting the panel, and so on), by Nystrom on midpoint grids."""
    fx = (np.arange(cells) + 0.5) * 4.0 / cells
    floor = np.array([(x, 0.0, z) for x in fx for z in fx])
    floor_area = (4.0 / cells) ** 2
    py = PANEL_Y[0] + (np.arange(cells) + 0.5) * (PANEL_Y[1] - PANEL_Y[0]) / cells
    pz = PANEL_Z[0] + (np.arange(cells) + 0.5) * (PANEL_Z[1] - PANEL_Z[0]) / cells
    panel = np.array([(0.0, y, z) for y in py for z in pz])
    panel_area = (PANEL_Y[1] - PANEL_Y[0]) * (PANEL_Z[1] - PANEL_Z[0]) / cells ** 2
    transfer = np.where(blocked(floor, panel), 0.0, kernel(floor, panel))  # (floor, panel)
    direct = panel_direct(panel[:, 1], panel[:, 2])
    floor_light = RHO_FLOOR / np.pi * transfer @ direct * panel_area  # first bounce, on the grid
    panel_indirect = np.zeros(len(panel))
    for _ in range(iterations):
        panel_indirect = RHO_PANEL / np.pi * transfer.T @ floor_light * floor_area
        floor_light = RHO_FLOOR / np.pi * transfer @ (direct + panel_indirect) * panel_area
    at_probes = np.stack([probes[:, 0], np.zeros(len(probes)), probes[:, 1]], axis=1)
    probe_transfer = np.where(blocked(at_probes, panel), 0.0, kernel(at_probes, panel))
    return RHO_FLOOR / np.pi * probe_transfer @ panel_indirect * panel_area


def reference(probes):
    return first_bounce(probes) + higher_bounces(probes)


def floor_values(result, probes):
    """Penumbra's displayed floor radiance (mean of RGB) at probes (x, z)."""
    import sys

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from defaults_benchmark import displayed

    points = np.stack([probes[:, 0], np.zeros(len(probes)), probes[:, 1]], axis=1)
    return displayed(result, points, np.zeros(len(probes), dtype=int)).mean(axis=1)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--probes", type=int, default=2000)
    parser.add_argument("--out", default=os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "build", "benchmarks"))
    args = parser.parse_args(argv)
    import penumbra
    from penumbra.generators import half_lit_panel

    rng = np.random.default_rng(7)
    probes = rng.uniform(0.01, 3.99, size=(args.probes, 2))
    start = time.perf_counter()
    expected = reference(probes)
    print("reference: %d floor probes in %.1f s; mean %.6g" % (len(probes),
                                                                time.perf_counter() - start,
                                                                expected.mean()))
    times = []
    for _ in range(args.runs):
        start = time.perf_counter()
        result = penumbra.solve(half_lit_panel(), threads=2)
        times.append(time.perf_counter() - start)
    shown = floor_values(result, probes)
    relative = np.abs(shown - expected) / expected.mean()
    print("solve: median %.2f s over %d runs (min %.2f, max %.2f), 2 threads"
          % (statistics.median(times), args.runs, min(times), max(times)))
    print("| floor | probes | RMS / mean | p99 / mean | max / mean | mean Penumbra / reference |")
    print("| --- | --- | --- | --- | --- | --- |")
    print("| half-lit panel | %d | %.3f%% | %.3f%% | %.3f%% | %.5f |"
          % (len(probes), 100 * np.sqrt(np.mean(relative ** 2)),
             100 * np.percentile(relative, 99), 100 * relative.max(),
             shown.mean() / expected.mean()))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    os.makedirs(args.out, exist_ok=True)
    n = 80
    grid = (np.arange(n) + 0.5) * 4.0 / n
    gx, gz = np.meshgrid(grid, grid, indexing="ij")
    where = np.stack([gx.ravel(), gz.ravel()], axis=1)
    truth = reference(where).reshape(n, n)
    mine = floor_values(result, where).reshape(n, n)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for axis, image, title in ((axes[0], truth, "reference"), (axes[1], mine, "Penumbra"),
                               (axes[2], (mine - truth) / truth.mean() * 100,
                                "difference (% of mean)")):
        shown_image = axis.imshow(image.T, origin="lower", extent=(0, 4, 0, 4),
                                  cmap="RdBu" if "difference" in title else "inferno")
        axis.set_title(title)
        axis.set_xlabel("x (m)")
        axis.set_ylabel("z (m)")
        fig.colorbar(shown_image, ax=axis)
    fig.suptitle("Floor lit only by a half-lit panel through a baffle's shadow")
    fig.tight_layout()
    path = os.path.join(args.out, "secondary_shadow.png")
    fig.savefig(path, dpi=90)
    print("wrote", path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
