#!/usr/bin/env bash
# Installs hencky's Debian dependencies (and nothing else) and configures + builds a Release build.
# Usage: scripts/setup.sh [build-dir]       (run as root on Debian 12)
# HENCKY_EXTRA_PACKAGES: more Debian packages to install with them (bench/setup.sh: CalculiX).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
read -r -a extra <<< "${HENCKY_EXTRA_PACKAGES:-}"
bash "$here/scripts/install-packages.sh" "$here/scripts/packages.txt" "${extra[@]}"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release ${HENCKY_CMAKE_ARGS:-}
cmake --build "$build" -j"$(nproc)"
