# SPDX-License-Identifier: GPL-3.0-or-later
"""The `penumbra` command line.

    penumbra solve SCENE -o OUT.vtp|.gltf|.glb|.ply [--png OUT.png] [--threads N]
                   [--method discontinuity|standard] [--set NAME=VALUE ...]
                   [--sensors POINTS.csv --sensors-out VALUES.csv]
    penumbra scene SCENE -o OUT.vtp|.gltf|.glb
    penumbra scenes [--json]
    penumbra settings [--markdown | --json]
    penumbra info OUT.vtp
    penumbra render IN.vtp -o OUT.png [--camera auto|cornell|X,Y,Z:FX,FY,FZ[:UX,UY,UZ]]

SCENE is a built-in scene name (see `penumbra scenes`) or a .vtp/.obj/.gltf/.glb file
following Penumbra's data contract. Exit status 0 on success, 2 for usage
errors, 1 for bad input or a failed solve, with a one-line message on
standard error; repaired input gives one warning line per kind of repair.
"""
import argparse
import os
import sys
import time


class ProgressBar:
    """A progress bar on standard error fed by VTK ProgressEvents.

    Draws in place on a terminal; elsewhere (logs, CI) prints one line per
    10% so that long work still shows life without flooding the log.
    """

    def __init__(self, label, stream=None, enabled=True):
        self.label = label
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.interactive = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.last_decile = -1

    def attach(self, algorithm):
        from vtkmodules.vtkCommonCore import vtkCommand

        algorithm.AddObserver(vtkCommand.ProgressEvent,
                              lambda caller, _event: self.update(caller.GetProgress(),
                                                                 caller.GetProgressText()))

    def update(self, fraction, text=None):
        if not self.enabled:
            return
        fraction = min(max(float(fraction), 0.0), 1.0)
        detail = " %s" % text if text else ""
        if self.interactive:
            filled = int(round(30 * fraction))
            self.stream.write("\r%s [%s%s] %3d%%%s" % (self.label, "#" * filled,
                                                       "." * (30 - filled),
                                                       int(100 * fraction), detail[:40]))
            if fraction >= 1.0:
                self.stream.write("\n")
            self.stream.flush()
        else:
            decile = int(10 * fraction)
            if decile != self.last_decile:
                self.last_decile = decile
                self.stream.write("%s %3d%%%s\n" % (self.label, 10 * decile, detail))
                self.stream.flush()


USAGE_ERROR = 2
INPUT_ERROR = 1


def _fail(message, status=INPUT_ERROR):
    sys.stderr.write("penumbra: error: %s\n" % " ".join(str(message).split()))
    return status


def _show_warnings():
    """Print PenumbraWarnings as one line each on standard error, each once."""
    import warnings
    from penumbra import PenumbraWarning

    shown = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        if not issubclass(category, PenumbraWarning):
            text = "%s: %s" % (category.__name__, text)
        if text not in shown:
            shown.add(text)
            sys.stderr.write("penumbra: warning: %s\n" % text)

    warnings.showwarning = show
    warnings.simplefilter("always", PenumbraWarning)


def _command_scenes(args):
    import penumbra

    if args.json:
        import json
        print(json.dumps([{"name": name, "description": description}
                          for name, description in penumbra.scenes()]))
        return 0
    for name, description in penumbra.scenes():
        print("%-10s %s" % (name, description))
    return 0


def _command_scene(args):
    import penumbra
    from . import export

    export.check_scene_path(args.output)
    scene = penumbra.load_scene(args.scene, strict=args.strict)
    export.write_scene(scene, args.output)
    print("wrote %s (%d polygons)" % (args.output, scene.GetNumberOfCells()))
    return 0


def _command_settings(args):
    from penumbra import settings

    if args.markdown:
        print(settings.markdown())
        return 0
    if args.json:
        import json
        print(json.dumps(settings.as_json()))
        return 0
    for class_name in settings.FILTERS:
        rows = settings.filter_settings(class_name)
        if rows:
            print(class_name)
            for s in rows:
                print("  %-26s %-12s %s" % (s.name, s.formatted_default(), s.formatted_range()))
    return 0


def _command_solve(args):
    import penumbra
    from penumbra import settings as filter_settings
    from . import export

    export.check_result_path(args.output)  # before the solve, not after
    start = time.time()
    bar = ProgressBar("solving", enabled=not args.quiet and not args.progress_lines)
    last = [-1.0]

    def progress(stage, fraction):
        if args.progress_lines and fraction - last[0] >= 0.005:
            last[0] = fraction
            sys.stderr.write("progress %.4f %s\n" % (fraction, stage))
            sys.stderr.flush()
        bar.update(fraction, stage)

    if (args.sensors is None) != (args.sensors_out is None):
        return _fail("--sensors and --sensors-out go together", USAGE_ERROR)
    from . import sensors as sensor_files
    sensors = None
    scene = args.scene
    if args.sensors is not None:
        sensors = sensor_files.read_csv(args.sensors)  # bad files fail before the solve
        # Read once, for the solve and the sensors.
        scene = penumbra.load_scene(args.scene, strict=args.strict)
    settings = {"unshot_fraction": args.unshot_fraction}
    solver_class = ("vtkPenumbraStandardRadiositySolver" if args.method == "standard"
                    else "vtkPenumbraSolver")
    if args.method == "standard":
        for given, option in ((args.direct_only, "--direct-only"),
                              (args.quality, "--quality"), (args.tolerance, "--tolerance"),
                              (args.compact is not None, "--compact"),
                              (args.dense, "--dense")):
            if given:
                return _fail("%s applies to the discontinuity method only" % option,
                             USAGE_ERROR)
        settings["element_size"] = args.element_size
    elif args.element_size is not None:
        return _fail("--element-size applies to --method standard only", USAGE_ERROR)
    else:
        settings["indirect"] = not args.direct_only
        settings["sampling_tolerance"] = args.tolerance
        if args.dense and args.compact is not None:
            return _fail("--dense and --compact exclude each other", USAGE_ERROR)
        if args.compact is not None:
            settings["compact_tolerance"] = args.compact
        if args.dense or args.compact == 0.0:
            settings["compact_tolerance"] = 0.0
            settings["compact_indirect_tolerance"] = 0.0
    for text in args.set or ():  # last: --set Indirect=off means what it says
        name, value = filter_settings.parse(solver_class, text)
        settings[name] = value
    result = penumbra.solve(scene, threads=args.threads, progress=progress,
                            method=args.method, strict=args.strict, quality=args.quality,
                            **settings)
    export.write_result(result, args.output)
    elapsed = time.time() - start
    print("wrote %s (%d triangles, %d boundary lines) in %.2f s"
          % (args.output, result.GetNumberOfPolys(), result.GetNumberOfLines(), elapsed))
    if sensors is not None:
        irradiance = sensor_files.evaluate(result, scene, *sensors)
        sensor_files.write_csv(args.sensors_out, sensors[0], sensors[1], irradiance)
        print("wrote %s (irradiance at %d sensors)" % (args.sensors_out, len(irradiance)))
    from .info import summary_lines
    for line in summary_lines(result):
        print(line)
    if args.png:
        from .rendering import render_png
        camera = "cornell" if args.scene == "cornell" else "auto"
        if args.output.lower().endswith(".vtp"):
            render_png(args.output, args.png, camera=camera)
        else:  # the renderer reads .vtp
            import tempfile
            with tempfile.TemporaryDirectory() as folder:
                vtp = os.path.join(folder, "result.vtp")
                export.write_result(result, vtp)
                render_png(vtp, args.png, camera=camera)
        print("wrote %s" % args.png)
    return 0


def _command_info(args):
    from .info import read_result, report_lines

    if not os.path.isfile(args.input):
        return _fail("file not found: %s" % args.input)
    for line in report_lines(read_result(args.input)):
        print(line)
    return 0


def _command_render(args):
    from .rendering import parse_camera, render_png

    try:
        parse_camera(args.camera)
    except ValueError as error:
        return _fail("--camera: %s" % error, USAGE_ERROR)
    if args.fov is not None and not 1.0 <= args.fov <= 179.0:
        return _fail("--fov must be in [1, 179] degrees, got %g" % args.fov, USAGE_ERROR)
    if not os.path.isfile(args.input):
        return _fail("file not found: %s" % args.input)
    render_png(args.input, args.output, camera=args.camera, size=tuple(args.size),
               exposure=args.exposure, fov=args.fov)
    print("wrote %s" % args.output)
    return 0


def _positive_int(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be a positive integer, got %s" % text)
    return value


def _in_range(setting):
    """An argparse type accepting the values a filter setting accepts."""
    def convert(text):
        value = float(text)
        if not setting.minimum <= value <= setting.maximum:
            raise argparse.ArgumentTypeError("must be in [%g, %g], got %s"
                                             % (setting.minimum, setting.maximum, text))
        return value
    return convert


# The presets' measured cost and accuracy (Benchmarks/compare_cornell.py --quality;
# figures in Documentation/benchmarks.md).
QUALITY_MEASURED = ("draft 1.6 s, floor 0.46% RMS; normal 2.4 s, 0.49%; high 5.2 s, 0.37% "
                    "against a path-traced reference")


def build_parser():
    parser = argparse.ArgumentParser(
        prog="penumbra",
        description="Penumbra: accurate radiosity (discontinuity meshing) for VTK.")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    solve = sub.add_parser("solve", help="solve a scene and write the result as .vtp, .gltf, "
                                         ".glb or .ply",
                           description="Solve SCENE (a built-in name or a .vtp/.obj/.gltf/.glb "
                                       "file) and write the result.")
    solve.add_argument("scene", metavar="SCENE",
                       help="built-in scene name (see 'penumbra scenes') or a "
                            ".vtp/.obj/.gltf/.glb file")
    solve.add_argument("-o", "--output", required=True, metavar="OUT",
                       help="the result, by its extension: .vtp (VTK XML polydata, every "
                            "array), .gltf/.glb (glTF 2.0: triangles with tone-mapped vertex "
                            "colours and the radiance as _RADIANCE) or .ply (triangles with "
                            "8-bit sRGB vertex colours)")
    solve.add_argument("--png", metavar="OUT.png", help="also render a picture of the result")
    solve.add_argument("--threads", type=_positive_int, metavar="N",
                       help="worker threads (default: all cores)")
    solve.add_argument("--method", choices=("discontinuity", "standard"),
                       default="discontinuity",
                       help="'discontinuity' (default): the paper's discontinuity meshing "
                            "pipeline; 'standard': the baseline it beat (uniform mesh, "
                            "progressive refinement, ray-cast form factors, adaptive "
                            "subdivision, Gouraud display)")
    from penumbra import settings as filter_settings
    element_size = filter_settings.find("vtkPenumbraStandardRadiositySolver", "ElementSize")
    unshot = filter_settings.find("vtkPenumbraSolver", "UnshotFraction")
    solve.add_argument("--element-size", type=_in_range(element_size), metavar="S",
                       help="--method standard: longest initial element edge relative to the "
                            "scene's size, in %s (default %s)"
                            % (element_size.formatted_range(), element_size.formatted_default()))
    solve.add_argument("--direct-only", action="store_true",
                       help="direct light only (no progressive shooting)")
    solve.add_argument("--unshot-fraction", "--unshot", dest="unshot_fraction",
                       type=_in_range(unshot), default=None, metavar="F",
                       help="stop shooting when the unshot power is below F times the "
                            "emitted power, in %s (default %s)"
                            % (unshot.formatted_range(), unshot.formatted_default()))
    from penumbra.settings import QUALITY_PRESETS
    tolerance = filter_settings.find("vtkPenumbraSolver", "SamplingTolerance")
    presets = "; ".join("%s: %s" % (name, ", ".join("%s=%g" % kv for kv in values.items())
                                    or "the defaults")
                        for name, values in QUALITY_PRESETS.items())
    solve.add_argument("--quality", choices=tuple(QUALITY_PRESETS), default=None,
                       help="a preset trading time for accuracy (%s). On the Cornell box "
                            "(2 cores): %s" % (presets, QUALITY_MEASURED.replace("%", "%%")))
    solve.add_argument("--tolerance", type=_in_range(tolerance), default=None, metavar="T",
                       help="the adaptive sampling tolerance, relative to each surface's "
                            "light (SamplingTolerance), in %s (default %s); smaller is more "
                            "accurate and slower"
                            % (tolerance.formatted_range(), tolerance.formatted_default()))
    compact = filter_settings.find("vtkPenumbraSolver", "CompactTolerance")
    indirect = filter_settings.find("vtkPenumbraSolver", "CompactIndirectTolerance")
    solve.add_argument("--compact", type=_in_range(compact), nargs="?", const=2e-3,
                       default=None, metavar="T",
                       help="how far the compact output may move from the dense display, "
                            "relative to each surface's mean radiance (CompactTolerance, in %s, "
                            "default %s; T defaults to 2e-3 when not given); where the "
                            "interreflections were shot on the coarse level (large scenes) it "
                            "may also move by %s of the scene's mean indirect radiance "
                            "(CompactIndirectTolerance). By default furnished_room(1000) comes "
                            "out in 0.44 million triangles instead of 3.2 million, as accurate "
                            "against a path-traced reference; --compact 0 is --dense"
                            % (compact.formatted_range(), compact.formatted_default(),
                               indirect.formatted_default()))
    solve.add_argument("--dense", action="store_true",
                       help="the dense display: every sample triangle cut into "
                            "SubdivisionLevel^2 (4) triangles, nothing merged "
                            "(CompactTolerance and CompactIndirectTolerance 0)")
    solve.add_argument("--strict", action="store_true",
                       help="repair nothing: reject non-planar, degenerate and duplicate "
                            "polygons and undefined OBJ materials instead of fixing them")
    solve.add_argument("--set", action="append", metavar="NAME=VALUE",
                       help="any setting of the method's solver filter (vtkPenumbraSolver, or "
                            "vtkPenumbraStandardRadiositySolver with --method standard), e.g. "
                            "--set SamplingTolerance=1e-3; repeatable; 'penumbra settings' "
                            "lists them")
    solve.add_argument("--sensors", metavar="POINTS.csv",
                       help="sensor points: a CSV file with a header line and columns "
                            "x,y,z,nx,ny,nz (anywhere in the scene, facing any way)")
    solve.add_argument("--sensors-out", metavar="VALUES.csv",
                       help="with --sensors: their irradiance (columns x,y,z,nx,ny,nz,"
                            "irradiance_r,irradiance_g,irradiance_b), direct light exact, "
                            "indirect light from the solution")
    solve.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    solve.add_argument("--progress-lines", action="store_true",
                       help="progress for programs: lines 'progress FRACTION STAGE' on "
                            "standard error instead of the bar")
    solve.set_defaults(handler=_command_solve)

    scene = sub.add_parser("scene", help="write a scene (built-in, .vtp, .obj, .gltf or .glb), "
                                         "validated, as .vtp, .gltf or .glb",
                           description="Write SCENE, validated against the data contract, "
                                       "as a VTK XML polydata file or as glTF 2.0 (materials "
                                       "from Reflectance and Emission).")
    scene.add_argument("scene", metavar="SCENE",
                       help="built-in scene name (see 'penumbra scenes') or a "
                            ".vtp/.obj/.gltf/.glb file")
    scene.add_argument("-o", "--output", required=True, metavar="OUT",
                       help="the scene, by its extension: .vtp, .gltf or .glb")
    scene.add_argument("--strict", action="store_true",
                       help="repair nothing: reject what would be repaired")
    scene.set_defaults(handler=_command_scene)

    info = sub.add_parser("info", help="print the record of a solved .vtp",
                          description="Print what a solve recorded in its result: surfaces, "
                                      "samples, triangles, shots, energy balance, estimated "
                                      "error, settings and time per stage.")
    info.add_argument("input", metavar="OUT.vtp")
    info.set_defaults(handler=_command_info)

    scenes = sub.add_parser("scenes", help="list the built-in scenes")
    scenes.add_argument("--json", action="store_true", help="as JSON, for programs")
    scenes.set_defaults(handler=_command_scenes)

    settings = sub.add_parser("settings", help="every filter setting with its default and range")
    output = settings.add_mutually_exclusive_group()
    output.add_argument("--markdown", action="store_true",
                        help="with the descriptions, as Documentation/settings.md")
    output.add_argument("--json", action="store_true",
                        help="with the descriptions, as JSON, for programs")
    settings.set_defaults(handler=_command_settings)

    render = sub.add_parser("render", help="render a .vtp scene or result to PNG")
    render.add_argument("input", metavar="IN.vtp")
    render.add_argument("-o", "--output", required=True, metavar="OUT.png")
    render.add_argument("--camera", default="auto", metavar="CAMERA",
                        help="'auto' (default): inside a closed room, from the room looking "
                             "at its most lit wall; otherwise from outside, framing the "
                             "scene. 'cornell': the Cornell box camera. 'X,Y,Z:FX,FY,FZ' or "
                             "'X,Y,Z:FX,FY,FZ:UX,UY,UZ': eye, focal point and view up "
                             "(default up: +y), in scene units")
    render.add_argument("--fov", type=float, default=None, metavar="DEGREES",
                        help="vertical field of view in degrees, in [1, 179] (default: 70 "
                             "inside rooms and with an explicit camera, 30 from outside)")
    render.add_argument("--size", type=_positive_int, nargs=2, default=(512, 512),
                        metavar=("W", "H"), help="picture size in pixels (default 512 512)")
    render.add_argument("--exposure", type=float, default=None,
                        help="radiance shown as white (default: 99th percentile)")
    render.set_defaults(handler=_command_render)
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        import penumbra
        print("penumbra %s" % penumbra.__version__)
        return 0
    if not getattr(args, "handler", None):
        parser.print_help()
        return 2
    _show_warnings()
    try:
        return args.handler(args)
    except Exception as error:  # one line on stderr, never a traceback, for bad input
        from . import PenumbraError
        from .rendering import RenderError
        if isinstance(error, (PenumbraError, RenderError, OSError, ValueError)):
            return _fail(error, INPUT_ERROR)
        raise
