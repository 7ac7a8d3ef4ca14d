#!/usr/bin/env bash
# Sets everything up (Debian packages, Release build with warnings as errors) and runs the
# whole test suite. This is what CI runs (.ci/run).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${HENCKY_BUILD_DIR:-$here/build}"
HENCKY_CMAKE_ARGS="-DHENCKY_WERROR=ON ${HENCKY_CMAKE_ARGS:-}" "$here/scripts/setup.sh" "$build"
cd "$build"
# Tests run two at a time on this 2-core class of machine: idle OpenMP threads must sleep,
# not spin, or the two test processes slow each other down many times over.
export OMP_WAIT_POLICY=PASSIVE
ctest --output-on-failure -j"$(nproc)" --timeout 900
