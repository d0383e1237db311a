# SPDX-License-Identifier: GPL-3.0-or-later
"""One source of defaults: every filter's settings, their documentation and the
generated settings page agree.

- A setting that two filters share (the composed solver and the stage it configures, or
  the two solvers) has one default and one range.
- Every setting's documentation states its default, and the default and range it states
  are the filter's.
- Documentation/settings.md is what `penumbra settings --markdown` generates now.
- The command line's help takes its defaults from the filters.
"""
import os
import re
import subprocess

import pytest

import penumbra
from penumbra import settings as S
from conftest import BUILD_DIR, SOURCE_DIR

ALL = [(class_name, s) for class_name in S.FILTERS for s in S.filter_settings(class_name)]


def test_shared_settings_have_one_default_and_range():
    by_name = {}
    for class_name, s in ALL:
        by_name.setdefault(s.name, []).append((class_name, s))
    shared = {name: entries for name, entries in by_name.items() if len(entries) > 1}
    assert "ExactPowerFraction" in shared and "SubdivisionLevel" in shared
    problems = []
    for name, entries in sorted(shared.items()):
        first_class, first = entries[0]
        for class_name, s in entries[1:]:
            if (s.default, s.minimum, s.maximum) != (first.default, first.minimum, first.maximum):
                problems.append("%s: %s has %s %s, %s has %s %s" % (
                    name, first_class, first.formatted_default(), first.formatted_range(),
                    class_name, s.formatted_default(), s.formatted_range()))
    assert not problems, "\n".join(problems)


NUMBER = r"-?(?:\d+/\d+|\d+(?:\.\d*)?(?:e[-+]?\d+)?)"


def _number(text):
    if "/" in text:
        numerator, denominator = text.split("/")
        return float(numerator) / float(denominator)
    return float(text)


def stated_default(doc):
    """The default a setting's documentation states, as text, or None."""
    for pattern in (r"\bDefault:? (\"[^\"]*\"|on|off|empty|" + NUMBER + r")",
                    r"\b([A-Z_]+) \(\d+, default\)", r"\((on|off), the default\)"):
        match = re.search(pattern, doc)
        if match:
            return match.group(1)
    return None


def stated_range(doc):
    match = re.search(r"\brange \[(" + NUMBER + r"), (" + NUMBER + r")\]", doc)
    return (_number(match.group(1)), _number(match.group(2))) if match else None


def _matches(text, value, cls, name):
    if isinstance(value, bool):
        return text == ("on" if value else "off")
    if isinstance(value, str):
        return text in ('"%s"' % value, "empty" if value == "" else None)
    if re.fullmatch(NUMBER, text):
        number = _number(text)
        return abs(number - value) <= 1e-12 * max(1.0, abs(value))
    # An enumeration: the name is a class constant with the default's value.
    return getattr(cls, text, None) == value


@pytest.mark.parametrize("class_name,setting", ALL,
                         ids=["%s.%s" % (c, s.name) for c, s in ALL])
def test_documentation_states_the_default_and_range(class_name, setting):
    cls = getattr(penumbra, class_name)
    text = stated_default(setting.doc)
    assert text is not None, "%s::%s documents no default: %s" % (class_name, setting.name,
                                                                  setting.doc)
    assert _matches(text, setting.default, cls, setting.name), (
        "%s::%s: documented default %s, actual %s" % (class_name, setting.name, text,
                                                      setting.formatted_default()))
    if setting.minimum is not None and (isinstance(setting.default, float)
                                        or stated_range(setting.doc) is not None):
        assert stated_range(setting.doc) == pytest.approx((setting.minimum, setting.maximum)), (
            "%s::%s: documented range %s, actual %s" % (class_name, setting.name,
                                                       stated_range(setting.doc),
                                                       setting.formatted_range()))


def test_settings_page_is_generated():
    with open(os.path.join(SOURCE_DIR, "Documentation", "settings.md")) as stream:
        page = stream.read()
    assert page.rstrip("\n") == S.markdown().rstrip("\n"), (
        "Documentation/settings.md is out of date: regenerate it with "
        "`penumbra settings --markdown > Documentation/settings.md`")


def test_command_line_help_shows_the_filters_defaults():
    out = subprocess.run([os.path.join(BUILD_DIR, "bin", "penumbra"), "solve", "--help"],
                         stdout=subprocess.PIPE, universal_newlines=True, check=True).stdout
    out = " ".join(out.split())
    unshot = penumbra.vtkPenumbraSolver().GetUnshotFraction()
    element = penumbra.vtkPenumbraStandardRadiositySolver().GetElementSize()
    assert "(default %g)" % unshot in out and "(default %g)" % element in out, out


@pytest.mark.parametrize("class_name", S.FILTERS)
def test_print_self_prints_every_setting(class_name):
    instance = getattr(penumbra, class_name)()
    printed = str(instance)
    missing = [s.name for s in S.filter_settings(class_name) if "%s:" % s.name not in printed]
    assert not missing, "%s::PrintSelf omits %s" % (class_name, ", ".join(missing))
