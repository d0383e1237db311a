# SPDX-License-Identifier: GPL-3.0-or-later
"""Sensor points (vtkPenumbraSensorEvaluator, penumbra.sensors, `penumbra
solve --sensors`): irradiance anywhere, against Lambert's formula, a fine
quadrature of an occluded light and a Monte Carlo gather of a solution."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkIdList, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkGenericCell

import penumbra
import penumbra.generators as generators
import penumbra.sensors as sensors
from conftest import run_penumbra
from test_irradiance import LUMINANCE, SOURCE, lambert_irradiance


def test_free_sensors_in_the_black_room_are_lamberts():
    """A work plane 0.8 m above the floor and vertical sensors in mid-air,
    facing the source: exact direct light, to rounding."""
    scene = generators.black_room(luminance=LUMINANCE)
    grid = np.linspace(0.25, 3.75, 8)
    positions = [(x, 0.8, z) for x in grid for z in grid]
    normals = [(0.0, 1.0, 0.0)] * len(positions)
    positions += [(1.0, 1.5, 2.0), (0.2, 2.9, 1.0), (3.0, 2.0, 0.5)]
    normals += [(1.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)]
    # A sensor facing down sees nothing of a source above it.
    positions.append((2.0, 1.0, 2.0))
    normals.append((0.0, -3.0, 0.0))  # normalised by the evaluator
    irradiance = sensors.evaluate(None, scene, positions, normals)
    for p, n, e in zip(positions, normals, irradiance):
        n = np.array(n) / np.linalg.norm(n)
        exact = lambert_irradiance(np.array(p), n, SOURCE, LUMINANCE) if n[1] > -0.5 else 0.0
        assert np.abs(e - exact).max() <= 1e-9 * max(exact, 1.0), (p, e, exact)


def quadrature_irradiance(point, normal, light, emission, occluder, n=1000):
    """Direct irradiance from the horizontal square `light` (centre, half
    side, height; facing down) past the horizontal square `occluder` (same
    form), by the midpoint rule on an n x n grid of the light."""
    (lx, ly, lz), lh = light[0], light[1]
    (ox, oy, oz), oh = occluder[0], occluder[1]
    u = (np.arange(n) + 0.5) / n * 2.0 * lh - lh
    gx, gz = np.meshgrid(lx + u, lz + u)
    samples = np.stack([gx.ravel(), np.full(gx.size, ly), gz.ravel()], axis=1)
    d = samples - point
    r2 = (d ** 2).sum(axis=1)
    cos_sensor = np.clip(d @ normal, 0.0, None) / np.sqrt(r2)
    cos_light = d[:, 1] / np.sqrt(r2)  # the light faces -y
    t = (oy - point[1]) / d[:, 1]
    hit = (t > 0) & (t < 1) & (np.abs(point[0] + t * d[:, 0] - ox) < oh) & \
          (np.abs(point[2] + t * d[:, 2] - oz) < oh)
    integrand = np.where(hit, 0.0, cos_sensor * cos_light / r2)
    return emission * integrand.sum() * (2.0 * lh / n) ** 2


def test_occluded_sensors_match_a_fine_quadrature():
    """The 'occluder' scene: sensors in the occluder's umbra, penumbra and
    full light, 0.5 m above the floor, facing up and tilted."""
    positions = [(x, 0.5, z) for x in (0.0, 0.3, 0.4, 0.5, 0.6, 0.8, 1.2) for z in (0.0, 0.15)]
    normals = [(0.0, 1.0, 0.0)] * len(positions)
    positions += [(0.5, 0.5, 0.1), (0.45, 0.7, -0.2)]
    normals += [(0.3, 1.0, 0.0), (-0.2, 1.0, 0.4)]
    irradiance = sensors.evaluate(None, "occluder", positions, normals)
    light, occluder = ((0.0, 2.0, 0.0), 0.25), ((0.0, 1.0, 0.0), 0.3)
    peak = quadrature_irradiance(np.array((2.0, 0.5, 0.0)), np.array((0.0, 1.0, 0.0)), light,
                                 50.0, occluder)
    for p, n, e in zip(positions, normals, irradiance):
        n = np.array(n) / np.linalg.norm(n)
        expected = quadrature_irradiance(np.array(p), n, light, 50.0, occluder)
        # The midpoint rule's error at the shadow's edges is O(1/n): 1e-3 of the peak.
        assert abs(e[0] - expected) <= 1e-3 * peak, (p, e[0], expected)
    assert irradiance[0, 0] == 0.0  # the umbra


def monte_carlo_gather(solution, emission, point, normal, strata=96, seed=1):
    """Irradiance at `point` from the solution's reflected radiance (Radiance
    less Emission, interpolated on its triangles), by cosine-weighted
    stratified sampling of the hemisphere (strata x strata directions):
    returns the estimate and its standard error."""
    locator = vtkCellLocator()
    locator.SetDataSet(solution)
    locator.BuildLocator()
    radiance = vtk_to_numpy(solution.GetPointData().GetArray("Radiance"))
    surface_ids = vtk_to_numpy(solution.GetCellData().GetArray("SurfaceId"))
    normal = np.asarray(normal, float) / np.linalg.norm(normal)
    helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    tangent = np.cross(normal, helper)
    tangent /= np.linalg.norm(tangent)
    bitangent = np.cross(normal, tangent)
    rng = np.random.default_rng(seed)
    cell = vtkGenericCell()
    values = np.zeros((strata * strata, 3))
    t, x, pcoords = mutable(0.0), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    sub_id, cell_id = mutable(0), mutable(0)
    weights = [0.0] * 3
    k = 0
    for i in range(strata):
        for j in range(strata):
            u1, u2 = (i + rng.random()) / strata, (j + rng.random()) / strata
            r, phi = np.sqrt(u1), 2.0 * np.pi * u2
            d = r * np.cos(phi) * tangent + r * np.sin(phi) * bitangent + \
                np.sqrt(1.0 - u1) * normal
            end = point + 10.0 * d
            if locator.IntersectWithLine(point + 1e-9 * d, end, 1e-12, t, x, pcoords, sub_id,
                                         cell_id, cell):
                cell.EvaluatePosition(x, [0.0, 0.0, 0.0], sub_id, pcoords, mutable(0.0), weights)
                ids = [cell.GetPointId(q) for q in range(3)]
                value = sum(w * radiance[q] for w, q in zip(weights, ids))
                values[k] = np.maximum(value - emission[surface_ids[cell_id.get()]], 0.0)
            k += 1
    # E = pi * mean of L over cosine-distributed directions.
    return np.pi * values.mean(axis=0), np.pi * values.std(axis=0) / np.sqrt(len(values))


@pytest.mark.parametrize("point, normal", [((0.4, 0.25, 0.1), (0.0, 0.0, 1.0)),
                                           ((0.2, 0.45, 0.3), (0.0, -1.0, 0.0))],
                         ids=["facing the back wall", "facing the floor"])
def test_sensor_indirect_light_matches_a_monte_carlo_gather(point, normal):
    """Cornell box, sensors in mid-air: the indirect part (the solution's
    reflected light, integrated exactly) against a stratified Monte Carlo
    estimate of the same integral, within four standard errors."""
    scene = penumbra.load_scene("cornell")
    solution = penumbra.solve(scene, threads=2)
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    total = sensors.evaluate(solution, scene, [point], [normal])[0]
    direct = sensors.evaluate(solution, scene, [point], [normal], direct_only=True)[0]
    estimate, error = monte_carlo_gather(solution, emission, np.array(point), normal)
    indirect = total - direct
    assert (indirect > 0.0).all()
    assert (np.abs(indirect - estimate) <= 4.0 * error + 1e-3 * estimate).all(), \
        (indirect, estimate, error)


def test_command_line_sensors(tmp_path):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z,nx,ny,nz\n2,0.8,2,0,1,0\n\n1,1.5,2,1,0,0\n")
    values = tmp_path / "values.csv"
    room = tmp_path / "room.vtp"
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(room))
    writer.SetInputData(generators.black_room(luminance=LUMINANCE))
    assert writer.Write()
    done = run_penumbra("solve", room, "-o", tmp_path / "out.vtp", "--quiet", "--sensors",
                        points, "--sensors-out", values)
    assert done.returncode == 0, done.stderr
    lines = values.read_text().splitlines()
    assert lines[0] == "x,y,z,nx,ny,nz,irradiance_r,irradiance_g,irradiance_b"
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert rows.shape == (2, 9)
    for row in rows:
        exact = lambert_irradiance(row[:3], row[3:6], SOURCE, LUMINANCE)
        assert np.abs(row[6:] - exact).max() <= 1e-9 * exact


@pytest.mark.parametrize("text, message", [
    ("x,y,z,nx,ny\n0,0,0,0,1\n", "line 1: the header has no column nz"),
    ("x,y,z,nx,ny,nz\n0,0,0,0,1,0\n0,0,zero,0,1,0\n", "line 3: not a number"),
    ("x,y,z,nx,ny,nz\n0,0,0,0,0,0\n", "line 2: the normal (nx, ny, nz) is zero"),
    ("x,y,z,nx,ny,nz\n0,0,0,0,1\n", "line 2: 5 columns"),
    ("x,y,z,nx,ny,nz\n0,nan,0,0,1,0\n", "line 2: not a finite number"),
    ("", "empty"),
])
def test_bad_sensor_files_name_the_line(tmp_path, text, message):
    points = tmp_path / "points.csv"
    points.write_text(text)
    done = run_penumbra("solve", "occluder", "-o", tmp_path / "out.vtp", "--quiet",
                        "--sensors", points, "--sensors-out", tmp_path / "values.csv")
    assert done.returncode != 0
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert message in done.stderr and "points.csv" in done.stderr, done.stderr
    assert not (tmp_path / "out.vtp").exists()  # refused before the solve
