# SPDX-License-Identifier: GPL-3.0-or-later
"""What the plugin's proxies run inside ParaView (the body of their
vtkPythonProgrammableFilter script; generate_paraview_plugin.py puts this file
into PenumbraParaView.xml, followed by the call of run_scene or run_solve).

ParaView runs its own VTK, and Penumbra is built against the system's: two
VTKs must never share a process. So this runs Penumbra's command line
(`penumbra scene`, `penumbra solve`) in a separate process on temporary
files, relays its progress to ParaView's progress bar, stops it on Abort or
when ParaView exits, and reads the result with ParaView's own XML reader.
It uses only the Python standard library and ParaView's vtkmodules, and
keeps to the Python of older ParaView releases (3.6).

COMMAND and PYTHON are set by the generator before this text.
"""
import os
import queue
import shutil
import subprocess
import tempfile
import threading

from vtkmodules.vtkCommonCore import vtkOutputWindow
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter


def penumbra_environment():
    """ParaView's Python paths would load ParaView's VTK into the command."""
    env = dict(os.environ)
    for name in ("PYTHONPATH", "PYTHONHOME"):
        env.pop(name, None)
    return env


def penumbra_die_with_parent():
    """In the command's process: end when ParaView ends (Linux), so that
    closing ParaView during a solve leaves no solver running."""
    try:
        import ctypes
        import signal
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def penumbra_error(message):
    vtkOutputWindow.GetInstance().DisplayErrorText(message + "\n")


def penumbra_command(algorithm, arguments):
    """Run the penumbra command with progress relayed and Abort honoured.
    Returns None on success, "aborted", or the command's one-line error."""
    command = os.environ.get("PENUMBRA_COMMAND") or COMMAND
    python = os.environ.get("PENUMBRA_PYTHON") or PYTHON
    try:
        process = subprocess.Popen([python, command] + arguments, env=penumbra_environment(),
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                   universal_newlines=True, preexec_fn=penumbra_die_with_parent)
    except OSError as error:
        return "cannot run %s: %s" % (command, error)
    lines = queue.Queue()

    def forward():
        for line in process.stderr:
            lines.put(line)

    reader = threading.Thread(target=forward, daemon=True)
    reader.start()
    messages = []
    while True:
        try:
            line = lines.get(timeout=0.1)
        except queue.Empty:
            line = None
        if line is not None:
            words = line.split(None, 2)
            if len(words) >= 2 and words[0] == "progress":
                algorithm.UpdateProgress(float(words[1]))
            else:
                messages.append(line.strip())
        if algorithm.GetAbortExecute():
            process.terminate()
            process.wait()
            return "aborted"
        if line is None and process.poll() is not None and lines.empty():
            break
    reader.join()
    if process.wait() == 0:
        return None
    failures = [m for m in messages if m.startswith("penumbra: error:")]
    if failures:
        return failures[-1][len("penumbra: error:"):].strip()
    return "the penumbra command failed: %s" % " ".join(messages[-3:])


def penumbra_run(algorithm, label, arguments_for, scene=None):
    """The common frame: a temporary folder (removed whatever happens), the
    input written there if there is one, the command run, the result read
    into the algorithm's output. On error: the message, an empty output."""
    algorithm.SetProgressText(label)  # ParaView's status bar names the filter
    output = algorithm.GetOutputDataObject(0)
    output.Initialize()  # the programmable filter starts from a copy of its input
    folder = tempfile.mkdtemp(prefix="penumbra-")
    try:
        if scene is not None:
            source = os.path.join(folder, "scene.vtp")
            writer = vtkXMLPolyDataWriter()
            writer.SetFileName(source)
            writer.SetInputData(scene)
            writer.SetDataModeToBinary()
            if not writer.Write():
                penumbra_error("%s: could not write the scene to %s" % (label, source))
                return
        else:
            source = None
        result = os.path.join(folder, "result.vtp")
        failure = penumbra_command(algorithm, arguments_for(source, result))
        if failure == "aborted":
            return  # stopped by the user: an empty output, not an error
        if failure is not None:
            penumbra_error("%s: %s" % (label, failure))
            return
        reader = vtkXMLPolyDataReader()
        reader.SetFileName(result)
        reader.Update()
        output.ShallowCopy(reader.GetOutput())
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def run_scene(algorithm, scene_name, file_name):
    """Penumbra Scene: a built-in scene, or a scene file when one is given."""
    scene = file_name or scene_name
    penumbra_run(algorithm, "Penumbra Scene",
                 lambda _source, result: ["scene", scene, "-o", result])


def run_solve(algorithm, method, threads, values, defaults):
    """Penumbra Solve on the algorithm's input. Settings at their default
    are left to the solver (its own default is the same by construction)."""

    def arguments_for(source, result):
        arguments = ["solve", source, "-o", result, "--progress-lines", "--method", method]
        if threads > 0:
            arguments += ["--threads", str(threads)]
        for name in sorted(values):
            value, default = values[name], defaults[name]
            if isinstance(default, bool):
                value = bool(value)
            if value == default:
                continue
            if method == "standard" and name != "UnshotFraction":
                continue  # a setting of the discontinuity method
            if name == "UnshotFraction":
                arguments += ["--unshot-fraction", repr(value)]
            else:
                text = ("on" if value else "off") if isinstance(value, bool) else repr(value)
                arguments += ["--set", "%s=%s" % (name, text)]
        return arguments

    penumbra_run(algorithm, "Penumbra Solve", arguments_for,
                 scene=algorithm.GetInputDataObject(0, 0))
