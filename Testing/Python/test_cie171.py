# SPDX-License-Identifier: GPL-3.0-or-later
"""CIE 171:2006 test cases 5.6 and 5.7: light from a uniformly lit diffuse
surface onto black measurement planes, without and with a black obstruction.

The lit surface S2 is modelled as a uniform Lambertian emitter of exitance
M = 1 (radiance 1 / pi), so the illuminance at a point is its configuration
factor to the part of S2 it sees, the quantity CIE tabulates (in %). The
sensors' values are checked against that factor computed here (Lambert's
polygon formula over the visible part of S2, found in closed form: the
obstruction of 5.7 spans S2's whole width, so it hides S2 below one
horizontal line), and against the published values: CIE's Table 17 for 5.6
(scenario 2), and the corrected values of 5.7 (CIE's Table 19 is known to
be wrong; the correction as published in NVIDIA's Iray validation report,
Table 14), each to its published digits. Coordinates as CIE draws them,
z up."""
import numpy as np
import pytest

import penumbra.sensors
from penumbra.generators import scene_from_polygons
from test_irradiance import lambert_irradiance

BLACK = (0.0, 0.0, 0.0)
SOURCE = (1.0 / np.pi,) * 3  # exitance 1


def polygon(vertices, emission=BLACK):
    return {"vertices": vertices, "reflectance": BLACK, "emission": emission}


def lambert(point, normal, vertices):
    """Configuration factor from `point` (unit `normal`) to a polygon wholly
    in front of it: Lambert's formula (test_irradiance) for unit radiance, / pi."""
    return abs(lambert_irradiance(point, normal, vertices, 1.0)) / np.pi


# Case 5.6, scenario 2: S2 the 4 x 4 m floor; S1-v a vertical plane on S2's
# edge (y = 0), from 0.5 m to 3 m up; S1-hz a horizontal plane 3 m up.
S2_FLOOR = [(0, 0, 0), (4, 0, 0), (4, 4, 0), (0, 4, 0)]  # facing +z
CASE_56 = {
    "B": ((2, 0, 0.75), (0, 1, 0), 35.901), "C": ((2, 0, 1.25), (0, 1, 0), 27.992),
    "D": ((2, 0, 1.75), (0, 1, 0), 21.639), "E": ((2, 0, 2.25), (0, 1, 0), 16.716),
    "F": ((2, 0, 2.75), (0, 1, 0), 12.967),
    "G": ((2, 0.25, 3), (0, 0, -1), 26.80), "H": ((2, 0.75, 3), (0, 0, -1), 30.94),
    "I": ((2, 1.25, 3), (0, 0, -1), 33.98), "J": ((2, 1.75, 3), (0, 0, -1), 35.57),
    "K": ((2, 2.25, 3), (0, 0, -1), 35.57), "L": ((2, 2.75, 3), (0, 0, -1), 33.98),
    "M": ((2, 3.25, 3), (0, 0, -1), 30.94), "N": ((2, 3.75, 3), (0, 0, -1), 26.80),
}


def scene_56():
    return scene_from_polygons([
        polygon(S2_FLOOR, SOURCE),
        polygon([(0, 0, 0.5), (0, 0, 3), (4, 0, 3), (4, 0, 0.5)]),  # S1-v, facing +y
        polygon([(0, 0, 3), (0, 4, 3), (4, 4, 3), (4, 0, 3)]),  # S1-hz, facing -z
    ])


# Case 5.7: S2 a 4 x 3 m wall at y = 4; S1-v the facing wall at y = 0; S1-hz
# the floor from y = 0 to 2.5; a black box 4 m long, 0.2 m thick, 1 m high
# at y = 2.5 to 2.7 stands between them.
S2_WALL = [(0, 4, 0), (4, 4, 0), (4, 4, 3), (0, 4, 3)]  # facing -y
BOX = (2.5, 2.7, 1.0)  # near face, far face, height
CASE_57 = {
    "A": ((2, 0, 2.75), (0, 1, 0), 16.07), "B": ((2, 0, 2.25), (0, 1, 0), 16.33),
    "C": ((2, 0, 1.75), (0, 1, 0), 15.40), "D": ((2, 0, 1.25), (0, 1, 0), 13.32),
    "E": ((2, 0, 0.75), (0, 1, 0), 10.32), "F": ((2, 0, 0.25), (0, 1, 0), 7.08),
    "G": ((2, 0.25, 0), (0, 0, 1), 3.38), "H": ((2, 0.75, 0), (0, 0, 1), 3.63),
    "I": ((2, 1.25, 0), (0, 0, 1), 3.01), "J": ((2, 1.75, 0), (0, 0, 1), 0.0),
    "K": ((2, 2.25, 0), (0, 0, 1), 0.0),
}


def box_faces(x0, x1, y0, y1, z0, z1):
    """The six faces of an axis-aligned box, facing out."""
    return [
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # top
        [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],  # bottom
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # near (-y)
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # far (+y)
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # -x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # +x
    ]


def scene_57():
    near, far, height = BOX
    return scene_from_polygons(
        [polygon(S2_WALL, SOURCE),
         polygon([(0, 0, 0), (0, 0, 3), (4, 0, 3), (4, 0, 0)]),  # S1-v, facing +y
         polygon([(0, 0, 0), (4, 0, 0), (4, 2.5, 0), (0, 2.5, 0)])]  # S1-hz, facing +z
        + [polygon(face) for face in box_faces(0, 4, near, far, 0, height)])


def visible_57(point):
    """The part of S2 the point sees past the box: S2 above the line where
    the plane through the point and the box's limiting top edge meets it
    (rising sight lines must clear the near top edge, falling ones the far)."""
    near, far, height = BOX
    y0, z0 = point[1], point[2]
    edge = near if z0 < height else far
    cut = z0 + (height - z0) * (4.0 - y0) / (edge - y0)
    if cut >= 3.0:
        return None
    low = max(cut, 0.0)
    return [(0, 4, low), (4, 4, low), (4, 4, 3), (0, 4, 3)]


def factors(scene, case):
    positions = np.array([p for p, _, _ in case.values()], dtype=float)
    normals = np.array([n for _, n, _ in case.values()], dtype=float)
    return 100.0 * penumbra.sensors.evaluate(None, scene, positions, normals)[:, 0]


def test_case_5_6_configuration_factors():
    computed = factors(scene_56(), CASE_56)
    for (name, (point, normal, published)), value in zip(CASE_56.items(), computed):
        exact = 100.0 * lambert(np.array(point, float), np.array(normal, float), S2_FLOOR)
        print("5.6 %s: Penumbra %.4f, closed form %.4f, CIE %.3f" % (name, value, exact, published))
        assert value == pytest.approx(exact, rel=1e-9)
        # CIE's values, to their published digits.
        assert value == pytest.approx(published, abs=0.006)


def test_case_5_7_configuration_factors_past_the_obstruction():
    computed = factors(scene_57(), CASE_57)
    for (name, (point, normal, published)), value in zip(CASE_57.items(), computed):
        visible = visible_57(np.array(point, float))
        exact = 0.0 if visible is None else 100.0 * lambert(
            np.array(point, float), np.array(normal, float), visible)
        print("5.7 %s: Penumbra %.4f, closed form %.4f, corrected CIE %.2f"
              % (name, value, exact, published))
        assert value == pytest.approx(exact, rel=1e-9, abs=1e-9)
        # The corrected values, to their published digits.
        assert value == pytest.approx(published, abs=0.006)
