# SPDX-License-Identifier: GPL-3.0-or-later
"""The composed Penumbra pipeline: `solve(scene)` wires the filters with good
defaults and returns the result vtkPolyData (design contract: triangles with
`SurfaceId`, point data `Radiance` and `RadianceErrorEstimate`, lines with
`DiscontinuityOrder` and `SourceId`). `solve(scene, method="standard")` runs
the standard radiosity baseline instead (vtkPenumbraStandardRadiositySolver: same
contract, no `RadianceErrorEstimate`)."""

import warnings as python_warnings

from vtkmodules.vtkCommonDataModel import vtkPolyData

METHODS = ("discontinuity", "standard")


def point_samples(points, surface_id):
    """Sample points for vtkPenumbraRadianceEvaluator's input port 0: one vertex cell
    per point (double precision), all on surface `surface_id` (cell data
    `SurfaceId`). The evaluator then gives the radiance at exactly these points."""
    from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray

    data = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    verts = vtkCellArray()
    ids = vtkIntArray()
    ids.SetName("SurfaceId")
    for p in points:
        verts.InsertNextCell(1)
        verts.InsertCellPoint(pts.InsertNextPoint(p))
        ids.InsertNextValue(surface_id)
    data.SetPoints(pts)
    data.SetVerts(verts)
    data.GetCellData().AddArray(ids)
    return data


def build_pipeline(scene_port, minimum_angle=None, subdivision_level=None, indirect=True,
                   unshot_fraction=None, exact_power_fraction=None, display_tolerance=None):
    """The filters of the pipeline, connected after `scene_port` (an algorithm
    output port producing a scene), as vtkPenumbraSolver wires them inside
    (settings left None keep the stages' defaults, which are the solver's).
    Returns them in order as a dict, for whoever needs the stages themselves."""
    import penumbra

    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(scene_port)
    apply_settings(mesher, "vtkPenumbraDiscontinuityMesher", {"minimum_angle": minimum_angle})
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputConnection(0, mesher.GetOutputPort())
    evaluator.SetSceneConnection(scene_port)
    stages = {"mesher": mesher, "evaluator": evaluator}
    last = evaluator
    if indirect:
        shooter = penumbra.vtkPenumbraProgressiveShooter()
        shooter.SetInputConnection(0, evaluator.GetOutputPort())
        shooter.SetSceneConnection(scene_port)
        apply_settings(shooter, "vtkPenumbraProgressiveShooter",
                       {"unshot_fraction": unshot_fraction,
                        "exact_power_fraction": exact_power_fraction})
        stages["shooter"] = shooter
        last = shooter
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputConnection(last.GetOutputPort())
    apply_settings(reconstructor, "vtkPenumbraRadianceReconstructor",
                   {"subdivision_level": subdivision_level,
                    "display_tolerance": display_tolerance})
    stages["reconstructor"] = reconstructor
    return stages


def build_standard(scene_port, unshot_fraction=None, element_size=None, patch_size=None,
                   subdivision_threshold=None, maximum_subdivision_depth=None,
                   shooter_samples=None, form_factor="analytic"):
    """The standard radiosity baseline after `scene_port`, as a one-stage dict
    {"standard": vtkPenumbraStandardRadiositySolver}; None keeps the filter's default.
    form_factor: "analytic" (closed form times the ray-cast visible fraction,
    the default) or "disc" (Wallace et al.'s disc sum, as published)."""
    import penumbra

    solver = penumbra.vtkPenumbraStandardRadiositySolver()
    modes = {"analytic": solver.ANALYTIC_VISIBILITY, "disc": solver.DISC}
    if form_factor not in modes:
        raise penumbra.PenumbraError("form_factor must be 'analytic' or 'disc', got '%s'"
                                     % form_factor)
    solver.SetFormFactorMode(modes[form_factor])
    solver.SetInputConnection(scene_port)
    apply_settings(solver, "vtkPenumbraStandardRadiositySolver",
                   {"unshot_fraction": unshot_fraction, "element_size": element_size,
                    "patch_size": patch_size, "subdivision_threshold": subdivision_threshold,
                    "maximum_subdivision_depth": maximum_subdivision_depth,
                    "shooter_samples": shooter_samples})
    return {"standard": solver}


def setting_names(class_name):
    """{snake_case name: filter setting name} of a filter's settings, e.g.
    {"exact_power_fraction": "ExactPowerFraction", ...}: the Python spelling of
    the filters' names."""
    from penumbra import settings

    return {settings.snake_case(s.name): s.name for s in settings.filter_settings(class_name)}


def apply_settings(algorithm, class_name, values):
    """Set `values` ({snake_case name: value}; None keeps the default) on a filter,
    rejecting names it does not have."""
    import penumbra

    names = setting_names(class_name)
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise penumbra.PenumbraError("%s: not a setting of %s (its settings: %s)"
                                     % (", ".join(unknown), class_name,
                                        ", ".join(sorted(names))))
    for key, value in values.items():
        if value is not None:
            getattr(algorithm, "Set" + names[key])(value)


def solve(scene, threads=None, progress=None, method="discontinuity", strict=False,
          quality=None, **settings):
    """Solve `scene` (a built-in name, a .vtp/.obj/.gltf/.glb path, or a scene vtkPolyData).

    Imported scenes are repaired where that is safe, with a PenumbraWarning
    per kind of repair (see penumbra.load_scene); strict=True rejects them
    instead. The solve's own warnings (each naming its stage) are issued as
    PenumbraWarnings too. quality: "draft", "normal" or "high" (settings.QUALITY_PRESETS,
    discontinuity method only); settings given by name override it.

    threads: worker threads (default: all cores). progress: a callable
    progress(stage_name, fraction) called as the solve runs (fraction of the
    whole solve, from 0 to 1). method: "discontinuity" (the default, the
    paper's method, vtkPenumbraSolver) or "standard" (the baseline:
    vtkPenumbraStandardRadiositySolver; it always computes the
    interreflections).

    settings: any setting of that filter under its snake_case name, e.g.
    indirect=False (direct light only), unshot_fraction=1e-4,
    exact_power_fraction=0.2, maximum_indirect_samples=400000 (or
    indirect_samples=400000),
    sampling_tolerance=5e-4; for the standard method element_size,
    patch_size, ..., and form_factor="analytic" or "disc". Settings left out
    or None keep the filter's defaults (`penumbra settings` lists them).
    Returns the result vtkPolyData; raises penumbra.PenumbraError for bad
    input or settings.
    """
    import penumbra
    from vtkmodules.vtkCommonCore import vtkCommand, vtkSMPTools
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    if "indirect_samples" in settings:  # the short name of maximum_indirect_samples
        settings.setdefault("maximum_indirect_samples", settings.pop("indirect_samples"))
    if method not in METHODS:
        raise penumbra.PenumbraError("unknown method '%s': give one of %s"
                                     % (method, ", ".join(METHODS)))
    if method == "standard" and settings.get("indirect", True) is False:
        raise penumbra.PenumbraError("the standard method always computes the interreflections")
    if method == "standard":
        settings.pop("indirect", None)
    if quality is not None:
        from penumbra.settings import QUALITY_PRESETS, snake_case
        if quality not in QUALITY_PRESETS:
            raise penumbra.PenumbraError("unknown quality '%s': give one of %s"
                                         % (quality, ", ".join(QUALITY_PRESETS)))
        if method == "standard":
            raise penumbra.PenumbraError("quality presets apply to the discontinuity method")
        for name, value in QUALITY_PRESETS[quality].items():
            if settings.get(snake_case(name)) is None:
                settings[snake_case(name)] = value
    if threads is not None:
        vtkSMPTools.Initialize(int(threads))
    if isinstance(scene, vtkPolyData):
        scene_data = penumbra.repair_scene(scene, strict=strict)
    else:
        scene_data = penumbra.load_scene(scene, strict=strict)
    if method == "standard":
        source = vtkTrivialProducer()
        source.SetOutput(scene_data)
        form_factor = settings.pop("form_factor", "analytic")
        algorithm = build_standard(source.GetOutputPort(), form_factor=form_factor)["standard"]
        apply_settings(algorithm, "vtkPenumbraStandardRadiositySolver", settings)
    else:
        # The composed pipeline is the C++ vtkPenumbraSolver (its defaults are
        # the stages', for C++, Python and the command line alike).
        algorithm = penumbra.vtkPenumbraSolver()
        algorithm.SetInputData(scene_data)
        apply_settings(algorithm, "vtkPenumbraSolver", settings)
    if progress is not None:
        algorithm.AddObserver(
            vtkCommand.ProgressEvent,
            lambda caller, _event: progress(caller.GetProgressText() or method,
                                            caller.GetProgress()))
    result = vtkPolyData()
    found = []
    result.ShallowCopy(penumbra.run_filter(algorithm, warnings=found))
    for message in found:
        python_warnings.warn(message, penumbra.PenumbraWarning, stacklevel=2)
    return result
