#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
#
# Creates (idempotently) the Python venv in which mitsuba_cornell.py renders
# the path-traced reference, and checks which Mitsuba variant works here.
#
#   Benchmarks/reference/setup_mitsuba.sh [VENV_DIR] [--install-llvm]
#
# VENV_DIR defaults to build/_deps/mitsuba-venv under the repository root. The
# venv is made by Debian's /usr/bin/python3 with --system-site-packages, so
# that it also sees python3-vtk9 and python3-numpy (mitsuba_cornell.py builds
# the scene from Penumbra's own polydata).
#
# Variants: scalar_rgb needs nothing more. llvm_ad_rgb (vectorised, several
# times faster) needs a libLLVM that Dr.Jit can generate code with: Debian
# 12's libllvm15 (installed with Mesa) loads but aborts at code generation
# ("LLVM ERROR: Cannot select: ... fminimum"); libllvm19 from bookworm's main
# archive (1:19.1.7-3~deb12u1) works. With --install-llvm, and as root, this
# script installs it with apt-get; otherwise it only says so and the
# reference script falls back to scalar_rgb.
#
# Prints the best working variant last and writes it to
# VENV_DIR/penumbra-mitsuba-variant.
set -euo pipefail

MITSUBA_VERSION=3.9.1
DRJIT_VERSION=1.5.0

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
venv="$repo/build/_deps/mitsuba-venv"
install_llvm=0
for arg in "$@"; do
  case "$arg" in
    --install-llvm) install_llvm=1 ;;
    -h|--help) sed -n '3,24p' "$0"; exit 0 ;;
    -*) echo "unknown option: $arg" >&2; exit 2 ;;
    *) venv="$arg" ;;
  esac
done

source "$here/ensure_python_venv.sh"
if [ ! -x "$venv/bin/python" ]; then
  echo "creating venv $venv"
  mkdir -p "$(dirname "$venv")"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
py="$venv/bin/python"

if ! "$py" - "$MITSUBA_VERSION" "$DRJIT_VERSION" 2>/dev/null <<'PY'
import sys
import drjit, mitsuba
sys.exit(0 if (mitsuba.__version__, drjit.__version__) == tuple(sys.argv[1:3]) else 1)
PY
then
  echo "installing mitsuba==$MITSUBA_VERSION drjit==$DRJIT_VERSION into $venv"
  "$py" -m pip install --disable-pip-version-check --quiet \
    "mitsuba==$MITSUBA_VERSION" "drjit==$DRJIT_VERSION"
fi

probe() { "$py" "$here/mitsuba_cornell.py" --probe "$1" 2>&1 | grep -v '^[[:space:]]*\(0x\|$\)' | tail -n 3; return "${PIPESTATUS[0]}"; }

if ! probe scalar_rgb; then
  echo "error: Mitsuba's scalar_rgb variant does not work in $venv" >&2
  exit 1
fi

have_llvm19() { compgen -G "/usr/lib/*-linux-gnu/libLLVM*.so*" >/dev/null && \
  ls /usr/lib/*-linux-gnu/libLLVM*.so* 2>/dev/null | grep -Eq 'libLLVM(-|\.so\.)(19|[2-9][0-9])'; }

if ! have_llvm19; then
  candidate=$(apt-cache policy libllvm19 2>/dev/null | sed -n 's/^ *Candidate: *//p')
  if [ -z "$candidate" ] || [ "$candidate" = "(none)" ]; then
    echo "note: libllvm19 is not available from the configured APT sources" \
         "(run apt-get update first?): llvm_ad_rgb may not work, scalar_rgb will be used"
  elif [ "$install_llvm" = 1 ] && [ "$(id -u)" = 0 ]; then
    echo "installing libllvm19 $candidate for Mitsuba's llvm_ad_rgb variant"
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends libllvm19 >/dev/null
  else
    echo "note: llvm_ad_rgb needs libllvm19 ($candidate in Debian's archive):" \
         "apt-get install libllvm19 (or rerun with --install-llvm as root)"
  fi
fi

variant=scalar_rgb
if probe llvm_ad_rgb; then
  variant=llvm_ad_rgb
else
  echo "llvm_ad_rgb does not work here; mitsuba_cornell.py will use scalar_rgb"
fi
echo "$variant" > "$venv/penumbra-mitsuba-variant"
echo "variant: $variant"
