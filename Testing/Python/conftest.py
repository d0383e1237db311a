# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures of the Python tests: where the source and build trees are,
and a runner for the `penumbra` command."""
import os
import subprocess
import sys

import pytest

SOURCE_DIR = os.environ.get("PENUMBRA_SOURCE_DIR",
                            os.path.dirname(os.path.dirname(os.path.dirname(
                                os.path.abspath(__file__)))))
BUILD_DIR = os.environ.get("PENUMBRA_BUILD_DIR", os.path.join(SOURCE_DIR, "build"))
BASELINE_DIR = os.path.join(SOURCE_DIR, "Testing", "Data", "Baseline")
SCENE_DIR = os.path.join(SOURCE_DIR, "Testing", "Data", "Scenes")


def run_penumbra(*args, cwd=None, env=None):
    """Run `python3 -m penumbra ARGS`; returns the CompletedProcess."""
    return subprocess.run([sys.executable, "-m", "penumbra"] + [str(a) for a in args],
                          cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=600)


@pytest.fixture
def penumbra_cli():
    return run_penumbra


def pytest_terminal_summary(terminalreporter):
    """Tables that tests leave in config.penumbra_report_lines (e.g. the
    adversarial suite's), printed after the results, uncaptured."""
    for line in getattr(terminalreporter.config, "penumbra_report_lines", []):
        terminalreporter.write_line(line)
