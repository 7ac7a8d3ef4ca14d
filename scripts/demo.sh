#!/usr/bin/env bash
# Sets everything up and runs the flagship example (a bracket with a bolt hole, thermal and
# mechanical load). Results go to examples/bracket/case.out; open results.pvd in ParaView.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/setup.sh" "$here/build"
"$here/build/hencky" run "$here/examples/bracket/case.yaml"
