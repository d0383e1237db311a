#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Penumbra's two commands, on a fresh Debian 12 machine or an existing checkout:
#   ./build.sh run    install what is missing, build, solve the Cornell box
#                     (writes cornell.vtp and cornell.png in the current folder)
#   ./build.sh test   install what is missing, build, run the whole test suite
# Both are idempotent: packages already present are not reinstalled and an
# existing build folder is reused. BUILD_DIR overrides the build folder.
set -euo pipefail

source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build_dir="${BUILD_DIR:-$source_dir/build}"
mode="${1:-}"
case "$mode" in
  run|test) ;;
  *) echo "usage: $0 run|test" >&2; exit 2 ;;
esac

packages=(
  cmake ninja-build g++ pkg-config
  libvtk9-dev python3-vtk9 vtk9
  libcgal-dev libgmp-dev libmpfr-dev libembree-dev libtbb-dev
  xvfb xauth
  python3-numpy python3-matplotlib python3-pytest python3-hypothesis
)
if [ "$mode" = test ]; then
  packages+=(paraview)
fi

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
fi

# ParaView's Python modules conflict with python3-vtk9 as a package; the
# real-client test uses them unpacked into a private folder instead.
if [ "$mode" = test ]; then
  paraview_python="$build_dir/_deps/python3-paraview"
  if [ ! -d "$paraview_python/usr/lib/python3/dist-packages/paraview" ]; then
    echo "== unpacking python3-paraview into $paraview_python"
    mkdir -p "$paraview_python"
    (cd "$paraview_python" && apt-get download -qq python3-paraview \
      && dpkg-deb -x python3-paraview_*.deb . && rm -f python3-paraview_*.deb)
  fi
fi

if [ ! -f "$build_dir/build.ninja" ]; then
  echo "== configuring in $build_dir"
  cmake -S "$source_dir" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DPython3_EXECUTABLE=/usr/bin/python3
fi
if [ "$mode" = test ] && ! grep -q '^BUILD_TESTING:BOOL=ON' "$build_dir/CMakeCache.txt"; then
  # A build folder configured without the tests (BUILD_TESTING=OFF) gets them.
  cmake -S "$source_dir" -B "$build_dir" -DBUILD_TESTING=ON
fi
echo "== building"
cmake --build "$build_dir"

if [ "$mode" = run ]; then
  "$build_dir/bin/penumbra" solve cornell -o cornell.vtp --png cornell.png
else
  cd "$build_dir"
  xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure --timeout 1500
fi
