# SPDX-License-Identifier: GPL-3.0-or-later
"""A solution's radiance at probe points, and its error against a reference.

Probe points lie on scene cells (e.g. penumbra.generators.furnished_room_probes);
the solution's value at a probe is its piecewise-linear radiance on the output
triangle of that cell (cell data `SurfaceId`) that contains the point, which is
what a viewer displays there.
"""
import numpy as np


def output_triangles(result):
    """(triangles (m, 3) point ids, their SurfaceId (m,)) of a solved output."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    lines = result.GetNumberOfLines() + result.GetNumberOfVerts()
    surface = vtk_to_numpy(result.GetCellData().GetArray("SurfaceId"))[lines:]
    polys = vtk_to_numpy(result.GetPolys().GetData()).reshape(-1, 4)
    if np.any(polys[:, 0] != 3):
        raise ValueError("the output has polygons that are not triangles")
    return polys[:, 1:], surface


def radiance_at(result, points, cells, array="Radiance"):
    """The output's `array` (n, 3) at `points` (n, 3), each on scene cell `cells[k]`.

    Each point takes the linear interpolant of the output triangle of its cell
    that contains it; a point outside every triangle of its cell (on no
    triangle within 1e-9 of the cell's size, e.g. under a solid standing on the
    surface, which is not output) gets NaN.
    """
    from vtkmodules.util.numpy_support import vtk_to_numpy

    triangles, surface = output_triangles(result)
    xyz = vtk_to_numpy(result.GetPoints().GetData()).astype(np.float64)
    values = vtk_to_numpy(result.GetPointData().GetArray(array)).astype(np.float64)
    points = np.asarray(points, dtype=np.float64)
    out = np.full((len(points), values.shape[1]), np.nan)
    order = np.argsort(surface, kind="stable")
    starts = np.searchsorted(surface[order], np.unique(cells), side="left")
    ends = np.searchsorted(surface[order], np.unique(cells), side="right")
    for cell, start, end in zip(np.unique(cells), starts, ends):
        tris = triangles[order[start:end]]
        if len(tris) == 0:
            continue
        a, b, c = xyz[tris[:, 0]], xyz[tris[:, 1]], xyz[tris[:, 2]]
        e1, e2 = b - a, c - a
        d11 = np.einsum("ij,ij->i", e1, e1)
        d12 = np.einsum("ij,ij->i", e1, e2)
        d22 = np.einsum("ij,ij->i", e2, e2)
        det = d11 * d22 - d12 * d12
        size = np.sqrt(max(d11.max(), d22.max()))
        for k in np.nonzero(cells == cell)[0]:
            r = points[k] - a
            r1 = np.einsum("ij,ij->i", r, e1)
            r2 = np.einsum("ij,ij->i", r, e2)
            with np.errstate(divide="ignore", invalid="ignore"):
                v = (d22 * r1 - d12 * r2) / det
                w = (d11 * r2 - d12 * r1) / det
            u = 1.0 - v - w
            inside = np.minimum(np.minimum(u, v), w)
            inside[~np.isfinite(inside)] = -np.inf
            best = int(np.argmax(inside))
            if inside[best] < -1e-9 * size:
                continue
            t = tris[best]
            out[k] = u[best] * values[t[0]] + v[best] * values[t[1]] + w[best] * values[t[2]]
    return out


def group_errors(values, reference, stderr, groups):
    """Per group: RMS and largest error relative to the group's reference mean.

    Returns {group: dict(points, mean, rms, max, noise, rms_denoised)} with
    errors as fractions of the mean over the group's points and the three
    channels; `noise` is the reference's own RMS standard error relative to
    the same mean, and `rms_denoised` = sqrt(max(rms^2 - noise^2, 0)) (the
    reference's independent noise removed in quadrature). Points with a NaN
    value count as missing and are reported, not dropped silently.
    """
    out = {}
    for name in sorted(set(groups)):
        pick = np.asarray(groups) == name
        ref, val, err = reference[pick], values[pick], stderr[pick]
        valid = np.all(np.isfinite(val), axis=1)
        mean = float(np.mean(ref[valid])) if np.any(valid) else float("nan")
        diff = (val[valid] - ref[valid]) / mean
        rms = float(np.sqrt(np.mean(diff ** 2))) if np.any(valid) else float("nan")
        noise = float(np.sqrt(np.mean(err[valid] ** 2)) / mean) if np.any(valid) else float("nan")
        out[name] = {"points": int(pick.sum()), "missing": int((~valid).sum()), "mean": mean,
                     "rms": rms, "max": float(np.max(np.abs(diff))) if np.any(valid) else
                     float("nan"), "noise": noise,
                     "rms_denoised": float(np.sqrt(max(rms ** 2 - noise ** 2, 0.0)))}
    return out
