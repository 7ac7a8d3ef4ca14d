#!/usr/bin/env bash
# Installs, with apt, those of the Debian packages listed in FILE (one per line, '#' comments)
# and given as further arguments that are not installed yet.
# Usage: scripts/install-packages.sh FILE [PACKAGE ...]       (run as root on Debian 12)
set -euo pipefail
mapfile -t pkgs < <(grep -v '^#' "$1" | sed '/^$/d')
shift
pkgs+=("$@")
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
