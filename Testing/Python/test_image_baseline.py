# SPDX-License-Identifier: GPL-3.0-or-later
"""Python baseline image tests with vtk.test.Testing (needs an X display:
ctest runs under xvfb-run)."""
import os

import pytest
from vtkmodules.test import Testing

import penumbra
from penumbra.rendering import make_render_window
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
