#!/usr/bin/env bash
# What checkpoints cost (issue 19): the strip with a hole (examples/plate-hole-overload, 10
# steps, every step written) on a refined mesh, with output.checkpoint off and on (every step),
# REPEAT times each, alternating; the medians of the total and output seconds and of the disk
# use, and a restart from the middle, into bench/results/checkpoint-<date>.md.
#
# Usage: run_checkpoint_bench.sh HENCKY_BINARY [N_ARC] [REPEAT]
#   N_ARC: elements per 45-degree arc of the strip's .geo (default 24; the example has 12)
set -eu
bin="$(readlink -f "${1:?usage: run_checkpoint_bench.sh HENCKY_BINARY [N_ARC] [REPEAT]}")"
n_arc="${2:-24}"
repeat="${3:-3}"
here="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$here/examples/plate-hole-overload/case.yaml" "$here/examples/plate-hole-overload/plate.geo" "$work/"
sed -E -i "s/^n = [0-9]+;/n = $n_arc;/" "$work/plate.geo"
sed -E 's/^output:/output:\n  checkpoint: off/' "$work/case.yaml" >"$work/off.yaml"
sed -E 's/^output:/output:\n  checkpoint: 1/' "$work/case.yaml" >"$work/on.yaml"
for i in $(seq "$repeat"); do
  for v in off on; do
    "$bin" run "$work/$v.yaml" --quiet -o "$work/$v-$i.out"
    du -sb "$work/$v-$i.out" | cut -f1 >"$work/$v-$i.bytes"
  done
done
# A restart at step 5 of the last run with checkpoints: its time to the end.
"$bin" run "$work/on.yaml" --quiet --restart "$work/on-$repeat.out" --from 0.8 -o "$work/restart.out"
out="$here/bench/results/checkpoint-$(date +%Y%m%d-%H%M%S).md"
/usr/bin/python3 - "$work" "$repeat" "$n_arc" "$out" <<'PY'
import json, statistics, sys
work, repeat, n_arc, out = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
def runs(v):
    s = [json.load(open(f"{work}/{v}-{i}.out/summary.json")) for i in range(1, repeat + 1)]
    b = [int(open(f"{work}/{v}-{i}.bytes").read()) for i in range(1, repeat + 1)]
    return s, b
off, off_b = runs("off")
on, on_b = runs("on")
r = json.load(open(f"{work}/restart.out/summary.json"))
med = lambda xs: statistics.median(xs)
t = lambda ss, k: med([s["wall_seconds"][k] for s in ss])
lines = [
    f"# Checkpoint cost: strip with a hole, n = {n_arc}",
    "",
    f"{off[0]['elements']} elements, {off[0]['nodes']} nodes, {off[0]['integration_points']} "
    f"integration points, {off[0]['steps']} steps, every step written; medians of {repeat} runs "
    "each, alternating, in one session.",
    "",
    "| output.checkpoint | total s | output s | disk MB |",
    "|---|---:|---:|---:|",
    f"| off | {t(off, 'total'):.2f} | {t(off, 'output'):.2f} | {med(off_b) / 1e6:.1f} |",
    f"| every step | {t(on, 'total'):.2f} | {t(on, 'output'):.2f} | {med(on_b) / 1e6:.1f} |",
    "",
    f"Ratio of totals (on / off): {t(on, 'total') / t(off, 'total'):.3f}; checkpoints add "
    f"{(t(on, 'output') - t(off, 'output')) / on[0]['steps']:.3f} s per step.",
    f"A restart from step {r['restart']['step']} to the end: {r['wall_seconds']['total']:.2f} s "
    f"({r['steps'] - r['restart']['step']} steps).",
]
open(out, "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
