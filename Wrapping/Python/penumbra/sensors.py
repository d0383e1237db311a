# SPDX-License-Identifier: GPL-3.0-or-later
"""Sensor points: irradiance (illuminance) anywhere in a scene.

    import penumbra, penumbra.sensors
    solution = penumbra.solve("cornell")
    positions, normals = penumbra.sensors.read_csv("points.csv")
    irradiance = penumbra.sensors.evaluate(solution, "cornell", positions, normals)
    penumbra.sensors.write_csv("values.csv", positions, normals, irradiance)

A sensor file has a header line naming the columns x, y, z, nx, ny, nz (in
any order; other columns are ignored) and one sensor per line. The values
file repeats those six columns and adds irradiance_r, irradiance_g,
irradiance_b (W m^-2, or lux when the scene's Emission is luminance in
cd m^-2). Direct light is exact at every sensor, indirect light comes from
the solution (vtkPenumbraSensorEvaluator).
"""
import csv

import numpy as np

COLUMNS = ("x", "y", "z", "nx", "ny", "nz")
VALUE_COLUMNS = ("irradiance_r", "irradiance_g", "irradiance_b")


def read_csv(path):
    """Positions and normals (two n x 3 arrays) of the sensors in `path`.
    Raises penumbra.PenumbraError naming the file and line of any problem."""
    import penumbra

    try:
        with open(path, newline="") as stream:
            rows = list(csv.reader(stream))
    except (OSError, UnicodeDecodeError) as error:
        raise penumbra.PenumbraError("cannot read sensors from %s: %s" % (path, error))
    if not rows:
        raise penumbra.PenumbraError("%s: empty (expected a header line %s)"
                                     % (path, ",".join(COLUMNS)))
    header = [name.strip().lower() for name in rows[0]]
    missing = [name for name in COLUMNS if name not in header]
    if missing:
        raise penumbra.PenumbraError("%s line 1: the header has no column %s (expected %s)"
                                     % (path, missing[0], ",".join(COLUMNS)))
    index = [header.index(name) for name in COLUMNS]
    values = []
    for number, row in enumerate(rows[1:], start=2):
        if not row or all(not cell.strip() for cell in row):
            continue  # blank lines
        try:
            numbers = [float(row[k]) for k in index]
        except IndexError:
            raise penumbra.PenumbraError("%s line %d: %d columns, the header has %d"
                                         % (path, number, len(row), len(header)))
        except ValueError:
            raise penumbra.PenumbraError("%s line %d: not a number in %s"
                                         % (path, number, ",".join(row)))
        if not np.isfinite(numbers).all():
            raise penumbra.PenumbraError("%s line %d: not a finite number in %s"
                                         % (path, number, ",".join(row)))
        if np.linalg.norm(numbers[3:]) <= 0.0:
            raise penumbra.PenumbraError("%s line %d: the normal (nx, ny, nz) is zero"
                                         % (path, number))
        values.append(numbers)
    if not values:
        raise penumbra.PenumbraError("%s: no sensors after the header" % path)
    values = np.array(values, dtype=float)
    return values[:, :3], values[:, 3:]


def write_csv(path, positions, normals, irradiance):
    """The values file: the sensors' columns and their irradiance."""
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(COLUMNS + VALUE_COLUMNS)
        for p, n, e in zip(positions, normals, irradiance):
            writer.writerow(["%.17g" % v for v in tuple(p) + tuple(n) + tuple(e)])


def evaluate(solution, scene, positions, normals, direct_only=False):
    """Irradiance (n x 3) at the sensors, from the scene's emitters (exact)
    and the solution's reflected light (none with direct_only, or when
    `solution` is None). `scene` is a built-in name, a file or a scene
    vtkPolyData; `solution` the vtkPolyData penumbra.solve returned for it."""
    import penumbra
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    positions = np.ascontiguousarray(positions, dtype=float).reshape(-1, 3)
    normals = np.ascontiguousarray(normals, dtype=float).reshape(-1, 3)
    if positions.shape != normals.shape:
        raise penumbra.PenumbraError("%d sensor positions but %d normals"
                                     % (len(positions), len(normals)))
    sensors = vtkPolyData()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(positions, deep=True))
    sensors.SetPoints(points)
    normal_array = numpy_to_vtk(normals, deep=True)
    normal_array.SetName("Normals")
    sensors.GetPointData().AddArray(normal_array)
    scene_data = scene if isinstance(scene, vtkPolyData) else penumbra.load_scene(scene)
    evaluator = penumbra.vtkPenumbraSensorEvaluator()
    evaluator.SetInputData(0, sensors)
    evaluator.SetInputData(1, scene_data)
    if solution is not None and not direct_only:
        evaluator.SetInputData(2, solution)
    output = penumbra.run_filter(evaluator)
    return vtk_to_numpy(output.GetPointData().GetArray("Irradiance")).copy()
