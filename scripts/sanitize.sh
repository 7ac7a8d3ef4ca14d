#!/usr/bin/env bash
# The sanitizer stage of CI (scripts/test.sh runs it after the Release tests): one clang build,
# RelWithDebInfo under AddressSanitizer + UndefinedBehaviorSanitizer, with the libFuzzer
# targets of fuzz/. It runs the unit tests, the CLI checks and each fuzz corpus, then a few
# seconds of fuzzing per target (scripts/fuzz.sh --smoke). The verification tests are not
# built, and the CLI checks that solve the most are left out (HENCKY_CLI_SKIP below): under the
# sanitizers they take half an hour and more (docs/development.md, "Sanitizers in CI").
# Usage: scripts/sanitize.sh [--build-only | --all]      (run as root on Debian 12)
#   --all: every CLI check too (about half an hour more)
# HENCKY_SANITIZE_BUILD_DIR: the build directory (build-san).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${HENCKY_SANITIZE_BUILD_DIR:-$here/build-san}"
bash "$here/scripts/install-packages.sh" "$here/scripts/packages.txt"
bash "$here/scripts/install-packages.sh" "$here/scripts/sanitize-packages.txt"
# -gline-tables-only: file:line in the reports is all the debug information they need, and it
# builds faster than -g. NDEBUG as in the Release build: Eigen's index checks on every
# coefficient access would slow the tests several times over, and ASan checks the accesses.
# -O1, ASan's own advice, compiled 14 % less CPU time but ran the unit tests 60 % longer.
flags="-O2 -gline-tables-only -DNDEBUG"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" \
  -DHENCKY_SANITIZE=ON -DHENCKY_FUZZ=ON -DHENCKY_VERIFICATION=OFF -DHENCKY_WERROR=ON
cmake --build "$build" -j"$(nproc)"
[ "${1:-}" = "--build-only" ] && exit 0

. "$here/scripts/sanitize-env.sh"
cd "$build"
export OMP_WAIT_POLICY=PASSIVE  # as in scripts/test.sh: two tests at a time on two cores
# Left out, as measured under the sanitizers on the shared 2-core machine (2026-11-26): the
# examples 517 s, the updated geometry 593 s, the MPI runs 403 s, the converging defaults 224 s,
# the heat analyses 195 s; the restarts of 60_restart.sh solve as much (every scheme, MPI
# ranks, signals); 80_inp.sh's runs of each deck are solves too (the deck reader itself is
# sanitized by its unit tests and its fuzz corpus). The checks kept (bad input, outputs, the crashes of issue 14, bad meshes)
# took 60 s, beside the unit tests.
if [ "${1:-}" != "--all" ]; then
  export HENCKY_CLI_SKIP="10_examples 40_parallel 45_converging_defaults 50_updated_geometry 55_heat 60_restart 80_inp"
  # and the runs on MPI ranks of the other case files (47's split mesh, 82's nodal forces):
  # tests/cli/cases/05_helpers.sh, with_mpi.
  export HENCKY_CLI_NO_MPI=1
fi
ctest --output-on-failure -j"$(nproc)"
# 3 s a target, two at a time: the corpora are replayed by ctest above; this is a few thousand
# new inputs per reader, the long runs are scripts/fuzz.sh --long.
bash "$here/scripts/fuzz.sh" --smoke 3
