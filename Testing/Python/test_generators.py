# SPDX-License-Identifier: GPL-3.0-or-later
"""penumbra.generators.box_room and furnished_room: valid scenes of the requested size,
deterministic, surfaces facing the right way, boxes that do not overlap, lights that emit;
a closed shell and probe points on their surfaces for the furnished room."""
import os
import time
import warnings

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import penumbra
from penumbra.generators import (LIGHT_EMISSION, ROOM_CELLS, ROOM_HEIGHT, box_room,
                                 furnished_room, furnished_room_probes)

# The scene has 6 + lights + 5 * boxes polygons: within 2 of any request that
# is at least 6 + lights.
COUNT_TOLERANCE = 2


def arrays(scene):
    """Points, (n, 4) quads, Reflectance, Emission and PartId as numpy arrays."""
    points = vtk_to_numpy(scene.GetPoints().GetData())
    offsets = vtk_to_numpy(scene.GetPolys().GetOffsetsArray())
    assert (np.diff(offsets) == 4).all()
    quads = vtk_to_numpy(scene.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    cell = scene.GetCellData()
    return (points, quads, vtk_to_numpy(cell.GetArray("Reflectance")),
            vtk_to_numpy(cell.GetArray("Emission")), vtk_to_numpy(cell.GetArray("PartId")))


def newell(corners):
    """Right-hand-rule (area-weighted) normals of (n, k, 3) polygons."""
    following = np.roll(corners, -1, axis=1)
    return 0.5 * np.cross(corners, following).sum(axis=1)


def light_count(scene):
    return int((arrays(scene)[4] == -2).sum())


@pytest.mark.parametrize("polygons", [7, 50, 237, 1000, 4321])
@pytest.mark.parametrize("seed", [0, 7])
def test_scene_loads_through_the_validator(polygons, seed, tmp_path):
    scene = box_room(polygons, seed=seed)
    path = os.path.join(str(tmp_path), "room.vtp")
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(scene)
    assert writer.Write() == 1
    loaded = penumbra.load_scene(path)
    assert loaded.GetNumberOfCells() == scene.GetNumberOfCells()
    validator = penumbra.vtkPenumbraSceneValidator()
    validator.SetInputData(scene)
    penumbra.run_filter(validator)


@pytest.mark.parametrize("polygons", [20, 57, 58, 59, 60, 61, 999, 1000, 1001, 10000, 12345])
@pytest.mark.parametrize("lights", [None, 1, 3])
def test_polygon_count_within_tolerance(polygons, lights):
    scene = box_room(polygons, lights=lights)
    count = scene.GetNumberOfCells()
    assert abs(count - polygons) <= COUNT_TOLERANCE
    nlights = light_count(scene)
    if lights is not None:
        assert nlights == lights
    assert (count - ROOM_CELLS - nlights) % 5 == 0


def test_small_requests_give_the_lit_empty_room():
    scene = box_room(3, lights=2)
    assert scene.GetNumberOfCells() == ROOM_CELLS + 2
    assert (arrays(scene)[4] >= 0).sum() == 0


def test_deterministic_for_a_seed():
    first, second = arrays(box_room(800, seed=11)), arrays(box_room(800, seed=11))
    for a, b in zip(first, second):
        np.testing.assert_array_equal(a, b)
    other = arrays(box_room(800, seed=12))
    assert other[0].shape != first[0].shape or not np.array_equal(other[0], first[0])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_surfaces_face_the_right_way(seed):
    scene = box_room(600, seed=seed)
    points, quads, _, _, part = arrays(scene)
    corners = points[quads]
    normals = newell(corners)
    centroids = corners.mean(axis=1)
    assert (np.linalg.norm(normals, axis=1) > 0).all()

    # Room surfaces face the room's centre.
    room = part == -1
    assert room.sum() == ROOM_CELLS and room[:ROOM_CELLS].all()
    lo, hi = points.min(axis=0), points.max(axis=0)
    assert lo[1] == 0 and hi[1] == ROOM_HEIGHT
    centre = 0.5 * (lo + hi)
    assert (np.einsum("ij,ij->i", normals[room], centre - centroids[room]) > 0).all()

    # Lights face straight down, under the ceiling.
    light = part == -2
    unit = normals[light] / np.linalg.norm(normals[light], axis=1)[:, None]
    np.testing.assert_allclose(unit, np.tile([0.0, -1.0, 0.0], (light.sum(), 1)), atol=1e-12)
    light_y = corners[light][:, :, 1]
    assert (light_y < ROOM_HEIGHT).all() and (light_y > ROOM_HEIGHT - 0.01).all()

    # Box faces face away from their box, the top faces up; no box reaches the lights.
    nboxes = part.max() + 1
    box = part >= 0
    box_corners = corners[box].reshape(nboxes, 5, 4, 3)
    box_centre = box_corners.reshape(nboxes, 20, 3).mean(axis=1)  # symmetric: the centroid
    box_normals = normals[box].reshape(nboxes, 5, 3)
    outward = box_corners.mean(axis=2) - box_centre[:, None, :]
    assert (np.einsum("bfi,bfi->bf", box_normals, outward) > 0).all()
    assert (box_normals[:, 0, 1] > 0).all()
    assert box_corners[..., 1].max() < light_y.min()


def footprints(scene):
    """Per box: its bottom ring (4, 2) in (x, z) and its bottom and top heights."""
    points, quads, _, _, part = arrays(scene)
    nboxes = part.max() + 1
    faces = points[quads[part >= 0]].reshape(nboxes, 5, 4, 3)
    # Side face (a_bottom, b_bottom, b_top, a_top): corners 0 of the 4 sides ring the bottom.
    ring = faces[:, 1:, 0, :]
    return ring[:, :, [0, 2]], ring[:, 0, 1], faces[:, 0, 0, 1]


def separated(a, b):
    """Whether the convex quads a and b (4, 2) are strictly apart (separating axis)."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        axes = np.stack([-edges[:, 1], edges[:, 0]], axis=1)
        pa, pb = a @ axes.T, b @ axes.T
        if ((pa.max(axis=0) < pb.min(axis=0)) | (pb.max(axis=0) < pa.min(axis=0))).any():
            return True
    return False


def inside(point, poly):
    """Whether a point is strictly inside the counter-clockwise-from-above quad."""
    edges = np.roll(poly, -1, axis=0) - poly
    rel = point - poly
    # Counter-clockwise seen from +y is clockwise in (x, z): interior on the right.
    return (edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0] < 0).all()


@pytest.mark.parametrize("seed", [0, 5])
def test_boxes_stand_apart_or_on_each_other(seed):
    scene = box_room(700, seed=seed)
    ring, bottom, top = footprints(scene)
    points = arrays(scene)[0]
    lo, hi = points.min(axis=0)[[0, 2]], points.max(axis=0)[[0, 2]]
    assert (ring > lo).all() and (ring < hi).all()
    on_floor = np.nonzero(bottom == 0)[0]
    stacked = np.nonzero(bottom > 0)[0]
    assert len(stacked) > 0 and len(on_floor) > len(stacked)
    for k, i in enumerate(on_floor):
        for j in on_floor[k + 1:]:
            assert separated(ring[i], ring[j]), (i, j)
    for i in stacked:
        # Exactly on the top of one floor box, inside its top face.
        base = on_floor[top[on_floor] == bottom[i]]
        assert len(base) == 1
        assert all(inside(p, ring[base[0]]) for p in ring[i])
        assert not (bottom == top[i]).any()  # nothing on a stacked box
    assert (top > bottom).all()


def test_lights_emit():
    for lights in (None, 1, 4):
        scene = box_room(500, seed=3, lights=lights)
        points, quads, reflectance, emission, part = arrays(scene)
        area = np.linalg.norm(newell(points[quads]), axis=1)
        power = np.pi * (area[:, None] * emission).sum(axis=0)
        assert (power > 0).all()
        assert (emission[part != -2] == 0).all()
        np.testing.assert_array_equal(emission[part == -2],
                                      np.tile(LIGHT_EMISSION, ((part == -2).sum(), 1)))
        assert (reflectance >= 0).all() and (reflectance < 1).all()


def test_negative_lights_rejected():
    with pytest.raises(ValueError, match="lights"):
        box_room(100, lights=-1)


def test_large_scene_has_the_requested_size():
    scene = box_room(20000, seed=1)
    assert abs(scene.GetNumberOfCells() - 20000) <= COUNT_TOLERANCE


def test_small_room_meshes_without_failures():
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputData(box_room(60, seed=2))
    out = penumbra.run_filter(mesher)
    field = out.GetFieldData()
    assert field.GetArray("ConstraintFailures").GetValue(0) == 0
    assert field.GetArray("SegmentsGenerated").GetValue(0) > 0
    assert field.GetArray("ContactSegments").GetValue(0) > 0


# furnished_room: an office of bays. Counts within 3 % of the request.
FURNISHED_COUNT_TOLERANCE = 0.03
PROBE_GROUPS = ("floor", "table", "wall", "ceiling", "gap", "behind_light", "contact")


def unit_normals(corners):
    normals = newell(corners)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def inside_polygons(points, corners, normals, margin=0.0):
    """Whether each point lies inside its convex polygon (counter-clockwise about
    its normal), at least `margin` from every edge line."""
    result = np.ones(len(points), dtype=bool)
    for k in range(corners.shape[1]):
        start, end = corners[:, k], corners[:, (k + 1) % corners.shape[1]]
        edge = end - start
        length = np.linalg.norm(edge, axis=-1)
        side = np.einsum("...i,...i->...", np.cross(edge, points - start), normals) / length
        result &= side > margin
    return result


def first_hits(origins, directions, corners, normals, chunk=256):
    """Distance to, and index of, the first polygon each ray meets beyond 1e-9
    (inf and -1 when it meets none)."""
    offsets = np.einsum("ij,ij->i", normals, corners[:, 0])
    distance = np.full(len(origins), np.inf)
    index = np.full(len(origins), -1)
    for lo in range(0, len(origins), chunk):
        o, d = origins[lo:lo + chunk], directions[lo:lo + chunk]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (offsets[None, :] - o @ normals.T) / (d @ normals.T)
        ok = np.isfinite(t) & (t > 1e-9)
        t = np.where(ok, t, np.inf)
        hit = o[:, None, :] + np.where(ok, t, 0.0)[..., None] * d[:, None, :]
        for k in range(corners.shape[1]):
            start, end = corners[:, k], corners[:, (k + 1) % corners.shape[1]]
            side = np.einsum("rmi,mi->rm", np.cross((end - start)[None], hit - start[None]),
                             normals)
            ok &= side >= 0
        t = np.where(ok, t, np.inf)
        index[lo:lo + chunk] = np.where(np.isfinite(t.min(axis=1)), t.argmin(axis=1), -1)
        distance[lo:lo + chunk] = t.min(axis=1)
    return distance, index


def furnished_boxes(scene):
    """Per box (PartId >= 0): its first cell, number of faces (4: the sides of
    a leg, 5: no bottom, 6: all), footprint ring (4, 2) in (x, z), bottom and
    top heights."""
    points, quads, _, _, part = arrays(scene)
    cells = np.nonzero(part >= 0)[0]
    faces = np.bincount(part[cells])
    assert set(np.unique(faces)) == {4, 5, 6}
    first = cells[0] + np.cumsum(faces) - faces
    assert (part[first] == np.arange(len(faces))).all()
    first_side = first + (faces > 4)
    # Side face (a bottom, b bottom, b top, a top): corners 0 ring the bottom.
    sides = points[quads[first_side[:, None] + np.arange(4)]]  # (n, 4 sides, 4, 3)
    ring = sides[:, :, 0, :]
    return first, faces, ring[:, :, [0, 2]], ring[:, 0, 1], sides[:, 0, 2, 1]


@pytest.mark.parametrize("polygons", [120, 500, 777, 1000, 1234, 5000, 20000])
def test_furnished_room_has_the_requested_size(polygons):
    count = furnished_room(polygons).GetNumberOfCells()
    assert abs(count - polygons) <= FURNISHED_COUNT_TOLERANCE * polygons
    assert abs(count - polygons) <= COUNT_TOLERANCE  # what the docstring promises


def test_furnished_room_of_100000_polygons():
    start = time.perf_counter()
    scene = furnished_room(100000, seed=4)
    elapsed = time.perf_counter() - start
    if elapsed > 10.0:
        pytest.skip("100,000 polygons took %.1f s here" % elapsed)
    assert abs(scene.GetNumberOfCells() - 100000) <= FURNISHED_COUNT_TOLERANCE * 100000


@pytest.mark.parametrize("seed", [0, 3])
def test_furnished_cells_are_planar_convex_quads(seed):
    points, quads, reflectance, emission, part = arrays(furnished_room(5000, seed=seed))
    corners = points[quads]
    area = np.linalg.norm(newell(corners), axis=1)
    assert area.min() > 1e-5
    normals = unit_normals(corners)
    off_plane = np.einsum("ckj,cj->ck", corners - corners.mean(axis=1)[:, None], normals)
    assert np.abs(off_plane).max() < 1e-9
    edges = np.roll(corners, -1, axis=1) - corners
    turns = np.einsum("ckj,cj->ck", np.cross(edges, np.roll(edges, -1, axis=1)), normals)
    assert (turns > 0).all()
    assert (reflectance >= 0).all() and reflectance.max() <= 0.85
    assert (reflectance[part >= 0] >= 0.1).all()
    light = part == -2
    np.testing.assert_array_equal(emission[light], np.tile(LIGHT_EMISSION, (light.sum(), 1)))
    assert (emission[~light] == 0).all()


@pytest.mark.parametrize("seed", [0, 1])
def test_furnished_surfaces_face_the_right_way(seed):
    scene = furnished_room(3000, seed=seed)
    points, quads, reflectance, _, part = arrays(scene)
    corners = points[quads]
    normals = unit_normals(corners)
    centroids = corners.mean(axis=1)
    lo, hi = points.min(axis=0), points.max(axis=0)
    assert lo[1] == 0 and hi[1] == ROOM_HEIGHT and lo[0] == 0 and lo[2] == 0

    # The shell faces inward: floor up, ceiling down, walls toward the middle.
    shell = part == -1
    on_floor, on_ceiling = centroids[:, 1] == 0, centroids[:, 1] == ROOM_HEIGHT
    np.testing.assert_array_equal(normals[shell & on_floor], [[0, 1, 0]] * (shell & on_floor).sum())
    np.testing.assert_array_equal(normals[shell & on_ceiling],
                                  [[0, -1, 0]] * (shell & on_ceiling).sum())
    walls = shell & ~on_floor & ~on_ceiling
    middle = 0.5 * (lo + hi)
    assert (np.einsum("ij,ij->i", normals[walls], middle - centroids[walls]) > 0).all()
    assert len(np.unique(np.round(normals[walls], 12), axis=0)) == 4

    # Lights face down, 5 mm under the ceiling, reflectance 0.78.
    light = part == -2
    np.testing.assert_allclose(normals[light], [[0, -1, 0]] * light.sum(), atol=1e-15)
    np.testing.assert_allclose(corners[light][..., 1], ROOM_HEIGHT - 0.005, rtol=0, atol=1e-15)
    assert (reflectance[light] == 0.78).all()

    # Box faces face out of their box (its centre is the middle of its
    # bounding box); the top faces up, a bottom face down.
    first, faces, _, bottom, top = furnished_boxes(scene)
    closed = faces == 6
    box = part[part >= 0]
    box_lo = np.full((len(faces), 3), np.inf)
    box_hi = np.full((len(faces), 3), -np.inf)
    np.minimum.at(box_lo, box, corners[part >= 0].min(axis=1))
    np.maximum.at(box_hi, box, corners[part >= 0].max(axis=1))
    centre = 0.5 * (box_lo + box_hi)[box]
    assert (np.einsum("ij,ij->i", normals[part >= 0], centroids[part >= 0] - centre) > 1e-6).all()
    topped = first[faces > 4]
    np.testing.assert_allclose(normals[topped], [[0, 1, 0]] * len(topped), atol=1e-15)
    np.testing.assert_allclose(normals[first[closed] + 5], [[0, -1, 0]] * closed.sum(), atol=1e-15)
    # Nothing but the lights within 10 cm of the ceiling.
    assert top.max() <= ROOM_HEIGHT - 0.1


@pytest.mark.parametrize("seed", [0, 2])
def test_furnished_shell_is_closed(seed):
    scene = furnished_room(1000, seed=seed)
    points, quads, _, _, part = arrays(scene)
    # Every edge of the shell is met once each way by its quads.
    shell = quads[part == -1]
    edges = np.stack([shell, np.roll(shell, -1, axis=1)], axis=-1).reshape(-1, 2)
    forward = {tuple(e) for e in edges}
    assert len(forward) == len(edges)
    assert forward == {(b, a) for a, b in edges}
    # Independently: rays from random points inside the room all meet the
    # shell from the front, and the first polygon any ray meets is inside the
    # shell's bounds: nothing escapes.
    rng = np.random.default_rng(seed)
    lo, hi = points.min(axis=0), points.max(axis=0)
    origins = rng.uniform(lo + 1e-3, hi - 1e-3, (2000, 3))
    directions = rng.normal(size=(2000, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    corners = points[quads]
    normals = unit_normals(corners)
    shell_cells = np.nonzero(part == -1)[0]
    distance, index = first_hits(origins, directions, corners[shell_cells], normals[shell_cells])
    assert (index >= 0).all()
    assert (np.einsum("ij,ij->i", directions, normals[shell_cells[index]]) < 0).all()
    distance, index = first_hits(origins, directions, corners, normals)
    assert (index >= 0).all()
    ends = origins + distance[:, None] * directions
    assert (ends >= lo - 1e-9).all() and (ends <= hi + 1e-9).all()


@pytest.mark.parametrize("seed", [0, 1])
def test_furnished_boxes_touch_only_where_they_stand(seed):
    scene = furnished_room(3000, seed=seed)
    _, faces, ring, bottom, top = furnished_boxes(scene)
    points = arrays(scene)[0]
    lo, hi = points.min(axis=0)[[0, 2]], points.max(axis=0)[[0, 2]]
    assert (ring > lo).all() and (ring < hi).all()
    assert (top > bottom).all()
    box_lo, box_hi = ring.min(axis=1), ring.max(axis=1)
    overlap_xz = ((box_lo[:, None] < box_hi[None]) & (box_lo[None] < box_hi[:, None])).all(axis=2)
    overlap_y = (bottom[:, None] <= top[None]) & (bottom[None] <= top[:, None])
    candidates = np.argwhere(np.triu(overlap_xz & overlap_y, 1))
    contacts = 0
    for i, j in candidates:
        if separated(ring[i], ring[j]):
            continue
        # Footprints overlap: one stands on the other, its footprint inside.
        lower, upper = (i, j) if top[i] == bottom[j] else (j, i)
        assert top[lower] == bottom[upper], (i, j)
        small, large = (lower, upper) if np.ptp(ring[lower], axis=0).prod() < np.ptp(
            ring[upper], axis=0).prod() else (upper, lower)
        assert all(inside(p, ring[large]) for p in ring[small]), (i, j)
        contacts += 1
    # Boxes without a bottom face stand on the floor or on another box; legs
    # (no top face either) hold up a box resting on them.
    supported, holding = bottom == 0, np.zeros(len(faces), dtype=bool)
    for i, j in candidates:
        for lower, upper in ((i, j), (j, i)):
            if top[lower] == bottom[upper] and not separated(ring[i], ring[j]):
                supported[upper] = holding[lower] = True
    assert supported[faces < 6].all()
    assert holding[faces == 4].all()
    assert contacts > 100


@pytest.mark.parametrize("polygons,seed", [(1000, 0), (5000, 6)])
def test_furnished_probes_lie_on_their_cells(polygons, seed):
    probes = furnished_room_probes(polygons, seed=seed)
    points, quads, _, _, part = arrays(furnished_room(polygons, seed=seed))
    n = len(probes["cells"])
    assert probes["points"].shape == (n, 3) and probes["normals"].shape == (n, 3)
    assert probes["cells"].dtype == np.int64 and probes["points"].dtype == np.float64
    counts = {g: int((probes["groups"] == g).sum()) for g in PROBE_GROUPS}
    assert set(probes["groups"]) == set(PROBE_GROUPS)
    assert all(c > 0 for c in counts.values())
    if polygons == 1000:
        assert all(50 <= c <= 70 for c in counts.values()), counts
    corners = points[quads[probes["cells"]]]
    normals = unit_normals(corners)
    np.testing.assert_allclose(probes["normals"], normals, rtol=0, atol=1e-12)
    off_plane = np.einsum("ij,ij->i", probes["points"] - corners[:, 0], normals)
    assert np.abs(off_plane).max() < 1e-9
    assert inside_polygons(probes["points"], corners, normals, margin=1e-4).all()


@pytest.mark.parametrize("seed", [0, 5])
def test_furnished_probe_groups_test_what_they_say(seed):
    probes = furnished_room_probes(2000, seed=seed)
    scene = furnished_room(2000, seed=seed)
    points, quads, _, _, part = arrays(scene)
    first, faces, ring, bottom, top = furnished_boxes(scene)
    corners = points[quads]
    normals = unit_normals(corners)
    group, p, n, cell = probes["groups"], probes["points"], probes["normals"], probes["cells"]

    def footprint_distance(q, rings):
        """Distance in (x, z) from points q (m, 2) to the nearest of the rings,
        negative inside one (rings counter-clockwise seen from +y)."""
        best = np.full(len(q), np.inf)
        for r in rings:
            edges = np.roll(r, -1, axis=0) - r
            rel = q[:, None, :] - r[None]
            # Signed distance to each edge line; inside is where all are < 0.
            length = np.linalg.norm(edges, axis=1)
            side = (edges[:, 0] * rel[..., 1] - edges[:, 1] * rel[..., 0]) / length
            t = np.clip(np.einsum("mki,ki->mk", rel, edges) / length ** 2, 0, 1)
            gap = np.linalg.norm(rel - t[..., None] * edges, axis=2).min(axis=1)
            best = np.minimum(best, np.where((side < 0).all(axis=1), -gap, gap))
        return best

    standing = ring[bottom == 0]
    legs = standing[np.ptp(standing, axis=1).max(axis=1) < 0.1]
    floor = group == "floor"
    assert (part[cell[floor]] == -1).all() and (p[floor, 1] == 0).all()
    assert (footprint_distance(p[floor][:, [0, 2]], standing) >= 0.02 - 1e-12).all()
    contact = group == "contact"
    assert (part[cell[contact]] == -1).all() and (p[contact, 1] == 0).all()
    near = footprint_distance(p[contact][:, [0, 2]], legs)
    assert (near >= 0.002 - 1e-12).all() and (near <= 0.005 + 1e-12).all()
    assert (footprint_distance(p[contact][:, [0, 2]], standing) >= near - 1e-12).all()

    table = group == "table"
    tops = part[cell[table]]
    assert (faces[tops] == 6).all() and (cell[table] == first[tops]).all()
    assert (p[table, 1] == top[tops]).all()
    on_tops = [ring[(bottom == top[t]) & (faces == 5)] for t in tops]
    for q, t, items in zip(p[table][:, [0, 2]], tops, on_tops):
        assert -footprint_distance(q[None], [ring[t]])[0] >= 0.02 - 1e-12
        assert footprint_distance(q[None], items)[0] >= 0.02 - 1e-12

    # Along the normal: a bookcase 1 cm in front of a gap point, a light 5 mm
    # under a point behind a light, neither in front of wall or ceiling points.
    distance, hit = first_hits(p, n, corners, normals)
    gap, behind = group == "gap", group == "behind_light"
    np.testing.assert_allclose(distance[gap], 0.01, atol=1e-12)
    assert (part[hit[gap]] >= 0).all()
    assert (np.einsum("ij,ij->i", normals[hit[gap]], n[gap]) < -0.999).all()
    np.testing.assert_allclose(distance[behind], 0.005, atol=1e-12)
    assert (part[hit[behind]] == -2).all()
    wall, ceiling = group == "wall", group == "ceiling"
    assert (part[cell[wall]] == -1).all() and (np.abs(n[wall, 1]) < 1e-12).all()
    assert (p[wall, 1] >= 0.3).all() and (p[wall, 1] <= ROOM_HEIGHT - 0.3).all()
    assert (distance[wall] > 0.05).all()
    assert (part[cell[ceiling]] == -1).all() and (p[ceiling, 1] == ROOM_HEIGHT).all()
    lights = corners[part == -2][:, :, [0, 2]][:, ::-1]  # counter-clockwise from +y
    assert (footprint_distance(p[ceiling][:, [0, 2]], lights) >= 0.1 - 1e-12).all()
    # Spread over the bays: floor and ceiling probes visit every bay.
    bays = ((part == -1) & (normals[:, 1] == 1)).sum()
    assert bays > 1 and len(np.unique(cell[floor])) == len(np.unique(cell[ceiling])) == bays


def test_furnished_room_is_deterministic():
    first, second = arrays(furnished_room(2500, seed=9)), arrays(furnished_room(2500, seed=9))
    for a, b in zip(first, second):
        np.testing.assert_array_equal(a, b)
    other = arrays(furnished_room(2500, seed=10))
    assert other[0].shape != first[0].shape or not np.array_equal(other[0], first[0])
    probes, again = furnished_room_probes(2500, seed=9), furnished_room_probes(2500, seed=9)
    assert probes.keys() == again.keys() == {"points", "normals", "cells", "groups"}
    for key in probes:
        np.testing.assert_array_equal(probes[key], again[key])
    assert not np.array_equal(furnished_room_probes(2500, seed=10)["points"], probes["points"])


def test_furnished_room_needs_no_repair():
    scene = furnished_room(1000, seed=2)
    validator = penumbra.vtkPenumbraSceneValidator()
    validator.SetInputData(scene)
    penumbra.run_filter(validator)
    with warnings.catch_warnings():
        warnings.simplefilter("error", penumbra.PenumbraWarning)
        repaired = penumbra.repair_scene(scene)
    assert repaired.GetNumberOfCells() == scene.GetNumberOfCells()
