# SPDX-License-Identifier: GPL-3.0-or-later
"""Generated test scenes of any size, for benchmarks and stress tests.

`box_room(polygons)` builds a closed room full of box furniture with a few
area lights under the ceiling, as a scene vtkPolyData that follows the data
contract of design.md §2 (one planar polygon per surface, counter-clockwise
seen from its front, cell arrays `Reflectance` and `Emission`)::

    import penumbra.generators
    scene = penumbra.generators.box_room(1000, seed=3)
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputData(scene)
    penumbra.run_filter(mesher)

Everything is vectorised with numpy: 20,000 polygons take a fraction of a
second.
"""
import numpy as np

__all__ = ["box_room", "black_room", "closed_cube", "closed_cube_radiance", "half_lit_panel",
           "scene_from_polygons", "ROOM_CELLS", "ROOM_HEIGHT", "LIGHT_EMISSION"]

#: Number of room surfaces (floor, ceiling, 4 walls): cells 0-5 of a box room.
ROOM_CELLS = 6
#: Height of the room (metres); the floor is at y = 0, y is up.
ROOM_HEIGHT = 3.0
#: Emitted radiance (W sr^-1 m^-2, RGB) of every light.
LIGHT_EMISSION = (20.0, 18.0, 15.0)

_CELL = 1.2            # side of the square floor cell that holds one box
_GAP = 0.02            # smallest clearance between a box and its cell's border
_WALL_MARGIN = 0.4     # free floor between the box grid and the walls
_FILL = 0.6            # fraction of floor cells that hold a box
_STACKED = 0.2         # fraction of boxes standing on another box
_LIGHT_SIZE = 0.6      # side of a square light (metres)
_LIGHT_DROP = 0.005    # lights hang this far below the ceiling
_ROOM_REFLECTANCE = (0.7, 0.7, 0.7)
_LIGHT_REFLECTANCE = (0.78, 0.78, 0.78)

# A box's 8 corners: 0-3 bottom, 4-7 top, each ring counter-clockwise seen
# from above (+y). The 5 faces (no bottom) listed counter-clockwise seen
# from outside: the top, then the side over bottom edge (i, i+1).
_BOX_FACES = np.array([[4, 5, 6, 7],
                       [0, 1, 5, 4],
                       [1, 2, 6, 5],
                       [2, 3, 7, 6],
                       [3, 0, 4, 7]])
_BOX_FACES_CLOSED = np.vstack([_BOX_FACES, [[0, 3, 2, 1]]])  # with the bottom
# Footprint corner offsets in units of the half extents (x, z); this order is
# counter-clockwise seen from +y (right-hand normal +y with y up).
_FOOTPRINT = np.array([[-1.0, -1.0], [-1.0, 1.0], [1.0, 1.0], [1.0, -1.0]])


def _default_lights(polygons):
    return 1 if polygons < 200 else 4


def _box_corners(center_x, center_z, half_w, half_d, angle, bottom, top):
    """(n, 8, 3) corners of n boxes rotated by `angle` about the vertical."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    lx = _FOOTPRINT[None, :, 0] * half_w[:, None]
    lz = _FOOTPRINT[None, :, 1] * half_d[:, None]
    x = center_x[:, None] + c * lx - s * lz
    z = center_z[:, None] + s * lx + c * lz
    corners = np.empty((len(center_x), 8, 3))
    corners[:, :4, 0] = corners[:, 4:, 0] = x
    corners[:, :4, 2] = corners[:, 4:, 2] = z
    corners[:, :4, 1] = bottom[:, None]
    corners[:, 4:, 1] = top[:, None]
    return corners


def _polydata(points, quads, reflectance, emission, part):
    """A vtkPolyData of quads from numpy arrays (no Python loop per cell)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    offsets = np.arange(0, 4 * len(quads) + 1, 4, dtype=np.int64)
    polys = vtkCellArray()
    polys.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(quads, dtype=np.int64).ravel(),
                                          deep=True))
    data = vtkPolyData()
    data.SetPoints(vtk_points)
    data.SetPolys(polys)
    for name, values in (("Reflectance", reflectance), ("Emission", emission)):
        array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
        array.SetName(name)
        data.GetCellData().AddArray(array)
    array = numpy_to_vtk(np.ascontiguousarray(part, dtype=np.int32), deep=True)
    array.SetName("PartId")
    data.GetCellData().AddArray(array)
    return data


def scene_from_polygons(polygons):
    """A scene vtkPolyData from a list of polygons, each a dict with "vertices" (a
    list of (x, y, z), counter-clockwise seen from the front), "reflectance" and
    "emission" (RGB triples)."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    data = vtkPolyData()
    points = vtkPoints()
    points.SetDataTypeToDouble()
    cells = vtkCellArray()
    arrays = {}
    for name in ("Reflectance", "Emission"):
        arrays[name] = vtkDoubleArray()
        arrays[name].SetName(name)
        arrays[name].SetNumberOfComponents(3)
    for p in polygons:
        cells.InsertNextCell(len(p["vertices"]))
        for vertex in p["vertices"]:
            cells.InsertCellPoint(points.InsertNextPoint(*vertex))
        arrays["Reflectance"].InsertNextTuple3(*p["reflectance"])
        arrays["Emission"].InsertNextTuple3(*p["emission"])
    data.SetPoints(points)
    data.SetPolys(cells)
    for array in arrays.values():
        data.GetCellData().AddArray(array)
    return data


def box_room(polygons, seed=0, lights=None):
    """A closed room full of boxes with `polygons` surfaces (approximately).

    Parameters
    ----------
    polygons : int
        The number of polygons wanted. The scene has exactly
        ``6 + lights + 5 * boxes`` polygons with ``boxes`` chosen so that this
        is the closest to `polygons`: it is within 2 of the request whenever
        ``polygons >= 6 + lights`` (smaller requests give the empty room with
        its lights).
    seed : int
        Seed of ``numpy.random.default_rng``; the same (polygons, seed,
        lights) always gives the same scene, point for point.
    lights : int or None
        The number of square area lights (0.6 m side), on a regular grid
        5 mm below the ceiling and facing down. None (default): 1 light for
        fewer than 200 polygons, else 4.

    Returns
    -------
    vtkPolyData
        Units are metres, y is up, the floor is at y = 0 and the ceiling at
        y = ROOM_HEIGHT. Every cell is a planar quad, counter-clockwise seen
        from its front (the emitting and reflecting side). Cell order:

        - cells 0-5: floor, ceiling and the 4 walls of the room, facing
          inward;
        - the next `lights` cells: the lights, Emission = LIGHT_EMISSION;
        - 5 cells per box (top, then 4 sides), all facing out of the box;
          boxes have no bottom. Boxes stand on the floor, or, for about a
          fifth of them, on the top of another box (its footprint inside the
          lower top, so the top is a contact receiver), never reaching the
          lights.

        Cell data: `Reflectance` (RGB in [0.15, 0.85] for boxes, 0.7 for the
        room, 0.78 for lights), `Emission` (RGB; non-zero on lights only) and
        `PartId` (int: -1 room, -2 light, else the box index).

    Layout: the floor is divided into 1.2 m cells and about 60 % of them,
    chosen at random, hold one box each: a random footprint (0.25-0.75 m per
    side), rotation about the vertical and position whose circumscribed
    circle stays inside the cell, so footprints never overlap or touch each
    other or the walls. The room grows (about sqrt(boxes) cells a side) with
    the number of boxes; its height stays ROOM_HEIGHT.
    """
    polygons = int(polygons)
    nlights = _default_lights(polygons) if lights is None else int(lights)
    if nlights < 0:
        raise ValueError("lights must be >= 0, got %d" % nlights)
    nboxes = max(0, int(np.floor((polygons - ROOM_CELLS - nlights) / 5.0 + 0.5)))
    rng = np.random.default_rng(seed)

    nstacked = int(round(_STACKED * nboxes)) if nboxes >= 2 else 0
    nground = nboxes - nstacked
    # Floor grid: about 1.5 : 1, at least 2 x 2 cells, enough free cells.
    ncells = max(4, int(np.ceil(nground / _FILL)))
    gx = max(2, int(np.ceil(np.sqrt(1.5 * ncells))))
    gz = max(2, int(np.ceil(ncells / gx)))
    width = gx * _CELL + 2 * _WALL_MARGIN
    depth = gz * _CELL + 2 * _WALL_MARGIN
    height = ROOM_HEIGHT

    # Ground boxes: one per chosen cell, never overlapping.
    cell = rng.choice(gx * gz, size=nground, replace=False)
    half_w = rng.uniform(0.125, 0.375, nground)
    half_d = rng.uniform(0.125, 0.375, nground)
    radius = np.hypot(half_w, half_d)
    slack = _CELL / 2 - _GAP - radius  # > 0: radius <= 0.53 < 0.58
    cx = _WALL_MARGIN + (cell % gx + 0.5) * _CELL + rng.uniform(-1, 1, nground) * slack
    cz = _WALL_MARGIN + (cell // gx + 0.5) * _CELL + rng.uniform(-1, 1, nground) * slack
    angle = rng.uniform(0, 0.5 * np.pi, nground)
    top = rng.uniform(0.3, 1.2, nground)
    ground = _box_corners(cx, cz, half_w, half_d, angle, np.zeros(nground), top)

    # Stacked boxes: on distinct ground boxes, circumscribed circle inside the
    # circle inscribed in the lower top, so any rotation fits.
    base = rng.choice(nground, size=nstacked, replace=False) if nstacked else np.zeros(0, int)
    room_for = np.minimum(half_w, half_d)[base] - _GAP  # inscribed radius, minus a gap
    scale = rng.uniform(0.4, 0.7, (2, nstacked))
    s_half_w = room_for * scale[0]
    s_half_d = room_for * scale[1]
    s_slack = room_for - np.hypot(s_half_w, s_half_d)
    jitter_r = s_slack * np.sqrt(rng.uniform(0, 1, nstacked))
    jitter_a = rng.uniform(0, 2 * np.pi, nstacked)
    stacked = _box_corners(cx[base] + jitter_r * np.cos(jitter_a),
                           cz[base] + jitter_r * np.sin(jitter_a),
                           s_half_w, s_half_d, rng.uniform(0, 0.5 * np.pi, nstacked),
                           top[base], top[base] + rng.uniform(0.2, 0.6, nstacked))
    # Interleave nothing: ground boxes first, then stacked ones.
    boxes = np.concatenate([ground, stacked]).reshape(-1, 3)

    # Room: the faces of the box [0, w] x [0, h] x [0, d] reversed (inward).
    room_corners = _box_corners(np.array([width / 2]), np.array([depth / 2]),
                                np.array([width / 2]), np.array([depth / 2]), np.zeros(1),
                                np.zeros(1), np.array([height]))[0]
    bottom_up = _BOX_FACES_CLOSED[5][::-1]  # the floor seen from above
    room_quads = np.vstack([bottom_up, _BOX_FACES_CLOSED[0][::-1], _BOX_FACES[1:, ::-1]])

    # Lights: a near-square grid of squares facing down (-y).
    lx = int(np.ceil(np.sqrt(nlights))) if nlights else 0
    lz = int(np.ceil(nlights / lx)) if nlights else 0
    index = np.arange(nlights)
    lcx = (index % lx + 0.5) / max(lx, 1) * width
    lcz = (index // lx + 0.5) / max(lz, 1) * depth
    y = height - _LIGHT_DROP
    light_corners = _box_corners(lcx, lcz, np.full(nlights, _LIGHT_SIZE / 2),
                                 np.full(nlights, _LIGHT_SIZE / 2), np.zeros(nlights),
                                 np.full(nlights, y), np.full(nlights, y))[:, :4]
    light_quads = (np.arange(nlights)[:, None] * 4 + np.array([3, 2, 1, 0]))  # reversed: down

    # Assemble: room points, light points, box points.
    points = np.concatenate([room_corners, light_corners.reshape(-1, 3), boxes])
    light_base = 8
    box_base = light_base + 4 * nlights
    box_quads = (box_base + 8 * np.arange(nboxes)[:, None, None] + _BOX_FACES[None]).reshape(-1, 4)
    quads = np.concatenate([room_quads, light_base + light_quads.reshape(-1, 4),
                            box_quads]).astype(np.int64)

    ncells_total = ROOM_CELLS + nlights + 5 * nboxes
    reflectance = np.empty((ncells_total, 3))
    reflectance[:ROOM_CELLS] = _ROOM_REFLECTANCE
    reflectance[ROOM_CELLS:ROOM_CELLS + nlights] = _LIGHT_REFLECTANCE
    box_colour = rng.uniform(0.15, 0.85, (nboxes, 3))
    reflectance[ROOM_CELLS + nlights:] = np.repeat(box_colour, 5, axis=0)
    emission = np.zeros((ncells_total, 3))
    emission[ROOM_CELLS:ROOM_CELLS + nlights] = LIGHT_EMISSION
    part = np.concatenate([np.full(ROOM_CELLS, -1), np.full(nlights, -2),
                           np.repeat(np.arange(nboxes), 5)])
    return _polydata(points, quads, reflectance, emission, part)


def closed_cube(reflectance, side=4.0, emitter_side=0.02, emission=1000.0):
    """CIE 171:2006 test case 5.8: a closed cube of side `side` (metres) whose six
    inner faces and a small emitter all have the grey `reflectance`. The emitter is a
    cube of side `emitter_side` at the centre, each face emitting `emission`
    (W sr^-1 m^-2) outward, so that it lights the six faces alike.

    Every photon stays inside, so flux balance gives the mean reflected radiance of
    every face exactly when the field is uniform: rho * Phi / (pi * S_T * (1 - rho)),
    with Phi = pi * emission * (emitter area) and S_T the area of all surfaces
    (`closed_cube_radiance`). The emitter is small enough (area 2.5e-5 of S_T by
    default) that the non-uniformity it causes is far below 1e-4 of that value.
    Cells 0-5 are the cube's faces (floor, ceiling, then the walls), 6-11 the
    emitter's."""
    h, e = side / 2.0, emitter_side / 2.0
    rho = (reflectance,) * 3

    def box(half, inward, emitted):
        c = np.array([[-1, -1, -1], [1, -1, -1], [1, -1, 1], [-1, -1, 1],
                      [-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1]], dtype=float) * half
        c[:, 1] += h  # the floor at y = 0
        # Faces counter-clockwise seen from outside: bottom, top, -z, +x, +z, -x.
        faces = [[0, 1, 2, 3], [4, 7, 6, 5], [0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3],
                 [3, 7, 4, 0]]
        return [{"vertices": [tuple(c[i]) for i in (f[::-1] if inward else f)],
                 "reflectance": rho, "emission": (emitted,) * 3} for f in faces]

    return scene_from_polygons(box(h, True, 0.0) + box(e, False, emission))


def closed_cube_radiance(reflectance, side=4.0, emitter_side=0.02, emission=1000.0):
    """The flux-balance value of `closed_cube`: the mean reflected radiance of each
    face, rho * Phi / (pi * S_T * (1 - rho))."""
    emitted = np.pi * emission * 6.0 * emitter_side ** 2
    total_area = 6.0 * (side ** 2 + emitter_side ** 2)
    return reflectance * emitted / (np.pi * total_area * (1.0 - reflectance))


def half_lit_panel():
    """A floor lit only through a half-lit panel (metres, y up): a light
    (0.4 m square at x = 1, facing -x, L^e = 50) above a black baffle
    (y = 1.5, x in [0, 1]) shines on the upper half of a white panel (x = 0,
    y in [0.5, 2.5], z in [1, 3], reflectance 0.9). The baffle touches the
    panel, hides the light from the grey floor (4 x 4 m, reflectance 0.5)
    and casts the panel's light into a shadow on it: every watt on the
    floor comes from the panel, through the baffle's secondary shadow.
    Cells: 0 floor, 1 panel, 2 light, 3 baffle."""
    black, grey, white = (0.0, 0.0, 0.0), (0.5, 0.5, 0.5), (0.9, 0.9, 0.9)

    def quad(corners, reflectance, emission=(0.0, 0.0, 0.0)):
        return {"vertices": corners, "reflectance": reflectance, "emission": emission}

    return scene_from_polygons([
        quad([(0, 0, 0), (0, 0, 4), (4, 0, 4), (4, 0, 0)], grey),
        quad([(0, 0.5, 1), (0, 2.5, 1), (0, 2.5, 3), (0, 0.5, 3)], white),
        quad([(1.0, 2.0, 1.8), (1.0, 2.0, 2.2), (1.0, 2.4, 2.2), (1.0, 2.4, 1.8)],
             black, (50.0, 50.0, 50.0)),
        quad([(0, 1.5, 0.5), (0, 1.5, 3.5), (1.0, 1.5, 3.5), (1.0, 1.5, 0.5)], black),
    ])


def black_room(luminance=1000.0, width=4.0, depth=4.0, height=3.0, source_side=1.0):
    """CIE 171:2006 test case 5.3: a room (metres, y up, floor at y = 0, x in
    [0, width], z in [0, depth]) whose surfaces are all black, lit by a square
    Lambertian source of side `source_side` in the middle of the ceiling,
    facing down, of luminance `luminance` (cd m^-2, or radiance W sr^-1 m^-2:
    the illuminance comes out in lux, or W m^-2). Black surfaces reflect
    nothing, so the illuminance anywhere is the source's direct light alone,
    given exactly by Lambert's polygon formula. The ceiling is four
    rectangles around the source's opening. Cells: 0 floor, 1-4 walls (x = 0,
    x = width, z = 0, z = depth), 5-8 ceiling, 9 the source."""
    black = (0.0, 0.0, 0.0)
    w, d, h = width, depth, height
    a0, a1 = (w - source_side) / 2.0, (w + source_side) / 2.0
    b0, b1 = (d - source_side) / 2.0, (d + source_side) / 2.0

    def quad(corners, emission=black):
        return {"vertices": corners, "reflectance": black, "emission": emission}

    def ceiling(x0, x1, z0, z1, emission=black):  # facing down
        return quad([(x0, h, z0), (x1, h, z0), (x1, h, z1), (x0, h, z1)], emission)

    return scene_from_polygons([
        quad([(0, 0, 0), (0, 0, d), (w, 0, d), (w, 0, 0)]),
        quad([(0, 0, 0), (0, h, 0), (0, h, d), (0, 0, d)]),
        quad([(w, 0, 0), (w, 0, d), (w, h, d), (w, h, 0)]),
        quad([(0, 0, 0), (w, 0, 0), (w, h, 0), (0, h, 0)]),
        quad([(0, 0, d), (0, h, d), (w, h, d), (w, 0, d)]),
        ceiling(0, w, 0, b0), ceiling(0, w, b1, d), ceiling(0, a0, b0, b1),
        ceiling(a1, w, b0, b1),
        ceiling(a0, a1, b0, b1, (luminance,) * 3),
    ])
