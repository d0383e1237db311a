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

`furnished_room(polygons)` builds a closed open-plan office of that size (bays
with desks, chairs, bookcases full of books, low partitions, strip lights),
the large-scene test of light leaks and contacts, and
`furnished_room_probes(polygons)` the points at which to compare its
solutions with a reference.

Everything is vectorised with numpy: 20,000 polygons take a fraction of a
second.
"""
import numpy as np

__all__ = ["box_room", "black_room", "closed_cube", "closed_cube_radiance", "furnished_room",
           "furnished_room_probes", "half_lit_panel", "scene_from_polygons", "ROOM_CELLS",
           "ROOM_HEIGHT", "LIGHT_EMISSION"]

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
    return _turned_box_corners(center_x, center_z, half_w, half_d, np.cos(angle), np.sin(angle),
                               bottom, top)


def _turned_box_corners(center_x, center_z, half_w, half_d, cos, sin, bottom, top):
    """(n, 8, 3) corners of n boxes whose half width `half_w` runs along
    (cos, 0, sin) and half depth `half_d` along (-sin, 0, cos): the rotation
    about the vertical given by its cosine and sine, exact for quarter turns."""
    c, s = cos[:, None], sin[:, None]
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


# Furnished interior: a grid of office bays. Every bay is a square of side
# _BAY (metres) seen in its own frame: u along the wall behind its bookcase,
# v away from that wall, the origin at the bay's centre, so that wall is at
# v = -_BAY / 2.
_BAY = 4.0
# Faces of a box: all 6 (it hangs free or rests on others), 5 (it stands on
# a surface: no bottom face) or 4 (a leg, against a surface at both ends:
# neither bottom nor top face, which would lie hidden against that surface).
_FREE, _STANDING, _POST = 6, 5, 4
# Floor and ceiling quads, 2 lights, desk (top 6, legs 4 x 4, monitor and
# keyboard 5 each), chair (seat 6, legs 4 x 4, back 5), bookcase (back panel,
# 2 side panels and plinth 5 each, 5 shelves 6 each).
_BAY_FIXED_POLYGONS = 2 + 2 + 32 + 27 + 50
_BOOKS_PER_BAY = 56           # aimed at when the bay grid is chosen
_PARTITION_LENGTH = 2.4       # centred on a bay edge: 0.8 m openings at both ends
_PARTITION_THICKNESS = 0.05
_PARTITION_HEIGHT = 1.8
_PARTITION_SETBACK = 0.01     # a partition stands this far inside the bay owning it
_WALL_GAP = 0.01              # between a bookcase's back and the wall behind it
_BOOKCASE_REACH = 1.1         # a bookcase stays within |u| <= this (inside the partition)
_BOOKCASE_DEPTH = 0.3
_BOOKCASE_HEIGHT = 1.75
_BACK_PANEL = 0.01            # thickness of the bookcase's back panel
_BOARD = 0.018                # thickness of its side panels and shelves
_BOARD_GAP = 0.002            # between a shelf (or the plinth) and the panels around it
_PLINTH = 0.07                # height of the bottom board, the lowest book level
_SHELVES = 5                  # boards above the plinth, the top one included
_BOOK_LEVELS = 5              # the plinth and the shelves below the top one
_BOOKS_PER_LEVEL = 16
_BOOK_MARGIN = 0.005          # free shelf between the books and the panels
_DESK_HALF = (0.7, 0.35)      # desk top 1.4 m x 0.7 m
_DESK_HEIGHT = 0.72
_DESK_TOP = 0.03
_DESK_LEG = 0.025             # half side of a square desk leg
_DESK_LEG_INSET = 0.04        # between a leg and the desk top's edges
_SEAT_HALF = 0.225
_SEAT_HEIGHT = 0.45
_SEAT = 0.05
_CHAIR_LEG = 0.015
_CHAIR_LEG_INSET = 0.02
_CHAIR_DISTANCE = 0.70        # from the desk's centre to the seat's, at least
_MONITOR = (0.275, 0.1, 0.4)  # half width, half depth, height
_KEYBOARD = (0.22, 0.07, 0.025)
_STRIP_LIGHT_HALF = (0.6, 0.15)   # a 1.2 m x 0.3 m light, along x
_STRIP_LIGHT_Z = (-0.9, 0.9)      # the 2 lights of a bay, from its centre along z
_FLOOR_REFLECTANCE = (0.38, 0.35, 0.31)
_CEILING_REFLECTANCE = (0.8, 0.8, 0.8)
# The walls at z = 0, x = max, z = max and x = 0: pale red, pale blue, pale
# green and warm white.
_WALL_REFLECTANCE = ((0.75, 0.45, 0.4), (0.45, 0.55, 0.75), (0.5, 0.7, 0.5),
                     (0.72, 0.7, 0.62))
# Cosine and sine of the bay frame whose bookcase wall (v = -_BAY / 2) is on
# side 0 (-z), 1 (+x), 2 (+z) or 3 (-x) of the bay: u = (cos, sin) and
# v = (-sin, cos) in (x, z).
_SIDE_COS = np.array([1.0, 0.0, -1.0, 0.0])
_SIDE_SIN = np.array([0.0, 1.0, 0.0, -1.0])


def _place(frame, u, v, cos=1.0, sin=0.0):
    """The frame at (u, v) of `frame` (x, z, cos, sin), turned by (cos, sin)
    about the vertical relative to it."""
    x, z, c, s = frame
    return x + c * u - s * v, z + s * u + c * v, c * cos - s * sin, s * cos + c * sin


def _signed_footprint_distance(px, pz, x, z, c, s, half_w, half_d):
    """Signed distance in the floor plane from points (px, pz) to turned
    rectangles (negative inside); the arguments broadcast."""
    dx, dz = px - x, pz - z
    du = np.abs(c * dx + s * dz) - half_w
    dv = np.abs(-s * dx + c * dz) - half_d
    return np.hypot(np.maximum(du, 0.0), np.maximum(dv, 0.0)) + np.minimum(np.maximum(du, dv), 0.0)


class _BoxList:
    """Boxes turned about the vertical, added a kind of part at a time: their
    frame (centre x, z and the rotation's cos, sin), half extents, bottom and
    top heights, number of faces (_FREE, _STANDING or _POST), colour and bay."""

    _COLUMNS = ("x", "z", "cos", "sin", "half_w", "half_d", "bottom", "top", "faces", "bay")

    def __init__(self):
        self._parts = {name: [] for name in self._COLUMNS + ("colour",)}
        self.count = 0

    def add(self, frame, half_w, half_d, bottom, top, faces, colour, bay):
        """Add len(bay) boxes (every argument broadcasts to that); return their indices."""
        n = len(bay)
        values = dict(zip(self._COLUMNS, (*frame, half_w, half_d, bottom, top, faces, bay)))
        for name, value in values.items():
            self._parts[name].append(np.broadcast_to(value, (n,)))
        self._parts["colour"].append(np.broadcast_to(colour, (n, 3)))
        self.count += n
        return np.arange(self.count - n, self.count)

    def arrays(self):
        out = {name: np.concatenate(parts) for name, parts in self._parts.items()}
        out["faces"] = out["faces"].astype(np.int64)
        out["bay"] = out["bay"].astype(np.int64)
        return out


def _office_fixed_polygons(nx, nz):
    """Polygons of an nx x nz bay grid without its books."""
    partitions = (nx - 1) * nz + nx * (nz - 1)
    return _BAY_FIXED_POLYGONS * nx * nz + 5 * partitions + 2 * (nx + nz)


def _office_grid(polygons):
    """(nx, nz, books) for a request: the square or nearly square bay grid
    (nx = nz or nz + 1) whose books per bay are closest to _BOOKS_PER_BAY
    while the shelves hold them all, the books filling the rest of the
    request."""
    capacity = _BOOK_LEVELS * _BOOKS_PER_LEVEL
    best = None
    largest = int(np.ceil(np.sqrt(max(polygons, 1) / 100.0))) + 2
    for nx in range(1, largest + 1):
        for nz in (nx - 1, nx) if nx > 1 else (1,):
            bays = nx * nz
            books = max(0, int(np.floor((polygons - _office_fixed_polygons(nx, nz)) / 5.0 + 0.5)))
            if books > capacity * bays:
                continue
            miss = abs(books / bays - _BOOKS_PER_BAY)
            if best is None or miss < best[0]:
                best = (miss, nx, nz, books)
    return best[1:]


def _add_desks(boxes, rng, frame, bay):
    """Per bay a desk on four legs with a monitor and a keyboard on its top,
    and a chair pulled up to it; returns the boxes of the desk tops, of the
    monitors and keyboards (n, 2) and of the legs (n, 8).

    The desk and its chair are turned by at least 0.05 rad from their bay's
    axes, the monitor and keyboard further the same way as their desk: no box
    is turned by a hair, which load_scene's repairs would straighten."""
    n = len(bay)
    desk_u = rng.uniform(-0.3, 0.3, n)
    desk_v = rng.uniform(-0.1, 0.2, n)
    turn = np.where(rng.uniform(size=n) < 0.5, -1.0, 1.0)
    desk_angle = turn * rng.uniform(0.05, 0.35, n)
    chair_u = rng.uniform(-0.3, 0.3, n)
    chair_pull = rng.uniform(0.0, 0.2, n)
    chair_angle = turn * rng.uniform(0.05, 0.5, n)
    monitor_u = rng.uniform(-0.3, 0.3, n)
    monitor_angle = turn * rng.uniform(0.05, 0.25, n)
    keyboard_u = monitor_u + rng.uniform(-0.1, 0.1, n)
    keyboard_angle = turn * rng.uniform(0.03, 0.15, n)
    desk_colour, chair_colour, monitor_colour, keyboard_colour = rng.uniform(0.1, 0.85, (4, n, 3))

    desk = _place(frame, desk_u, desk_v, np.cos(desk_angle), np.sin(desk_angle))
    desk_bottom = _DESK_HEIGHT - _DESK_TOP
    desk_top = boxes.add(desk, _DESK_HALF[0], _DESK_HALF[1], desk_bottom, _DESK_HEIGHT, _FREE,
                         desk_colour, bay)
    leg_u = _DESK_HALF[0] - _DESK_LEG_INSET - _DESK_LEG
    leg_v = _DESK_HALF[1] - _DESK_LEG_INSET - _DESK_LEG
    legs = [boxes.add(_place(desk, su * leg_u, sv * leg_v), _DESK_LEG, _DESK_LEG, 0.0,
                      desk_bottom, _POST, desk_colour, bay)
            for su, sv in _FOOTPRINT]
    monitor = boxes.add(_place(desk, monitor_u, -0.15, np.cos(monitor_angle),
                               np.sin(monitor_angle)),
                        _MONITOR[0], _MONITOR[1], _DESK_HEIGHT, _DESK_HEIGHT + _MONITOR[2],
                        _STANDING, monitor_colour, bay)
    keyboard = boxes.add(_place(desk, keyboard_u, 0.15, np.cos(keyboard_angle),
                                np.sin(keyboard_angle)),
                         _KEYBOARD[0], _KEYBOARD[1], _DESK_HEIGHT, _DESK_HEIGHT + _KEYBOARD[2],
                         _STANDING, keyboard_colour, bay)
    # Chair: a seat on four legs, its back standing on the seat, facing the
    # desk from its +v side; its circumscribed circle clears the desk.
    relative = chair_angle - desk_angle
    chair = _place(desk, chair_u, _CHAIR_DISTANCE + chair_pull, np.cos(relative), np.sin(relative))
    seat_bottom = _SEAT_HEIGHT - _SEAT
    boxes.add(chair, _SEAT_HALF, _SEAT_HALF, seat_bottom, _SEAT_HEIGHT, _FREE, chair_colour, bay)
    leg_offset = _SEAT_HALF - _CHAIR_LEG_INSET - _CHAIR_LEG
    legs += [boxes.add(_place(chair, su * leg_offset, sv * leg_offset), _CHAIR_LEG, _CHAIR_LEG,
                       0.0, seat_bottom, _POST, chair_colour, bay)
             for su, sv in _FOOTPRINT]
    boxes.add(_place(chair, 0.0, _SEAT_HALF - 0.03), 0.2, 0.015, _SEAT_HEIGHT, _SEAT_HEIGHT + 0.45,
              _STANDING, chair_colour, bay)
    return desk_top, np.stack([monitor, keyboard], axis=1), np.stack(legs, axis=1)


def _add_bookcases(boxes, rng, frame, bay, wall_face, nbooks):
    """Per bay a bookcase backing onto the wall `wall_face` from its bay's edge
    (v = wall_face - _BAY / 2), and `nbooks` books on their shelves; returns
    the bookcases' frames (origin on the back face's middle) and half widths.

    A back panel over the whole width, side panels and boards _BOARD_GAP
    clear of each other, a plinth and shelves. A random choice of the
    shelves' slots sets how many books stand on each level; they stand side
    by side from the level's left, 1-4 mm apart, squeezed together (to no
    less than 0.8 mm) when they would not fit."""
    n = len(bay)
    width = rng.uniform(0.8, 1.0, n)
    shift = rng.uniform(-1.0, 1.0, n) * (_BOOKCASE_REACH - width / 2)
    colour = rng.uniform(0.1, 0.85, (n, 3))
    case = _place(frame, shift, wall_face - _BAY / 2 + _WALL_GAP)
    half_width = width / 2
    boxes.add(_place(case, 0.0, _BACK_PANEL / 2), half_width, _BACK_PANEL / 2, 0.0,
              _BOOKCASE_HEIGHT, _STANDING, colour, bay)
    panel_v = (_BACK_PANEL + _BOARD_GAP + _BOOKCASE_DEPTH) / 2
    panel_half_d = (_BOOKCASE_DEPTH - _BACK_PANEL - _BOARD_GAP) / 2
    for sign in (-1.0, 1.0):
        boxes.add(_place(case, sign * (half_width - _BOARD / 2), panel_v), _BOARD / 2,
                  panel_half_d, 0.0, _BOOKCASE_HEIGHT, _STANDING, colour, bay)
    # The boards span the panels' depth, _BOARD_GAP clear of all three.
    board_half_w = half_width - _BOARD - _BOARD_GAP
    board_frame = _place(case, 0.0, panel_v)
    boxes.add(board_frame, board_half_w, panel_half_d, 0.0, _PLINTH, _STANDING, colour, bay)
    pitch = (_BOOKCASE_HEIGHT - _BOARD - _PLINTH) / _SHELVES
    shelf_bottom = _PLINTH + pitch * np.arange(1, _SHELVES + 1)
    shelf_bottom[-1] = _BOOKCASE_HEIGHT - _BOARD
    for bottom in shelf_bottom:
        boxes.add(board_frame, board_half_w, panel_half_d, bottom, bottom + _BOARD, _FREE,
                  colour, bay)
    level_surface = np.concatenate([[_PLINTH], shelf_bottom[:_BOOK_LEVELS - 1] + _BOARD])

    nlevels = n * _BOOK_LEVELS
    slots = rng.choice(nlevels * _BOOKS_PER_LEVEL, size=nbooks, replace=False)
    per_level = np.bincount(slots // _BOOKS_PER_LEVEL, minlength=nlevels)
    level = np.repeat(np.arange(nlevels), per_level)
    book_bay = level // _BOOK_LEVELS
    book_width = rng.uniform(0.018, 0.05, nbooks)
    gap = rng.uniform(0.001, 0.004, nbooks)
    height = rng.uniform(0.16, 0.29, nbooks)
    depth = rng.uniform(0.14, 0.22, nbooks)
    setback = rng.uniform(0.005, 0.025, nbooks)
    book_colour = rng.uniform(0.1, 0.85, (nbooks, 3))
    step = book_width + gap
    before = np.cumsum(step) - step  # along the level, from its first book
    before -= np.concatenate([[0.0], np.cumsum(step)])[np.cumsum(per_level) - per_level][level]
    room = 2 * (board_half_w - _BOOK_MARGIN)
    filled = np.bincount(level, weights=step, minlength=nlevels)
    squeeze = np.minimum(1.0, room[np.arange(nlevels) // _BOOK_LEVELS] /
                         np.maximum(filled, 1e-300))[level]
    left = -board_half_w[book_bay] + _BOOK_MARGIN + squeeze * before
    book_width = squeeze * book_width
    surface = level_surface[level % _BOOK_LEVELS]
    boxes.add(_place(tuple(np.asarray(a)[book_bay] for a in case), left + book_width / 2,
                     _BOOKCASE_DEPTH - setback - depth / 2),
              book_width / 2, depth / 2, surface, surface + height, _STANDING, book_colour,
              book_bay)
    return case, half_width


def _add_partitions(boxes, rng, nx, nz):
    """Partitions along the edges between bays, centred on them, each owned by
    the bay on its -x or -z side and standing _PARTITION_SETBACK inside it;
    returns the boxes of those on the bays' +x edges, then on their +z edges."""
    px_i, px_j = (a.ravel() for a in np.meshgrid(np.arange(nx - 1), np.arange(nz)))
    pz_i, pz_j = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(nz - 1)))
    inset = _PARTITION_SETBACK + _PARTITION_THICKNESS / 2
    half_t, half_l = _PARTITION_THICKNESS / 2, _PARTITION_LENGTH / 2
    colour = rng.uniform(0.1, 0.85, (len(px_i) + len(pz_i), 3))
    along_z = boxes.add(((px_i + 1) * _BAY - inset, (px_j + 0.5) * _BAY, 1.0, 0.0), half_t,
                        half_l, 0.0, _PARTITION_HEIGHT, _STANDING, colour[:len(px_i)],
                        px_j * nx + px_i)
    along_x = boxes.add(((pz_i + 0.5) * _BAY, (pz_j + 1) * _BAY - inset, 1.0, 0.0), half_l,
                        half_t, 0.0, _PARTITION_HEIGHT, _STANDING, colour[len(px_i):],
                        pz_j * nx + pz_i)
    return along_z, along_x


def _office_shell(nx, nz):
    """The shell of an nx x nz bay grid: its points (grid points on the floor,
    then on the ceiling), quads (a floor quad per bay, a ceiling quad per bay,
    a wall quad per bay edge on the outline, all facing inward) and, per wall
    quad, its first and second floor corner, side (0 at z = 0, 1 at x = max,
    2 at z = max, 3 at x = 0) and bay. The quads share their corners: they
    tile the shell exactly."""
    gx, gz = np.meshgrid(np.arange(nx + 1) * _BAY, np.arange(nz + 1) * _BAY)
    level = (nx + 1) * (nz + 1)
    points = np.concatenate([
        np.stack([gx.ravel(), np.zeros(level), gz.ravel()], axis=1),
        np.stack([gx.ravel(), np.full(level, ROOM_HEIGHT), gz.ravel()], axis=1)])

    def grid(i, j):
        return j * (nx + 1) + i

    bay = np.arange(nx * nz)
    i, j = bay % nx, bay // nx
    floor = np.stack([grid(i, j), grid(i, j + 1), grid(i + 1, j + 1), grid(i + 1, j)], axis=1)
    ceiling = floor[:, ::-1] + level
    # A wall quad (a, b, b above, a above) faces (b - a) x y: inward when a to
    # b runs +x along z = 0, +z along x = max, -x along z = max, -z along x = 0.
    ii, jj = np.arange(nx), np.arange(nz)
    start = np.concatenate([grid(ii, 0), grid(nx, jj), grid(ii + 1, nz), grid(0, jj + 1)])
    end = np.concatenate([grid(ii + 1, 0), grid(nx, jj + 1), grid(ii, nz), grid(0, jj)])
    walls = np.stack([start, end, end + level, start + level], axis=1)
    side = np.repeat([0, 1, 2, 3], [nx, nz, nx, nz])
    wall_bay = np.concatenate([ii, jj * nx + nx - 1, (nz - 1) * nx + ii, jj * nx])
    return (points, np.concatenate([floor, ceiling, walls]), points[start], points[end], side,
            wall_bay)


def _office_layout(polygons, seed):
    """The furnished office of `furnished_room` as arrays: the scene's
    `points`, `quads`, `reflectance`, `emission` and `part`; the boxes
    (`box`, columns of _BoxList, and `box_cell`, each box's first cell) with
    those of the desk tops, the things on them and the legs; per bay its
    frame, its bookcase's frame, half width and backing cell; the wall quads
    and the lights. `rng` is the generator the layout drew from, left for the
    probes to continue."""
    from types import SimpleNamespace

    nx, nz, nbooks = _office_grid(int(polygons))
    rng = np.random.default_rng(seed)
    nbays = nx * nz
    bay = np.arange(nbays)
    bay_i, bay_j = bay % nx, bay // nx

    # The bookcase stands against a shell wall if the bay has one, else
    # against one of the partitions the bay owns (those on its +x and +z
    # edges), so that no bookcase reaches the floor of another bay.
    on_shell = np.stack([bay_j == 0, bay_i == nx - 1, bay_j == nz - 1, bay_i == 0], axis=1)
    choice = rng.uniform(size=(nbays, 4)) + on_shell
    choice[:, [0, 3]] = np.where(on_shell[:, [0, 3]], choice[:, [0, 3]], -1.0)
    side = np.argmax(choice, axis=1)
    side_on_shell = on_shell[bay, side]
    frame = ((bay_i + 0.5) * _BAY, (bay_j + 0.5) * _BAY, _SIDE_COS[side], _SIDE_SIN[side])
    wall_face = np.where(side_on_shell, 0.0, _PARTITION_SETBACK + _PARTITION_THICKNESS)

    boxes = _BoxList()
    desk_top, desk_items, legs = _add_desks(boxes, rng, frame, bay)
    case, case_half_width = _add_bookcases(boxes, rng, frame, bay, wall_face, nbooks)
    partition_x, partition_z = _add_partitions(boxes, rng, nx, nz)
    box = boxes.arrays()
    nboxes = boxes.count
    shell_points, shell_quads, wall_from, wall_to, wall_side, wall_bay = _office_shell(nx, nz)
    nshell = len(shell_quads)

    # Lights: two strips per bay, 5 mm under the ceiling, facing down.
    light_bay = np.repeat(bay, len(_STRIP_LIGHT_Z))
    light_x = frame[0][light_bay]
    light_z = frame[1][light_bay] + np.tile(_STRIP_LIGHT_Z, nbays)
    nlights = len(light_bay)
    light_y = np.full(nlights, ROOM_HEIGHT - _LIGHT_DROP)
    light_corners = _turned_box_corners(light_x, light_z, np.full(nlights, _STRIP_LIGHT_HALF[0]),
                                        np.full(nlights, _STRIP_LIGHT_HALF[1]), np.ones(nlights),
                                        np.zeros(nlights), light_y, light_y)[:, :4]
    light_quads = np.arange(nlights)[:, None] * 4 + np.array([3, 2, 1, 0])

    # Box faces: the top (not on legs), the 4 sides, then the bottom of free boxes.
    corners = _turned_box_corners(box["x"], box["z"], box["half_w"], box["half_d"], box["cos"],
                                  box["sin"], box["bottom"], box["top"])
    faces = box["faces"]
    box_cell = nshell + nlights + np.cumsum(faces) - faces
    kept = np.ones((nboxes, 6), dtype=bool)
    kept[:, 0] = faces != _POST
    kept[:, 5] = faces == _FREE
    box_base = len(shell_points) + 4 * nlights
    box_quads = (box_base + 8 * np.arange(nboxes)[:, None, None] + _BOX_FACES_CLOSED[None])[kept]

    points = np.concatenate([shell_points, light_corners.reshape(-1, 3), corners.reshape(-1, 3)])
    quads = np.concatenate([shell_quads, len(shell_points) + light_quads, box_quads])
    ncells = len(quads)
    reflectance = np.empty((ncells, 3))
    reflectance[:nbays] = _FLOOR_REFLECTANCE
    reflectance[nbays:2 * nbays] = _CEILING_REFLECTANCE
    reflectance[2 * nbays:nshell] = np.asarray(_WALL_REFLECTANCE)[wall_side]
    reflectance[nshell:nshell + nlights] = _LIGHT_REFLECTANCE
    reflectance[nshell + nlights:] = np.repeat(box["colour"], faces, axis=0)
    emission = np.zeros((ncells, 3))
    emission[nshell:nshell + nlights] = LIGHT_EMISSION
    part = np.concatenate([np.full(nshell, -1), np.full(nlights, -2),
                           np.repeat(np.arange(nboxes), faces)])

    # The face each bookcase backs onto: a wall quad, or the face of its
    # partition toward the bay owning it: the -x side (cell 1 of the box)
    # of a partition on the bay's +x edge, the -z side (cell 4) on its +z edge.
    wall_cell = 2 * nbays + np.arange(len(wall_side))
    bay_wall = np.full((nbays, 4), -1)
    bay_wall[wall_bay, wall_side] = wall_cell
    owned_x = np.full(nbays, -1)
    owned_x[box["bay"][partition_x]] = partition_x
    owned_z = np.full(nbays, -1)
    owned_z[box["bay"][partition_z]] = partition_z
    backing = np.where(side_on_shell, bay_wall[bay, side],
                       np.where(side == 1, box_cell[owned_x] + 1, box_cell[owned_z] + 4))
    return SimpleNamespace(
        nx=nx, nz=nz, nbays=nbays, nbooks=nbooks, rng=rng,
        points=points, quads=quads, reflectance=reflectance, emission=emission, part=part,
        box=box, box_cell=box_cell, frame=frame, case=case, case_half_width=case_half_width,
        backing=backing, desk_top=desk_top, desk_items=desk_items, legs=legs,
        wall_cell=wall_cell, wall_from=wall_from, wall_to=wall_to, wall_side=wall_side,
        wall_bay=wall_bay, side=side, light_x=light_x, light_z=light_z, light_bay=light_bay)


def furnished_room(polygons, seed=0):
    """A closed, furnished open-plan office with `polygons` surfaces (approximately).

    The large-scene test of light leaks and contacts: thin gaps (lights 5 mm
    under the ceiling, bookcases 1 cm in front of walls, books 1-4 mm apart),
    contacts everywhere (legs on the floor and under desk tops and seats,
    books on shelves, a monitor and a keyboard on every desk), low partitions
    that light flows over and around, coloured walls.

    Parameters
    ----------
    polygons : int
        The number of polygons wanted. The scene has ``113 * bays + 5 *
        partitions + 2 * (nx + nz)`` polygons without its books, for a grid
        of ``bays = nx * nz`` bays (nx = nz or nz + 1) and ``partitions =
        (nx - 1) * nz + nx * (nz - 1)``, plus 5 per book. The grid is the one
        whose books per bay come closest to 56 (of at most 80) when books
        fill the rest of the request, so the count is within 2 of any request
        of at least 120 polygons (one bay) and books make up about 70 % of
        it: 1,000 polygons give 2 x 1 bays, 5,000 give 4 x 3, 20,000 give
        7 x 7 and 100,000 give 16 x 16.
    seed : int
        Seed of ``numpy.random.default_rng``; the same (polygons, seed)
        always gives the same scene, point for point.

    Returns
    -------
    vtkPolyData
        Units are metres, y is up, the floor is at y = 0 and the ceiling at
        y = ROOM_HEIGHT; the building covers [0, 4 nx] x [0, 4 nz] in (x, z).
        Every cell is a planar convex quad, counter-clockwise seen from its
        front. Cell order:

        - the shell, facing inward: one floor quad per bay (cell b for bay
          b = j * nx + i, the bay over [4i, 4i + 4] x [4j, 4j + 4]), one
          ceiling quad per bay, then the walls, one quad per bay edge on the
          outline (along z = 0, x = max, z = max, x = 0). The quads share
          their corners: no gap, overlap or T-junction;
        - two lights per bay, 1.2 m x 0.3 m, 5 mm under the ceiling, facing
          down, Emission = LIGHT_EMISSION: the ceiling right above them is
          lit only through that gap;
        - the boxes' faces (the top, the 4 sides, then the bottom), facing
          out of their box, without those that lie against another surface:
          a box standing on a surface (floor, desk top, seat, shelf) has no
          bottom face, its footprint inside that surface; legs, against the
          floor and the desk top or seat they hold, have neither bottom nor
          top face (4 faces); desk tops, seats and shelves have all 6 faces.

        Cell data: `Reflectance` (RGB: floor 0.31-0.38, ceiling 0.8, the 4
        walls pale red, blue, green and warm white in [0.4, 0.75], lights
        0.78, every piece of furniture, partition and book a random colour in
        [0.1, 0.85]), `Emission` (RGB; non-zero on lights only) and `PartId`
        (int: -1 shell, -2 light, else the index of the box).

    Layout: the floor is a grid of 4 m x 4 m bays. Partitions (5 cm thick,
    1.8 m tall, 2.4 m long, centred along every edge between two bays, 1 cm
    inside one of them) leave 0.8 m openings at both ends, so all bays
    connect. Every bay holds a desk (1.4 m x 0.7 m top, 0.72 m high, on four
    legs) with a monitor and a keyboard on it, a chair (seat on four legs,
    back on the seat) pulled up to it, the group turned a little about the
    vertical, and a bookcase (0.8-1.0 m wide, 0.3 m deep, 1.75 m high: back
    panel, two side panels, plinth and five shelves) standing 1 cm in front
    of a shell wall or of one of its bay's partitions, its plinth and four
    lower shelves holding up to 16 books each. Boxes never intersect; they
    touch only where one stands on (or holds up) another, and the gaps
    between the others are at least 0.8 mm. Nothing but the lights comes
    within 1.2 m of the ceiling.
    """
    layout = _office_layout(polygons, seed)
    return _polydata(layout.points, layout.quads, layout.reflectance, layout.emission, layout.part)


def _probe_count(polygons):
    """Probes per group: 60 for 1,000 polygons, about 200 for 100,000."""
    return max(12, int(round(60.0 * (max(polygons, 1) / 1000.0) ** 0.26)))


def _draw_probes(rng, count, nitems, propose):
    """`count` probes from `propose(items)`, which returns, for candidates on
    the given items, (points, cells, accepted). The items are visited in a
    random order, cycling, so the probes spread over them."""
    order = rng.permutation(nitems)
    kept_points, kept_cells = [], []
    found, start = 0, 0
    for _ in range(100):
        n = 2 * (count - found) + 8
        items = order[(start + np.arange(n)) % nitems]
        start += n
        points, cells, accepted = propose(items)
        kept_points.append(points[accepted])
        kept_cells.append(cells[accepted])
        found += int(accepted.sum())
        if found >= count:
            break
    return np.concatenate(kept_points)[:count], np.concatenate(kept_cells)[:count]


def furnished_room_probes(polygons, seed=0):
    """Probe points of `furnished_room(polygons, seed)`, to compare a solution
    with a reference where it matters.

    Returns
    -------
    dict of numpy arrays
        `points` (n, 3): points on the scene's surfaces, each inside its
        cell's polygon, away from its edges; `normals` (n, 3): the unit
        normal of that cell's front; `cells` (n,) int64: the index of that
        cell; `groups` (n,) str, what the point tests:

        - ``floor``: the floor, at least 2 cm from any footprint (legs,
          bookcases, partitions);
        - ``table``: desk tops, at least 2 cm from their edges and from the
          monitor and keyboard on them;
        - ``wall``: shell walls between 0.3 m and 2.7 m high, not behind a
          bookcase (at least 5 cm outside its outline seen from the wall);
        - ``ceiling``: the ceiling, at least 10 cm from any light's outline;
        - ``gap``: the wall or partition face right behind a bookcase,
          inside its outline at least 5 cm from it: the 1 cm gap;
        - ``behind_light``: the ceiling right above a light, inside its
          outline at least 5 cm from it: the 5 mm gap;
        - ``contact``: the floor 2-5 mm from a desk or chair leg.

        Every group has the same number of points: 60 for 1,000 polygons,
        growing slowly with the scene (about 90 for 5,000, 130 for 20,000
        and 200 for 100,000), spread over the bays in a random order that
        follows from `seed`: the same arguments give the same probes.
    """
    office = _office_layout(polygons, seed)
    rng, box, frame = office.rng, office.box, office.frame
    count = _probe_count(int(polygons))
    nbays = office.nbays
    half_bay = _BAY / 2

    # Footprints on the floor, per bay, padded with far-away dummies.
    standing = np.nonzero(box["bottom"] == 0.0)[0]
    standing = standing[np.argsort(box["bay"][standing], kind="stable")]
    per_bay = np.bincount(box["bay"][standing], minlength=nbays)
    footprints = np.full((nbays, per_bay.max()), -1)
    rank = np.arange(len(standing)) - (np.cumsum(per_bay) - per_bay)[box["bay"][standing]]
    footprints[box["bay"][standing], rank] = standing

    def footprint_distance(x, z, candidates):
        """Smallest signed distance from (x, z) to the boxes `candidates` (m, k)."""
        valid = candidates >= 0
        index = np.where(valid, candidates, 0)
        distance = _signed_footprint_distance(
            x[:, None], z[:, None], box["x"][index], box["z"][index], box["cos"][index],
            box["sin"][index], box["half_w"][index], box["half_d"][index])
        return np.where(valid, distance, np.inf).min(axis=1)

    def in_bay(items):
        corner_x = frame[0][items] - half_bay
        corner_z = frame[1][items] - half_bay
        x = corner_x + rng.uniform(0.02, _BAY - 0.02, len(items))
        z = corner_z + rng.uniform(0.02, _BAY - 0.02, len(items))
        return x, z

    def on_floor(items):
        x, z = in_bay(items)
        points = np.stack([x, np.zeros(len(items)), z], axis=1)
        return points, items, footprint_distance(x, z, footprints[items]) >= 0.02

    desk_items = office.desk_items

    def on_table(items):
        top = office.desk_top[items]
        u = rng.uniform(-1, 1, len(items)) * (_DESK_HALF[0] - 0.02)
        v = rng.uniform(-1, 1, len(items)) * (_DESK_HALF[1] - 0.02)
        x, z, _, _ = _place(tuple(box[k][top] for k in ("x", "z", "cos", "sin")), u, v)
        points = np.stack([x, box["top"][top], z], axis=1)
        return points, office.box_cell[top], footprint_distance(x, z, desk_items[items]) >= 0.02

    def on_wall(items):
        along = rng.uniform(0.02, _BAY - 0.02, len(items))
        y = rng.uniform(0.3, ROOM_HEIGHT - 0.3, len(items))
        start, end = office.wall_from[items], office.wall_to[items]
        points = start + (end - start) * (along / _BAY)[:, None]
        points[:, 1] = y
        owner = office.wall_bay[items]
        behind = office.side[owner] == office.wall_side[items]
        case = tuple(np.asarray(a)[owner] for a in office.case)
        u = case[2] * (points[:, 0] - case[0]) + case[3] * (points[:, 2] - case[1])
        hidden = behind & (np.abs(u) < office.case_half_width[owner] + 0.05) & (
            y < _BOOKCASE_HEIGHT + 0.05)
        return points, office.wall_cell[items], ~hidden

    lights_of_bay = np.arange(len(office.light_bay)).reshape(nbays, -1)

    def on_ceiling(items):
        x, z = in_bay(items)
        lights = lights_of_bay[items]
        distance = _signed_footprint_distance(
            x[:, None], z[:, None], office.light_x[lights], office.light_z[lights], 1.0, 0.0,
            _STRIP_LIGHT_HALF[0], _STRIP_LIGHT_HALF[1]).min(axis=1)
        points = np.stack([x, np.full(len(items), ROOM_HEIGHT), z], axis=1)
        return points, nbays + items, distance >= 0.1

    def in_gap(items):
        half_width = office.case_half_width[items]
        u = rng.uniform(-1, 1, len(items)) * (half_width - 0.05)
        y = rng.uniform(0.05, _BOOKCASE_HEIGHT - 0.05, len(items))
        x, z, _, _ = _place(tuple(np.asarray(a)[items] for a in office.case), u, -_WALL_GAP)
        points = np.stack([x, y, z], axis=1)
        return points, office.backing[items], np.ones(len(items), dtype=bool)

    def behind_light(items):
        x = office.light_x[items] + rng.uniform(-1, 1, len(items)) * (_STRIP_LIGHT_HALF[0] - 0.05)
        z = office.light_z[items] + rng.uniform(-1, 1, len(items)) * (_STRIP_LIGHT_HALF[1] - 0.05)
        points = np.stack([x, np.full(len(items), ROOM_HEIGHT), z], axis=1)
        return points, nbays + office.light_bay[items], np.ones(len(items), dtype=bool)

    legs = office.legs.ravel()

    def near_leg(items):
        leg = legs[items]
        n = len(items)
        side = rng.integers(0, 4, n)
        along = rng.uniform(-0.9, 0.9, n)
        off = rng.uniform(0.002, 0.005, n)
        half_w, half_d = box["half_w"][leg], box["half_d"][leg]
        normal_u = np.array([1.0, -1.0, 0.0, 0.0])[side]
        normal_v = np.array([0.0, 0.0, 1.0, -1.0])[side]
        u = normal_u * (half_w + off) + np.abs(normal_v) * along * half_w
        v = normal_v * (half_d + off) + np.abs(normal_u) * along * half_d
        x, z, _, _ = _place(tuple(box[k][leg] for k in ("x", "z", "cos", "sin")), u, v)
        points = np.stack([x, np.zeros(n), z], axis=1)
        bays = box["bay"][leg]
        nearest = footprint_distance(x, z, footprints[bays])
        return points, bays, nearest >= off - 1e-9

    groups = [("floor", nbays, on_floor), ("table", nbays, on_table),
              ("wall", len(office.wall_cell), on_wall), ("ceiling", nbays, on_ceiling),
              ("gap", nbays, in_gap), ("behind_light", len(office.light_bay), behind_light),
              ("contact", len(legs), near_leg)]
    points, cells, names = [], [], []
    for name, nitems, propose in groups:
        group_points, group_cells = _draw_probes(rng, count, nitems, propose)
        points.append(group_points)
        cells.append(group_cells)
        names.append(np.full(len(group_cells), name))
    points = np.concatenate(points)
    cells = np.concatenate(cells).astype(np.int64)

    # Onto the cell's plane exactly, and the cell's unit normal.
    corners = office.points[office.quads[cells]]
    normals = 0.5 * np.cross(corners, np.roll(corners, -1, axis=1)).sum(axis=1)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    points -= np.einsum("ij,ij->i", points - corners[:, 0], normals)[:, None] * normals
    return {"points": points, "normals": normals, "cells": cells, "groups": np.concatenate(names)}


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
