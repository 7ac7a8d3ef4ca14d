#!/usr/bin/env bash
# Installs hencky's Debian dependencies (and nothing else) and configures + builds a Release build.
# Usage: scripts/setup.sh [build-dir]       (run as root on Debian 12)
# HENCKY_EXTRA_PACKAGES: more Debian packages to install with them (bench/setup.sh: CalculiX).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
mapfile -t pkgs < <(grep -v '^#' "$here/scripts/packages.txt" | sed '/^$/d')
read -r -a extra <<< "${HENCKY_EXTRA_PACKAGES:-}"
pkgs+=("${extra[@]}")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release ${HENCKY_CMAKE_ARGS:-}
cmake --build "$build" -j"$(nproc)"
