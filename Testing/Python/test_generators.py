# SPDX-License-Identifier: GPL-3.0-or-later
"""penumbra.generators.box_room: valid scenes of the requested size, deterministic,
surfaces facing the right way, boxes that do not overlap, lights that emit."""
import os

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import penumbra
from penumbra.generators import LIGHT_EMISSION, ROOM_CELLS, ROOM_HEIGHT, box_room

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
