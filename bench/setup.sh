#!/usr/bin/env bash
# Installs what the benchmarks need beyond scripts/packages.txt (calculix-ccx, calculix-ccx-test
# for its test decks (bench/run_beampiso.sh), and time for
# /usr/bin/time -v) together with the project's own packages, and makes a Release build in
# build-bench: scripts/setup.sh with HENCKY_EXTRA_PACKAGES.
# Usage: bash bench/setup.sh          (run as root on Debian 12, from anywhere)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
HENCKY_EXTRA_PACKAGES="calculix-ccx calculix-ccx-test time ${HENCKY_EXTRA_PACKAGES:-}" \
  exec bash "$here/scripts/setup.sh" "$here/build-bench"
