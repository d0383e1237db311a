# SPDX-License-Identifier: GPL-3.0-or-later
"""The composed Penumbra pipeline: `solve(scene)` wires the filters with good
defaults and returns the result vtkPolyData (design contract: triangles with
`SurfaceId`, point data `Radiance` and `RadianceErrorEstimate`, lines with
`DiscontinuityOrder` and `SourceId`)."""
from vtkmodules.vtkCommonDataModel import vtkPolyData


def build_pipeline(scene_port, minimum_angle=0.0, subdivision_level=2):
    """The filters of the pipeline, connected after `scene_port` (an algorithm
    output port producing a scene). Returns them in order as a dict."""
    import penumbra

    mesher = penumbra.vtkDiscontinuityMesher()
    mesher.SetInputConnection(scene_port)
    mesher.SetMinimumAngle(minimum_angle)
    evaluator = penumbra.vtkRadianceEvaluator()
    evaluator.SetInputConnection(0, mesher.GetOutputPort())
    evaluator.SetSceneConnection(scene_port)
    reconstructor = penumbra.vtkRadianceReconstructor()
    reconstructor.SetInputConnection(evaluator.GetOutputPort())
    reconstructor.SetSubdivisionLevel(subdivision_level)
    return {"mesher": mesher, "evaluator": evaluator, "reconstructor": reconstructor}


def solve(scene, threads=None, minimum_angle=0.0, subdivision_level=2, progress=None):
    """Solve `scene` (a built-in name, a .vtp/.obj path, or a scene vtkPolyData).

    threads: worker threads (default: all cores). progress: a callable
    progress(stage_name, fraction) called as the stages run. Returns the
    result vtkPolyData; raises penumbra.PenumbraError for bad input.
    """
    import penumbra
    from vtkmodules.vtkCommonCore import vtkCommand, vtkSMPTools
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    if threads is not None:
        vtkSMPTools.Initialize(int(threads))
    if isinstance(scene, vtkPolyData):
        validator = penumbra.vtkPenumbraSceneValidator()
        validator.SetInputData(scene)
        scene_data = penumbra.run_filter(validator)
    else:
        scene_data = penumbra.load_scene(scene)
    source = vtkTrivialProducer()
    source.SetOutput(scene_data)
    stages = build_pipeline(source.GetOutputPort(), minimum_angle, subdivision_level)
    if progress is not None:
        for name, algorithm in stages.items():
            algorithm.AddObserver(
                vtkCommand.ProgressEvent,
                lambda caller, _event, name=name: progress(name, caller.GetProgress()))
    result = vtkPolyData()
    result.ShallowCopy(penumbra.run_filter(stages["reconstructor"]))
    return result
