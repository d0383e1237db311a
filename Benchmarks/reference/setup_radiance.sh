#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
#
# Creates (idempotently) the Python venv holding Radiance, the lighting
# simulator used as a peer: PyPI's pyradiance wheel bundles the Radiance
# binaries (oconv, rtrace, ...) and their library files.
#
#   Benchmarks/reference/setup_radiance.sh [VENV_DIR]
#
# VENV_DIR defaults to build/_deps/radiance-venv under the repository root.
# Prints the folder of the binaries last.
set -euo pipefail

PYRADIANCE_VERSION=1.3.1

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
venv="${1:-$repo/build/_deps/radiance-venv}"
source "$here/ensure_python_venv.sh"
if [ ! -x "$venv/bin/python" ]; then
  /usr/bin/python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import pyradiance" 2>/dev/null; then
  "$venv/bin/pip" install -q "pyradiance==$PYRADIANCE_VERSION"
fi
"$venv/bin/python" -c "import os, pyradiance; print(os.path.join(os.path.dirname(pyradiance.__file__), 'bin'))"
