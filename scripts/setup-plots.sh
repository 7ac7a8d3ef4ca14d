#!/usr/bin/env bash
# Installs the Debian packages of scripts/render.py (ParaView, headless through xvfb) and of the
# examples' plot.py scripts (matplotlib), listed in scripts/plot-packages.txt.
# Usage: scripts/setup-plots.sh       (run as root on Debian 12)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bash "$here/scripts/install-packages.sh" "$here/scripts/plot-packages.txt"
