# SPDX-License-Identifier: GPL-3.0-or-later
"""Illuminance on a work plane, as a lighting designer reads it: a grid of
upward-facing sensors 0.8 m above the floor of a room, written as CSV and
drawn as a map with its minimum, mean and uniformity (min / mean).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
        Examples/Python/work_plane_illuminance.py [OUT.png] [OUT.csv]

The room is a 4 x 4 x 3 m box with grey walls (reflectance 0.5), a lighter
floor and ceiling, and a 1 m^2 ceiling luminaire of luminance 1000 cd/m^2:
Emission in cd/m^2 gives Irradiance in lux.
"""
import sys

import numpy as np

import penumbra
import penumbra.generators as generators
import penumbra.sensors as sensors


def grey_room():
    """penumbra.generators.black_room's geometry with reflecting surfaces."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    scene = generators.black_room(luminance=1000.0)
    # Cells: 0 floor, 1-4 walls, 5-8 ceiling, 9 the luminaire.
    reflectance = np.array([[0.3] * 3] + [[0.5] * 3] * 4 + [[0.8] * 3] * 4 + [[0.0] * 3])
    array = numpy_to_vtk(reflectance, deep=True)
    array.SetName("Reflectance")
    scene.GetCellData().AddArray(array)
    return scene


def main(png="work_plane.png", table="work_plane.csv"):
    scene = grey_room()
    solution = penumbra.solve(scene, threads=2)
    grid = np.arange(0.1, 4.0, 0.2)  # a 20 x 20 grid, 0.1 m from the walls
    positions = np.array([(x, 0.8, z) for z in grid for x in grid])
    normals = np.tile((0.0, 1.0, 0.0), (len(positions), 1))
    lux = sensors.evaluate(solution, scene, positions, normals)[:, 0]
    direct = sensors.evaluate(solution, scene, positions, normals, direct_only=True)[:, 0]
    sensors.write_csv(table, positions, normals, np.repeat(lux[:, None], 3, axis=1))
    print("work plane 0.8 m: mean %.1f lx, min %.1f lx, uniformity %.2f, indirect %.0f%%"
          % (lux.mean(), lux.min(), lux.min() / lux.mean(),
             100.0 * (lux - direct).sum() / lux.sum()))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(figsize=(5.2, 4.2))
    image = axes.imshow(lux.reshape(len(grid), len(grid)), origin="lower", cmap="inferno",
                        extent=(0.0, 4.0, 0.0, 4.0))
    levels = np.linspace(lux.min(), lux.max(), 8)
    axes.contour(grid, grid, lux.reshape(len(grid), len(grid)), levels=levels, colors="white",
                 linewidths=0.5)
    fig.colorbar(image, label="illuminance (lx)")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("z (m)")
    axes.set_title("Work plane 0.8 m: mean %.0f lx, min/mean %.2f" % (lux.mean(),
                                                                     lux.min() / lux.mean()))
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    print("wrote %s and %s" % (png, table))


if __name__ == "__main__":
    main(*sys.argv[1:3])
