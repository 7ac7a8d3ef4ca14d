#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (built by scripts/sanitize.sh, which it calls first).
# Usage: scripts/fuzz.sh --smoke [SECONDS]          each target SECONDS (5), from its seed
#                                                   corpus; nothing is written to the repo (CI)
#        scripts/fuzz.sh --long SECONDS [TARGET...] each target (all by default) SECONDS; the
#                                                   corpus grows in BUILD/fuzz-work/TARGET and
#                                                   is kept between runs
# Prints each target's executions; a crash, a sanitizer report, a time-out (10 s for one input)
# or 2 GB of memory is a failure, whose input libFuzzer writes to BUILD/fuzz-artifacts/TARGET/.
# Reproduce one with BUILD/fuzz/fuzz_TARGET FILE; once fixed, add the file to fuzz/corpus/TARGET/
# (ctest replays every corpus) and a regression test (docs/development.md, "Fuzzing").
# HENCKY_SANITIZE_BUILD_DIR: the build directory (build-san).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${HENCKY_SANITIZE_BUILD_DIR:-$here/build-san}"
mode="${1:-}"
case "$mode" in
  --smoke) seconds="${2:-5}"; shift $(($# < 2 ? $# : 2)) ;;
  --long) seconds="${2:?usage: fuzz.sh --long SECONDS [TARGET...]}"; shift 2 ;;
  *) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in "$here"/fuzz/fuzz_*.cpp; do n="$(basename "$f" .cpp)"; targets+=("${n#fuzz_}"); done
fi

mkdir -p "$build"
bash "$here/scripts/sanitize.sh" --build-only >"$build/fuzz-build.log" 2>&1 ||
  { cat "$build/fuzz-build.log"; exit 1; }
. "$here/scripts/sanitize-env.sh"

scratch="$(mktemp -d)"; trap 'rm -rf "$scratch"' EXIT
# One target: its libFuzzer run, its log in $scratch/TARGET.log, "ok" or "FAILED" in .status.
fuzz_one() {
  local t="$1" seeds="$here/fuzz/corpus/$1" artifacts="$build/fuzz-artifacts/$1" work args
  mkdir -p "$artifacts"
  if [ "$mode" = --smoke ]; then work="$scratch/$t"; else work="$build/fuzz-work/$t"; fi
  mkdir -p "$work"
  args=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
        -artifact_prefix="$artifacts/")
  [ -f "$here/fuzz/$t.dict" ] && args+=(-dict="$here/fuzz/$t.dict")
  # New inputs go to the first folder, the work corpus; the seeds are only read.
  if "$build/fuzz/fuzz_$t" "${args[@]}" "$work" "$seeds" >"$scratch/$t.log" 2>&1; then
    echo ok >"$scratch/$t.status"
  else
    echo FAILED >"$scratch/$t.status"
  fi
}
# As many targets at a time as there are cores (each libFuzzer run is one process); the
# results are printed in the targets' order once all have run.
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait
failed=()
printf '%-16s %12s %8s %10s %s\n' target executions seconds exec/s corpus
for t in "${targets[@]}"; do
  artifacts="$build/fuzz-artifacts/$t"
  log="$scratch/$t.log"
  status="$(cat "$scratch/$t.status" 2>/dev/null || echo FAILED)"
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  units="$(sed -n 's/.*\bcorp: \([0-9]*\)\/.*/\1/p' "$log" | tail -1)"
  time="$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)"
  rate="-"; [ -n "$runs" ] && [ -n "$time" ] && [ "$time" -gt 0 ] && rate=$((runs / time))
  printf '%-16s %12s %8s %10s %s\n' "$t" "${runs:-?}" "${time:-?}" "$rate" "${units:-?} inputs"
  if [ "$status" = FAILED ]; then
    failed+=("$t")
    cp "$log" "$artifacts/last-failure.log"
    { grep -E "^(==[0-9]+==ERROR|SUMMARY|fuzz:|.*runtime error|terminate called|  what\(\)|Parse)" "$log" || tail -5 "$log"; } | head -20 | sed 's/^/    /'
    echo "    full log: $artifacts/last-failure.log; input: $(ls -t "$artifacts" | grep -v last-failure | head -1)"
  fi
done
if [ ${#failed[@]} -gt 0 ]; then echo "fuzz: FAILED: ${failed[*]}"; exit 1; fi
echo "fuzz: ${#targets[@]} targets, no failure"
