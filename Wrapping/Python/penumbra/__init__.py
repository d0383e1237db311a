# SPDX-License-Identifier: GPL-3.0-or-later
"""Penumbra: accurate radiosity for VTK.

The VTK filters of the pipeline are importable from here, e.g.::

    import penumbra
    source = penumbra.vtkPenumbraSceneSource()
    source.SetSceneName("cornell")
    source.Update()

`penumbra.scenes()` lists the built-in scenes; the command line is
`python3 -m penumbra --help`.
"""
# The wrapped classes derive from VTK's: load those modules first.
import vtkmodules.vtkCommonCore  # noqa: F401
import vtkmodules.vtkCommonDataModel  # noqa: F401
import vtkmodules.vtkCommonExecutionModel  # noqa: F401

from .vtkPenumbraFilters import (  # noqa: F401
    vtkPenumbraAlgorithm,
    vtkPenumbraDiscontinuityMesher,
    vtkPenumbraGLTFReader,
    vtkPenumbraOBJReader,
    vtkPenumbraSceneRepair,
    vtkPenumbraSceneSource,
    vtkPenumbraSceneValidator,
    vtkPenumbraSensorEvaluator,
    vtkPenumbraSolver,
    vtkPenumbraProgressiveShooter,
    vtkPenumbraRadianceEvaluator,
    vtkPenumbraRadianceReconstructor,
    vtkPenumbraStandardRadiositySolver,
)

# The stage filters under the names of the paper's stages, without the prefix.
vtkDiscontinuityMesher = vtkPenumbraDiscontinuityMesher
vtkRadianceEvaluator = vtkPenumbraRadianceEvaluator
vtkProgressiveShooter = vtkPenumbraProgressiveShooter
vtkRadianceReconstructor = vtkPenumbraRadianceReconstructor
vtkStandardRadiositySolver = vtkPenumbraStandardRadiositySolver

import os  # noqa: E402

from .pipeline import solve  # noqa: E402,F401

__version__ = "0.1.0"


class PenumbraError(RuntimeError):
    """Bad input or settings; the message names the offending cell or setting."""


class PenumbraWarning(UserWarning):
    """Input that was repaired, or a scene that will come out black or odd.

    Issued through Python's `warnings` module, one line each (e.g. "12
    non-planar polygons triangulated into 24 triangles (largest distance from
    the plane 0.0017)"); `warnings.simplefilter("error", PenumbraWarning)`
    turns them into errors.
    """


def scenes():
    """The built-in scenes as a list of (name, description) pairs."""
    source = vtkPenumbraSceneSource
    return [(source.GetSceneName(i), source.GetSceneDescription(i))
            for i in range(source.GetNumberOfScenes())]


def run_filter(algorithm, context=None, warnings=None):
    """Update `algorithm`; on failure raise PenumbraError with VTK's first error.

    VTK reports errors through ErrorEvent, the output window and its logger
    rather than exceptions. While the algorithm runs, all three are captured
    (nothing reaches the terminal) and the first error becomes the exception's
    message, prefixed with `context` (e.g. a file name) when given. A Penumbra
    filter's warnings (vtkPenumbraAlgorithm.GetWarning) are appended to the
    list `warnings` when given (and dropped otherwise).
    """
    from vtkmodules.vtkCommonCore import (vtkCommand, vtkLogger, vtkOutputWindow,
                                          vtkStringOutputWindow)

    messages = []

    def on_error(_caller, _event, message=None):
        messages.append(str(message) if message is not None else "unknown error")

    on_error.CallDataType = vtkmodules.vtkCommonCore.VTK_STRING
    previous_window = vtkOutputWindow.GetInstance()
    previous_verbosity = vtkLogger.GetCurrentVerbosityCutoff()
    window = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(window)
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    tag = algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
    try:
        algorithm.Update()
    finally:
        algorithm.RemoveObserver(tag)
        vtkOutputWindow.SetInstance(previous_window)
        vtkLogger.SetStderrVerbosity(previous_verbosity)
    if warnings is not None and isinstance(algorithm, vtkPenumbraAlgorithm):
        warnings.extend(algorithm.GetWarning(k) for k in range(algorithm.GetNumberOfWarnings()))
    # The output window holds errors of helper objects (e.g. the XML parser,
    # whose message is the most specific) in order, before the filter's own.
    texts = [vtkPenumbraAlgorithm.ErrorText(m)
             for m in [window.GetOutput()] + messages]
    texts = [t for t in texts if t]
    if texts:
        message = texts[0]
        raise PenumbraError("%s: %s" % (context, message) if context else message)
    return algorithm.GetOutputDataObject(0)


# zlib, the densest compressor VTK writes, packs at most ~1032 bytes into one.
_MAX_EXPANSION = 1100


def _check_vtp_counts(path):
    """Reject element counts that the file cannot hold before VTK allocates them.

    VTK's XML reader trusts NumberOfPoints and friends and aborts the process
    when an absurd count cannot be allocated; each point or cell needs at least
    one byte of (possibly compressed) data, so larger counts are corrupt.
    """
    import re

    size = os.path.getsize(path)
    with open(path, "rb") as stream:
        head = stream.read(1 << 16).decode("latin-1")
    for name, text in re.findall(r'(Number[A-Za-z]*)="([^"]*)"', head):
        if not re.fullmatch(r"\s*\d+\s*", text):
            raise PenumbraError('%s: %s="%s" is not a non-negative integer' % (path, name, text))
        if int(text) > _MAX_EXPANSION * size:
            raise PenumbraError('%s: %s="%s" is more than a %d-byte file can hold'
                                % (path, name, text.strip(), size))


def load_scene(scene, strict=False):
    """A validated scene vtkPolyData from a built-in name or a .vtp, .obj, .gltf or .glb path.

    Imported scenes are repaired where that is safe (vtkPenumbraSceneRepair:
    near-duplicate vertices welded, non-planar polygons triangulated, zero-area
    and duplicate polygons dropped; OBJ materials that are missing get the
    default grey), one PenumbraWarning per kind of repair; strict=True repairs
    nothing and rejects such input. Scenes that will come out black (no
    emitter, emitters facing away or lighting backs) are warned about in both
    modes. Raises PenumbraError naming the offending cell, array or line.
    """
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    names = [name for name, _ in scenes()]
    if scene in names:
        reader = vtkPenumbraSceneSource()
        reader.SetSceneName(scene)
    elif scene.lower().endswith((".obj", ".gltf", ".glb")):
        if not os.path.isfile(scene):
            raise PenumbraError("scene file not found: %s" % scene)
        obj = scene.lower().endswith(".obj")
        reader = vtkPenumbraOBJReader() if obj else vtkPenumbraGLTFReader()
        reader.SetFileName(scene)
        if obj:
            reader.SetStrict(bool(strict))
    elif scene.lower().endswith(".vtp"):
        if not os.path.isfile(scene):
            raise PenumbraError("scene file not found: %s" % scene)
        _check_vtp_counts(scene)
        reader = vtkXMLPolyDataReader()
        reader.SetFileName(scene)
    else:
        raise PenumbraError(
            "unknown scene '%s': give a built-in name (%s) or a .vtp/.obj/.gltf/.glb file"
            % (scene, ", ".join(names)))
    found = []
    # The OBJ and glTF readers name the file themselves; XML errors need it added.
    run_filter(reader, context=scene if scene.lower().endswith(".vtp") else None,
               warnings=found)
    return _repaired(lambda repair: repair.SetInputConnection(reader.GetOutputPort()), strict,
                     None if scene in names else scene, found)


def repair_scene(polydata, strict=False):
    """A scene vtkPolyData repaired and validated as load_scene does for files."""
    return _repaired(lambda repair: repair.SetInputData(polydata), strict)


def _repaired(connect, strict, context=None, found=()):
    """vtkPenumbraSceneRepair's output for the input `connect(repair)` gives it;
    its warnings, after those in `found`, issued as PenumbraWarnings that name
    `context` (a file) when given."""
    import warnings as python_warnings

    repair = vtkPenumbraSceneRepair()
    repair.SetStrict(bool(strict))
    connect(repair)
    found = list(found)
    result = run_filter(repair, context=context, warnings=found)
    for message in found:
        text = message if context is None or message.startswith(context) else (
            "%s: %s" % (context, message))
        python_warnings.warn(text, PenumbraWarning, stacklevel=3)
    return result
