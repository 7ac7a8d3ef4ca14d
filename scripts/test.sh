#!/usr/bin/env bash
# Sets everything up (Debian packages, Release build with warnings as errors) and runs the
# whole test suite. This is what CI runs (.ci/run).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${HENCKY_BUILD_DIR:-$here/build}"
HENCKY_CMAKE_ARGS="-DHENCKY_WERROR=ON ${HENCKY_CMAKE_ARGS:-}" "$here/scripts/setup.sh" "$build"
cd "$build"
ctest --output-on-failure -j"$(nproc)" --timeout 900
