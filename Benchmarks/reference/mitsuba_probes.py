#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Path-traced reference of the outgoing radiance at probe points of a Penumbra scene.

Mitsuba 3 (installed by ``setup_mitsuba.sh`` in its own venv) estimates the
outgoing radiance (emitted + reflected, linear RGB, W sr^-1 m^-2) of the
surface at arbitrary probe points of any scene vtkPolyData that follows
Penumbra's data contract (one planar convex polygon per cell,
counter-clockwise seen from its front, cell arrays ``Reflectance`` and
``Emission``). The probe value is a point value, not an area average.

The scene as Mitsuba sees it (the same model as ``mitsuba_cornell.py``):

* cells with identical (Reflectance, Emission) form one in-memory triangle
  mesh (``mi.Mesh``; a fan of each convex polygon, winding kept, so every
  face normal is the cell's front normal; face normals). With more than
  ``--max-groups`` (64) non-emitting materials, all non-emitting cells form
  a single mesh whose diffuse reflectance is a per-face attribute instead
  (the integrator's cost per pass grows with the number of distinct BSDFs:
  3 times slower with 4,000 meshes, 30 times with 20,000); both give
  identical results.
  100,000 polygons load in about a second;
* ``Reflectance`` -> one-sided ``diffuse`` BSDF, non-zero ``Emission`` ->
  ``area`` emitter (front side only), plain RGB (``llvm_ad_rgb``);
* ``path`` integrator, ``max_depth -1`` (no limit), Russian roulette from
  depth 5 (unbiased), independent sampler;
* the scene is translated so that its bounding box is centred on the origin
  (radiance does not change; float32 coordinates and Mitsuba's ray offset
  get smaller). Mitsuba starts every secondary ray (1 + R) x 8.9e-5 m off
  its surface along the normal, R the largest |coordinate|: 0.45 mm for a
  1,000-polygon furnished room (R = 4 m), 1.3 mm at 20,000 polygons, 2.8 mm
  at 100,000. Gaps thinner than that (books 0.8-4 mm apart) are then not
  resolved: rays start inside the neighbouring box and are lost.

The estimator. For probe point p with unit front normal n, every sample is a
ray from o = p + eps n along -n: it hits the surface at p after a distance
eps, and the integrator's ``sample(scene, sampler, ray)`` returns the radiance
leaving p towards o, i.e. along n. All probes x samples of a pass form one
wavefront (one vectorised call in the ``llvm_ad_rgb`` variant). eps defaults
to max(1e-5 m, 2^-20 R), R the largest centred coordinate: at least 16
float32 units in the last place of R, so that o lies strictly in front of
the surface after rounding to float32, and far smaller than the thinnest
gaps (0.8 mm between books, 5 mm behind lights) and clearances (probes 2 mm
from a leg) of the scenes, so nothing can lie between o and p (up to R = 80 m
eps stays below 1e-4 m). Before rendering, ``scene.ray_intersect`` checks every
probe ray: the first hit must be within 1e-4 m of p, on a face whose normal
is n (and on the probe's own cell when cells are given); probes that fail
are reported and masked (radiance NaN).

Noise: ``batches`` independent batches (distinct sampler seeds);
``stderr`` = std(batch means, ddof=1) / sqrt(batches).

Python use::

    import mitsuba_probes
    res = mitsuba_probes.render_probes(scene, points, normals, spp=65536)
    res["radiance"], res["stderr"], res["valid"]

Command line (with the venv's Python, from the repository root)::

    build/_deps/mitsuba-venv/bin/python Benchmarks/reference/mitsuba_probes.py \\
        --scene furnished_room --polygons 1000 --seed 0 --out ref.npz
    build/_deps/mitsuba-venv/bin/python Benchmarks/reference/mitsuba_probes.py --self-check

``--scene furnished_room`` takes the scene and probes from
``penumbra.generators.furnished_room(polygons, seed)`` and
``furnished_room_probes(polygons, seed)``; ``--scene box_room`` from
``box_room(polygons, seed)`` and ``box_room_probes`` below (floor, ceiling,
walls and box sides). ``--self-check`` compares the estimator with closed
forms (direct light against Lambert's form factor; the closed cube's flux
balance) and prints the results.

The output ``.npz`` holds ``points``, ``normals``, ``cells``, ``groups`` (the
probes), ``valid``, ``radiance``, ``stderr`` (n, 3), ``batch_radiance``
(batches, n, 3), ``hit_distance``, the per-group noise (``group_names``,
``group_count``, ``group_mean``, ``group_noise_rel`` (G, 3) = RMS(stderr) /
mean radiance per channel, ``group_noise_rel_all``, ``group_probe_noise_rms``
= RMS over probes and channels of stderr / radiance) and the metadata
(``scene``, ``polygons``, ``seed``, ``scene_cells``, ``scene_sha256`` as
``mitsuba_cornell.py`` computes it, ``spp`` per probe, ``spp_per_pass``,
``passes``, ``batches``, ``seconds`` and ``cpu_seconds`` of the rendering,
``paths_per_second``, ``paths_per_cpu_second``, ``load_seconds``,
``variant``, ``mitsuba_version``, ``drjit_version``, ``threads``, ``eps``,
``shift``, ``max_depth``, ``rr_depth``, ``render_seed``, ``shapes``,
``merged``, ``nonfinite``; strings are 0-d unicode arrays).
"""

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from mitsuba_cornell import (REPO, choose_variant, configure_llvm,  # noqa: E402
                             import_penumbra, polygons_from_polydata, scene_digest)

DEFAULT_PYTHONPATH = os.environ.get(
    "PENUMBRA_PYTHONPATH", os.path.join(REPO, "build", "lib", "python3", "dist-packages"))

#: Default samples per probe (in total over the batches), batches and the
#: largest wavefront (probes x samples of one vectorised pass).
DEFAULT_SPP = 1 << 21
DEFAULT_BATCHES = 16
DEFAULT_WAVEFRONT = 1 << 21
#: Above this many non-emitting materials, non-emitting cells share one mesh.
DEFAULT_MAX_GROUPS = 64
#: A probe ray's first hit must lie this close to the probe point (metres).
HIT_TOLERANCE = 1e-4

_MITSUBA = {}


# --------------------------------------------------------------------------
# Mitsuba set-up
# --------------------------------------------------------------------------

def mitsuba_modules(variant="auto", threads=0):
    """(mi, dr) with the variant set: 'auto' = llvm_ad_rgb if a probe render
    works in a child process, else scalar_rgb (decided once per process)."""
    if "mi" not in _MITSUBA:
        configure_llvm()
        chosen = choose_variant(variant)
        import drjit as dr
        import mitsuba as mi
        mi.set_variant(chosen)
        _MITSUBA.update(mi=mi, dr=dr)
    mi, dr = _MITSUBA["mi"], _MITSUBA["dr"]
    if variant != "auto" and mi.variant() != variant:
        mi.set_variant(variant)
    if threads and threads > 0:
        dr.set_thread_count(int(threads))
    return mi, dr


# --------------------------------------------------------------------------
# Scene polygons -> grouped triangle meshes
# --------------------------------------------------------------------------

def fan_triangulation(polygons):
    """Fan triangles of every convex polygon, vectorised over polygons with the
    same number of vertices (the per-polygon ``mitsuba_cornell.fan_triangles``
    takes about 70 us a polygon). Same rules: the winding is kept, triangles
    of area <= 1e-14 are skipped, a triangle turning against the polygon's
    (Newell) normal means a non-convex cell (error).

    Returns (vertices (V, 3) = all polygons' vertices concatenated, cell by
    cell; triangles (T, 3) int64 indices into vertices; the cell of each
    triangle (T,))."""
    counts = np.fromiter((len(p) for p in polygons), dtype=np.int64, count=len(polygons))
    vertices = np.concatenate(polygons).astype(np.float64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    triangles, cells = [], []
    for m in np.unique(counts):
        idx = np.nonzero(counts == m)[0]
        corner = starts[idx][:, None] + np.arange(m)[None, :]
        P = vertices[corner]                                   # (k, m, 3)
        normal = np.cross(P, np.roll(P, -1, axis=1)).sum(axis=1)
        length = np.linalg.norm(normal, axis=1)
        normal /= np.where(length > 0, length, 1.0)[:, None]
        for j in range(1, m - 1):
            t = np.cross(P[:, j] - P[:, 0], P[:, j + 1] - P[:, 0])
            keep = 0.5 * np.linalg.norm(t, axis=1) > 1e-14
            bad = keep & (np.einsum("ij,ij->i", t, normal) <= 0)
            if np.any(bad):
                raise RuntimeError("cell %d is not convex: fan triangulation fails"
                                   % idx[np.argmax(bad)])
            triangles.append(corner[keep][:, [0, j, j + 1]])
            cells.append(idx[keep])
    return vertices, np.concatenate(triangles), np.concatenate(cells)


def material_groups(refl, emis):
    """(group of each cell, group materials (G, 6) = reflectance, emission):
    cells with identical (Reflectance, Emission) share a group."""
    key = np.ascontiguousarray(np.hstack([refl, emis]), dtype=np.float64)
    materials, group = np.unique(key, axis=0, return_inverse=True)
    return group.ravel(), materials


def build_mitsuba_scene(mi, polygons, refl, emis, shift, max_depth=-1, rr_depth=5,
                        max_groups=DEFAULT_MAX_GROUPS):
    """The Mitsuba scene, translated by -shift: one triangle mesh per material
    group (identical Reflectance and Emission). When there are more than
    `max_groups` groups without emission, all non-emitting cells form a single
    mesh instead, whose diffuse reflectance is the per-face attribute
    ``face_reflectance`` (a ``mesh_attribute`` texture: the cell's RGB value,
    unchanged): the integrator's cost per pass grows with the number of
    distinct BSDFs and shapes.

    Every face carries the attribute ``face_cell`` (float32, exact up to 2^24
    cells): the Penumbra cell it belongs to. Returns (scene, number of meshes,
    whether the non-emitting cells were merged)."""
    group, materials = material_groups(refl, emis)
    emitting = np.any(materials[:, 3:] > 0, axis=1)
    merge = int(np.sum(~emitting)) > max_groups
    if merge:      # one mesh key for every non-emitting cell, after the emitters'
        ids = np.cumsum(emitting) - 1
        mesh_of_cell = np.where(emitting[group], ids[group], int(emitting.sum()))
        mesh_material = [materials[g] for g in np.nonzero(emitting)[0]] + [None]
    else:
        mesh_of_cell = group
        mesh_material = list(materials)
    nmesh = len(mesh_material)
    order = np.argsort(mesh_of_cell, kind="stable")         # cells, mesh by mesh
    vertices, triangles, tri_cell = fan_triangulation([polygons[c] for c in order])
    tri_cell = order[tri_cell]                               # back to scene cell ids
    tri_mesh = mesh_of_cell[tri_cell]
    sort = np.argsort(tri_mesh, kind="stable")
    triangles, tri_cell, tri_mesh = triangles[sort], tri_cell[sort], tri_mesh[sort]
    counts = np.fromiter((len(polygons[c]) for c in order), dtype=np.int64, count=len(order))
    vertex_end = np.concatenate([[0], np.cumsum(counts)])
    cell_end = np.cumsum(np.bincount(mesh_of_cell, minlength=nmesh))
    tri_end = np.cumsum(np.bincount(tri_mesh, minlength=nmesh))
    vertices32 = (vertices - shift).astype(np.float32)

    def rgb(v):
        return {"type": "rgb", "value": [float(x) for x in v]}

    scene = {"type": "scene",
             "integrator": {"type": "path", "max_depth": int(max_depth),
                            "rr_depth": int(rr_depth), "hide_emitters": False}}
    v0 = t0 = 0
    for g, mat in enumerate(mesh_material):
        v1, t1 = int(vertex_end[cell_end[g]]), int(tri_end[g])
        if t1 > t0:
            props = mi.Properties()
            props["face_normals"] = True
            reflectance = (rgb(mat[:3]) if mat is not None else
                           {"type": "mesh_attribute", "name": "face_reflectance"})
            props["bsdf"] = mi.load_dict({"type": "diffuse", "reflectance": reflectance})
            if mat is not None and np.any(mat[3:] > 0):
                props["emitter"] = mi.load_dict({"type": "area", "radiance": rgb(mat[3:])})
            mesh = mi.Mesh("mesh%d" % g, v1 - v0, t1 - t0, props, False, False)
            params = mi.traverse(mesh)
            floats, ints = type(params["vertex_positions"]), type(params["faces"])
            params["vertex_positions"] = floats(np.ascontiguousarray(vertices32[v0:v1]).ravel())
            params["faces"] = ints((triangles[t0:t1] - v0).astype(np.uint32).ravel())
            params.update()
            mesh.add_attribute("face_cell", 1, floats(tri_cell[t0:t1].astype(np.float32)))
            if mat is None:
                mesh.add_attribute("face_reflectance", 3, floats(
                    refl[tri_cell[t0:t1]].astype(np.float32).ravel()))
            scene["mesh%d" % g] = mesh
        v0, t0 = v1, t1
    return mi.load_dict(scene), len(scene) - 2, merge


# --------------------------------------------------------------------------
# Probe rays
# --------------------------------------------------------------------------

def default_eps(polygons, shift):
    """max(1e-5 m, 2^-20 R), R = the largest |coordinate| after the shift."""
    R = max(float(np.max(np.abs(np.concatenate(polygons) - shift))), 1.0)
    return max(1e-5, R * 2.0 ** -20)


def _to_vector(mi, cls, a):
    a = np.ascontiguousarray(a, dtype=np.float32)
    return cls(mi.Float(a[:, 0]), mi.Float(a[:, 1]), mi.Float(a[:, 2]))


def check_probe_rays(mi, scene, origins, directions, eps, cells=None,
                     tolerance=HIT_TOLERANCE):
    """First hit of each probe ray: returns (valid, |hit distance - eps|, hit
    cell or -1, cos(hit normal, -direction)). Valid: the hit lies within
    `tolerance` of the probe point, on a face facing the ray's origin with
    the probe's normal (cos > 1 - 1e-6) and, if `cells` is given, on that
    cell."""
    n = len(origins)
    if mi.variant().startswith("scalar"):
        dist, cell, cos = np.full(n, np.inf), np.full(n, -1), np.zeros(n)
        for i in range(n):
            si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*origins[i]),
                                              mi.Vector3f(*directions[i])))
            if si.is_valid():
                dist[i] = si.t
                cell[i] = int(round(si.shape.eval_attribute_1("face_cell", si)))
                cos[i] = -np.dot(list(si.n), directions[i])
    else:
        ray = mi.Ray3f(_to_vector(mi, mi.Point3f, origins), _to_vector(mi, mi.Vector3f, directions))
        si = scene.ray_intersect(ray)
        active = si.is_valid()
        hit = np.array(active, dtype=bool)
        dist = np.where(hit, np.array(si.t, dtype=np.float64), np.inf)
        face_cell = np.array(si.shape.eval_attribute_1("face_cell", si, active),
                             dtype=np.float64)
        cell = np.where(hit, np.rint(face_cell).astype(np.int64), -1)
        nn = np.asarray(si.n, dtype=np.float64).reshape(3, n).T
        cos = np.where(hit, -np.einsum("ij,ij->i", nn, directions), 0.0)
    error = np.abs(dist - eps)
    valid = (error <= tolerance) & (cos > 1 - 1e-6)
    if cells is not None:
        valid &= cell == np.asarray(cells)
    return valid, error, cell, cos


def _seed(seed, *index):
    """A 32-bit sampler seed for (seed, batch, pass[, probe]): distinct streams."""
    return int(np.random.SeedSequence([int(seed)] + [int(i) for i in index])
               .generate_state(1, dtype=np.uint32)[0])


def _pass_llvm(mi, dr, scene, integrator, sampler, ray, seed, n, spp):
    """Sum over the spp samples of each of n probes (float64 (n, 3)), and the
    number of non-finite samples (counted as 0)."""
    sampler.seed(dr.opaque(mi.UInt32, seed), n * spp)
    spec, _, _ = integrator.sample(scene, sampler, ray)
    values = np.asarray(spec, dtype=np.float64).reshape(3, n, spp)
    bad = ~np.isfinite(values)
    if np.any(bad):
        values = np.where(bad, 0.0, values)
    return values.sum(axis=2).T, int(bad.any(axis=0).sum())


def _pass_scalar(mi, scene, integrator, sampler, origins, directions, seed, batch, npass, spp):
    """The same, one Python call per ray (slow; without a usable LLVM only)."""
    n = len(origins)
    out, nonfinite = np.zeros((n, 3)), 0
    for i in range(n):
        sampler.seed(_seed(seed, batch, npass, i), 1)
        ray = mi.RayDifferential3f(mi.Ray3f(mi.Point3f(*origins[i]), mi.Vector3f(*directions[i])))
        for _ in range(spp):
            spec, _, _ = integrator.sample(scene, sampler, ray)
            v = np.array([spec[0], spec[1], spec[2]], dtype=np.float64)
            if np.all(np.isfinite(v)):
                out[i] += v
            else:
                nonfinite += 1
            sampler.advance()
    return out, nonfinite


# --------------------------------------------------------------------------
# The reference
# --------------------------------------------------------------------------

def render_probes(scene, points, normals, spp=DEFAULT_SPP, batches=DEFAULT_BATCHES, seed=1,
                  threads=0, variant="auto", verbose=False, cells=None, max_depth=-1,
                  rr_depth=5, eps=None, max_wavefront=DEFAULT_WAVEFRONT,
                  max_groups=DEFAULT_MAX_GROUPS):
    """Outgoing radiance at probe points of a Penumbra scene, path-traced by Mitsuba.

    Parameters
    ----------
    scene : vtkPolyData
        Penumbra scene (planar convex polygons, counter-clockwise seen from
        the front, cell arrays Reflectance and Emission, RGB).
    points, normals : (n, 3) array_like
        Probe points on the surfaces and their unit front normals.
    spp : int
        Samples per probe in total; rounded up to batches x passes x
        samples per pass.
    batches : int
        Independent batches (distinct seeds, >= 2) for the standard error.
    seed : int
        Render seed: batch b, pass p seeds Mitsuba's sampler with a hash of
        (seed, b, p).
    threads : int
        Dr.Jit worker threads (0: all cores).
    variant : str
        'llvm_ad_rgb', 'scalar_rgb' (one Python call per ray: slow) or 'auto'.
    cells : (n,) int array_like, optional
        The cell each probe lies on; then a probe ray must hit that cell.
    max_depth, rr_depth : int
        Path integrator settings (-1: no depth limit; 2: emission + direct
        light only).
    eps : float, optional
        Ray origin distance in front of the point (default: see the module
        docstring).
    max_wavefront : int
        Largest number of rays traced in one vectorised pass.
    max_groups : int
        Above this many non-emitting materials, the non-emitting cells form
        one mesh with a per-face reflectance (see ``build_mitsuba_scene``).

    Returns
    -------
    dict
        ``radiance``, ``stderr`` (n, 3) float64 (NaN for invalid probes),
        ``batch_radiance`` (batches, n, 3), ``valid`` (n,) bool,
        ``hit_distance`` (n,) |first hit - eps| in metres, ``hit_cell`` (n,),
        and metadata: ``spp``, ``spp_per_pass``, ``passes``, ``batches``,
        ``seconds`` (rendering, wall time), ``cpu_seconds`` (all threads),
        ``load_seconds`` (scene conversion and load), ``paths_per_second``,
        ``paths_per_cpu_second``, ``variant``, ``mitsuba_version``,
        ``drjit_version``, ``threads``, ``eps``, ``shift``, ``max_depth``,
        ``rr_depth``, ``render_seed``, ``shapes`` (meshes), ``merged``
        (non-emitting cells in one mesh), ``nonfinite`` (samples
        counted as 0), ``scene_sha256``.
    """
    if batches < 2:
        raise ValueError("batches must be at least 2 (the standard error needs them)")
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    normals = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    normals = normals / np.linalg.norm(normals, axis=1)[:, None]
    n = len(points)
    mi, dr = mitsuba_modules(variant, threads)
    import mitsuba
    import drjit

    t_load = time.time()
    polygons, refl, emis = polygons_from_polydata(scene)
    digest = scene_digest(polygons, refl, emis)
    allv = np.concatenate(polygons)
    shift = 0.5 * (allv.min(axis=0) + allv.max(axis=0))
    if eps is None:
        eps = default_eps(polygons, shift)
    mscene, shapes, merged = build_mitsuba_scene(mi, polygons, refl, emis, shift, max_depth,
                                                 rr_depth, max_groups)
    load_seconds = time.time() - t_load
    if verbose:
        print("scene: %d cells in %d meshes%s, loaded in %.2f s; eps %.3g m, shift %s" % (
            len(polygons), shapes, " (non-emitting cells merged)" if merged else "",
            load_seconds, eps, np.array2string(shift, precision=4)), flush=True)

    origins = points - shift + eps * normals
    directions = -normals
    valid, hit_error, hit_cell, _ = check_probe_rays(mi, mscene, origins, directions, eps, cells)
    if verbose or not valid.all():
        print("probe rays: %d of %d hit their surface at the point%s" % (
            valid.sum(), n, "" if valid.all() else
            "; masked: %s" % np.nonzero(~valid)[0][:20].tolist()), flush=True)
    ids = np.nonzero(valid)[0]
    m = len(ids)

    per_batch = -(-int(spp) // batches)
    spp_pass = max(1, min(per_batch, max_wavefront // max(m, 1)))
    passes = -(-per_batch // spp_pass)
    spp_pass = -(-per_batch // passes)
    integrator = mscene.integrator()
    sampler = mi.load_dict({"type": "independent", "sample_count": spp_pass})
    scalar = mi.variant().startswith("scalar")
    if not scalar and m:
        o = np.repeat(origins[ids], spp_pass, axis=0)
        d = np.repeat(directions[ids], spp_pass, axis=0)
        ray = mi.RayDifferential3f(mi.Ray3f(_to_vector(mi, mi.Point3f, o),
                                            _to_vector(mi, mi.Vector3f, d)))
        del o, d
    batch_means = np.full((batches, n, 3), np.nan)
    nonfinite = 0
    t0, c0 = time.time(), time.process_time()
    for b in range(batches):
        acc = np.zeros((m, 3))
        for p in range(passes if m else 0):
            if scalar:
                s, bad = _pass_scalar(mi, mscene, integrator, sampler, origins[ids],
                                      directions[ids], seed, b, p, spp_pass)
            else:
                s, bad = _pass_llvm(mi, dr, mscene, integrator, sampler, ray,
                                    _seed(seed, b, p), m, spp_pass)
            acc += s
            nonfinite += bad
        batch_means[b, ids] = acc / (passes * spp_pass)
        if verbose:
            el = time.time() - t0
            print("  batch %d/%d: %.1f s elapsed, ~%.0f s left" % (
                b + 1, batches, el, el / (b + 1) * (batches - b - 1)), flush=True)
    seconds = time.time() - t0
    cpu_seconds = time.process_time() - c0
    if nonfinite:
        print("warning: %d non-finite samples counted as 0" % nonfinite, file=sys.stderr)
    total = batches * passes * spp_pass
    return {
        "radiance": batch_means.mean(axis=0),
        "stderr": batch_means.std(axis=0, ddof=1) / np.sqrt(batches),
        "batch_radiance": batch_means,
        "valid": valid,
        "hit_distance": hit_error,
        "hit_cell": hit_cell,
        "spp": total,
        "spp_per_pass": spp_pass,
        "passes": passes,
        "batches": batches,
        "seconds": seconds,
        "cpu_seconds": cpu_seconds,
        "load_seconds": load_seconds,
        "paths_per_second": m * total / seconds if seconds > 0 else float("nan"),
        "paths_per_cpu_second": m * total / cpu_seconds if cpu_seconds > 0 else float("nan"),
        "variant": mi.variant(),
        "mitsuba_version": mitsuba.__version__,
        "drjit_version": drjit.__version__,
        "threads": int(threads) if threads else os.cpu_count(),
        "eps": eps,
        "shift": shift,
        "max_depth": max_depth,
        "rr_depth": rr_depth,
        "render_seed": seed,
        "shapes": shapes,
        "merged": merged,
        "nonfinite": nonfinite,
        "scene_sha256": digest,
    }


def group_noise(radiance, stderr, groups, valid):
    """Per probe group: (names, count, mean (G, 3), RMS(stderr)/mean (G, 3),
    the same over all channels (G,), RMS over probes and channels of
    stderr/radiance (G,))."""
    groups = np.asarray(groups)
    names = list(dict.fromkeys(groups.tolist()))
    count, mean, rel, rel_all, probe_rms = [], [], [], [], []
    for g in names:
        k = (groups == g) & valid
        count.append(int(k.sum()))
        if not k.any():
            mean.append([np.nan] * 3)
            rel.append([np.nan] * 3)
            rel_all.append(np.nan)
            probe_rms.append(np.nan)
            continue
        mu = radiance[k].mean(axis=0)
        mean.append(mu)
        rel.append(np.sqrt((stderr[k] ** 2).mean(axis=0)) / mu)
        rel_all.append(np.sqrt((stderr[k] ** 2).mean()) / mu.mean())
        r = radiance[k]
        pos = r > 0
        probe_rms.append(np.sqrt(np.mean((stderr[k][pos] / r[pos]) ** 2)) if pos.any()
                         else np.nan)
    return (names, np.array(count), np.array(mean, dtype=np.float64),
            np.array(rel, dtype=np.float64), np.array(rel_all), np.array(probe_rms))


def print_group_noise(res, groups):
    names, count, mean, rel, rel_all, probe_rms = group_noise(
        res["radiance"], res["stderr"], groups, res["valid"])
    print("%-14s %5s  %-27s %-24s %8s %10s" % ("group", "n", "mean radiance R, G, B",
                                               "RMS(stderr)/mean R,G,B", "all", "per probe"))
    for g, c, mu, r, ra, pr in zip(names, count, mean, rel, rel_all, probe_rms):
        print("%-14s %5d  %-27s %-24s %7.3f%% %9.3f%%" % (
            g, c, "%.4g, %.4g, %.4g" % tuple(mu), "%.3f, %.3f, %.3f %%" % tuple(100 * r),
            100 * ra, 100 * pr))
    return names, count, mean, rel, rel_all, probe_rms


# --------------------------------------------------------------------------
# Probes for box_room (development and timing scenes)
# --------------------------------------------------------------------------

def box_room_probes(scene, count=400, seed=0, margin=0.02):
    """About `count` probes on a ``penumbra.generators.box_room`` scene, in four
    groups of equal size: 'floor' (not under a box), 'ceiling' (not above a
    light), 'walls' and 'box_sides', each a uniformly random point at least
    `margin` from its polygon's edges. Returns a dict like
    ``furnished_room_probes``: points, normals, cells, groups."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    polygons = polygons_from_polydata(scene)[0]
    part = vtk_to_numpy(scene.GetCellData().GetArray("PartId"))
    rng = np.random.default_rng(seed)
    per = max(1, count // 4)
    P = np.array(polygons)                                   # all quads: (cells, 4, 3)
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 3] - P[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]

    def on_quad(c, k):
        """k random points of quad c (a rectangle), `margin` from its edges."""
        a, b, d = P[c, 0], P[c, 1], P[c, 3]
        u, v = b - a, d - a
        lu, lv = np.linalg.norm(u), np.linalg.norm(v)
        s = rng.uniform(margin / lu, 1 - margin / lu, k)
        t = rng.uniform(margin / lv, 1 - margin / lv, k)
        return a + s[:, None] * u + t[:, None] * v

    def inside_xz(x, quads, pad):
        """Whether the xz projections of points x lie within `pad` of any quad."""
        hit = np.zeros(len(x), dtype=bool)
        for q in quads:
            q2 = q[:, [0, 2]]
            e = np.roll(q2, -1, axis=0) - q2
            rel = x[:, None, [0, 2]] - q2[None]
            cross = e[None, :, 0] * rel[..., 1] - e[None, :, 1] * rel[..., 0]
            cross /= np.linalg.norm(e, axis=1)[None]
            hit |= np.all(cross >= -pad, axis=1) | np.all(cross <= pad, axis=1)
        return hit

    boxes = np.nonzero(part >= 0)[0]
    tops = boxes[::5]
    ground_tops = [P[c] for c in tops if np.min(P[c + 1][:, 1]) < 1e-9]
    lights = [P[c] for c in np.nonzero(part == -2)[0]]
    out = {"points": [], "normals": [], "cells": [], "groups": []}

    def add(name, x, c):
        out["points"].append(x)
        out["normals"].append(np.repeat(normal[c][None], len(x), axis=0)
                              if np.ndim(c) == 0 else normal[c])
        out["cells"].append(np.broadcast_to(c, len(x)).astype(np.int64))
        out["groups"].append(np.full(len(x), name))

    for name, cell, blockers in (("floor", 0, ground_tops), ("ceiling", 1, lights)):
        pts = np.zeros((0, 3))
        while len(pts) < per:
            x = on_quad(cell, 4 * per)
            pts = np.vstack([pts, x[~inside_xz(x, blockers, 0.05)]])
        add(name, pts[:per], cell)
    walls = rng.choice(np.arange(2, 6), per)
    add("walls", np.array([on_quad(c, 1)[0] for c in walls]), walls)
    sides = rng.choice(boxes[np.arange(len(boxes)) % 5 != 0], per)
    add("box_sides", np.array([on_quad(c, 1)[0] for c in sides]), sides)
    return {k: np.concatenate(v) for k, v in out.items()}


# --------------------------------------------------------------------------
# Self-check against closed forms
# --------------------------------------------------------------------------

def _direct_scene(generators):
    """A square light (1 m, at y = 1, facing down) over a floor (10 m, y = 0)
    and a wall (x = 2, facing -x), coloured so that RGB mix-ups show."""
    def quad(v, r, e=(0.0, 0.0, 0.0)):
        return {"vertices": v, "reflectance": r, "emission": e}
    le = (10.0, 20.0, 5.0)
    polys = [
        quad([(-5, 0, -5), (-5, 0, 5), (5, 0, 5), (5, 0, -5)], (0.3, 0.5, 0.7)),
        quad([(2, 0, -5), (2, 3, -5), (2, 3, 5), (2, 0, 5)][::-1], (0.6, 0.4, 0.2)),
        quad([(-0.5, 1, -0.5), (0.5, 1, -0.5), (0.5, 1, 0.5), (-0.5, 1, 0.5)],
             (0.78, 0.78, 0.78), le),
    ]
    return generators.scene_from_polygons(polys), polys, np.array(le)


def _report_z(label, model, res, ids=None):
    r, s = res["radiance"], res["stderr"]
    if ids is not None:
        r, s, model = r[ids], s[ids], model[ids]
    z = (r - model) / s
    ratio = r.mean(axis=0) / model.mean(axis=0)
    print("%s: %d probes, mean Mitsuba / closed form (R, G, B) %s, RMS z %.3f, "
          "max |z| %.2f (noise alone: RMS z ~ %.2f)" % (
              label, len(r), np.array2string(ratio, precision=5), np.sqrt(np.mean(z ** 2)),
              np.max(np.abs(z)), np.sqrt((res["batches"] - 1) / (res["batches"] - 3))))
    return z


def self_check(args):
    """Closed-form checks of the estimator; prints the results, returns True if
    they pass."""
    import_penumbra(args.penumbra_pythonpath)
    from penumbra import generators
    from check_reference import form_factor
    ok = True

    # 1. Direct light (max_depth 2) against Lambert's point-to-polygon form factor.
    scene, polys, le = _direct_scene(generators)
    light = np.array(polys[2]["vertices"], dtype=float)
    xs, zs = np.meshgrid(np.linspace(-4.5, 1.9, 7), np.linspace(-4, 4, 5))
    floor = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    ys, zw = np.meshgrid(np.linspace(0.05, 0.95, 4), np.linspace(-3, 3, 5))
    wall = np.stack([np.full(ys.size, 2.0), ys.ravel(), zw.ravel()], axis=1)
    extra = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.5], [0.49, 0.0, 0.0], [0.51, 0.0, 0.0]])
    points = np.vstack([floor, extra, wall, [[0.1, 1.0, 0.2]]])
    normals = np.vstack([np.tile([0.0, 1.0, 0.0], (len(floor) + len(extra), 1)),
                         np.tile([-1.0, 0.0, 0.0], (len(wall), 1)), [[0.0, -1.0, 0.0]]])
    cells = np.r_[np.zeros(len(floor) + len(extra), int), np.ones(len(wall), int), 2]
    rho = np.vstack([np.tile(polys[0]["reflectance"], (len(floor) + len(extra), 1)),
                     np.tile(polys[1]["reflectance"], (len(wall), 1)), [[0, 0, 0]]])
    F = np.array([form_factor(x, nn, light) for x, nn in zip(points[:-1], normals[:-1])] + [0])
    model = rho * le[None] * F[:, None]
    model[-1] = le                                           # a probe on the light: Le
    t = time.time()
    res = render_probes(scene, points, normals, spp=args.check_spp, batches=args.batches,
                        seed=args.render_seed, threads=args.threads, variant=args.variant,
                        cells=cells, max_depth=2, verbose=args.verbose)
    print("[1] direct light, max_depth 2, %d spp (%.1f s): all %d probe rays valid: %s" % (
        res["spp"], time.time() - t, len(points), bool(res["valid"].all())))
    z = _report_z("    floor + wall", model, res, np.arange(len(points) - 1))
    on_light = abs(res["radiance"][-1] - le).max() / le.max()
    print("    probe on the light: %s (Le %s), relative difference %.1e" % (
        np.array2string(res["radiance"][-1], precision=6), le, on_light))
    ok &= bool(res["valid"].all()) and np.sqrt(np.mean(z ** 2)) < 1.5 and on_light < 1e-5

    # 2. The closed cube (CIE 171 test 5.8): face means against flux balance.
    rho_c, side, es, emission = args.cube_reflectance, 4.0, 0.02, 1000.0
    scene = generators.closed_cube(rho_c, side, es, emission)
    exact = generators.closed_cube_radiance(rho_c, side, es, emission)
    k = args.cube_grid
    h = side / 2
    x, w = np.polynomial.legendre.leggauss(k)                # k x k Gauss-Legendre points
    a, b = [v.ravel() for v in np.meshgrid(h * x, h * x)]
    weight = np.outer(w, w).ravel() / 4.0                     # sums to 1 on each face
    pts, nrm, face = [], [], []
    for f, (axis, sign) in enumerate([(1, -1), (1, 1), (2, -1), (0, 1), (2, 1), (0, -1)]):
        p = np.zeros((k * k, 3))
        others = [i for i in range(3) if i != axis]
        p[:, others[0]], p[:, others[1]] = a, b
        p[:, axis] = sign * h
        p[:, 1] += h                                          # the floor at y = 0
        nn = np.zeros(3)
        nn[axis] = -sign
        pts.append(p)
        nrm.append(np.tile(nn, (k * k, 1)))
        face.append(np.full(k * k, f))
    points, normals, face = np.vstack(pts), np.vstack(nrm), np.concatenate(face)
    # Direct irradiance from the emitter's six faces (convex: each face seen
    # from p is wholly visible when p is in front of it).
    emitter_polys = polygons_from_polydata(scene)[0][6:]
    direct = np.zeros(len(points))
    for poly in emitter_polys:
        en = np.cross(poly[1] - poly[0], poly[2] - poly[0])
        front = (points - poly[0]) @ en > 0
        direct[front] += [np.pi * emission * form_factor(x, nn, poly)
                          for x, nn in zip(points[front], normals[front])]
    direct_mean = np.pi * emission * es ** 2 / side ** 2     # = Phi / 6 / side^2, exactly
    t = time.time()
    res = render_probes(scene, points, normals, spp=args.cube_spp, batches=args.batches,
                        seed=args.render_seed + 1, threads=args.threads, variant=args.variant,
                        cells=face, verbose=args.verbose)
    print("[2] closed cube, rho %.2g, %d x %d Gauss-Legendre probes on each face, %d spp "
          "(%.1f s): "
          "all probe rays valid: %s" % (rho_c, k, k, res["spp"], time.time() - t,
                                        bool(res["valid"].all())))
    # Face means: Gauss-Legendre quadrature, with the (small) quadrature error
    # of its direct part removed (the exact face mean of that part is known).
    corr = rho_c / np.pi * (direct_mean - (direct * np.tile(weight, 6)).sum() / 6)
    bm = res["batch_radiance"].mean(axis=2)                  # grey: mean of R, G, B
    per_face = np.array([bm[:, face == f] @ weight for f in range(6)]).T + corr
    est, err = per_face.mean(axis=0), per_face.std(axis=0, ddof=1) / np.sqrt(res["batches"])
    allf = per_face.mean(axis=1)
    est_all, err_all = allf.mean(), allf.std(ddof=1) / np.sqrt(res["batches"])
    print("    flux balance: L = %.6f; face means (quadrature-corrected by %.2e) %s" % (
        exact, corr, np.array2string(est, precision=6)))
    print("    face means / L - 1 (1e-4): %s, stderr %s" % (
        ", ".join("%+.1f" % x for x in 1e4 * (est / exact - 1)),
        ", ".join("%.1f" % x for x in 1e4 * err / exact)))
    zc = (est_all - exact) / err_all
    print("    all six faces: %.6f, / L - 1 = %+.2e +- %.2e (z = %+.2f)" % (
        est_all, est_all / exact - 1, err_all / exact, zc))
    # Point values, by symmetry: node j of every face has the same radiance.
    v = res["radiance"][:, 0].reshape(6, k * k)
    var = (res["stderr"][:, 0] ** 2).reshape(6, k * k).mean(axis=0)   # pooled over faces
    chi2 = ((v - v.mean(axis=0)) ** 2).sum(axis=0) / var
    dof = 5 * k * k
    expect = (6 * (res["batches"] - 1)) / (6 * (res["batches"] - 1) - 2)
    print("    symmetry (the same node on the six faces): chi^2/dof %.3f over %d dof "
          "(noise alone: %.3f +- %.3f)" % (chi2.sum() / dof, dof, expect, np.sqrt(2.0 / dof)))
    # Point values against 'direct + uniform indirect' (a loose model only).
    uniform = rho_c / np.pi * (direct + np.pi * exact / rho_c - direct_mean)
    dev = res["radiance"].mean(axis=1) / uniform - 1
    centre = np.argmin(np.linalg.norm(points - [0, 0, 0], axis=1) + 10 * (face != 0))
    print("    point values / (direct + uniform indirect) - 1: from %+.2f%% to %+.2f%% "
          "(RMS %.2f%%); floor centre: %.6f vs %.6f" % (
              100 * dev.min(), 100 * dev.max(), 100 * np.sqrt(np.mean(dev ** 2)),
              res["radiance"][centre].mean(), uniform[centre]))
    ok &= bool(res["valid"].all()) and abs(zc) < 4 and abs(est_all / exact - 1) < 1e-3
    ok &= abs(chi2.sum() / dof - expect) < 5 * np.sqrt(2.0 / dof) + 0.05

    # 3. The furnace: the closed cube's six faces all emitting Le and
    # reflecting rho give L = Le / (1 - rho) at every point, exactly.
    rho_f, le_f = 0.8, np.array([1.0, 2.0, 0.5])
    walls = polygons_from_polydata(generators.closed_cube(rho_f))[0][:6]
    scene = generators.scene_from_polygons([
        {"vertices": [tuple(v) for v in w], "reflectance": (rho_f,) * 3,
         "emission": tuple(le_f)} for w in walls])
    rng = np.random.default_rng(5)
    per = 24
    pts, nrm, face = [], [], []
    for f, w in enumerate(walls):
        u, v = w[1] - w[0], w[3] - w[0]
        # Anywhere on the face, half of them within 1 cm of an edge or corner.
        st = rng.uniform(0, 1, (per, 2))
        st[: per // 2] = np.where(rng.uniform(size=(per // 2, 2)) < 0.5, 0.0025, 0.9975)
        st[: per // 4, 0] = rng.uniform(0, 1, per // 4)
        pts.append(w[0] + st[:, :1] * u + st[:, 1:] * v)
        n = np.cross(u, v)
        nrm.append(np.tile(n / np.linalg.norm(n), (per, 1)))
        face.append(np.full(per, f))
    points, normals, face = np.vstack(pts), np.vstack(nrm), np.concatenate(face)
    t = time.time()
    res = render_probes(scene, points, normals, spp=args.furnace_spp, batches=args.batches,
                        seed=args.render_seed + 2, threads=args.threads, variant=args.variant,
                        cells=face, verbose=args.verbose)
    print("[3] furnace: closed cube, every face emitting Le = %s with rho %.2g, %d probes "
          "(half within 1 cm of an edge), %d spp (%.1f s): all probe rays valid: %s" % (
              le_f, rho_f, len(points), res["spp"], time.time() - t, bool(res["valid"].all())))
    exact_f = le_f / (1 - rho_f)
    z = _report_z("    L = Le / (1 - rho) = %s" % exact_f, np.tile(exact_f, (len(points), 1)), res)
    dev = (res["batch_radiance"] / exact_f).mean(axis=(1, 2)) - 1   # per batch, all probes
    near = np.tile(np.arange(per) < per // 2, 6)
    dev_near = (res["batch_radiance"][:, near] / exact_f).mean(axis=(1, 2)) - 1
    sq = np.sqrt(res["batches"])
    print("    mean over all probes / L - 1 = %+.1e +- %.1e; within 1 cm of an edge: "
          "%+.1e +- %.1e" % (dev.mean(), dev.std(ddof=1) / sq, dev_near.mean(),
                             dev_near.std(ddof=1) / sq))
    ok &= bool(res["valid"].all()) and np.sqrt(np.mean(z ** 2)) < 1.5 and np.abs(z).max() < 5
    ok &= abs(dev.mean()) < 4 * dev.std(ddof=1) / sq + 1e-5
    print("self-check %s" % ("passed" if ok else "FAILED"))
    return ok


# --------------------------------------------------------------------------
# Command line
# --------------------------------------------------------------------------

def make_scene_and_probes(name, polygons, seed, probes, pythonpath):
    import_penumbra(pythonpath)
    from penumbra import generators
    if name == "furnished_room":
        scene = generators.furnished_room(polygons, seed)
        pr = generators.furnished_room_probes(polygons, seed)
    elif name == "box_room":
        scene = generators.box_room(polygons, seed)
        pr = box_room_probes(scene, probes, seed)
    else:
        raise SystemExit("--scene %s: probes are known for furnished_room and box_room only"
                         % name)
    return scene, pr


def argument_parser():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="furnished_room",
                    help="furnished_room (default) or box_room (penumbra.generators)")
    ap.add_argument("--polygons", type=int, default=1000, help="scene size (1000)")
    ap.add_argument("--seed", type=int, default=0, help="scene and probe seed (0)")
    ap.add_argument("--probes", type=int, default=400,
                    help="number of probes for box_room (400)")
    ap.add_argument("--out", help="output .npz")
    ap.add_argument("--spp", type=int, default=DEFAULT_SPP,
                    help="samples per probe in total (%d)" % DEFAULT_SPP)
    ap.add_argument("--batches", type=int, default=DEFAULT_BATCHES,
                    help="independent batches for the standard error (%d)" % DEFAULT_BATCHES)
    ap.add_argument("--threads", type=int, default=0, help="worker threads (0 = all cores)")
    ap.add_argument("--variant", default="auto", help="llvm_ad_rgb, scalar_rgb or auto")
    ap.add_argument("--render-seed", type=int, default=1, help="sampler seed (1)")
    ap.add_argument("--max-depth", type=int, default=-1, help="path max_depth (-1: unlimited)")
    ap.add_argument("--rr-depth", type=int, default=5, help="Russian roulette start (5)")
    ap.add_argument("--eps", type=float, help="ray origin distance in front of the probe "
                    "(default max(1e-5, 2^-20 R) m)")
    ap.add_argument("--max-wavefront", type=int, default=DEFAULT_WAVEFRONT,
                    help="rays per vectorised pass (%d)" % DEFAULT_WAVEFRONT)
    ap.add_argument("--max-groups", type=int, default=DEFAULT_MAX_GROUPS,
                    help="above this many non-emitting materials, one mesh with per-face "
                         "reflectance for them (%d)" % DEFAULT_MAX_GROUPS)
    ap.add_argument("--penumbra-pythonpath", default=DEFAULT_PYTHONPATH,
                    help="where `import penumbra` is found (default: the build tree; "
                         "env PENUMBRA_PYTHONPATH)")
    ap.add_argument("--self-check", action="store_true",
                    help="check the estimator against closed forms and exit")
    ap.add_argument("--check-spp", type=int, default=1 << 20,
                    help="samples per probe of the direct-light check (1048576)")
    ap.add_argument("--cube-spp", type=int, default=1 << 13,
                    help="samples per probe of the closed-cube check (8192)")
    ap.add_argument("--cube-grid", type=int, default=32,
                    help="closed-cube probes: k x k Gauss-Legendre points on each face (32)")
    ap.add_argument("--cube-reflectance", type=float, default=0.5,
                    help="closed-cube reflectance (0.5)")
    ap.add_argument("--furnace-spp", type=int, default=1 << 18,
                    help="samples per probe of the furnace check (262144)")
    ap.add_argument("--verbose", action="store_true", help="progress per batch")
    return ap


def main(argv=None):
    ap = argument_parser()
    args = ap.parse_args(argv)
    if args.batches < 2:
        ap.error("--batches must be at least 2")
    if args.self_check:
        sys.exit(0 if self_check(args) else 1)
    if not args.out:
        ap.error("--out is required (or --self-check)")

    t = time.time()
    scene, pr = make_scene_and_probes(args.scene, args.polygons, args.seed, args.probes,
                                      args.penumbra_pythonpath)
    points = np.asarray(pr["points"], dtype=np.float64)
    normals = np.asarray(pr["normals"], dtype=np.float64)
    cells = np.asarray(pr["cells"]) if pr.get("cells") is not None else None
    groups = np.asarray(pr["groups"]) if pr.get("groups") is not None \
        else np.full(len(points), "all")
    print("%s(%d, seed %d): %d cells, %d probes in groups %s (built in %.1f s)" % (
        args.scene, args.polygons, args.seed, scene.GetNumberOfCells(), len(points),
        list(dict.fromkeys(groups.tolist())), time.time() - t), flush=True)

    res = render_probes(scene, points, normals, spp=args.spp, batches=args.batches,
                        seed=args.render_seed, threads=args.threads, variant=args.variant,
                        verbose=args.verbose, cells=cells, max_depth=args.max_depth,
                        rr_depth=args.rr_depth, eps=args.eps, max_wavefront=args.max_wavefront,
                        max_groups=args.max_groups)
    print("%s, Mitsuba %s, Dr.Jit %s, %d threads: %d spp x %d probes in %.1f s, %.1f s CPU "
          "(%.3g paths/s, %.3g per CPU second; scene load %.2f s, %d meshes)" % (
              res["variant"], res["mitsuba_version"], res["drjit_version"], res["threads"],
              res["spp"], res["valid"].sum(), res["seconds"], res["cpu_seconds"],
              res["paths_per_second"], res["paths_per_cpu_second"], res["load_seconds"],
              res["shapes"]))
    names, count, mean, rel, rel_all, probe_rms = print_group_noise(res, groups)

    out = {
        "points": points, "normals": normals, "groups": groups.astype(str),
        "cells": cells if cells is not None else np.full(len(points), -1),
        "valid": res["valid"],
        "radiance": res["radiance"], "stderr": res["stderr"],
        "batch_radiance": res["batch_radiance"].astype(np.float32),
        "hit_distance": res["hit_distance"], "hit_cell": res["hit_cell"],
        "group_names": np.array(names, dtype=str), "group_count": count, "group_mean": mean,
        "group_noise_rel": rel, "group_noise_rel_all": rel_all,
        "group_probe_noise_rms": probe_rms,
        "scene": np.array(args.scene), "polygons": np.int64(args.polygons),
        "seed": np.int64(args.seed), "scene_cells": np.int64(scene.GetNumberOfCells()),
        "integrator": np.array("path"), "sampler": np.array("independent"),
    }
    for key in ("spp", "spp_per_pass", "passes", "batches", "seconds", "cpu_seconds",
                "load_seconds", "paths_per_second", "paths_per_cpu_second", "variant",
                "mitsuba_version", "drjit_version", "threads", "eps", "shift", "max_depth",
                "rr_depth", "render_seed", "shapes", "merged", "nonfinite", "scene_sha256"):
        out[key] = np.asarray(res[key])
    np.savez_compressed(args.out, **out)
    print("wrote %s (%d bytes)" % (args.out, os.path.getsize(args.out)))


if __name__ == "__main__":
    main()
