#!/bin/bash
# Issue 17: what the report's choices buy under `solver.geometry: updated`, on the elastica of
# tests/cli/inputs/updated/elastica (PL^2/EI up to 5): correction_form previous (2.30) against
# current (2.31), for meshes of N elements along the beam and S steps. Writes a Markdown table: iterations, the equilibrium defect each step
# leaves on the configuration it reached (the log's "equilibrium defect at t" figure, relative
# to the internal forces: the median over the steps and that of the last step; a step is
# logged at the start of the next, so the last step's is that of the step before the end),
# and the tip deflection's error against
# the elastica at PL^2/EI = 1 and 5 (or the time the run stopped).
# Usage: bench/run_updated_forms.sh BINARY OUT.md [N:S ...]   (default 40:5 40:10 40:50 20:10)
set -u
export ELASTICA="$(cd "$(dirname "$0")/.." && pwd)/tests/tools/elastica.py"
bin="$(realpath "$1")"; out="$2"; shift 2
runs=("$@"); [ ${#runs[@]} -eq 0 ] && runs=(40:5 40:10 40:50 20:10)
src="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
{
  echo "| mesh (elements along) | steps | correction_form | iterations | defect left, median | defect left by the last step | error of v at PL²/EI = 1 | at 5 |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|"
} > "$out"
for run in "${runs[@]}"; do
  n="${run%%:*}"; steps="${run##*:}"
  for form in previous current; do
      d="$work/$n-$steps-$form"; mkdir -p "$d"
      sed "s/^n = [0-9]*;/n = $n;/" "$src/tests/cli/inputs/updated/elastica/beam.geo" > "$d/beam.geo"
      sed "s/^  steps: [0-9]*/  steps: $steps/; s/^  geometry: updated/  geometry: updated\n  correction_form: $form/" \
        "$src/tests/cli/inputs/updated/elastica/case.yaml" > "$d/case.yaml"
      "$bin" run "$d/case.yaml" --quiet > /dev/null 2>&1
      /usr/bin/python3 - "$d" "$n" "$steps" "$form" >> "$out" <<'PY'
import csv, re, statistics, sys
d, n, steps, form = sys.argv[1:]
import importlib.util, os
spec = importlib.util.spec_from_file_location('elastica', os.environ['ELASTICA'])
el = importlib.util.module_from_spec(spec); spec.loader.exec_module(el)
rows = list(csv.DictReader(open(d + '/case.out/history.csv')))
its = sum(int(r['iterations']) for r in rows)
defects = [float(m.group(1)) for m in re.finditer(r'on its configuration: \S+ \((\S+) relative\)', open(d + '/case.out/hencky.log').read())]
def err(alpha):
    for r in rows:
        if abs(5 * float(r['time']) - alpha) < 1e-9:
            return '%+.2e' % (float(r['tip.displacement.y']) / el.elastica(alpha)[1] - 1)
    return 'stopped at t = %s' % rows[-1]['time'][:6]
med = '%.1e' % statistics.median(defects) if defects else '-'
mx = '%.1e' % defects[-1] if defects else '-'
print('| %s | %s | %s | %d | %s | %s | %s | %s |' % (n, steps, form, its, med, mx, err(1), err(5)))
PY
  done
done
cat "$out"
