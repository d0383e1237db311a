# SPDX-License-Identifier: GPL-3.0-or-later
"""No light leaks where the interreflections are computed on the coarse level.

furnished_room(1000) has strip lights hung 5 mm below the ceiling (the ceiling
behind them is lit only through that gap), bookcases 1 cm in front of walls
and legs standing on the floor. The solve uses the coarse indirect level (fewer
points shot on than samples); at the leak probes of the stored path-traced
reference (Benchmarks/reference/furnished_room_1000_seed0.npz, independent of
Penumbra) the solution's mean, relative to the surrounding surface's mean,
must match the reference's within that surface's accuracy target (2% of the
mean for walls and floors, 3% for the ceiling). A leak interpolated across a
fixture's back or into the gap behind a bookcase gives tens of percent.
"""
import os
import sys

import numpy as np
import pytest

import penumbra
from penumbra.generators import furnished_room

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCHMARKS = os.path.join(SOURCE, "Benchmarks")
REFERENCE = os.path.join(BENCHMARKS, "reference", "furnished_room_1000_seed0.npz")

#: Leak group -> (surrounding group, accuracy target relative to its mean).
TARGETS = {"gap": ("wall", 0.02), "behind_light": ("ceiling", 0.03), "contact": ("floor", 0.02)}


@pytest.fixture(scope="module")
def solution():
    sys.path.insert(0, BENCHMARKS)
    from scale_benchmark import probe_errors

    scene = furnished_room(1000, seed=0)
    result = penumbra.solve(scene, threads=2)
    return result, probe_errors(result, scene, np.load(REFERENCE))


def test_the_coarse_level_is_used(solution):
    result, _ = solution
    field = result.GetFieldData()
    shot_on = field.GetArray("IndirectSamples").GetValue(0)
    samples = field.GetArray("Evaluations").GetValue(0)
    assert 0 < shot_on < samples


@pytest.mark.parametrize("leak", [
    "behind_light", "gap",
    # The floor 2-5 mm from legs gets 0.540 of the floor's mean against the
    # reference's 0.505: the coarse level does not follow the legs' contact
    # shadows of interreflected light (Documentation/benchmarks.md, "Large
    # scenes"). Strict: the test reports when that is fixed.
    pytest.param("contact", marks=pytest.mark.xfail(
        strict=True, reason="contact shadows of interreflected light on the coarse level"))])
def test_leak_places_are_as_dark_as_the_reference(solution, leak):
    _, errors = solution
    host, target = TARGETS[leak]
    found = errors[leak]["solution_over_host"]
    expected = errors[leak]["reference_over_host"]
    print("%s: %.4f of the %s's mean, reference %.4f" % (leak, found, host, expected))
    assert abs(found - expected) <= target
