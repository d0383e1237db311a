# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraDiscontinuityMesher: output contract, areas, contacts, settings, errors."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy

import penumbra


def mesh(scene_name, **settings):
    source = penumbra.vtkPenumbraSceneSource()
    source.SetSceneName(scene_name)
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    for name, value in settings.items():
        getattr(mesher, "Set" + name)(value)
    return penumbra.run_filter(mesher), penumbra.run_filter(source)


def polygon_area(points):
    normal = np.zeros(3)
    for a, b in zip(points, np.roll(points, -1, axis=0)):
        normal += np.cross(a, b)
    return 0.5 * np.linalg.norm(normal)


def cell_arrays(data):
    return {name: vtk_to_numpy(data.GetCellData().GetArray(name))
            for name in ("SurfaceId", "DiscontinuityOrder", "SourceId")}


@pytest.mark.parametrize("name", ["cornell", "seven", "blind"])
def test_triangles_cover_each_receiver(name):
    out, scene = mesh(name)
    arrays = cell_arrays(out)
    lines = out.GetNumberOfLines()
    assert out.GetNumberOfPolys() > 0 and lines > 0
    assert (arrays["DiscontinuityOrder"][lines:] == -2).all()
    assert set(np.unique(arrays["DiscontinuityOrder"][:lines])) <= {-1, 0, 1, 2}
    points = vtk_to_numpy(out.GetPoints().GetData())
    polys = vtk_to_numpy(out.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    tri = points[polys]
    areas = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    assert areas.min() > 0
    removed = 0.0
    for i in range(scene.GetNumberOfCells()):
        cell = scene.GetCell(i)
        expected = polygon_area(np.array([cell.GetPoints().GetPoint(k)
                                          for k in range(cell.GetNumberOfPoints())]))
        meshed = areas[arrays["SurfaceId"][lines:] == i].sum()
        assert meshed <= expected * (1 + 1e-9)
        removed += expected - meshed
    # Only the Cornell floor loses area: the footprints of the two blocks.
    if name == "cornell":
        short_top = [(130, 65), (82, 225), (240, 272), (290, 114)]
        tall_top = [(423, 247), (265, 296), (314, 456), (472, 406)]
        footprint = sum(polygon_area(np.array([(x / 1000, 0, z / 1000) for x, z in top]))
                        for top in (short_top, tall_top))
        assert removed == pytest.approx(footprint, rel=1e-9)
        assert (arrays["DiscontinuityOrder"][:lines] == 0).sum() >= 8
    else:
        assert removed == pytest.approx(0, abs=1e-12)
    field = out.GetFieldData()
    assert field.GetArray("ConstraintFailures").GetValue(0) == 0
    assert field.GetArray("SegmentsKept").GetValue(0) <= field.GetArray("SegmentsGenerated").GetValue(0)


def test_shadow_lines_name_their_source():
    out, scene = mesh("cornell")
    arrays = cell_arrays(out)
    lines = out.GetNumberOfLines()
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    light = int(np.nonzero(emission.max(axis=1))[0][0])
    orders, sources = arrays["DiscontinuityOrder"][:lines], arrays["SourceId"][:lines]
    # Lines of no source and order 1 on the ceiling are its cover lines: the
    # light, hung 0.5 mm below it, covers it (penumbraCovers.h). They lie
    # inside the light's outline seen from below.
    points = vtk_to_numpy(out.GetPoints().GetData())
    ids = vtk_to_numpy(out.GetLines().GetData()).reshape(-1, 3)[:, 1:]
    on_ceiling = np.all(np.abs(points[ids][:, :, 1] - 0.5488) < 1e-9, axis=1)
    cover = (sources == -1) & (orders == 1) & on_ceiling
    assert cover.sum() >= 8  # the outline and at least one loop
    assert (sources[(orders >= 1) & ~cover] == light).all()
    assert (sources[orders <= 0] == -1).all()
    light_points = vtk_to_numpy(scene.GetPoints().GetData())[
        [scene.GetCell(light).GetPointId(k) for k in range(4)]]
    low, high = light_points.min(axis=0), light_points.max(axis=0)
    ends = points[ids[cover]].reshape(-1, 3)
    assert (ends[:, [0, 2]] >= low[[0, 2]] - 1e-9).all()
    assert (ends[:, [0, 2]] <= high[[0, 2]] + 1e-9).all()


def test_minimum_angle_refines_and_jump_threshold_drops():
    coarse, _ = mesh("seven")
    fine, _ = mesh("seven", MinimumAngle=20.0)
    assert fine.GetNumberOfPolys() > coarse.GetNumberOfPolys()
    thresholded, _ = mesh("seven", JumpThreshold=0.5)
    field = thresholded.GetFieldData()
    assert field.GetArray("SegmentsKept").GetValue(0) < field.GetArray("SegmentsGenerated").GetValue(0)


def test_settings_clamp_and_print():
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetMinimumAngle(45)
    assert mesher.GetMinimumAngle() == 20.6
    mesher.SetJumpThreshold(-1)
    assert mesher.GetJumpThreshold() == 0
    text = str(mesher)
    for setting in ("ShooterIds", "ShooterPowerFraction", "MinimumAngle", "OccluderOccluderEvents",
                    "InteriorEvents", "PlaneEvents", "Contacts", "JumpThreshold", "ContactTolerance",
                    "CullWedges"):
        assert setting + ":" in text


def test_bad_shooter_id_is_an_error():
    source = penumbra.vtkPenumbraSceneSource()
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    mesher.AddShooterId(99)
    with pytest.raises(penumbra.PenumbraError, match="ShooterIds: 99"):
        penumbra.run_filter(mesher)


def boundary_lines(scene, **settings):
    """The mesher's output lines grouped by (SurfaceId, DiscontinuityOrder, SourceId)."""
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputData(scene)
    for name, value in settings.items():
        getattr(mesher, "Set" + name)(value)
    out = penumbra.run_filter(mesher)
    lines = out.GetNumberOfLines()
    ends = vtk_to_numpy(out.GetLines().GetConnectivityArray()).reshape(-1, 2)
    points = vtk_to_numpy(out.GetPoints().GetData())
    arrays = {name: values[:lines] for name, values in cell_arrays(out).items()}
    groups = {}
    for k, key in enumerate(zip(arrays["SurfaceId"], arrays["DiscontinuityOrder"],
                                arrays["SourceId"])):
        groups.setdefault(tuple(int(v) for v in key), []).append(points[ends[k]])
    field = out.GetFieldData()
    counts = {name: int(field.GetArray(name).GetValue(0))
              for name in ("SegmentsGenerated", "Wedges", "Triangles")}
    return {key: np.array(value) for key, value in groups.items()}, counts


@pytest.mark.parametrize("generator,seed,jump", [("box_room", 1, 0.0), ("box_room", 2, 0.0),
                                                 ("furnished_room", 0, 0.0),
                                                 ("furnished_room", 0, 3e-3)])
def test_wedge_culling_keeps_every_boundary(generator, seed, jump):
    # A random room of ~300 polygons, and a furnished bay (books on shelves
    # and in front of a bookcase's back, a keyboard and monitor on a desk:
    # features hidden by screens): the same lines (each surface, order and
    # source; end points within 1e-9 of the room size, either direction)
    # with and without culling, and far fewer wedges traced with it.
    from penumbra import generators

    scene = getattr(generators, generator)(300, seed=seed)
    tol = 1e-9 * max(np.ptp(vtk_to_numpy(scene.GetPoints().GetData()), axis=0))
    culled, culled_counts = boundary_lines(scene, JumpThreshold=jump)
    traced, traced_counts = boundary_lines(scene, JumpThreshold=jump, CullWedges=False)
    assert culled.keys() == traced.keys()
    def distance(lines, other):
        """Largest end point distance of each line to its nearest line of `other`."""
        a, b = lines[:, None, 0], lines[:, None, 1]
        forward = np.maximum(np.linalg.norm(other[None, :, 0] - a, axis=2),
                             np.linalg.norm(other[None, :, 1] - b, axis=2))
        backward = np.maximum(np.linalg.norm(other[None, :, 0] - b, axis=2),
                              np.linalg.norm(other[None, :, 1] - a, axis=2))
        return np.minimum(forward, backward).min(axis=1)

    for key, lines in traced.items():
        other = culled[key]
        assert len(other) == len(lines), key
        # Sorted by midpoint the lists pair up; the few that do not (equal
        # midpoints) are searched among all lines of the group.
        lines = lines[np.argsort(lines.sum(axis=1)[:, 0], kind="stable")]
        other = other[np.argsort(other.sum(axis=1)[:, 0], kind="stable")]
        paired = np.maximum(np.linalg.norm(lines[:, 0] - other[:, 0], axis=1),
                            np.linalg.norm(lines[:, 1] - other[:, 1], axis=1))
        swapped = np.maximum(np.linalg.norm(lines[:, 0] - other[:, 1], axis=1),
                             np.linalg.norm(lines[:, 1] - other[:, 0], axis=1))
        rest = lines[np.minimum(paired, swapped) > tol]
        if len(rest):
            assert distance(rest, other).max() <= tol, key
    assert culled_counts["SegmentsGenerated"] <= traced_counts["SegmentsGenerated"]
    assert culled_counts["Triangles"] == traced_counts["Triangles"]
    assert 2 * culled_counts["Wedges"] < traced_counts["Wedges"]


def test_a_shooter_restricted_to_receivers_meshes_only_them():
    """A shooter added with receivers adds its boundaries there and nowhere
    else: on each surface the lines are those of meshing with that shooter
    everywhere (on its receivers) or without it (elsewhere)."""
    from vtkmodules.vtkCommonCore import vtkIdList
    scene = penumbra.load_scene("cornell")
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    lights = [int(c) for c in np.flatnonzero(emission.max(axis=1) > 0)]
    floor, back = 0, 3  # the Cornell box's floor and back wall (scene order)

    def lines_per_surface(secondary_receivers):
        mesher = penumbra.vtkPenumbraDiscontinuityMesher()
        mesher.SetInputData(scene)
        for light in lights:
            mesher.AddShooterId(light)
        if secondary_receivers is not None:
            ids = vtkIdList()
            for r in secondary_receivers:
                ids.InsertNextId(r)
            mesher.AddShooterId(floor, ids)
        out = penumbra.run_filter(mesher)
        lines = out.GetNumberOfLines()
        surface = vtk_to_numpy(out.GetCellData().GetArray("SurfaceId"))[:lines]
        order = vtk_to_numpy(out.GetCellData().GetArray("DiscontinuityOrder"))[:lines]
        shadows = surface[order >= 1]
        return {int(s): int((shadows == s).sum()) for s in range(scene.GetNumberOfCells())}

    alone = lines_per_surface(None)
    everywhere = lines_per_surface([])  # an empty list: every receiver
    restricted = lines_per_surface([back])
    assert everywhere[back] > alone[back], "the floor casts no boundaries on the back wall"
    assert restricted[back] == everywhere[back]
    for surface in alone:
        if surface != back:
            assert restricted[surface] == alone[surface], surface
    assert sum(everywhere.values()) > sum(restricted.values())


def test_shooter_receivers_out_of_range_is_an_error():
    from vtkmodules.vtkCommonCore import vtkIdList
    source = penumbra.vtkPenumbraSceneSource()
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    ids = vtkIdList()
    ids.InsertNextId(1000)
    mesher.AddShooterId(0, ids)
    with pytest.raises(penumbra.PenumbraError, match="receiver id 1000"):
        penumbra.run_filter(mesher)


@pytest.mark.parametrize("height, covers", [(0.005, True), (0.05, True), (0.3, False)])
def test_covers_mesh_the_receiver_under_a_plate(height, covers):
    """A 1 x 0.5 plate `height` above a 4 x 4 floor covers it when the gap is
    at most a tenth of the plate's width (penumbraCovers.h; not at 0.3): the floor's mesh
    then has the plate's outline and loops inset by the gap, 4 times the gap,
    ... (order 1, no source), all inside the outline."""
    from penumbra.generators import scene_from_polygons
    floor = [(0, 0, 0), (0, 0, 4), (4, 0, 4), (4, 0, 0)]
    plate = [(1.5, height, 1.75), (2.5, height, 1.75), (2.5, height, 2.25), (1.5, height, 2.25)]
    light = [(1.8, 2.0, 1.8), (2.2, 2.0, 1.8), (2.2, 2.0, 2.2), (1.8, 2.0, 2.2)]
    scene = scene_from_polygons([
        {"vertices": floor, "reflectance": (0.5,) * 3, "emission": (0,) * 3},
        {"vertices": plate, "reflectance": (0.5,) * 3, "emission": (0,) * 3},
        {"vertices": light, "reflectance": (0,) * 3, "emission": (1,) * 3}])
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputData(scene)
    out = penumbra.run_filter(mesher)
    arrays = cell_arrays(out)
    lines = out.GetNumberOfLines()
    ids = vtk_to_numpy(out.GetLines().GetData()).reshape(-1, 3)[:, 1:]
    points = vtk_to_numpy(out.GetPoints().GetData())
    surface = arrays["SurfaceId"][:lines]
    ends = points[ids].reshape(-1, 2, 3)
    inside = np.all((ends[:, :, 0] >= 1.5 - 1e-12) & (ends[:, :, 0] <= 2.5 + 1e-12) &
                    (ends[:, :, 2] >= 1.75 - 1e-12) & (ends[:, :, 2] <= 2.25 + 1e-12), axis=1)
    cover = (surface == 0) & (arrays["SourceId"][:lines] == -1) & \
        (arrays["DiscontinuityOrder"][:lines] == 1) & inside
    # (The plate's underside, facing the floor, is covered by the floor as
    # well: those lines are on surface 1.)
    count = out.GetFieldData().GetArray("CoverSegments").GetValue(0)
    if not covers:
        assert not cover.any()
        return
    ends = ends[cover].reshape(-1, 3)
    assert np.allclose(ends[:, 1], 0.0)
    # Loops at the distances d = gap * 4^k from the outline while d < 0.25.
    distance = np.minimum(np.minimum(ends[:, 0] - 1.5, 2.5 - ends[:, 0]),
                          np.minimum(ends[:, 2] - 1.75, 2.25 - ends[:, 2]))
    loops = [0.0] + [height * 4 ** k for k in range(12) if height * 4 ** k < 0.25]
    assert np.allclose(sorted(set(np.round(distance, 9))), loops)
    assert cover.sum() >= 4 * len(loops) and count >= 4 * len(loops)


def box_faces(lo, hi):
    """The six faces of an axis-aligned box, counter-clockwise seen from outside."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return [[(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],
            [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],
            [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
            [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],
            [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],
            [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]]


def facing_down(cx, height, cz, half):
    return [(cx - half, height, cz - half), (cx + half, height, cz - half),
            (cx + half, height, cz + half), (cx - half, height, cz + half)]


def test_jump_threshold_judges_shadows_by_the_light_received():
    # A floor under a strong light A hidden by a black baffle, lit by a weak
    # light B below the baffle. B's shadows are the floor's whole light: a
    # box's must stay at JumpThreshold 0.05 (judged against A's unoccluded
    # light they would look faint), while a 2 cm cube high up hides at most
    # (radius / distance)^2 ~ 2e-4 of the sky against B's ~0.013: its lines go.
    from penumbra.generators import scene_from_polygons

    grey, black = (0.5, 0.5, 0.5), (0.0, 0.0, 0.0)
    polygons = [{"vertices": [(-2, 0, -2), (-2, 0, 2), (2, 0, 2), (2, 0, -2)],
                 "reflectance": grey, "emission": black},
                {"vertices": facing_down(0, 2.0, 0, 3.0), "reflectance": black, "emission": black},
                {"vertices": facing_down(0, 2.5, 0, 0.25), "reflectance": black,
                 "emission": (100.0, 100.0, 100.0)},
                {"vertices": facing_down(0, 1.5, 0, 0.15), "reflectance": black,
                 "emission": (1.0, 1.0, 1.0)}]
    light_b = 3
    for face in box_faces((-0.6, 0.4, -0.2), (-0.2, 0.8, 0.2)) + \
            box_faces((0.4, 1.0, 0.0), (0.42, 1.02, 0.02)):
        polygons.append({"vertices": face, "reflectance": grey, "emission": black})
    scene = scene_from_polygons(polygons)

    def floor_lines(threshold):
        lines, _ = boundary_lines(scene, JumpThreshold=threshold)
        found = [v for (surface, order, source), v in lines.items()
                 if surface == 0 and order > 0 and source == light_b]
        mids = np.concatenate(found).mean(axis=1) if found else np.zeros((0, 3))
        return (mids[:, 0] < 0).sum(), (mids[:, 0] > 0.5).sum()

    box_all, cube_all = floor_lines(0.0)
    assert box_all > 0 and cube_all > 0
    box_kept, cube_kept = floor_lines(0.05)
    assert box_kept == box_all
    assert cube_kept == 0
