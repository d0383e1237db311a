# SPDX-License-Identifier: GPL-3.0-or-later
"""Every setting of Penumbra's filters, read from the filters themselves.

The defaults are the filters' (which copy them from the core's settings structs), the
ranges those of their clamped setters, the descriptions their documentation. Used by
`penumbra settings`, which writes Documentation/settings.md.
"""
import re

#: The filters, in pipeline order.
FILTERS = (
    "vtkPenumbraSceneSource",
    "vtkPenumbraOBJReader",
    "vtkPenumbraGLTFReader",
    "vtkPenumbraSceneRepair",
    "vtkPenumbraSceneValidator",
    "vtkPenumbraDiscontinuityMesher",
    "vtkPenumbraRadianceEvaluator",
    "vtkPenumbraProgressiveShooter",
    "vtkPenumbraRadianceReconstructor",
    "vtkPenumbraSolver",
    "vtkPenumbraStandardRadiositySolver",
)


#: `penumbra solve --quality` and `penumbra.solve(quality=...)`: vtkPenumbraSolver
#: settings by name; "normal" is the filters' defaults. Measured on the Cornell box
#: in Documentation/benchmarks.md ("Quality presets").
QUALITY_PRESETS = {
    "draft": {"SamplingTolerance": 1e-2, "UnshotFraction": 3e-3},
    "normal": {},
    "high": {"MaximumSampleSpacing": 1.0 / 64.0, "UnshotFraction": 1e-4},
}


class Setting:
    """One setting of a filter: name, default, range (None when unbounded), doc."""

    def __init__(self, name, default, minimum, maximum, doc):
        self.name = name
        self.default = default
        self.minimum = minimum
        self.maximum = maximum
        self.doc = doc

    def formatted_default(self):
        return format_value(self.default)

    def formatted_range(self):
        if self.minimum is None:
            return ""
        return "[%s, %s]" % (format_value(self.minimum), format_value(self.maximum))


def format_value(value):
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, float):
        return "%.6g" % value
    if value is None:
        return ""
    return str(value)


def _documentation(method):
    """The C++ documentation of a wrapped method: its docstring after the last
    "C++:" signature line."""
    lines = (method.__doc__ or "").splitlines()
    signatures = [k for k, line in enumerate(lines) if line.startswith("C++: ")]
    body = lines[signatures[-1] + 1:] if signatures else lines
    return " ".join(" ".join(body).split())


def filter_settings(class_name):
    """The settings of one filter, in name order: the Set/Get pairs it adds to
    vtkPenumbraAlgorithm (inputs and file names included)."""
    import penumbra

    cls = getattr(penumbra, class_name)
    inherited = set(dir(penumbra.vtkPenumbraAlgorithm))
    own = [name for name in dir(cls) if name not in inherited]
    instance = cls()
    result = []
    for method in own:
        name = method[3:]
        if not method.startswith("Set") or "Get" + name not in own:
            continue
        getter = getattr(instance, "Get" + name)
        try:
            default = getter()
        except TypeError:  # a getter with arguments is not a setting
            continue
        if hasattr(cls, "Get%sMinValue" % name):
            minimum = getattr(instance, "Get%sMinValue" % name)()
            maximum = getattr(instance, "Get%sMaxValue" % name)()
        else:
            minimum = maximum = None
        if isinstance(default, int) and hasattr(cls, "Set%sOn" % name):
            default = bool(default)
        result.append(Setting(name, default, minimum, maximum,
                              _documentation(getattr(cls, method))))
    return result


def find(class_name, name):
    """One setting of a filter (see filter_settings)."""
    return next(s for s in filter_settings(class_name) if s.name == name)


def markdown():
    """Documentation/settings.md: one table per filter."""
    lines = ["# Settings", "",
             "Every setting of every Penumbra filter, with its default and range. Generated "
             "from the filters by `penumbra settings --markdown`; a test checks that this page "
             "is up to date. The defaults are written once, in the core's settings structs "
             "(see [design.md](design.md#settings-and-their-defaults)); Python "
             "(`penumbra.solve`) and the command line take theirs from `vtkPenumbraSolver`.",
             ""]
    for class_name in FILTERS:
        settings = filter_settings(class_name)
        if not settings:
            continue
        lines += ["## %s" % class_name, "",
                  "| setting | default | range | description |",
                  "| --- | --- | --- | --- |"]
        for s in settings:
            lines.append("| `%s` | %s | %s | %s |" % (s.name, s.formatted_default(),
                                                       s.formatted_range(),
                                                       s.doc.replace("|", "\\|")))
        lines.append("")
    return "\n".join(lines)


def snake_case(name):
    """A filter setting's Python spelling: ExactPowerFraction -> exact_power_fraction."""
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def parse(class_name, text):
    """A setting given as text "Name=value" (or "name_in_snake_case=value") for
    a filter: returns (snake_case name, value of the setting's type), or raises
    penumbra.PenumbraError naming the setting (unknown name, a value that is
    not of its type, or out of its range)."""
    import penumbra

    name, sep, value = text.partition("=")
    name, value = name.strip(), value.strip()
    settings = {s.name: s for s in filter_settings(class_name)}
    snake = {snake_case(key): key for key in settings}
    key = name if name in settings else snake.get(name.lower())
    if not sep or key is None:
        raise penumbra.PenumbraError(
            "'%s': give NAME=VALUE with NAME a setting of %s (%s)"
            % (text, class_name, ", ".join(sorted(settings))))
    setting = settings[key]
    try:
        if isinstance(setting.default, bool):
            words = {"on": True, "true": True, "1": True, "off": False, "false": False, "0": False}
            parsed = words[value.lower()]
        elif isinstance(setting.default, int):
            parsed = int(value)
        else:
            parsed = float(value)
    except (KeyError, ValueError):
        raise penumbra.PenumbraError("%s: '%s' is not a %s" % (
            key, value, type(setting.default).__name__)) from None
    if setting.minimum is not None and not setting.minimum <= parsed <= setting.maximum:
        raise penumbra.PenumbraError("%s: %s is outside its range %s"
                                     % (key, value, setting.formatted_range()))
    return snake_case(key), parsed


def as_json(class_names=FILTERS):
    """Every setting of the given filters as JSON-ready dicts (name, default,
    minimum, maximum, doc), per filter: for clients that cannot import the
    filters, such as the ParaView plugin."""
    return {class_name: [{"name": s.name, "default": s.default, "minimum": s.minimum,
                          "maximum": s.maximum, "doc": s.doc}
                         for s in filter_settings(class_name)]
            for class_name in class_names}

