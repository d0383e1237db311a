#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Valgrind memcheck of a whole Cornell-box solve (scene source, mesher,
# evaluator, shooter, reconstructor) by the C++ test program TestCornellSolve.
#   Testing/Scripts/valgrind.sh [build folder, default build]
#     [unshot fraction, default 0.1] [sampling tolerance, default 0.002]
# (the defaults: every direct-light setting as penumbra.solve's, the shooting
# loop stopped early): 33 minutes; "build 0.1 0.05": 5 minutes.
# Uses an existing (Release) build; needs valgrind (apt-get install valgrind).
# Fails when memcheck reports an error or a definite leak. No suppression is
# needed (measured: 0 errors, 0 bytes definitely or indirectly lost). The 336
# bytes "possibly lost" are the thread-local block of a TBB worker thread that
# Embree's rtcCommitScene starts (TBB keeps its pool for the process's life).
set -euo pipefail

source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_dir="${1:-$source_dir/build}"
unshot_fraction="${2:-0.1}"
sampling_tolerance="${3:-0.002}"
ninja -C "$build_dir" -j2 TestCornellSolve

# VTK's sequential SMP backend: valgrind serialises threads anyway, and TBB's
# worker pool would only add its never-freed arenas to the report.
export VTK_SMP_BACKEND_IN_USE=Sequential
valgrind --tool=memcheck --error-exitcode=99 --leak-check=full \
  --show-leak-kinds=definite --errors-for-leak-kinds=definite \
  --track-origins=yes --num-callers=30 \
  "$build_dir/bin/TestCornellSolve" "$unshot_fraction" "$sampling_tolerance"
