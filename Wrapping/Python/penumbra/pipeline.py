# SPDX-License-Identifier: GPL-3.0-or-later
"""The composed Penumbra pipeline: `solve(scene)` wires the filters with good
defaults and returns the result vtkPolyData (design contract: triangles with
`SurfaceId`, point data `Radiance` and `RadianceErrorEstimate`, lines with
`DiscontinuityOrder` and `SourceId`). `solve(scene, method="standard")` runs
the standard radiosity baseline instead (vtkPenumbraStandardRadiositySolver: same
contract, no `RadianceErrorEstimate`)."""

METHODS = ("discontinuity", "standard")
STANDARD_SETTINGS = ("element_size", "patch_size", "subdivision_threshold",
                     "maximum_subdivision_depth", "shooter_samples", "form_factor")
from vtkmodules.vtkCommonDataModel import vtkPolyData


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
                   unshot_fraction=None, exact_power_fraction=None):
    """The filters of the pipeline, connected after `scene_port` (an algorithm
    output port producing a scene), as vtkPenumbraSolver wires them inside
    (settings left None take its defaults). Returns them in order as a dict,
    for whoever needs the stages themselves."""
    import penumbra

    defaults = penumbra.vtkPenumbraSolver()
    minimum_angle = defaults.GetMinimumAngle() if minimum_angle is None else minimum_angle
    subdivision_level = (defaults.GetSubdivisionLevel() if subdivision_level is None
                         else subdivision_level)
    unshot_fraction = defaults.GetUnshotFraction() if unshot_fraction is None else unshot_fraction
    exact_power_fraction = (defaults.GetExactPowerFraction() if exact_power_fraction is None
                            else exact_power_fraction)

    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(scene_port)
    mesher.SetMinimumAngle(minimum_angle)
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputConnection(0, mesher.GetOutputPort())
    evaluator.SetSceneConnection(scene_port)
    stages = {"mesher": mesher, "evaluator": evaluator}
    last = evaluator
    if indirect:
        shooter = penumbra.vtkPenumbraProgressiveShooter()
        shooter.SetInputConnection(0, evaluator.GetOutputPort())
        shooter.SetSceneConnection(scene_port)
        shooter.SetUnshotFraction(unshot_fraction)
        shooter.SetExactPowerFraction(exact_power_fraction)
        stages["shooter"] = shooter
        last = shooter
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputConnection(last.GetOutputPort())
    reconstructor.SetSubdivisionLevel(subdivision_level)
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
    for setter, value in ((solver.SetUnshotFraction, unshot_fraction),
                          (solver.SetElementSize, element_size),
                          (solver.SetPatchSize, patch_size),
                          (solver.SetSubdivisionThreshold, subdivision_threshold),
                          (solver.SetMaximumSubdivisionDepth, maximum_subdivision_depth),
                          (solver.SetShooterSamples, shooter_samples)):
        if value is not None:
            setter(value)
    return {"standard": solver}


def solve(scene, threads=None, minimum_angle=None, subdivision_level=None, indirect=True,
          unshot_fraction=None, exact_power_fraction=None, progress=None,
          method="discontinuity", indirect_samples=None, reuse_transport=None,
          **standard_settings):
    """Solve `scene` (a built-in name, a .vtp/.obj path, or a scene vtkPolyData).

    threads: worker threads (default: all cores). indirect: run the
    progressive shooter for interreflections (False: direct light only);
    unshot_fraction: stop shooting when the unshot power is below this
    fraction of the emitted power. indirect_samples: largest number of
    points the interreflections are shot onto (more samples: a coarse
    level, vtkPenumbraSolver::MaximumIndirectSamples);
    reuse_transport: weak shots as Jacobi sweeps through a transport
    recorded once (vtkPenumbraSolver::ReuseTransport, default on). Settings
    left None keep the defaults of vtkPenumbraSolver (or
    vtkPenumbraStandardRadiositySolver). progress: a callable
    progress(stage_name, fraction) called as the solve runs (fraction of
    the whole solve, from 0 to 1). method:
    "discontinuity" (the default, the paper's method) or "standard" (the
    baseline: uniform mesh, progressive refinement, adaptive subdivision;
    `indirect` must then be True, and standard_settings may set
    element_size, patch_size, subdivision_threshold,
    maximum_subdivision_depth, shooter_samples and form_factor, see
    build_standard).
    Returns the result vtkPolyData; raises penumbra.PenumbraError for bad
    input or settings.
    """
    import penumbra
    from vtkmodules.vtkCommonCore import vtkCommand, vtkSMPTools
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    if method not in METHODS:
        raise penumbra.PenumbraError("unknown method '%s': give one of %s"
                                     % (method, ", ".join(METHODS)))
    if method == "standard" and not indirect:
        raise penumbra.PenumbraError("the standard method always computes the interreflections")
    unknown = set(standard_settings) - set(STANDARD_SETTINGS)
    if unknown or (method != "standard" and standard_settings):
        raise penumbra.PenumbraError(
            "%s: not a setting of the %s method" % (", ".join(sorted(unknown or standard_settings)),
                                                    method))
    if threads is not None:
        vtkSMPTools.Initialize(int(threads))
    if isinstance(scene, vtkPolyData):
        validator = penumbra.vtkPenumbraSceneValidator()
        validator.SetInputData(scene)
        scene_data = penumbra.run_filter(validator)
    else:
        scene_data = penumbra.load_scene(scene)
    if method == "standard":
        source = vtkTrivialProducer()
        source.SetOutput(scene_data)
        algorithm = build_standard(source.GetOutputPort(), unshot_fraction,
                                   **standard_settings)["standard"]
    else:
        # The composed pipeline is the C++ vtkPenumbraSolver (one definition
        # of the defaults for C++, Python and the command line).
        algorithm = penumbra.vtkPenumbraSolver()
        algorithm.SetInputData(scene_data)
        algorithm.SetIndirect(bool(indirect))
        for setter, value in ((algorithm.SetMinimumAngle, minimum_angle),
                              (algorithm.SetSubdivisionLevel, subdivision_level),
                              (algorithm.SetUnshotFraction, unshot_fraction),
                              (algorithm.SetExactPowerFraction, exact_power_fraction),
                              (algorithm.SetMaximumIndirectSamples, indirect_samples),
                              (algorithm.SetReuseTransport, reuse_transport)):
            if value is not None:
                setter(value)
    if progress is not None:
        algorithm.AddObserver(
            vtkCommand.ProgressEvent,
            lambda caller, _event: progress(caller.GetProgressText() or method,
                                            caller.GetProgress()))
    result = vtkPolyData()
    result.ShallowCopy(penumbra.run_filter(algorithm))
    return result
