#!/usr/bin/env bash
# Sets everything up (Debian packages, Release build with warnings as errors) and runs the
# whole test suite; then the sanitizer stage (scripts/sanitize.sh: unit tests, CLI checks and
# a few seconds of fuzzing per reader, under ASan + UBSan). This is what CI runs (.ci/run).
# HENCKY_SANITIZE_STAGE=0 skips the sanitizer stage.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${HENCKY_BUILD_DIR:-$here/build}"
HENCKY_CMAKE_ARGS="-DHENCKY_WERROR=ON ${HENCKY_CMAKE_ARGS:-}" "$here/scripts/setup.sh" "$build"
(
  cd "$build"
  # Tests run two at a time on this 2-core class of machine: idle OpenMP threads must sleep,
  # not spin, or the two test processes slow each other down many times over.
  export OMP_WAIT_POLICY=PASSIVE
  ctest --output-on-failure -j"$(nproc)" --timeout 900
)
if [ "${HENCKY_SANITIZE_STAGE:-1}" != 0 ]; then
  HENCKY_SANITIZE_BUILD_DIR="${HENCKY_SANITIZE_BUILD_DIR:-$build-san}" bash "$here/scripts/sanitize.sh"
fi
