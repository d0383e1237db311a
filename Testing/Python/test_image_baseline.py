# SPDX-License-Identifier: GPL-3.0-or-later
"""Python baseline image tests with vtk.test.Testing (needs an X display:
ctest runs under xvfb-run)."""
import os

import pytest
from vtkmodules.test import Testing

import penumbra
from penumbra.rendering import make_comparison_window, make_render_window
from conftest import BASELINE_DIR, BUILD_DIR


@pytest.fixture(autouse=True)
def _temp_dir(tmp_path):
    Testing.VTK_TEMP_DIR = str(tmp_path)


def _window(scene_name):
    window = make_render_window(penumbra.load_scene(scene_name), camera="cornell", size=(300, 300))
    window.Render()
    return window


def test_cornell_scene_matches_baseline():
    Testing.compareImage(_window("cornell"),
                         os.path.join(BASELINE_DIR, "TestPythonCornellScene.png"), threshold=0.15)


def test_a_different_picture_fails_the_comparison():
    baseline = os.path.join(BASELINE_DIR, "TestPythonCornellScene.png")
    assert os.path.isfile(baseline), "without the baseline this test would prove nothing"
    with pytest.raises(RuntimeError, match="Failed image test"):
        Testing.compareImage(_window("blind"),
                             os.path.join(BASELINE_DIR, "TestPythonCornellScene.png"),
                             threshold=0.15)


def _seven_floor_reconstructions():
    """The seven-occluder scene's direct light, reconstructed with Clough-Tocher
    (the default) and with Linear interpolation from the same samples, taken
    at a coarse sampling tolerance (5%) where linear interpolation shows its
    Mach bands."""
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer
    from penumbra.pipeline import build_pipeline

    source = vtkTrivialProducer()
    source.SetOutput(penumbra.load_scene("seven"))
    stages = build_pipeline(source.GetOutputPort(), indirect=False)
    stages["evaluator"].SetSamplingTolerance(0.05)
    linear = penumbra.vtkPenumbraRadianceReconstructor()
    linear.SetInputConnection(stages["evaluator"].GetOutputPort())
    linear.SetModeToLinear()
    linear.SetSubdivisionLevel(stages["reconstructor"].GetSubdivisionLevel())
    return [penumbra.run_filter(stages["reconstructor"]), penumbra.run_filter(linear)]


def test_reconstructed_floor_beside_linear_matches_baseline():
    # Left: the piecewise-cubic reconstruction; right: linear interpolation of
    # the same samples, with its Mach bands along the shadow outlines.
    window = make_comparison_window(_seven_floor_reconstructions(), surface_id=0,
                                    size=(800, 400),
                                    titles=["Clough-Tocher", "Linear"])
    window.Render()
    Testing.compareImage(window, os.path.join(BASELINE_DIR, "TestReconstructedFloor.png"),
                         threshold=0.15)


def test_solved_cornell_box_matches_baseline():
    window = make_render_window(penumbra.solve("cornell"), camera="cornell", size=(300, 300))
    window.Render()
    Testing.compareImage(window, os.path.join(BASELINE_DIR, "TestSolvedCornellBox.png"),
                         threshold=0.15)


def _red_pixels(window):
    """Number of pixels of the rendered `window` that are clearly red."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    window.Render()
    grabber = vtkWindowToImageFilter()
    grabber.SetInput(window)
    grabber.ReadFrontBufferOff()
    grabber.Update()
    rgb = vtk_to_numpy(grabber.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
    return int(((rgb[:, 0] > 180) & (rgb[:, 1] < 90) & (rgb[:, 2] < 90)).sum())


def test_comparison_window_marks_points_inside_the_view():
    # The grey floor of the strip scene, direct light: red dots appear where
    # marks are asked for, only inside view_bounds, and nowhere without marks.
    import numpy as np

    solution = penumbra.solve("strip", indirect=False)
    low, high = np.array(solution.GetBounds()[0::2]), np.array(solution.GetBounds()[1::2])
    floor_y = low[1]
    corner = low + 0.25 * (high - low)  # a quarter of the floor, from its low corner
    view = (low[0], corner[0], floor_y, floor_y, low[2], corner[2])
    inside = [(low[0] + f * (corner[0] - low[0]), floor_y, low[2] + g * (corner[2] - low[2]))
              for f in (0.3, 0.7) for g in (0.3, 0.7)]
    outside = [(high[0] - 0.1 * (high[0] - low[0]), floor_y, high[2] - 0.1 * (high[2] - low[2]))]

    def red(marks):
        window = make_comparison_window([solution], surface_id=0, size=(200, 200),
                                        marks=marks, mark_size=6, view_bounds=view)
        count = _red_pixels(window)
        window.Finalize()
        return count

    assert red(None) == 0
    assert red([np.array(outside)]) == 0
    dots = red([np.array(inside)])
    assert 4 * 10 <= dots <= 4 * 60, dots  # four dots about 6 pixels across
