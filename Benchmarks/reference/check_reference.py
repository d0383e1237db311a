#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Sanity checks of the cached Mitsuba reference (cornell_reference.npz).

1. Metadata, mask statistics and the noise level RMS(stderr)/mean per sensor.
2. Direct lighting against a closed form: for every valid pixel that sees the
   whole light (tested by casting segments from 4 x 4 points of the pixel to
   9 x 9 points of the light against every scene triangle, in numpy), the
   direct-only radiance rho * Le * F, with F Lambert's point-to-polygon form
   factor averaged over the 4 x 4 points, is compared with a Mitsuba render at
   max_depth 2 (emitted + direct light only). Then the direct part of the
   reference itself under the light is printed beside the full value.
3. Symmetry: the 'occluder' scene (a square light, a parallel square plate and
   a floor, symmetric under x -> -x, z -> -z and x <-> z) is rendered on a 40 x
   40 floor grid; pixels that map onto each other under the 8 symmetries are
   compared in units of their standard error (a chi-square per degree of
   freedom near 1 means they differ by noise only: the pixel mapping, the
   geometry and the noise estimate are right).

Checks 2 and 3 render with Mitsuba, so run this with the venv's Python:

    build/_deps/mitsuba-venv/bin/python Benchmarks/reference/check_reference.py

``--skip-render`` runs check 1 and the closed-form part of 2 only (no Mitsuba).
"""

import argparse
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import mitsuba_cornell as mc  # noqa: E402


def form_factor(x, n, poly):
    """Lambert's point-to-polygon form factor (polygon wholly in front of x)."""
    R = poly - x
    f = 0.0
    for k in range(len(poly)):
        a, b = R[k], R[(k + 1) % len(poly)]
        c = np.cross(a, b)
        gamma = np.arctan2(np.linalg.norm(c), np.dot(a, b))
        f += gamma * np.dot(n, c) / np.linalg.norm(c)
    return abs(f) / (2 * np.pi)


def triangles_of(polygons):
    tris = []
    for c, poly in enumerate(polygons):
        for t in mc.fan_triangles(poly, c):
            tris.append((c, poly[list(t)]))
    return tris


def segments_blocked(p, q, tris, skip):
    """Whether any segment p[i] -> q[j] (all pairs) hits a triangle whose cell
    is not in skip (Moller-Trumbore, open segment)."""
    d = q[None, :, :] - p[:, None, :]            # (P, Q, 3)
    for c, t in tris:
        if c in skip:
            continue
        e1, e2 = t[1] - t[0], t[2] - t[0]
        h = np.cross(d, e2)
        a = h @ e1
        ok = np.abs(a) > 1e-15
        f = np.where(ok, 1.0 / np.where(ok, a, 1.0), 0.0)
        s = p[:, None, :] - t[0]
        u = f * np.einsum("pqk,pqk->pq", s, h)
        qv = np.cross(s, e1)
        v = f * np.einsum("pqk,pqk->pq", d, qv)
        tt = f * (qv @ e2)
        hit = ok & (u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9) \
            & (tt > 1e-9) & (tt < 1 - 1e-9)
        if hit.any():
            return True
    return False


def direct_closed_form(polygons, refl, emis, s, sub=4, light_grid=9):
    """Per valid pixel: closed-form direct radiance if the light is wholly
    visible from the pixel, else NaN."""
    lights = [c for c in range(len(polygons)) if np.any(emis[c] > 0)]
    tris = triangles_of(polygons)
    H, W = s["shape"]
    out = np.full((H, W, 3), np.nan)
    g = (np.arange(sub) + 0.5) / sub
    rho = refl[s["cell"]]
    for i, j in zip(*np.nonzero(s["mask"])):
        pts = np.array([s["origin"] + (j + a) * s["pixel"] * s["u"]
                        + (i + b) * s["pixel"] * s["v"] for b in g for a in g])
        value = np.zeros(3)
        visible = True
        for L in lights:
            poly = polygons[L]
            w = np.linspace(0, 1, light_grid)
            lp = np.array([poly[0] + a * (poly[1] - poly[0]) + b * (poly[3] - poly[0])
                           for a in w for b in w]) if len(poly) == 4 else poly
            if segments_blocked(pts + 1e-9 * s["normal"], lp, tris, {s["cell"], L}):
                visible = False
                break
            F = np.mean([form_factor(x, s["normal"], poly) for x in pts])
            value += rho * emis[L] * F
        if visible:
            out[i, j] = value
    return out


def render(args, extra, path):
    cmd = ["--threads", str(args.threads), "--output", path] + extra
    mc.main(cmd)
    return np.load(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reference", default=os.path.join(HERE, "cornell_reference.npz"))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--skip-render", action="store_true")
    ap.add_argument("--penumbra-pythonpath", default=None)
    args = ap.parse_args()

    ref = np.load(args.reference)
    print("== 1. reference: Mitsuba %s (%s), %d spp = %d batches x %d passes x %d, max_depth %d,"
          " rr_depth %d, sampler %s" % (ref["mitsuba_version"], ref["variant"], ref["spp"],
                                        ref["batches"], ref["passes"], ref["spp_per_pass"],
                                        ref["max_depth"], ref["rr_depth"], ref["sampler"]))
    names = str(ref["sensors"]).split(",")
    for n in names:
        m = ref[n + "_mask"]
        L = ref[n + "_radiance"].astype(float)
        se = ref[n + "_stderr"].astype(float)
        mu = L[m].mean(axis=0)
        print("%-5s %s px, %d valid, %d masked; mean L %s; RMS(stderr)/mean %s %%, all "
              "channels %.3f %%, max pixel stderr/mean %s %%; %.0f s wall, %.0f s CPU" % (
                  n, "x".join(map(str, m.shape)), m.sum(), m.size - m.sum(),
                  np.array2string(mu, precision=5),
                  np.array2string(100 * np.sqrt((se[m] ** 2).mean(axis=0)) / mu, precision=3),
                  100 * np.sqrt((se[m] ** 2).mean()) / mu.mean(),
                  np.array2string(100 * se[m].max(axis=0) / mu, precision=3),
                  ref[n + "_render_seconds"], ref.get(n + "_render_cpu_seconds", np.nan)))

    pp = args.penumbra_pythonpath or os.environ.get(
        "PENUMBRA_PYTHONPATH", os.path.join(mc.REPO, "build", "lib", "python3", "dist-packages"))
    try:
        polygons, refl, emis = mc.load_penumbra_polygons(str(ref["scene"]), pp)
        if mc.scene_digest(polygons, refl, emis) != str(ref["scene_sha256"]):
            print("WARNING: the Penumbra scene changed since the reference was rendered")
        else:
            print("the Penumbra scene matches the one rendered (sha256 %s...)"
                  % str(ref["scene_sha256"])[:12])
    except ImportError as e:
        print("penumbra not importable (%s): using the scene stored in the reference" % e)
        off = ref["scene_offsets"]
        polygons = [ref["scene_points"][off[c]:off[c + 1]] for c in range(len(off) - 1)]
        refl, emis = ref["scene_reflectance"], ref["scene_emission"]
    sensors = {s["name"]: s for s in mc.make_sensors(
        polygons, names, float(ref[names[0] + "_pixel_size"]),
        float(ref[names[0] + "_sensor_height"]), 1e-3)}

    print("== 2. direct light, closed form vs Mitsuba")
    closed = {}
    for n in names:
        s = sensors[n]
        if not np.array_equal(s["mask"], ref[n + "_mask"]):
            print("WARNING: %s mask differs from the reference's" % n)
        closed[n] = direct_closed_form(polygons, refl, emis, s)
        print("%-5s %d of %d valid pixels see the whole light" % (
            n, np.isfinite(closed[n][..., 0]).sum(), s["mask"].sum()))

    if not args.skip_render:
        with tempfile.TemporaryDirectory() as tmp:
            d = render(args, ["--max-depth", "2", "--spp-per-pass", "1024", "--passes", "1",
                              "--batches", "16", "--seed", "900001"],
                       os.path.join(tmp, "direct.npz"))
            for n in names:
                c = closed[n]
                ok = np.isfinite(c[..., 0])
                D = d[n + "_radiance"].astype(float)[ok]
                se = d[n + "_stderr"].astype(float)[ok]
                z = (D - c[ok]) / se
                # With 16 batches (M-C)/stderr follows Student's t with 15
                # degrees of freedom: RMS sqrt(15/13) = 1.074 if M-C is noise.
                print("%-5s direct: Mitsuba/closed-form mean ratio %s, RMS((M-C)/stderr) %s "
                      "(noise only: 1.07), max |M-C|/stderr %s, max |M-C|/C %s %%" % (
                          n, np.array2string(D.mean(axis=0) / c[ok].mean(axis=0), precision=5),
                          np.array2string(np.sqrt((z ** 2).mean(axis=0)), precision=3),
                          np.array2string(np.abs(z).max(axis=0), precision=3),
                          np.array2string(100 * np.abs(D - c[ok]).max(axis=0)
                                          / c[ok].mean(axis=0), precision=3)))
                Lf = ref[n + "_radiance"].astype(float)[ok]
                print("%-5s full/direct (pixels seeing the whole light): mean %s" % (
                    n, np.array2string(Lf.mean(axis=0) / c[ok].mean(axis=0), precision=4)))

    # The valid floor pixel nearest below the light's centre that sees the
    # whole light.
    if "floor" in names:
        s = sensors["floor"]
        L = [c for c in range(len(polygons)) if np.any(emis[c] > 0)][0]
        centre = polygons[L].mean(axis=0)
        ok = np.argwhere(np.isfinite(closed["floor"][..., 0]))
        xy = (ok[:, ::-1] + 0.5) * s["pixel"]
        c2 = np.array([(centre - s["origin"]) @ s["u"], (centre - s["origin"]) @ s["v"]])
        i, j = ok[np.argmin(np.linalg.norm(xy - c2, axis=1))]
        x = s["origin"] + (j + 0.5) * s["pixel"] * s["u"] + (i + 0.5) * s["pixel"] * s["v"]
        F = form_factor(x, s["normal"], polygons[L])
        print("floor pixel [%d, %d] (centre %s m; light centre %s m): form factor at the "
              "pixel centre %.5f, direct rho*Le*F = %s, closed form averaged over the pixel "
              "%s, reference %s +- %s, so indirect = %s %% of the total" % (
                  i, j, np.array2string(x, precision=3), np.array2string(centre, precision=4),
                  F, np.array2string(refl[s["cell"]] * emis[L] * F, precision=5),
                  np.array2string(closed["floor"][i, j], precision=5),
                  np.array2string(ref["floor_radiance"][i, j], precision=5),
                  np.array2string(ref["floor_stderr"][i, j], precision=2),
                  np.array2string(100 * (1 - closed["floor"][i, j]
                                         / ref["floor_radiance"][i, j]), precision=3)))

    if not args.skip_render:
        print("== 3. symmetry of the 'occluder' scene (floor, 40 x 40)")
        with tempfile.TemporaryDirectory() as tmp:
            o = render(args, ["--scene", "occluder", "--sensors", "floor", "--pixel", "0.1",
                              "--spp-per-pass", "4096", "--passes", "1", "--batches", "16",
                              "--seed", "800001"], os.path.join(tmp, "occ.npz"))
            L = o["floor_radiance"].astype(float)[..., 0]
            se = o["floor_stderr"].astype(float)[..., 0]
            H, W = L.shape
            # Orbits of the 8 symmetries of the square grid. Per orbit of k
            # distinct pixels: chi^2 = sum (L_p - mean)^2 / pooled stderr^2 with
            # k - 1 degrees of freedom (pooled over the orbit, so that the
            # 15-dof stderr estimates hardly inflate it).
            seen = np.zeros((H, W), dtype=bool)
            chi2, dof, dark, worst = 0.0, 0, 0.0, 0.0
            for i in range(H):
                for j in range(W):
                    if seen[i, j]:
                        continue
                    orbit = set()
                    for a, b in ((i, j), (j, i)):
                        for fa in (a, H - 1 - a):
                            for fb in (b, W - 1 - b):
                                orbit.add((fa, fb))
                    idx = tuple(np.array(sorted(orbit)).T)
                    seen[idx] = True
                    vals, errs = L[idx], se[idx]
                    worst = max(worst, np.max(np.abs(vals - vals.mean())))
                    if np.all(errs == 0):
                        dark = max(dark, np.max(np.abs(vals)))
                        continue
                    chi2 += np.sum((vals - vals.mean()) ** 2) / np.mean(errs ** 2)
                    dof += len(vals) - 1
            print("occluder floor: chi^2 per degree of freedom of the mirror-image orbits %.3f "
                  "(%d dof; noise only: 1 +- %.3f); zero-variance pixels (umbra) %d, largest "
                  "value there %.3g; largest deviation from an orbit's mean %.3g %% of the "
                  "mean radiance" % (chi2 / dof, dof, np.sqrt(2.0 / dof), (se == 0).sum(), dark,
                                     100 * worst / L.mean()))


if __name__ == "__main__":
    main()
