# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh,
# the mpirun ones among them). Issue 19: checkpoints, restart and interruption.
#  - A run restarted from its checkpoint at step k writes the uninterrupted run's history.csv and
#    fields files byte for byte: elastic steps and plastic ones under every scheme (the strip
#    with a hole), contact (the plastic indentation), heat conduction; on MPI ranks, to the
#    solver's tolerance, on as many ranks as wrote it and on others.
#  - SIGINT keeps the converged steps (exit status 4) and a restart completes the run as if it
#    had not stopped; a second SIGINT stops at once (130) and leaves a directory to restart from.
#  - A checkpoint of a newer format, a damaged one, and a case whose mesh or materials changed
#    are refused with a message that names what is wrong.
rd="$work/restart"
rm -rf "$rd"
mkdir -p "$rd"

# identical NAME DIR_A DIR_B: history.csv and every fields file of A are B's, byte for byte.
identical() {
  local diff="" f
  cmp -s "$2/history.csv" "$3/history.csv" || diff="history.csv"
  for f in "$2"/step_*.vtu; do cmp -s "$f" "$3/$(basename "$f")" || diff="$diff $(basename "$f")"; done
  [ -f "$3/results.pvd" ] && cmp -s "$2/results.pvd" "$3/results.pvd" || diff="$diff results.pvd"
  if [ -z "$diff" ]; then ok "$1"; else bad "$1" "differ: $diff"; fi
}

# --- The strip with a hole (elastic to t = 0.4, plastic to t = 1.1, elastic unloading after):
# restarted at t = 0.4 (elastic), t = 0.8 (plastic) and t = 1.5 (unloading), under each scheme.
cp "$src/examples/plate-hole-overload/case.yaml" "$src/examples/plate-hole-overload/plate.geo" "$rd/"
ex_set "$rd/plate.geo" "^n = 12;" "n = 6;"  # coarser: 6 elements per arc
for scheme in newton initial-stress initial-strain variable-stiffness initial-stress-stiffness \
  initial-strain-stiffness; do
  sed -E "s/^solver:/solver:\n  scheme: $scheme/" "$rd/case.yaml" >"$rd/$scheme.yaml"
  "$bin" run "$rd/$scheme.yaml" --quiet >/dev/null 2>&1 || bad "restart: the $scheme run failed"
  froms="0.8"
  [ "$scheme" = newton ] && froms="0.4 0.8 1.5"
  for from in $froms; do
    expect "restart: $scheme from t = $from" 0 "" -- run "$rd/$scheme.yaml" --quiet \
      --restart "$rd/$scheme.out" --from "$from" -o "$rd/$scheme-$from.out"
    identical "restart: $scheme from t = $from gives the uninterrupted run's results to the bit" \
      "$rd/$scheme.out" "$rd/$scheme-$from.out"
  done
done
ex_check "restart: the summary says where the run continued from" "$rd/newton-0.8.out/summary.json" \
  's["restart"]["step"] == 5 and s["restart"]["time"] == 0.8 and s["steps"] == 10 and s["status"] == "converged"'
# Into the directory it continues (the usual way): the newest checkpoint is the last step's, so
# nothing is left to do; the outputs stay whole.
cp -r "$rd/newton.out" "$rd/newton-copy.out"
expect "restart: from the newest checkpoint into the same directory" 0 \
  "restart: from .*step_000010.hckp \(step 10, t = 2\)" -- run "$rd/newton.yaml" \
  --restart "$rd/newton-copy.out" -o "$rd/newton-copy.out"
identical "restart: ... which keeps every output" "$rd/newton.out" "$rd/newton-copy.out"

# --- geometry: updated (issue 45): the plastically stretched block turned by 90 degrees,
# restarted in the stretch (t = 0.6) and in the rotation (t = 1.4). The configuration and
# J(t) of a step are the state's; nothing else is carried.
mkdir -p "$rd/upd"
cp "$src/tests/cli/inputs/updated/rotation/plastic.yaml" "$src/tests/cli/inputs/updated/rotation/block.geo" "$rd/upd/"
sed -i -E 's/^  probes:/  every: 1\n  probes:/' "$rd/upd/plastic.yaml"
"$bin" run "$rd/upd/plastic.yaml" --quiet >/dev/null 2>&1 || bad "restart: the updated run failed"
for from in 0.6 1.4; do
  expect "restart: updated, plastic rotation from t = $from" 0 "" -- run "$rd/upd/plastic.yaml" \
    --quiet --restart "$rd/upd/plastic.out" --from "$from" -o "$rd/upd/from-$from.out"
  identical "restart: updated, plastic rotation from t = $from is the uninterrupted run, to the bit" \
    "$rd/upd/plastic.out" "$rd/upd/from-$from.out"
done

# --- An elastic model: the thermal plate (temperature-dependent E and α, four steps).
cp -r "$src/examples/thermal-plate" "$rd/tp"
rm -rf "$rd/tp"/*.out
"$bin" run "$rd/tp/case.yaml" --quiet >/dev/null 2>&1 || bad "restart: the thermal plate failed"
expect "restart: thermal plate (elastic) from t = 0.5" 0 "" -- run "$rd/tp/case.yaml" --quiet \
  --restart "$rd/tp/case.out" --from 0.5 -o "$rd/tp/from-0.5.out"
identical "restart: the elastic thermal plate from t = 0.5 is the uninterrupted run, to the bit" \
  "$rd/tp/case.out" "$rd/tp/from-0.5.out"

# --- Contact: the plastic indentation, pressed and lifted back (the contact set, the forces and
# κ, and newton's predictor carry over).
cp -r "$src/tests/cli/inputs/issue16/indentation-unload" "$rd/ind"
"$bin" run "$rd/ind/case.yaml" --quiet >/dev/null 2>&1 || bad "restart: the indentation failed"
for from in 0.5 1.5; do
  expect "restart: indentation from t = $from" 0 "" -- run "$rd/ind/case.yaml" --quiet \
    --restart "$rd/ind/case.out" --from "$from" -o "$rd/ind/from-$from.out"
  identical "restart: the indentation from t = $from is the uninterrupted run, to the bit" \
    "$rd/ind/case.out" "$rd/ind/from-$from.out"
done

# --- Heat conduction (Crank-Nicolson with its backward-Euler start, k(T), radiation).
cp -r "$src/tests/cli/inputs/heat" "$rd/heat"
"$bin" run "$rd/heat/case.yaml" --quiet >/dev/null 2>&1 || bad "restart: the heat case failed"
expect "restart: heat from t = 30" 0 "" -- run "$rd/heat/case.yaml" --quiet \
  --restart "$rd/heat/case.out" --from 30 -o "$rd/heat/from-30.out"
identical "restart: the heat case from t = 30 is the uninterrupted run, to the bit" \
  "$rd/heat/case.out" "$rd/heat/from-30.out"

# --- MPI: written on 2 ranks, restarted on 1, 2 and 3; the same results to the solvers'
# tolerance (MUMPS's and CHOLMOD's 1e-8 relative, as 40_parallel.sh).
if with_mpi; then
  mpi 2 run "$rd/newton.yaml" --quiet -o "$rd/mpi.out" >/dev/null 2>&1 ||
    bad "restart: the run on 2 ranks failed"
  for np in 1 2 3; do
    if [ "$np" = 1 ]; then
      expect "restart: written on 2 ranks, restarted on 1" 0 "" -- run "$rd/newton.yaml" --quiet \
        --restart "$rd/mpi.out" --from 0.8 -o "$rd/mpi-$np.out"
    else
      mpi_expect "restart: written on 2 ranks, restarted on $np" 0 "" "$np" -- run \
        "$rd/newton.yaml" --quiet --restart "$rd/mpi.out" --from 0.8 -o "$rd/mpi-$np.out"
    fi
    same "restart: ... on $np ranks, the results of the uninterrupted run on 2" "$rd/mpi.out" \
      "$rd/mpi-$np.out" 1e-6 "displacement,stress,plastic_strain"
  done
  # Contact on the distributed mesh (issue 21): the states of the contact points are gathered
  # into the checkpoint in the whole model's order, and each rank takes its part's back.
  with_linear direct "$rd/ind/case.yaml"
  mpi 2 run "$rd/ind/case-direct.yaml" --quiet -o "$rd/ind/mpi.out" >/dev/null 2>&1 ||
    bad "restart: the indentation on 2 ranks failed"
  same "restart: the indentation on 2 ranks = serial to 1e-6" "$rd/ind/case.out" "$rd/ind/mpi.out" \
    1e-6 "displacement,stress,plastic_strain,contact_pressure"
  mpi_expect "restart: the indentation written on 2 ranks, restarted at t = 1.5 on 3" 0 "" 3 -- \
    run "$rd/ind/case-direct.yaml" --quiet --restart "$rd/ind/mpi.out" --from 1.5 \
    -o "$rd/ind/mpi-3.out"
  same "restart: ... the results of the uninterrupted run on 2" "$rd/ind/mpi.out" \
    "$rd/ind/mpi-3.out" 1e-6 "displacement,stress,plastic_strain,contact_pressure"
  expect "restart: ... and at t = 0.5 on 1" 0 "" -- run "$rd/ind/case-direct.yaml" --quiet \
    --restart "$rd/ind/mpi.out" --from 0.5 -o "$rd/ind/mpi-1.out"
  same "restart: ... the results of the uninterrupted run on 2" "$rd/ind/mpi.out" \
    "$rd/ind/mpi-1.out" 1e-6 "displacement,stress,plastic_strain,contact_pressure"
fi

# --- Interruption: SIGINT once. The indentation in 24 steps; the signal comes when the third
# step is in the history; the run stops at its next iteration with status 4, keeps its
# converged steps and their checkpoint, and a restart completes it as if it had not stopped.
sed -E 's/^  times: .*/  steps: 24\n  end: 2/' "$rd/ind/case.yaml" >"$rd/ind/long.yaml"
"$bin" run "$rd/ind/long.yaml" --quiet -o "$rd/ind/long-full.out" >/dev/null 2>&1 ||
  bad "restart: the long indentation failed"
# interrupt NAME SIGNALS... : runs the long case and, once three steps are in the work
# directory's history, stops the process (SIGSTOP), sends the signals and lets it go on: two
# signals are then both pending when it resumes, and are seen one after the other (two of the
# same kind would merge into one); sets $irc and $iout.
interrupt() {
  local name="$1" pid n=0 i; shift
  rm -rf "$rd/ind/long.out" "$rd/ind/long.out".*
  "$bin" run "$rd/ind/long.yaml" -o "$rd/ind/long.out" >"$rd/ind/interrupt.log" 2>&1 &
  pid=$!
  while [ "$n" -lt 600 ]; do
    if [ "$(cat "$rd/ind/long.out".partial-*/history.csv 2>/dev/null | wc -l)" -ge 4 ]; then break; fi
    sleep 0.05; n=$((n + 1))
  done
  kill -s STOP "$pid"
  for i in "$@"; do kill -s "$i" "$pid" 2>/dev/null; done
  kill -s CONT "$pid"
  wait "$pid"; irc=$?
  iout="$(cat "$rd/ind/interrupt.log")"
}
interrupt "SIGINT" INT
if [ "$irc" -eq 4 ] && grep -q "interrupted" <<<"$iout"; then ok "restart: SIGINT stops the run with status 4"
else bad "restart: SIGINT: exit $irc, expected 4" "$iout"; fi
ex_check "restart: ... the steps that converged are in the output directory, with a checkpoint at the last" \
  "$rd/ind/long.out/summary.json" \
  's["status"] == "interrupted" and 3 <= s["steps"] < 24 and s["checkpoints"] >= 1'
last_cp="$(tail -n 1 "$rd/ind/long.out/checkpoints/index.csv" | cut -d, -f1)"
steps="$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["steps"])' "$rd/ind/long.out/summary.json")"
[ "$last_cp" = "$steps" ] && ok "restart: ... its newest checkpoint is its last converged step" ||
  bad "restart: the newest checkpoint is step $last_cp, the last converged step $steps"
expect "restart: the interrupted run continues" 0 "" -- run "$rd/ind/long.yaml" --quiet \
  --restart "$rd/ind/long.out" -o "$rd/ind/long.out"
identical "restart: ... and ends with the results of the run that was not interrupted" \
  "$rd/ind/long-full.out" "$rd/ind/long.out"
# Under mpirun: SIGTERM to the ranks themselves (docs/cli.md; `pkill -TERM -x hencky`). Ctrl-C to
# mpirun is not the way: Debian 12's Open MPI 4.1.4 ends mpirun a second after a SIGINT or
# SIGTERM without passing it on, and the ranks run to the end (measured 2026-11-28: `mpirun -np 2
# sleep 20` killed by SIGINT leaves both sleeps running; the check of that path, dropped on
# 2026-11-26 as flaky, was timing whether the run ended before the orphaned ranks did). The
# ranks are stopped, signalled and let go on together (as `interrupt` does above), so the check
# does not depend on when each sees its signal: every rank stops at the same iteration whatever
# the order (the step loop's par::any), and mpirun passes on their status 4.
if with_mpi; then
  rm -rf "$rd/ind/mpi-long.out" "$rd/ind/mpi-long.out".*
  mpirun -np 2 --oversubscribe --bind-to none -x OMP_NUM_THREADS=1 "$bin" run \
    "$rd/ind/long.yaml" -o "$rd/ind/mpi-long.out" >"$rd/ind/mpi-interrupt.log" 2>&1 &
  pid=$!
  n=0
  while [ "$n" -lt 1200 ] && [ "$(cat "$rd/ind/mpi-long.out".partial-*/history.csv 2>/dev/null | wc -l)" -lt 3 ]; do
    sleep 0.05; n=$((n + 1))
  done
  ranks="$(pgrep -P "$pid" -x hencky | tr '\n' ' ')"
  # shellcheck disable=SC2086
  { kill -s STOP $ranks; kill -s TERM $ranks; kill -s CONT $ranks; } 2>/dev/null
  wait "$pid"; irc=$?
  if [ "$irc" -eq 4 ] && [ "$(wc -w <<<"$ranks")" -eq 2 ]; then
    ok "restart: SIGTERM to both ranks of mpirun stops the run with status 4"
  else
    bad "restart: SIGTERM to the ranks '$ranks' of mpirun: exit $irc, expected 4" "$(tail -5 "$rd/ind/mpi-interrupt.log")"
  fi
  ex_check "restart: ... keeping the steps that converged on both ranks" \
    "$rd/ind/mpi-long.out/summary.json" \
    's["status"] == "interrupted" and s["ranks"] == 2 and 2 <= s["steps"] < 24 and s["checkpoints"] >= 1'
  mpi_expect "restart: ... and continues on 2 ranks" 0 "" 2 -- run "$rd/ind/long.yaml" --quiet \
    --restart "$rd/ind/mpi-long.out" -o "$rd/ind/mpi-long.out"
  same "restart: ... to the serial uninterrupted run's results (1e-6)" "$rd/ind/long-full.out" \
    "$rd/ind/mpi-long.out" 1e-6 "displacement,stress,plastic_strain,contact_pressure"
fi
# SIGTERM too.
interrupt "SIGTERM" TERM
[ "$irc" -eq 4 ] && ok "restart: SIGTERM stops the run with status 4" ||
  bad "restart: SIGTERM: exit $irc, expected 4" "$iout"
# Twice (SIGINT, then SIGTERM or SIGINT): at once (130), the work directory is left with its
# checkpoints; it can be restarted.
interrupt "SIGINT twice" INT TERM
work_left="$(ls -d "$rd/ind/long.out".partial-* 2>/dev/null | head -n 1)"
if [ "$irc" -eq 130 ] && [ -n "$work_left" ] && grep -q "stopped at once" <<<"$iout"; then
  ok "restart: a second SIGINT stops at once (130) and names the directory left"
else bad "restart: SIGINT twice: exit $irc, expected 130 and a .partial directory" "$iout"; fi
if [ -n "$work_left" ] && [ -f "$work_left/checkpoints/index.csv" ]; then
  expect "restart: ... from which the run continues" 0 "" -- run "$rd/ind/long.yaml" --quiet \
    --restart "$work_left" -o "$rd/ind/after-abort.out"
  identical "restart: ... to the results of the run that was not interrupted" \
    "$rd/ind/long-full.out" "$rd/ind/after-abort.out"
else
  ok "restart: the second SIGINT came before the first checkpoint (nothing to restart)"
fi
rm -rf "$rd/ind/long.out".partial-*

# --- The default: a case without an output section writes a checkpoint at every step.
cp -r "$src/tests/cli/inputs/restart" "$rd/cube"
expect "restart: a case without an output section" 0 "" -- run "$rd/cube/case.yaml" --quiet
[ "$(cut -d, -f1 "$rd/cube/case.out/checkpoints/index.csv" 2>&1 | tr '\n' ' ')" = "step 1 2 " ] &&
  ok "restart: ... writes a checkpoint at every step (the default)" ||
  bad "restart: default checkpoints" "$(cat "$rd/cube/case.out/checkpoints/index.csv" 2>&1)"

# --- output.checkpoint and output.checkpoint_keep.
sed -E 's/^output:/output:\n  checkpoint: off/' "$rd/newton.yaml" >"$rd/off.yaml"
expect "restart: output.checkpoint: off writes none" 0 "" -- run "$rd/off.yaml" --quiet
[ ! -e "$rd/off.out/checkpoints" ] && ok "restart: ... no checkpoints folder" ||
  bad "restart: output.checkpoint: off left $(ls "$rd/off.out/checkpoints")"
expect "restart: a directory without checkpoints is refused" 1 \
  "'--restart'.*off.out holds no checkpoints" -- run "$rd/off.yaml" --restart "$rd/off.out"
sed -E 's/^output:/output:\n  checkpoint: 3\n  checkpoint_keep: 2/' "$rd/newton.yaml" >"$rd/keep.yaml"
expect "restart: checkpoint: 3, checkpoint_keep: 2" 0 "" -- run "$rd/keep.yaml" --quiet
[ "$(cut -d, -f1 "$rd/keep.out/checkpoints/index.csv" | tr '\n' ' ')" = "step 9 10 " ] &&
  [ "$(ls "$rd/keep.out/checkpoints" | wc -l)" = 3 ] &&
  ok "restart: ... keeps the checkpoints of steps 9 and 10 (every third, and the last)" ||
  bad "restart: checkpoint_keep" "$(cat "$rd/keep.out/checkpoints/index.csv"; ls "$rd/keep.out/checkpoints")"

# --- Refused restarts: a clear error, nothing written.
expect "restart: --from a time without a checkpoint names the times there are" 1 \
  "'--from'.*no checkpoint at t = 0.75; it has checkpoints at t = 0.4, 0.5" -- \
  run "$rd/newton.yaml" --restart "$rd/newton.out" --from 0.75 -o "$rd/x.out"
expect "restart: --from without --restart" 1 "'--from'.*--restart" -- run "$rd/newton.yaml" --from 1
sed -E 's/nu: 0.3/nu: 0.29/' "$rd/newton.yaml" >"$rd/other-nu.yaml"
ex_bad "restart: a material that changed is named" \
  "step_000005.hckp: 'materials': material 'S355' is not the one the checkpoint was computed with" \
  "$rd/other-nu.yaml" --restart "$rd/newton.out" --from 0.8
sed -E 's/^n = 6;/n = 7;/' "$rd/plate.geo" >"$rd/plate2.geo"
sed -E 's/plate.geo/plate2.geo/' "$rd/newton.yaml" >"$rd/other-mesh.yaml"
ex_bad "restart: another mesh is refused" "'mesh': the mesh plate2.geo is not the mesh" \
  "$rd/other-mesh.yaml" --restart "$rd/newton.out" --from 0.8
cp -r "$rd/newton.out" "$rd/damaged.out"
/usr/bin/python3 - "$rd/damaged.out/checkpoints/step_000005.hckp" "$rd/damaged.out/checkpoints/step_000006.hckp" <<'PY'
import struct, sys
with open(sys.argv[1], "r+b") as f:   # a newer format version
    f.seek(8); f.write(struct.pack("<I", 2))
with open(sys.argv[2], "r+b") as f:   # one byte of the data changed
    f.seek(4000); b = f.read(1); f.seek(4000); f.write(bytes([b[0] ^ 0x10]))
PY
ex_bad "restart: a checkpoint of a newer format is refused" \
  "format version 2, written by a newer hencky; this hencky reads version 1" \
  "$rd/newton.yaml" --restart "$rd/damaged.out" --from 0.8
ex_bad "restart: a damaged checkpoint is refused" "damaged: its checksum \(CRC-32\) does not match" \
  "$rd/newton.yaml" --restart "$rd/damaged.out" --from 0.9

# --- A full disk. Mid-run, with a file size limit (checkpoints of 0.8 MB, fields files of
# 0.3 MB on the coarse strip, a limit of 0.5 MB): the first checkpoint cannot be written; the run
# stops with status 2 and the step's fields are kept in place.
rm -rf "$rd/fsize.out"
out="$( (ulimit -f 500; trap '' XFSZ; "$bin" run "$rd/newton.yaml" --quiet -o "$rd/fsize.out") 2>&1)"; rc=$?
if [ "$rc" -eq 2 ] && grep -q "the outputs of step 1 (t = 0.4) cannot be written: cannot write .*step_000001.hckp.tmp: File too large" <<<"$out" &&
  [ -f "$rd/fsize.out/step_0001.vtu" ] && [ -f "$rd/fsize.out/summary.json" ]; then
  ok "restart: an output that cannot be written stops the run (2) and keeps what was written"
else bad "restart: file size limit: exit $rc, expected 2 with the message and step_0001.vtu kept" "$out"; fi
# A real full file system, where one can be mounted (root): 1 MB cannot hold the first step's
# outputs (an error before solving, nothing written); 3 MB holds a few steps (a warning before,
# status 2 when it is full, the steps written are kept).
tfs="$rd/tmpfs"
mkdir -p "$tfs"
if mount -t tmpfs -o size=1m tmpfs "$tfs" 2>/dev/null; then
  expect "restart: a file system without room for one step is refused before solving" 1 \
    "'-o': the file system of .*tmpfs/small.out has 1.0 MB free; the outputs of one step need about 1.[0-9] MB" \
    -- run "$rd/newton.yaml" -o "$tfs/small.out"
  [ -z "$(ls -A "$tfs")" ] && ok "restart: ... and nothing is written" || bad "restart: left $(ls "$tfs")"
  umount "$tfs"
  mount -t tmpfs -o size=3m tmpfs "$tfs"
  out="$("$bin" run "$rd/newton.yaml" -o "$tfs/full.out" 2>&1)"; rc=$?
  if [ "$rc" -eq 2 ] && grep -q "warning: the outputs of this run will take about" <<<"$out" &&
    grep -q "No space left on device" <<<"$out" && [ -f "$tfs/full.out/step_0001.vtu" ]; then
    ok "restart: a file system that fills up: warned before, status 2, the steps written kept"
  else bad "restart: full file system: exit $rc" "$out"; fi
  umount "$tfs"
else
  echo "skip restart: full file system (tmpfs cannot be mounted here)"
fi
