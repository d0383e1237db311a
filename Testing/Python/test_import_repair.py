# SPDX-License-Identifier: GPL-3.0-or-later
"""Messy imports: each flaw a modeller's export has, written into an OBJ beside
its hand-cleaned twin. The messy file solves with the expected warnings and
matches the twin's radiance within 0.5% RMS at independent points; strict
mode rejects the flaws that need repair with the validator's messages; scenes
that will come out black are warned about."""
import os
import warnings

import numpy as np
import pytest

import penumbra
from penumbra import PenumbraError, PenumbraWarning

MATERIALS = {"floor": ((0.4, 0.4, 0.4), None), "wall": ((0.6, 0.5, 0.4), None),
             "box": ((0.7, 0.7, 0.7), None), "lamp": ((0.0, 0.0, 0.0), (10.0, 10.0, 10.0))}


def quad(centre, u, v):
    """A rectangle counter-clockwise about u x v (its front)."""
    c, u, v = (np.asarray(x, dtype=float) for x in (centre, u, v))
    return [c - u - v, c + u - v, c + u + v, c - u + v]


def clean_faces():
    """(material, vertices) of an open room: floor, two walls, a box standing
    on the floor (a contact) and a lamp facing down beside it (a shadow)."""
    return [
        ("floor", quad((2, 0, 2), (0, 0, 2), (2, 0, 0))),
        ("wall", quad((0, 1.5, 2), (0, 1.5, 0), (0, 0, 2))),
        ("wall", quad((2, 1.5, 0), (2, 0, 0), (0, 1.5, 0))),
        ("box", quad((1.5, 1, 1.5), (0, 0, .5), (.5, 0, 0))),
        ("box", quad((1, .5, 1.5), (0, 0, .5), (0, .5, 0))),
        ("box", quad((2, .5, 1.5), (0, .5, 0), (0, 0, .5))),
        ("box", quad((1.5, .5, 1), (0, .5, 0), (.5, 0, 0))),
        ("box", quad((1.5, .5, 2), (.5, 0, 0), (0, .5, 0))),
        ("lamp", quad((2.7, 2.5, 2.7), (.5, 0, 0), (0, 0, .5))),
    ]


def write_obj(folder, name, faces, materials=MATERIALS, mtl=True, usemtl=None):
    """Write faces as OBJ (+ MTL): every face its own vertices, as many
    exporters do (the reader does not need shared indices)."""
    path = os.path.join(folder, name + ".obj")
    with open(path, "w") as obj:
        if mtl:
            obj.write("mtllib %s.mtl\n" % name)
        count = 0
        for material, vertices in faces:
            obj.write("usemtl %s\n" % (usemtl or {}).get(material, material))
            for p in vertices:
                obj.write("v %.17g %.17g %.17g\n" % tuple(p))
            obj.write("f %s\n" % " ".join(str(count + k + 1) for k in range(len(vertices))))
            count += len(vertices)
    if mtl:
        with open(os.path.join(folder, name + ".mtl"), "w") as lib:
            for material, (kd, ke) in materials.items():
                lib.write("newmtl %s\nKd %g %g %g\n" % ((material,) + tuple(kd)))
                if ke:
                    lib.write("Ke %g %g %g\n" % tuple(ke))
    return path


def load(path, strict=False):
    """The scene and the PenumbraWarnings it gave, as strings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = penumbra.load_scene(path, strict=strict)
    return scene, [str(w.message) for w in caught if issubclass(w.category, PenumbraWarning)]


# Independent points: a grid on the floor (outside the box's footprint, where
# the floor is hidden) and on the wall x = 0, away from the edges.
FLOOR_POINTS = [(x, 0.0, z) for x in np.linspace(0.15, 3.85, 12) for z in np.linspace(0.15, 3.85, 12)
                if not (0.95 < x < 2.05 and 0.95 < z < 2.05)]
WALL_POINTS = [(0.0, y, z) for y in np.linspace(0.15, 2.85, 8) for z in np.linspace(0.15, 3.85, 8)]


def radiance_at(result, points, normal):
    """The displayed radiance (linear over the output triangles) at `points`,
    on the triangles facing `normal`."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import mutable
    from vtkmodules.vtkCommonDataModel import vtkStaticCellLocator

    locator = vtkStaticCellLocator()
    locator.SetDataSet(result)
    locator.BuildLocator()
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
    values = []
    for p in points:
        # Probe from just in front of the surface, so the closest cell is on it.
        query = np.asarray(p) + 1e-4 * np.asarray(normal)
        closest, cell_id, sub, dist2 = [0.0] * 3, mutable(0), mutable(0), mutable(0.0)
        locator.FindClosestPoint(list(query), closest, cell_id, sub, dist2)
        cell = result.GetCell(int(cell_id))
        weights, pcoords, x, sub_id, d = [0.0] * 3, [0.0] * 3, [0.0] * 3, mutable(0), mutable(0.0)
        cell.EvaluatePosition(list(p), x, sub_id, pcoords, d, weights)
        ids = [cell.GetPointId(k) for k in range(3)]
        values.append(sum(w * radiance[i] for w, i in zip(weights, ids)))
    return np.array(values)


def relative_rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.mean(np.abs(b)))


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The hand-cleaned scene's radiance at the independent points."""
    folder = str(tmp_path_factory.mktemp("clean"))
    scene, found = load(write_obj(folder, "clean", clean_faces()))
    assert found == [], "a clean scene gives no warning"
    result = penumbra.solve(scene, threads=2)
    return (radiance_at(result, FLOOR_POINTS, (0, 1, 0)),
            radiance_at(result, WALL_POINTS, (1, 0, 0)))


def bent(faces):
    """The wall x = 0 with one corner 1.7 mm out of its plane."""
    faces = [(m, [p.copy() for p in v]) for m, v in faces]
    faces[1][1][2][0] += 0.0017
    return faces


def duplicated(faces):
    """Every corner written once per face (as many exporters do), the copies
    after the first off by up to 1e-7 (single-precision rounding), a repeated
    vertex and a repeated face."""
    faces = [(m, [p.copy() for p in v]) for m, v in faces]
    rng = np.random.default_rng(3)
    seen = set()
    for _, vertices in faces:
        for p in vertices:
            key = tuple(np.round(p, 9))
            if key in seen:
                p += rng.uniform(-1e-7, 1e-7, 3)
            seen.add(key)
    faces[3] = (faces[3][0], faces[3][1][:2] + [faces[3][1][1].copy()] + faces[3][1][2:])
    faces.append(faces[5])
    return faces


def single_precision(faces):
    """Every coordinate rounded to single precision, as many exporters write
    them, plus noise of that size: corners 1e-7 off their planes and off each
    other, the box's base 1e-7 above or below the floor."""
    faces = [(m, [np.float32(p).astype(float) for p in v]) for m, v in faces]
    rng = np.random.default_rng(5)
    for _, vertices in faces:
        for p in vertices:
            p += rng.uniform(-1e-7, 1e-7, 3)
    return faces


def slivers(faces):
    """Zero-area faces: a collinear triangle, a sliver far below the degeneracy
    tolerance, a face whose corners all coincide."""
    faces = list(faces)
    faces.append(("wall", [np.array([1.0, 0.0, 4.0]), np.array([2.0, 0.0, 4.0]),
                           np.array([3.0, 0.0, 4.0])]))
    faces.append(("box", [np.array([3.0, 0.0, 3.0]), np.array([3.5, 0.0, 3.0]),
                          np.array([3.25, 1e-14, 3.0])]))
    faces.append(("floor", [np.array([1.0, 1.0, 1.0])] * 3))
    return faces


def topology(faces):
    """A concave floor (an L and the square that completes it) and a wall split
    in two, its middle vertex on the floor's edge (a T-junction)."""
    faces = list(faces)
    ell = [np.array(p, dtype=float) for p in
           [(0, 0, 0), (0, 0, 4), (4, 0, 4), (4, 0, 2), (2, 0, 2), (2, 0, 0)]]
    square = [np.array(p, dtype=float) for p in [(2, 0, 0), (2, 0, 2), (4, 0, 2), (4, 0, 0)]]
    wall_a = quad((0, 1.5, 1), (0, 1.5, 0), (0, 0, 1))
    wall_b = quad((0, 1.5, 3), (0, 1.5, 0), (0, 0, 1))
    return [("floor", ell), ("floor", square), ("wall", wall_a), ("wall", wall_b)] + faces[2:]


CASES = {
    # name: (messy faces, warnings expected (fragments), strict error or None)
    "non-planar": (bent, ["1 non-planar polygon triangulated into 2 triangles"],
                   "non-planar polygon"),
    "duplicates": (duplicated, ["vertices welded onto a neighbour",
                                "1 polygon with repeated consecutive vertices cleaned",
                                "1 duplicate polygon dropped"],
                   "degenerate polygon: vertices 1 and 2 coincide"),
    "slivers": (slivers, ["3 zero-area polygons dropped",
                          # the sliver's apex, 1e-14 off the floor's plane
                          "1 vertex snapped onto the axis-aligned plane"], "degenerate polygon"),
    "single precision": (single_precision, ["vertices welded onto a neighbour",
                                            "snapped onto the axis-aligned plane"], None),
    "concave and T-junctions": (topology, [], None),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_messy_scene_repairs_and_matches_its_clean_twin(case, tmp_path, reference):
    make, expected, strict_error = CASES[case]
    path = write_obj(str(tmp_path), "messy", make(clean_faces()))
    scene, found = load(path)
    for fragment in expected:
        assert sum(fragment in w for w in found) == 1, (fragment, found)
    assert len(found) == len(expected), found
    assert all(w.startswith(path) for w in found), "each warning names the file"
    result = penumbra.solve(scene, threads=2)
    floor = radiance_at(result, FLOOR_POINTS, (0, 1, 0))
    wall = radiance_at(result, WALL_POINTS, (1, 0, 0))
    assert relative_rms(floor, reference[0]) <= 0.005
    assert relative_rms(wall, reference[1]) <= 0.005
    if strict_error is None:
        load(path, strict=True)  # valid input: strict mode takes it as it is
    else:
        with pytest.raises(PenumbraError, match=strict_error):
            load(path, strict=True)


def test_material_names_and_a_missing_library(tmp_path, reference):
    # Names that differ in case from the library's, as exporters write them.
    path = write_obj(str(tmp_path), "cased", clean_faces(),
                     usemtl={"wall": "Wall", "floor": "FLOOR "})
    scene, found = load(path)
    assert len(found) == 2 and all("differs only in case or spacing" in w for w in found), found
    result = penumbra.solve(scene, threads=2)
    assert relative_rms(radiance_at(result, FLOOR_POINTS, (0, 1, 0)), reference[0]) <= 1e-9
    with pytest.raises(PenumbraError, match="cased.obj:2: unknown material 'FLOOR'"):
        load(path, strict=True)
    # An OBJ whose MTL is missing: default grey, no emitter, said so.
    path = write_obj(str(tmp_path), "bare", clean_faces())
    os.remove(os.path.join(str(tmp_path), "bare.mtl"))
    scene, found = load(path)
    assert any("cannot open material library 'bare.mtl'" in w for w in found)
    assert any("no surface emits light" in w for w in found)
    with pytest.raises(PenumbraError, match="cannot open material library 'bare.mtl'"):
        load(path, strict=True)


def test_scenes_that_come_out_black_are_warned_about(tmp_path):
    faces = clean_faces()
    # The lamp above the walls, turned to face up at the open sky.
    up = faces[:-1] + [("lamp", quad((2.7, 3.2, 2.7), (0, 0, .5), (.5, 0, 0)))]
    _, found = load(write_obj(str(tmp_path), "up", up))
    assert len(found) == 1 and "every emitter faces away from every surface (cells 8)" \
        in found[0], found
    # A lamp inside the box, facing its lid: all its light falls on the lid's back.
    inside = faces[:-1] + [("lamp", quad((1.5, 0.5, 1.5), (0, 0, .2), (.2, 0, 0)))]
    _, found = load(write_obj(str(tmp_path), "inside", inside))
    assert len(found) == 1 and "of their light onto the backs of surfaces" in found[0], found
    assert "(cells 8)" in found[0] and "100%" in found[0]
    # With a second lamp in the room, the enclosed one is still named.
    both = inside + [faces[-1]]
    _, found = load(write_obj(str(tmp_path), "both", both))
    assert len(found) == 1 and "1 of 2 emitters (cells 8)" in found[0], found


def test_builtin_scenes_pass_unchanged():
    from vtkmodules.util.numpy_support import vtk_to_numpy

    for name, _ in penumbra.scenes():
        source = penumbra.vtkPenumbraSceneSource()
        source.SetSceneName(name)
        source.Update()
        scene, found = load(name)
        assert found == [], (name, found)
        assert scene.GetNumberOfCells() == source.GetOutput().GetNumberOfCells()
        assert np.array_equal(vtk_to_numpy(scene.GetPoints().GetData()),
                              vtk_to_numpy(source.GetOutput().GetPoints().GetData()))
        assert scene.GetCellData().GetArray("InputCellId") is None


def test_unusable_input_stays_an_error_naming_the_input_cell(tmp_path):
    faces = clean_faces()
    # Reflectance 1 on a face that follows a dropped one: the cell named is the file's.
    faces.insert(1, ("floor", [np.array([1.0, 1.0, 1.0])] * 3))
    materials = dict(MATERIALS)
    materials["wall"] = ((1.0, 0.5, 0.4), None)
    path = write_obj(str(tmp_path), "white", faces, materials=materials)
    with pytest.raises(PenumbraError, match=r"cell 2: Reflectance red is 1, outside \[0, 1\)"):
        load(path)
    path = write_obj(str(tmp_path), "empty", [("floor", [np.array([1.0, 1.0, 1.0])] * 3)])
    with pytest.raises(PenumbraError, match="no polygons left"):
        load(path)


def test_contacts_at_any_orientation_are_made_exact(tmp_path):
    # The room turned off the axes, its floor's corners then moved by up to
    # 1e-7: the box's base, exact before, now rests 1e-7 off the floor's plane.
    # It is moved onto it (no axis plane to snap to) and matches the twin.
    turn = np.array([[np.cos(0.3), 0, np.sin(0.3)], [0, 1, 0], [-np.sin(0.3), 0, np.cos(0.3)]]) @ \
        np.array([[1, 0, 0], [0, np.cos(0.2), -np.sin(0.2)], [0, np.sin(0.2), np.cos(0.2)]])
    clean = [(m, [turn @ p for p in v]) for m, v in clean_faces()]
    noisy = [(m, [p.copy() for p in v]) for m, v in clean]
    rng = np.random.default_rng(3)
    for p in noisy[0][1]:
        p += rng.uniform(-1e-7, 1e-7, 3)
    points = [turn @ np.array(p) for p in FLOOR_POINTS]
    normal = turn @ np.array([0.0, 1.0, 0.0])
    twin, found = load(write_obj(str(tmp_path), "turned", clean))
    assert found == []
    scene, found = load(write_obj(str(tmp_path), "noisy", noisy))
    assert any("4 vertices resting on a polygon snapped onto its plane" in w for w in found), found
    reference = radiance_at(penumbra.solve(twin, threads=2), points, normal)
    assert relative_rms(radiance_at(penumbra.solve(scene, threads=2), points, normal),
                        reference) <= 0.005
