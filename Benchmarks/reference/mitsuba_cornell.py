#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Independent path-traced reference for Penumbra's built-in Cornell box.

Mitsuba 3 (installed by ``setup_mitsuba.sh`` in its own venv) renders the
outgoing radiance of the floor and of the back wall with orthographic sensors
placed just in front of them. The scene is built from Penumbra's own scene
polydata (``penumbra.load_scene('cornell')``), so geometry and materials always
match what Penumbra solves:

* every polygon cell becomes one Mitsuba triangle mesh (a fan of its convex
  polygon; the winding, hence the front normal, is kept),
* ``Reflectance`` becomes a one-sided ``diffuse`` BSDF (black from the back:
  surfaces reflect on their front only, as in Penumbra's data contract),
* a non-zero ``Emission`` becomes an ``area`` emitter (front side only),
* both are plain linear RGB: the variant is an RGB one (``llvm_ad_rgb`` or
  ``scalar_rgb``), so there is no spectral upsampling.

The integrator is ``path`` (unidirectional path tracing with next-event
estimation and MIS), unbiased Russian roulette after ``--rr-depth`` bounces and
no depth limit by default (``--max-depth -1``).

Output: ``cornell_reference.npz`` (float32 unless stated), for each sensor
``S`` in (``floor``, ``back``):

``S_radiance``   (H, W, 3) mean outgoing radiance, linear RGB, W sr^-1 m^-2
``S_stderr``     (H, W, 3) standard error of that mean, from the spread of
                 ``batches`` independent renders (different seeds)
``S_mask``       (H, W) bool: True = valid pixel. False where the pixel's
                 footprint is not entirely on the surface polygon, or overlaps
                 the base of an object standing on it (the blocks on the floor:
                 the floor under them is unlit; a pixel touching that region
                 mixes lit and unlit floor and is left out too)
``S_origin``     (3,) float64 world point, metres
``S_u``, ``S_v`` (3,) float64 unit vectors in the surface plane
``S_pixel_size`` float64, metres (pixels are squares)
``S_shape``      (2,) int: (H, W) = (rows, columns)
``S_cell_id``    int: the cell of the Penumbra scene the sensor looks at
``S_normal``     (3,) float64: that cell's front normal (sensor looks along -normal)

Pixel footprints (row order!): pixel ``[i, j]`` -- row ``i``, column ``j`` of
the arrays -- is the average radiance over the square

    { origin + a * u + b * v :  j*p <= a <= (j+1)*p,  i*p <= b <= (i+1)*p }

with ``p = pixel_size``. Row ``i`` grows along ``v``, column ``j`` along ``u``;
row 0 is the one through ``origin`` (it is NOT necessarily the top of a
picture). For the Cornell box the defaults give

    floor: origin (0, 0, 0),      u = +x, v = +z,  p = 0.01 m, 56 x 56
    back:  origin (0, 0, 0.5592), u = +x, v = +y,  p = 0.01 m, 55 x 56

so the floor's pixel [i, j] covers x in [j, j+1] cm, z in [i, i+1] cm, and
the back wall's pixel [i, j] covers x in [j, j+1] cm, y in [i, i+1] cm.
Radiance is averaged over the square with a box reconstruction filter
(uniform samples over the pixel), i.e. an area average, not a point value.

Per sensor also: ``S_noise_rel`` (3,) = RMS(stderr) / mean(radiance) over the
valid pixels per channel, ``S_noise_rel_all`` the same over all channels,
``S_render_seconds`` and ``S_render_cpu_seconds``, ``S_seeds`` (first and
last seed), ``S_sensor_height``. Run metadata: ``mitsuba_version``,
``drjit_version``, ``variant``, ``integrator``, ``max_depth``, ``rr_depth``,
``sampler``, ``spp`` (per pixel in total = ``spp_per_pass`` x ``passes`` x
``batches``), ``threads``, ``scene``, ``scene_sha256`` (of the geometry and
materials); strings are 0-d unicode arrays. The scene itself is
stored too: ``scene_points`` (float64), ``scene_offsets`` (cell c's vertices
are ``scene_points[scene_offsets[c]:scene_offsets[c+1]]``),
``scene_reflectance`` and ``scene_emission`` (float64, per cell).

Run with the venv made by setup_mitsuba.sh, e.g. from the repository root:

    Benchmarks/reference/setup_mitsuba.sh
    build/_deps/mitsuba-venv/bin/python Benchmarks/reference/mitsuba_cornell.py

``--help`` lists the settings (samples, batches, threads, variant, ...).
"""

import argparse
import hashlib
import os
import struct
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


# --------------------------------------------------------------------------
# Penumbra scene -> plain numpy polygons
# --------------------------------------------------------------------------

def import_penumbra(pythonpath):
    """`import penumbra` with the directories of `pythonpath` (os.pathsep
    separated) first on sys.path; returns the module."""
    if pythonpath:
        for p in reversed(pythonpath.split(os.pathsep)):
            if p and p not in sys.path:
                sys.path.insert(0, p)
    import penumbra  # noqa: E402 (needs the path above)
    return penumbra


def polygons_from_polydata(pd):
    """A scene vtkPolyData's polygons as (list of (m,3) float64 arrays, refl,
    emission), cell by cell (vectorised: 100,000 cells take a fraction of a
    second)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    if pd.GetNumberOfCells() != pd.GetNumberOfPolys():
        raise RuntimeError("the scene has non-polygon cells")
    points = vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64)
    refl = vtk_to_numpy(pd.GetCellData().GetArray("Reflectance")).astype(np.float64)
    emis = vtk_to_numpy(pd.GetCellData().GetArray("Emission")).astype(np.float64)
    polys = pd.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64)
    connectivity = vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64)
    polygons = np.split(points[connectivity], offsets[1:-1]) if len(offsets) > 1 else []
    return polygons, refl.reshape(-1, 3), emis.reshape(-1, 3)


def load_penumbra_polygons(scene_name, pythonpath):
    """The built-in scene's polygons as (list of (m,3) float64 arrays, refl,
    emission)."""
    penumbra = import_penumbra(pythonpath)
    return polygons_from_polydata(penumbra.load_scene(scene_name))


def polygon_normal(poly):
    """Unit right-hand-rule normal (Newell's method)."""
    n = np.zeros(3)
    for k in range(len(poly)):
        a, b = poly[k], poly[(k + 1) % len(poly)]
        n += np.cross(a, b)
    return n / np.linalg.norm(n)


def fan_triangles(poly, cell):
    """Fan triangulation of a convex polygon, checking convexity and winding."""
    n = polygon_normal(poly)
    tris = []
    for k in range(1, len(poly) - 1):
        t = np.cross(poly[k] - poly[0], poly[k + 1] - poly[0])
        area = 0.5 * np.linalg.norm(t)
        if area <= 1e-14:
            continue
        if np.dot(t, n) <= 0:
            raise RuntimeError("cell %d is not convex: fan triangulation fails" % cell)
        tris.append((0, k, k + 1))
    return tris


def scene_digest(polygons, refl, emis):
    h = hashlib.sha256()
    for poly, r, e in zip(polygons, refl, emis):
        h.update(np.ascontiguousarray(poly, dtype="<f8").tobytes())
        h.update(np.ascontiguousarray(r, dtype="<f8").tobytes())
        h.update(np.ascontiguousarray(e, dtype="<f8").tobytes())
    return h.hexdigest()


def write_ply(path, vertices, triangles):
    """Binary little-endian PLY with float32 vertices and triangle faces."""
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\n"
                 "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(vertices), len(triangles))).encode("ascii"))
        for v in vertices:
            f.write(struct.pack("<3f", *v))
        for t in triangles:
            f.write(struct.pack("<B3i", 3, *t))


# --------------------------------------------------------------------------
# Sensor grids and masks (pure geometry, no Mitsuba)
# --------------------------------------------------------------------------

def plane_coords(points, origin, u, v):
    d = np.asarray(points) - origin
    return np.stack([d @ u, d @ v], axis=-1)


def convex_hull_2d(pts):
    pts = sorted(set(map(tuple, np.round(pts, 12))))
    if len(pts) <= 2:
        return np.array(pts)

    def half(points):
        out = []
        for p in points:
            while len(out) >= 2 and np.cross(np.subtract(out[-1], out[-2]),
                                             np.subtract(p, out[-2])) <= 0:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def ccw(poly2):
    a = 0.5 * sum(poly2[k][0] * poly2[(k + 1) % len(poly2)][1]
                  - poly2[(k + 1) % len(poly2)][0] * poly2[k][1] for k in range(len(poly2)))
    return poly2 if a > 0 else poly2[::-1]


def inside_convex(poly2, p, tol):
    """p inside (or on, within tol) the counter-clockwise convex polygon."""
    for k in range(len(poly2)):
        a, b = poly2[k], poly2[(k + 1) % len(poly2)]
        e = b - a
        if (e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0])) / np.linalg.norm(e) < -tol:
            return False
    return True


def convex_overlap(p, q, tol):
    """Whether two convex 2D polygons overlap with positive area (SAT)."""
    for poly in (p, q):
        for k in range(len(poly)):
            e = poly[(k + 1) % len(poly)] - poly[k]
            axis = np.array([-e[1], e[0]]) / np.linalg.norm(e)
            a, b = p @ axis, q @ axis
            if a.max() <= b.min() + tol or b.max() <= a.min() + tol:
                return False
    return True


def sensor_grid(polygons, cell, pixel):
    """Origin, u, v, (H, W) for a sensor covering cell's bounding rectangle.

    u and v are the two world axes spanned by the (axis-aligned) cell, in
    x, y, z order, oriented so that u x v = -normal (the viewing direction);
    the origin is the corner of the cell's bounding rectangle with the
    smallest coordinates along u and v."""
    poly = polygons[cell]
    n = polygon_normal(poly)
    axis = int(np.argmax(np.abs(n)))
    if abs(n[axis]) < 1 - 1e-9:
        raise RuntimeError("cell %d is not axis-aligned" % cell)
    a, b = [k for k in range(3) if k != axis]
    u, v = np.eye(3)[a], np.eye(3)[b]
    if np.dot(np.cross(u, v), n) > 0:  # make u x v = -n
        u, v = v, u
    lo = poly.min(axis=0)
    hi = poly.max(axis=0)
    origin = np.zeros(3)
    origin[axis] = poly[0][axis]
    for e in (u, v):
        k = int(np.argmax(np.abs(e)))
        origin[k] = lo[k]
    W = int(np.ceil((hi - lo) @ np.abs(u) / pixel - 1e-9))
    H = int(np.ceil((hi - lo) @ np.abs(v) / pixel - 1e-9))
    return origin, u, v, n, (H, W)


def sensor_mask(polygons, cell, origin, u, v, n, shape, pixel, tol=1e-9):
    """True where a pixel's footprint lies entirely on the cell and touches no
    base of an object standing on it (see the module docstring)."""
    H, W = shape
    target = ccw(plane_coords(polygons[cell], origin, u, v))
    plane_d = np.dot(n, polygons[cell][0])
    # Objects standing on the receiver: polygons with an edge lying in the
    # receiver plane strictly inside the receiver (not along its boundary).
    standing = []
    for c, poly in enumerate(polygons):
        if c == cell:
            continue
        on = [p for p in poly if abs(np.dot(n, p) - plane_d) < 1e-7]
        if len(on) < 2:
            continue
        on2 = plane_coords(on, origin, u, v)
        mid = on2.mean(axis=0)
        if inside_convex(target, mid, -1e-6):  # strictly inside
            standing.append((c, on2))
    # Group them into objects by shared vertices; each object's base is the
    # convex hull of its vertices in the plane (conservative).
    groups = []
    for c, on2 in standing:
        merged = [g for g in groups
                  if np.min(np.linalg.norm(g[1][:, None] - on2[None], axis=2)) < 1e-7]
        new = (set([c]), on2)
        for g in merged:
            groups.remove(g)
            new = (new[0] | g[0], np.vstack([new[1], g[1]]))
        groups.append(new)
    bases = [(sorted(g[0]), ccw(convex_hull_2d(g[1]))) for g in groups]
    mask = np.zeros((H, W), dtype=bool)
    for i in range(H):
        for j in range(W):
            sq = pixel * np.array([[j, i], [j + 1, i], [j + 1, i + 1], [j, i + 1]], float)
            ok = all(inside_convex(target, p, tol) for p in sq)
            if ok:
                ok = not any(convex_overlap(sq, base, tol) for _, base in bases)
            mask[i, j] = ok
    return mask, bases


def find_receiver(polygons, name):
    """The floor (lowest polygon facing +y) or back wall (farthest facing -z)."""
    normals = [polygon_normal(p) for p in polygons]
    if name == "floor":
        cells = [c for c in range(len(polygons)) if normals[c][1] > 1 - 1e-9]
        key, pick = (lambda c: polygons[c][:, 1].mean()), min
    elif name == "back":
        cells = [c for c in range(len(polygons)) if normals[c][2] < -1 + 1e-9]
        key, pick = (lambda c: polygons[c][:, 2].mean()), max
    else:
        raise ValueError("unknown sensor %r (valid: floor, back)" % name)
    if not cells:
        raise ValueError("the scene has no %s polygon" % name)
    return pick(cells, key=key)


def make_sensors(polygons, names, pixel, height, near_clip):
    """Geometry, mask and camera transform of each named sensor."""
    sensors = []
    for name in names:
        cell = find_receiver(polygons, name)
        origin, u, v, n, shape = sensor_grid(polygons, cell, pixel)
        mask, bases = sensor_mask(polygons, cell, origin, u, v, n, shape, pixel)
        sensors.append(dict(name=name, cell=cell, origin=origin, u=u, v=v, normal=n,
                            shape=shape, pixel=pixel, mask=mask, bases=bases,
                            height=height, near_clip=near_clip,
                            to_world=sensor_to_world(origin, u, v, n, shape, pixel, height)))
    return sensors


# --------------------------------------------------------------------------
# Mitsuba
# --------------------------------------------------------------------------

def configure_llvm():
    """Point Dr.Jit at the newest system libLLVM unless DRJIT_LIBLLVM_PATH is
    set. Dr.Jit globs /usr/lib/<arch>/libLLVM*.so.* itself, but may pick an
    old one: Debian 12's LLVM 15 (pulled in by Mesa) loads and then aborts the
    process at code generation ("LLVM ERROR: Cannot select: ... fminimum");
    its libllvm19 package works. Call before importing drjit/mitsuba."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return os.environ["DRJIT_LIBLLVM_PATH"]
    import glob
    import re
    best = None
    for path in glob.glob("/usr/lib/*-linux-gnu/libLLVM*.so*"):
        m = re.search(r"libLLVM(?:-|\.so\.)(\d+)", os.path.basename(path))
        if m and (best is None or int(m.group(1)) > best[0]):
            best = (int(m.group(1)), path)
    if best:
        os.environ["DRJIT_LIBLLVM_PATH"] = best[1]
        return best[1]
    return None


def probe(variant):
    """Render a tiny scene with `variant`; exit status 0 if it works."""
    configure_llvm()
    import mitsuba as mi
    mi.set_variant(variant)
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 4},
        "ball": {"type": "sphere", "bsdf": {"type": "diffuse"}},
        "sky": {"type": "constant"},
        "cam": {"type": "orthographic", "film": {"type": "hdrfilm", "width": 4, "height": 4},
                "to_world": mi.ScalarTransform4f().look_at(
                    origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0])},
    })
    img = np.asarray(mi.render(scene, spp=16))
    if not (np.all(np.isfinite(img)) and img.mean() > 0.1):
        raise RuntimeError("probe render gave %s" % img)
    print("Mitsuba %s variant %s works%s" % (
        mi.__version__, variant,
        (" (LLVM: %s)" % os.environ.get("DRJIT_LIBLLVM_PATH", "found by Dr.Jit"))
        if variant.startswith("llvm") else ""))


def choose_variant(requested):
    """'auto': llvm_ad_rgb if a probe render works in a child process (an
    unusable LLVM aborts the process), else scalar_rgb."""
    if requested != "auto":
        return requested
    import subprocess
    try:
        r = subprocess.run([sys.executable, os.path.abspath(__file__), "--probe", "llvm_ad_rgb"],
                           capture_output=True, text=True, timeout=300)
        if r.returncode == 0:
            return "llvm_ad_rgb"
        lines = r.stderr.strip().splitlines() or ["?"]
        why = next((ln for ln in lines if "ERROR" in ln or "Error" in ln), lines[-1])
        print("llvm_ad_rgb unusable (%s); using scalar_rgb. On Debian 12: "
              "apt-get install libllvm19" % why.strip(), file=sys.stderr)
    except subprocess.TimeoutExpired:
        print("llvm_ad_rgb probe timed out; using scalar_rgb", file=sys.stderr)
    return "scalar_rgb"


def sensor_to_world(origin, u, v, n, shape, pixel, height):
    """Camera-to-world matrix of Mitsuba's orthographic sensor.

    Mitsuba maps film column 0 to camera +x and film row 0 to camera +y, the
    camera looks along +z and sees x in [-1, 1], y in [-H/W, H/W]
    (orthographic_projection in mitsuba/render/sensor.h). With camera x =
    -u*s, y = -v*s (s = half the image width), z = -n (a proper rotation since
    u x v = -n) and the centre `height` in front of the surface, film row r,
    column c covers exactly the footprint of pixel [r, c]."""
    H, W = shape
    s = 0.5 * W * pixel
    centre = origin + 0.5 * W * pixel * u + 0.5 * H * pixel * v + height * n
    m = np.eye(4)
    m[:3, 0] = -s * u
    m[:3, 1] = -s * v
    m[:3, 2] = -n
    m[:3, 3] = centre
    return m


def film_to_pixels(img):
    return np.ascontiguousarray(np.asarray(img)[:, :, :3], dtype=np.float64)


def build_scene_dict(mi, polygons, refl, emis, sensors, args, tmpdir):
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": args.max_depth,
                       "rr_depth": args.rr_depth, "hide_emitters": False},
    }
    for c, poly in enumerate(polygons):
        tris = fan_triangles(poly, c)
        path = os.path.join(tmpdir, "cell%03d.ply" % c)
        write_ply(path, poly, tris)
        shape = {
            "type": "ply", "filename": path, "face_normals": True,
            "bsdf": {"type": "diffuse",
                     "reflectance": {"type": "rgb", "value": [float(x) for x in refl[c]]}},
        }
        if np.any(emis[c] > 0):
            shape["emitter"] = {"type": "area",
                                "radiance": {"type": "rgb",
                                             "value": [float(x) for x in emis[c]]}}
        scene["cell%03d" % c] = shape
    for k, s in enumerate(sensors):
        H, W = s["shape"]
        scene["sensor%d_%s" % (k, s["name"])] = {
            "type": "orthographic",
            "near_clip": args.near_clip,
            "far_clip": 100.0,
            "to_world": mi.ScalarTransform4f(s["to_world"].tolist()),
            "film": {"type": "hdrfilm", "width": W, "height": H,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb",
                     "component_format": "float32", "sample_border": False},
            "sampler": {"type": args.sampler, "sample_count": args.spp_per_pass},
        }
    return scene


def check_sensor_rays(mi, scene, s):
    """Rays through the centre and near the corners of every valid pixel must
    first hit the sensor's own surface plane from the front: nothing lies
    between the camera and the surface there."""
    p = s["pixel"]
    start = s["height"] - s["near_clip"]
    ii, jj = np.nonzero(s["mask"])
    pts = []
    for (a, b) in [(0.5, 0.5), (0.01, 0.01), (0.99, 0.01), (0.01, 0.99), (0.99, 0.99)]:
        pts.append(s["origin"][None] + ((jj + a) * p)[:, None] * s["u"][None]
                   + ((ii + b) * p)[:, None] * s["v"][None] + start * s["normal"][None])
    pts = np.vstack(pts)
    d = [float(x) for x in -s["normal"]]
    if mi.variant().startswith("scalar"):
        t, n = [], []
        for q in pts:
            si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*q), mi.Vector3f(*d)))
            t.append(si.t if si.is_valid() else np.inf)
            n.append(list(si.n) if si.is_valid() else [0, 0, 0])
        t, n = np.array(t), np.array(n)
    else:
        ray = mi.Ray3f(mi.Point3f(pts[:, 0], pts[:, 1], pts[:, 2]), mi.Vector3f(*d))
        si = scene.ray_intersect(ray)
        valid = np.array(si.is_valid())
        t = np.where(valid, np.array(si.t), np.inf)
        n = np.array(si.n).reshape(3, -1).T if np.array(si.n).shape[0] == 3 \
            else np.array(si.n)
    ok = (np.abs(t - start) < 1e-5) & (n @ s["normal"] > 1 - 1e-5)
    return int(np.sum(~ok))


def render_sensor(mi, scene, k, s, args, seed_base):
    """batches x passes renders; returns mean, stderr, seeds, seconds."""
    H, W = s["shape"]
    batches = np.zeros((args.batches, H, W, 3), dtype=np.float64)
    seeds = []
    t0, c0 = time.time(), time.process_time()
    for b in range(args.batches):
        acc = np.zeros((H, W, 3))
        for p in range(args.passes):
            seed = seed_base + b * args.passes + p
            seeds.append(seed)
            img = mi.render(scene, sensor=k, seed=seed, spp=args.spp_per_pass)
            acc += film_to_pixels(img)
        batches[b] = acc / args.passes
        if args.verbose:
            el = time.time() - t0
            print("  %s: batch %d/%d done, %.1f s elapsed, ~%.0f s left" % (
                s["name"], b + 1, args.batches, el, el / (b + 1) * (args.batches - b - 1)),
                flush=True)
    seconds = time.time() - t0
    cpu_seconds = time.process_time() - c0
    mean = batches.mean(axis=0)
    stderr = batches.std(axis=0, ddof=1) / np.sqrt(args.batches) if args.batches > 1 \
        else np.full_like(mean, np.nan)
    return mean, stderr, seeds, seconds, cpu_seconds


def argument_parser():
    """The command line's parser; `argument_parser().parse_args([...])` gives
    the settings (defaults included) to other scripts too."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="cornell", help="Penumbra built-in scene (default cornell)")
    ap.add_argument("--penumbra-pythonpath",
                    default=os.environ.get("PENUMBRA_PYTHONPATH",
                                           os.path.join(REPO, "build", "lib", "python3",
                                                        "dist-packages")),
                    help="where `import penumbra` is found (default: the build tree; "
                         "env PENUMBRA_PYTHONPATH)")
    ap.add_argument("--variant", default="auto",
                    help="llvm_ad_rgb, scalar_rgb or auto (llvm if it works; default)")
    ap.add_argument("--threads", type=int, default=0,
                    help="worker threads (default 0 = all cores)")
    ap.add_argument("--pixel", type=float, default=0.01, help="pixel size in metres (0.01)")
    ap.add_argument("--height", type=float, default=2e-3,
                    help="sensor distance in front of the surface, metres (0.002)")
    ap.add_argument("--near-clip", type=float, default=1e-3,
                    help="near clip distance, metres (0.001): rays start "
                         "height - near_clip in front of the surface")
    ap.add_argument("--spp-per-pass", type=int, default=1024,
                    help="samples per pixel of one mi.render call (1024)")
    ap.add_argument("--passes", type=int, default=10, help="mi.render calls per batch (10)")
    ap.add_argument("--batches", type=int, default=16,
                    help="independent batches (distinct seeds) for the standard error (16)")
    ap.add_argument("--sampler", default="independent", help="Mitsuba sampler (independent)")
    ap.add_argument("--max-depth", type=int, default=-1,
                    help="path integrator max_depth (-1 = unlimited, Russian roulette)")
    ap.add_argument("--rr-depth", type=int, default=5, help="Russian roulette start depth (5)")
    ap.add_argument("--seed", type=int, default=1, help="first seed (1)")
    ap.add_argument("--sensors", default="floor,back",
                    help="comma-separated subset of floor,back")
    ap.add_argument("--output", default=os.path.join(HERE, "cornell_reference.npz"),
                    help="output .npz (default: beside this script)")
    ap.add_argument("--verbose", action="store_true", help="progress per batch")
    ap.add_argument("--probe", metavar="VARIANT",
                    help="only check that VARIANT renders (exit status 0 if so)")
    return ap


def main(argv=None):
    ap = argument_parser()
    args = ap.parse_args(argv)
    if args.probe:
        probe(args.probe)
        return

    if not 0 < args.near_clip < args.height:
        ap.error("need 0 < --near-clip < --height")
    if args.batches < 2:
        ap.error("--batches must be at least 2 (the standard error needs them)")
    polygons, refl, emis = load_penumbra_polygons(args.scene, args.penumbra_pythonpath)
    digest = scene_digest(polygons, refl, emis)

    sensors = make_sensors(polygons, args.sensors.split(","), args.pixel, args.height,
                           args.near_clip)
    for s in sensors:
        H, W = s["shape"]
        print("%s: cell %d, %d x %d pixels of %.4g m, %d valid, %d masked (%d standing "
              "object(s): cells %s)" % (s["name"], s["cell"], H, W, s["pixel"],
                                        s["mask"].sum(), H * W - s["mask"].sum(),
                                        len(s["bases"]), [b[0] for b in s["bases"]]))

    configure_llvm()
    variant = choose_variant(args.variant)
    import mitsuba as mi
    mi.set_variant(variant)
    import drjit as dr
    if args.threads > 0:
        dr.set_thread_count(args.threads)
    print("Mitsuba %s, Dr.Jit %s, variant %s, threads %s" % (
        mi.__version__, dr.__version__, variant, args.threads or "all"))

    with tempfile.TemporaryDirectory(prefix="penumbra-mitsuba-") as tmp:
        scene = mi.load_dict(build_scene_dict(mi, polygons, refl, emis, sensors, args, tmp))

    for k, s in enumerate(sensors):
        bad = check_sensor_rays(mi, scene, s)
        if bad:
            raise RuntimeError("%s: %d valid-pixel rays do not hit the surface first"
                               % (s["name"], bad))

    out = {
        "mitsuba_version": np.array(mi.__version__),
        "drjit_version": np.array(dr.__version__),
        "variant": np.array(variant),
        "scene": np.array(args.scene),
        "scene_sha256": np.array(digest),
        "integrator": np.array("path"),
        "max_depth": np.int32(args.max_depth),
        "rr_depth": np.int32(args.rr_depth),
        "sampler": np.array(args.sampler),
        "spp": np.int64(args.spp_per_pass * args.passes * args.batches),
        "spp_per_pass": np.int32(args.spp_per_pass),
        "passes": np.int32(args.passes),
        "batches": np.int32(args.batches),
        "threads": np.int32(args.threads or os.cpu_count()),
        "sensors": np.array(",".join(s["name"] for s in sensors)),
        # The scene as rendered: cell c has vertices
        # scene_points[scene_offsets[c]:scene_offsets[c + 1]].
        "scene_points": np.vstack(polygons),
        "scene_offsets": np.cumsum([0] + [len(p) for p in polygons]).astype(np.int32),
        "scene_reflectance": refl,
        "scene_emission": emis,
    }
    seed_base = args.seed
    for k, s in enumerate(sensors):
        mean, stderr, seeds, seconds, cpu_seconds = render_sensor(mi, scene, k, s, args, seed_base)
        seed_base += len(seeds)
        m = s["mask"]
        mu = mean[m].mean(axis=0)
        noise = np.sqrt((stderr[m] ** 2).mean(axis=0)) / mu
        noise_all = np.sqrt((stderr[m] ** 2).mean()) / mu.mean()
        print("%s: %.1f s (%.1f s CPU), mean radiance (valid pixels) %s, RMS(stderr)/mean "
              "per channel %s, all channels %.3g%%" % (
                  s["name"], seconds, cpu_seconds, np.array2string(mu, precision=4),
                  np.array2string(100 * noise, precision=3) + " %", 100 * noise_all),
              flush=True)
        name = s["name"]
        out.update({
            name + "_radiance": mean.astype(np.float32),
            name + "_stderr": stderr.astype(np.float32),
            name + "_mask": m,
            name + "_origin": s["origin"],
            name + "_u": s["u"],
            name + "_v": s["v"],
            name + "_normal": s["normal"],
            name + "_pixel_size": np.float64(s["pixel"]),
            name + "_shape": np.array(s["shape"], dtype=np.int32),
            name + "_cell_id": np.int32(s["cell"]),
            name + "_sensor_height": np.float64(s["height"]),
            name + "_seeds": np.array([seeds[0], seeds[-1]], dtype=np.int64),
            name + "_render_seconds": np.float64(seconds),
            name + "_render_cpu_seconds": np.float64(cpu_seconds),
            name + "_noise_rel": noise.astype(np.float64),
            name + "_noise_rel_all": np.float64(noise_all),
        })
    np.savez_compressed(args.output, **out)
    print("wrote %s (%d bytes)" % (args.output, os.path.getsize(args.output)))


if __name__ == "__main__":
    main()
