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
    vtkPenumbraOBJReader,
    vtkPenumbraSceneSource,
    vtkPenumbraSceneValidator,
)

__version__ = "0.1.0"


class PenumbraError(RuntimeError):
    """Bad input or settings; the message names the offending cell or setting."""


def scenes():
    """The built-in scenes as a list of (name, description) pairs."""
    source = vtkPenumbraSceneSource
    return [(source.GetSceneName(i), source.GetSceneDescription(i))
            for i in range(source.GetNumberOfScenes())]


def run_filter(algorithm):
    """Update `algorithm` and raise PenumbraError with VTK's error message if it fails.

    VTK reports errors through ErrorEvent rather than exceptions; this turns
    the first error into a Python exception and keeps it off the terminal.
    """
    messages = []

    def on_error(_caller, _event, message=None):
        messages.append(str(message) if message is not None else "unknown error")

    on_error.CallDataType = vtkmodules.vtkCommonCore.VTK_STRING
    tag = algorithm.AddObserver(vtkmodules.vtkCommonCore.vtkCommand.ErrorEvent, on_error)
    executive_tag = algorithm.GetExecutive().AddObserver(
        vtkmodules.vtkCommonCore.vtkCommand.ErrorEvent, on_error)
    try:
        algorithm.Update()
    finally:
        algorithm.RemoveObserver(tag)
        algorithm.GetExecutive().RemoveObserver(executive_tag)
    if messages:
        raise PenumbraError(_strip_vtk_prefix(messages[0]))
    return algorithm.GetOutputDataObject(0)


def _strip_vtk_prefix(message):
    # VTK prefixes "ERROR: In file, line N\nvtkClass (0x...): "; keep the text.
    text = message.strip().splitlines()[-1] if message.strip() else message
    if "): " in text:
        text = text.split("): ", 1)[1]
    return text.strip()


def load_scene(scene):
    """A validated scene vtkPolyData from a built-in name, a .vtp or an .obj path.

    Raises PenumbraError naming the offending cell, array or line.
    """
    import os
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    names = [name for name, _ in scenes()]
    if scene in names:
        reader = vtkPenumbraSceneSource()
        reader.SetSceneName(scene)
    elif scene.lower().endswith(".obj"):
        if not os.path.isfile(scene):
            raise PenumbraError("scene file not found: %s" % scene)
        reader = vtkPenumbraOBJReader()
        reader.SetFileName(scene)
    elif scene.lower().endswith(".vtp"):
        if not os.path.isfile(scene):
            raise PenumbraError("scene file not found: %s" % scene)
        reader = vtkXMLPolyDataReader()
        reader.SetFileName(scene)
    else:
        raise PenumbraError(
            "unknown scene '%s': give a built-in name (%s) or a .vtp/.obj file"
            % (scene, ", ".join(names)))
    run_filter(reader)
    validator = vtkPenumbraSceneValidator()
    validator.SetInputConnection(reader.GetOutputPort())
    return run_filter(validator)
