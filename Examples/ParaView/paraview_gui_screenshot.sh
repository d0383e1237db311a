#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The README's ParaView picture: the real ParaView GUI, on a virtual X
# display, with the plugin's Cornell box solved and the Penumbra Solve
# properties panel, grabbed from the screen.
#
#   Examples/ParaView/paraview_gui_screenshot.sh PLUGIN OUTPUT.png
#
# Needs Xvfb, xwd (x11-apps), xdotool and convert (imagemagick); with Debian's
# ParaView 5.11, python3-paraview on PYTHONPATH (build.sh test unpacks it
# into build/_deps/python3-paraview).
set -euo pipefail
plugin="$(realpath "$1")"
output="$(realpath -m "$2")"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d)"
trap 'kill "${paraview_pid:-}" "${xvfb_pid:-}" 2>/dev/null || true; rm -rf "$work"' EXIT
cat > "$work/gui.py" <<PYTHON
import sys
sys.path.insert(0, "$here")
from paraview import simple
simple.LoadPlugin("$plugin")
scene = simple.PenumbraScene(Scene="cornell")
solve = simple.PenumbraSolve(Input=scene)
solve.UpdatePipeline()
from render_cornell import show_radiance
view = simple.GetActiveViewOrCreate("RenderView")
show_radiance(solve, size=None, view=view)
simple.SetActiveSource(solve)
simple.Render(view)
open("$work/ready", "w").close()
PYTHON
display_number=$((90 + RANDOM % 100))
Xvfb ":$display_number" -screen 0 1130x750x24 >/dev/null 2>&1 &
xvfb_pid=$!
sleep 2
DISPLAY=":$display_number" paraview --script="$work/gui.py" >"$work/paraview.log" 2>&1 &
paraview_pid=$!
for _ in $(seq 300); do
  [ -f "$work/ready" ] && break
  sleep 1
done
[ -f "$work/ready" ] || { cat "$work/paraview.log"; exit 1; }
sleep 3
# ParaView 5.11 opens its welcome dialog once the startup script has run.
# Close it with its button (where it sits on this screen size).
DISPLAY=":$display_number" xdotool mousemove 892 576 click 1 2>/dev/null || true
sleep 3  # let the GUI paint
DISPLAY=":$display_number" xwd -root -silent | convert xwd:- "$output"
echo "wrote $output"
