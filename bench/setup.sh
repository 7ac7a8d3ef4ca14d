#!/usr/bin/env bash
# Installs what the benchmarks need beyond scripts/packages.txt (calculix-ccx, time for /usr/bin/time -v),
# then the project's own packages and a Release build in build-bench (scripts/setup.sh build-bench).
# Usage: bash bench/setup.sh          (run as root on Debian 12, from anywhere)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
pkgs=(calculix-ccx time)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "bench/setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
cd "$here"
bash scripts/setup.sh build-bench
