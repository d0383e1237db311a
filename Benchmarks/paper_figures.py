#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The paper's Figs. 5 and 6 in 3D: the seven-occluder floor, new method against standard radiosity.

    PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
        Benchmarks/paper_figures.py [--out Documentation/images] [--size 800 400] [--threads 2]

Solves the `seven` scene (direct light only: its light does not reflect and
its occluders face away from the floor) twice:

- discontinuity meshing, the default pipeline without the shooter
  (build_pipeline(..., indirect=False): exact evaluation, adaptive
  sampling, cubic reconstruction);
- standard radiosity (penumbra.solve(method="standard")) at the element
  size among ELEMENT_SIZES whose floor has the number of vertices closest
  to the number of sample points of the new method's floor (the points of
  the evaluator's output), shooter samples scaled with the element size as
  in speed_accuracy.py.

Draws the part of the floor over --region (x and z bounds, metres; the
counts in the captions are of the whole floor), side by side at one
exposure (the new method's):

- OUT/seven_samples.png: the floors with their samples marked as dots (the
  new method: the evaluator's output points on the floor; standard
  radiosity: its mesh vertices on the floor), as in the paper's Fig. 5;
- OUT/seven_floor.png: the same without marks, as in Fig. 6.

Prints the sample counts, element size and solve times. Needs an X
display: run under xvfb-run.
"""
import argparse
import os
import sys
import time

import numpy as np

# Candidate initial element sizes of standard radiosity (relative to the
# scene's size); the one closest in floor sample count is drawn.
ELEMENT_SIZES = (0.05, 0.035, 0.025, 0.018, 0.0125, 0.009)
FLOOR = 0  # the floor is surface 0 of the built-in scenes
# The part of the 6 m x 6 m floor drawn: five of the seven shadows, large
# enough on the picture for the samples to be told apart.
REGION = (-2.2, 1.0, -1.6, 1.6)


def shooter_samples(element_size):
    """Visibility rays per side of a shooting patch, refined with the mesh as
    in speed_accuracy.py (h = 0.1: 2, 0.05: 4, 0.025: 8, 0.0125: 16)."""
    return int(min(16, max(2, round(0.2 / element_size))))


def solve_new(scene):
    """The default pipeline, direct light only; returns (result, evaluator
    output, seconds)."""
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    import penumbra
    from penumbra.pipeline import build_pipeline

    source = vtkTrivialProducer()
    source.SetOutput(scene)
    stages = build_pipeline(source.GetOutputPort(), indirect=False)
    start = time.perf_counter()
    result = penumbra.run_filter(stages["reconstructor"])
    seconds = time.perf_counter() - start
    return result, stages["evaluator"].GetOutput(), seconds


def solve_standard(scene, floor_samples):
    """Standard radiosity at the candidate element size whose floor vertex
    count is closest to `floor_samples`; returns (result, element size,
    seconds)."""
    import penumbra
    from penumbra.rendering import extract_surface

    best = None
    for size in ELEMENT_SIZES:
        start = time.perf_counter()
        result = penumbra.solve(scene, method="standard", element_size=size,
                                shooter_samples=shooter_samples(size))
        seconds = time.perf_counter() - start
        count = extract_surface(result, FLOOR).GetNumberOfPoints()
        gap = abs(np.log(count / floor_samples))
        if best is None or gap < best[0]:
            best = (gap, result, size, seconds)
        if count > floor_samples:
            break  # the sizes decrease: the next ones are only further away
    return best[1:]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--out", default=os.path.join(os.path.dirname(here), "Documentation",
                                                      "images"))
    parser.add_argument("--size", type=int, nargs=2, default=(800, 400))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--region", type=float, nargs=4, default=REGION,
                        metavar=("X0", "X1", "Z0", "Z1"),
                        help="the part of the floor drawn (default %s; the whole floor: "
                             "-3 3 -3 3)" % " ".join("%g" % v for v in REGION))
    args = parser.parse_args()

    from vtkmodules.vtkCommonCore import vtkSMPTools

    import penumbra
    from penumbra.rendering import extract_surface, make_comparison_window, save_window_png

    vtkSMPTools.Initialize(args.threads)
    scene = penumbra.load_scene("seven")
    new, evaluated, new_seconds = solve_new(scene)
    new_samples = extract_surface(evaluated, FLOOR)
    count = new_samples.GetNumberOfPoints()
    evaluations = int(evaluated.GetFieldData().GetArray("Evaluations").GetValue(0))
    standard, element_size, standard_seconds = solve_standard(scene, count)
    standard_samples = extract_surface(standard, FLOOR)
    print("new method: %d floor samples (%d evaluations in all), %.2f s"
          % (count, evaluations, new_seconds))
    print("standard radiosity: element size %g, %d shooter samples, %d floor vertices, %.2f s"
          % (element_size, shooter_samples(element_size), standard_samples.GetNumberOfPoints(),
             standard_seconds))

    os.makedirs(args.out, exist_ok=True)
    x0, x1, z0, z1 = args.region
    view = (x0, x1, 0.0, 0.0, z0, z1)
    titles = ["discontinuity meshing: %d samples" % count,
              "standard radiosity: %d vertices" % standard_samples.GetNumberOfPoints()]
    supersampling = 3
    big = [supersampling * n for n in args.size]
    for name, marks in (("seven_samples.png", [new_samples, standard_samples]),
                        ("seven_floor.png", None)):
        window = make_comparison_window([new, standard], FLOOR, size=big, titles=titles,
                                        marks=marks, mark_size=1.5 * supersampling,
                                        view_bounds=view)
        path = os.path.join(args.out, name)
        save_window_png(window, path, args.size)
        window.Finalize()
        print("wrote %s (%d bytes)" % (path, os.path.getsize(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
