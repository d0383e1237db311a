# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes PenumbraParaView.xml, the ParaView plugin (run by the build and by
`cmake --install`).

    generate_paraview_plugin.py --query PENUMBRA --command PENUMBRA \
        --python PYTHON --runtime RUNTIME.py --version V -o PenumbraParaView.xml

The plugin is server-manager XML only: two proxies of ParaView's
vtkPythonProgrammableFilter whose script (penumbra_paraview_runtime.py) runs
the `penumbra` command in its own process. XML plugins load in every
ParaView built with Python, through Tools > Manage Plugins as through
LoadPlugin, without ParaView's Python plugin loader (which fails on
Python 3.11 in ParaView 5.11). Scene names and the solver's settings, with
their defaults, ranges and documentation, come from the command the build
made (`penumbra scenes --json`, `penumbra settings --json`), so the panel's
defaults are the filters' own and never drift. COMMAND is the command the
plugin runs: the build tree's or the install prefix's.
"""
import argparse
import json
import subprocess
import sys
from xml.sax.saxutils import escape, quoteattr

# Settings of vtkPenumbraSolver shown in the panel, in this order; the others
# keep their defaults.
SOLVER_SETTINGS = ("Indirect", "UnshotFraction", "SamplingTolerance", "ExactPowerFraction",
                   "MaximumIndirectSamples", "MaximumSamples", "MaximumSampleSpacing",
                   "SecondaryShooterFraction",
                   "ReuseTransport", "MinimumAngle", "DisplayTolerance", "CompactTolerance",
                   "CompactIndirectTolerance", "SubdivisionLevel")
METHODS = ("discontinuity", "standard")


def query(python, command, *arguments):
    done = subprocess.run([python, command] + list(arguments), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, universal_newlines=True, check=False)
    if done.returncode != 0:
        sys.exit("generate_paraview_plugin: %s %s failed: %s"
                 % (command, " ".join(arguments), done.stderr.strip()))
    return json.loads(done.stdout)


def documentation(text):
    return "<Documentation>%s</Documentation>" % escape(text)


def parameter_xml(name, parameter, default, doc, minimum=None, maximum=None):
    """One property passed to the script as the variable `parameter`."""
    common = ('name="%s" command="SetParameter" initial_string="%s" number_of_elements="1"'
              % (name, parameter))
    if isinstance(default, bool):
        return ('<IntVectorProperty %s default_values="%d"><BooleanDomain name="bool"/>%s'
                '</IntVectorProperty>' % (common, int(default), documentation(doc)))
    kind = "Int" if isinstance(default, int) else "Double"
    domain = ""
    if minimum is not None:
        domain = '<%sRangeDomain name="range" min="%r" max="%r"/>' % (kind, minimum, maximum)
    return ('<%sVectorProperty %s default_values="%r">%s%s</%sVectorProperty>'
            % (kind, common, default, domain, documentation(doc), kind))


def enumeration_xml(name, parameter, entries, default, doc):
    values = "".join('<Entry value="%d" text="%s"/>' % (k, escape(text))
                     for k, text in enumerate(entries))
    return ('<IntVectorProperty name="%s" command="SetParameter" initial_string="%s" '
            'number_of_elements="1" default_values="%d"><EnumerationDomain name="enum">%s'
            '</EnumerationDomain>%s</IntVectorProperty>'
            % (name, parameter, default, values, documentation(doc)))


def script_xml(script):
    return ('<StringVectorProperty name="Script" command="SetScript" number_of_elements="1" '
            'panel_visibility="never" default_values=%s/>' % quoteattr(script))


OUTPUT_TYPE_XML = ('<IntVectorProperty name="OutputDataSetType" command="SetOutputDataSetType" '
                   'number_of_elements="1" default_values="0" panel_visibility="never"/>')


def proxy_xml(name, label, doc, properties):
    return ('<SourceProxy name="%s" class="vtkPythonProgrammableFilter" label="%s">'
            '%s%s%s<Hints><ShowInMenu category="Penumbra"/></Hints></SourceProxy>'
            % (name, label, documentation(doc), "".join(properties), OUTPUT_TYPE_XML))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--query", required=True, help="the penumbra command to ask")
    parser.add_argument("--command", required=True, help="the penumbra command to run")
    parser.add_argument("--python", required=True, help="the interpreter that runs it")
    parser.add_argument("--runtime", required=True, help="penumbra_paraview_runtime.py")
    parser.add_argument("--version", required=True)
    parser.add_argument("-o", "--output", required=True)
    arguments = parser.parse_args()

    scenes = query(arguments.python, arguments.query, "scenes", "--json")
    solver = {s["name"]: s for s in
              query(arguments.python, arguments.query, "settings", "--json")["vtkPenumbraSolver"]}
    missing = [name for name in SOLVER_SETTINGS if name not in solver]
    if missing:
        sys.exit("generate_paraview_plugin: vtkPenumbraSolver has no setting %s" % missing[0])
    with open(arguments.runtime) as runtime_file:
        runtime = runtime_file.read()
    preamble = "COMMAND = %r\nPYTHON = %r\n" % (arguments.command, arguments.python)
    scene_names = [s["name"] for s in scenes]

    scene_call = ("run_scene(self, %r[scene_index], file_name)\n" % (scene_names,))
    scene_properties = [
        enumeration_xml("Scene", "scene_index", scene_names,
                        scene_names.index("cornell") if "cornell" in scene_names else 0,
                        "The built-in scene: " + "; ".join(
                            "%s: %s" % (s["name"], s["description"]) for s in scenes)),
        '<StringVectorProperty name="FileName" command="SetParameter" initial_string="file_name" '
        'number_of_elements="1" default_values=""><FileListDomain name="files"/><Hints>'
        '<FileChooser extensions="obj gltf glb vtp" file_description="Penumbra scenes"/></Hints>'
        + documentation("A scene file (.obj with its .mtl, .gltf or .glb, or .vtp with the data "
                        "contract's cell arrays) instead of the built-in scene; empty: the built-in "
                        "scene.") + '</StringVectorProperty>',
        script_xml(preamble + runtime + scene_call)]

    defaults = {name: solver[name]["default"] for name in SOLVER_SETTINGS}
    solve_call = ("run_solve(self, %r[method_index], threads, {%s}, %r)\n"
                  % (METHODS, ", ".join("%r: %s" % (n, n) for n in SOLVER_SETTINGS), defaults))
    solve_properties = [
        '<InputProperty name="Input" command="SetInputConnection"><ProxyGroupDomain '
        'name="groups"><Group name="sources"/><Group name="filters"/></ProxyGroupDomain>'
        '<DataTypeDomain name="input_type"><DataType value="vtkPolyData"/></DataTypeDomain>'
        + documentation("A scene: polygons with the cell arrays Reflectance and Emission "
                        "(see the data contract).") + '</InputProperty>',
        enumeration_xml("Method", "method_index", METHODS, 0,
                        "discontinuity (default): the paper's discontinuity meshing pipeline, "
                        "vtkPenumbraSolver; standard: the baseline it beat (uniform mesh, "
                        "progressive refinement); with it only UnshotFraction applies."),
        parameter_xml("Threads", "threads", 0, "Worker threads of the solve; 0 (default): "
                      "all cores.", 0, 256)]
    for name in SOLVER_SETTINGS:
        setting = solver[name]
        solve_properties.append(parameter_xml(name, name, setting["default"], setting["doc"],
                                              setting["minimum"], setting["maximum"]))
    solve_properties.append(script_xml(preamble + runtime + solve_call))

    xml = ('<ServerManagerConfiguration>\n<!-- Penumbra %s: generated by '
           'generate_paraview_plugin.py from the penumbra command; do not edit. -->\n'
           '<ProxyGroup name="sources">\n%s\n</ProxyGroup>\n<ProxyGroup name="filters">\n%s\n'
           '</ProxyGroup>\n</ServerManagerConfiguration>\n'
           % (arguments.version,
              proxy_xml("PenumbraScene", "Penumbra Scene",
                        "A Penumbra scene: a built-in scene, or an .obj, .gltf, .glb or .vtp "
                        "scene file.",
                        scene_properties),
              proxy_xml("PenumbraSolve", "Penumbra Solve",
                        "Penumbra's radiosity solution of the input scene (vtkPenumbraSolver, "
                        "or the standard radiosity baseline), computed by the penumbra "
                        "command in its own process.", solve_properties)))
    with open(arguments.output, "w") as output:
        output.write(xml)


if __name__ == "__main__":
    main()
