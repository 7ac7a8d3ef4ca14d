# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 20: `solver.linear: auto`, the default, chooses as documented (docs/case-reference.md,
# solve/linear_choice.hpp) and says so in the log; the thresholds are injected through the
# environment (HENCKY_AUTO_ANALYZE_FROM, HENCKY_AUTO_CROSSOVER, HENCKY_AUTO_MEMORY) so that a
# small model reaches every branch. Whatever it chooses, the answer is the same.

la_dir="$work/linear-auto"
rm -rf "$la_dir"
mkdir -p "$la_dir"
cp "$src/examples/lame-cylinder/case.yaml" "$src/examples/lame-cylinder/cylinder.geo" "$la_dir/"
# A coarser mesh: the choice, not the accuracy, is under test.
ex_set "$la_dir/cylinder.geo" '^h = [0-9.e-]+;' 'h = 0.02;'

la_log() { cat "$la_dir/$1.out/hencky.log" 2>/dev/null; }

# The default, on a small model: CHOLMOD, with the reason.
expect "auto, default: runs" 0 "" -- run "$la_dir/case.yaml" -o "$la_dir/default.out" --quiet
if grep -Eq "linear solver \(solver.linear: auto\): CHOLMOD sparse Cholesky; [0-9]+ unknowns, fewer than the 150000 from which CG \+ GAMG may be faster" <<<"$(la_log default)"; then
  ok "auto, default: the log says CHOLMOD and why"
else
  bad "auto, default: no log line for the choice" "$(grep -i "linear" "$la_dir/default.out/hencky.log")"
fi
ex_check "auto, default: summary names CHOLMOD" "$la_dir/default.out/summary.json" \
  '"CHOLMOD" in s["linear_solver"]["method"]'

# The factor predicted (the analysis size injected below the model's): cheaper than the
# crossover, CHOLMOD, with the ordering of the prediction.
expect_cmd "auto, analysed: runs" 0 "" -- env HENCKY_AUTO_ANALYZE_FROM=100 \
  "$bin" run "$la_dir/case.yaml" -o "$la_dir/analysed.out" --quiet
expect_cmd "auto, analysed: the log gives the factor's cost and the crossover" 0 \
  "CHOLMOD sparse Cholesky; [0-9]+ unknowns: the factorization should cost .* Gflop, .* Mflop per unknown, below the [0-9.e+-]+ from which CG \+ GAMG would be faster at this size.*symbolic analysis of the node graph" \
  -- cat "$la_dir/analysed.out/hencky.log"
ex_check "auto, analysed: the answer of the unanalysed run to 1e-9" "$la_dir/analysed.out/summary.json" \
  "close(s['probes']['bore']['displacement']['x'], $("$ex_py" -c "import json; print(json.load(open('$la_dir/default.out/summary.json'))['probes']['bore']['displacement']['x'])"), 1e-9)"

# The crossover injected below the model's cost: CG + GAMG, the same answer.
expect_cmd "auto, crossover 1 flop: runs" 0 "" -- env HENCKY_AUTO_ANALYZE_FROM=100 \
  HENCKY_AUTO_CROSSOVER=1 "$bin" run "$la_dir/case.yaml" -o "$la_dir/small.out" --quiet
expect_cmd "auto, crossover 1 flop: the log says CG + GAMG and why" 0 \
  "linear solver \(solver.linear: auto\): PETSc CG \+ GAMG; [0-9]+ unknowns: the factorization would cost .* Mflop per unknown, at least the [0-9.e+-]+ from which CG \+ GAMG is faster at this size" \
  -- cat "$la_dir/small.out/hencky.log"
ex_check "auto, crossover 1 flop: summary names GAMG" "$la_dir/small.out/summary.json" \
  '"gamg" in s["linear_solver"]["method"]'
ex_check "auto, crossover 1 flop: the bore displacement of the direct solve (1e-7)" \
  "$la_dir/small.out/summary.json" \
  "close(s['probes']['bore']['displacement']['x'], $("$ex_py" -c "import json; print(json.load(open('$la_dir/default.out/summary.json'))['probes']['bore']['displacement']['x'])"), 1e-7)"

# Too little memory for the predicted factor: CG + GAMG, below the size threshold.
expect_cmd "auto, 1 MB available: runs" 0 "" -- env HENCKY_AUTO_MEMORY=1e6 \
  "$bin" run "$la_dir/case.yaml" -o "$la_dir/memory.out" --quiet
expect_cmd "auto, 1 MB available: the log says CG + GAMG, the factor would not fit" 0 \
  "PETSc CG \+ GAMG; [0-9]+ unknowns: a sparse Cholesky factorization would take about .* GiB, more than 70 % of the 0.0 GiB available" \
  -- cat "$la_dir/memory.out/hencky.log"

# An explicit choice is not overridden, and says nothing of auto.
sed -i -E 's/^  steps: 2$/  steps: 2\n  linear: direct/' "$la_dir/case.yaml"
expect_cmd "auto, linear: direct with the crossover at 1 flop: runs" 0 "" -- \
  env HENCKY_AUTO_ANALYZE_FROM=100 HENCKY_AUTO_CROSSOVER=1 "$bin" run "$la_dir/case.yaml" \
  -o "$la_dir/direct.out" --quiet
if grep -q "solver.linear: auto" "$la_dir/direct.out/hencky.log"; then
  bad "auto: an explicit 'linear: direct' went through the auto rule"
else
  ok "auto: an explicit 'linear: direct' is kept"
fi
ex_check "auto, linear: direct: summary names CHOLMOD" "$la_dir/direct.out/summary.json" \
  '"CHOLMOD" in s["linear_solver"]["method"]'

# The BLAS kernels (linalg/blas_kernels.hpp). Debian 12's OpenBLAS runs its SSE3 fallback
# ("Prescott") on CPUs it does not know; hencky then starts itself again with
# OPENBLAS_CORETYPE set. On a CPU with AVX2 the kernels in use must use it; with
# HENCKY_BLAS_KERNELS=keep they are OpenBLAS's own choice, and a user's OPENBLAS_CORETYPE wins.
la_kernels() { "$ex_py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["linear_solver"].get("blas_kernels", ""))' "$1"; }
k_default="$(la_kernels "$la_dir/default.out/summary.json")"
if [ -n "${OPENBLAS_CORETYPE:-}" ]; then
  # The user's choice is kept (no restart): the kernels are the ones asked for.
  if [ "${k_default,,}" = "${OPENBLAS_CORETYPE,,}" ]; then
    ok "blas kernels: OPENBLAS_CORETYPE=$OPENBLAS_CORETYPE of the environment is kept"
  else
    bad "blas kernels: OPENBLAS_CORETYPE=$OPENBLAS_CORETYPE in the environment, but '$k_default' in use"
  fi
elif ! grep -qw avx2 /proc/cpuinfo || [ -z "$k_default" ]; then
  ok "blas kernels: no AVX2 or not OpenBLAS here ('$k_default'), nothing to check"
elif grep -Eqix "prescott|core2|penryn|dunnington|nehalem|atom|sandybridge" <<<"$k_default"; then
  bad "blas kernels: OpenBLAS runs '$k_default' on a CPU with AVX2"
else
  ok "blas kernels: '$k_default' on a CPU with AVX2"
fi
# The restart itself, wherever OpenBLAS knows the CPU: HENCKY_BLAS_TEST_CHOSEN makes the first
# start see the fallback's name (linalg/blas_kernels.cpp), as on the Xeon (model 207) that
# Debian 12's OpenBLAS does not know. Without the environment's OPENBLAS_CORETYPE, which would
# keep the kernels.
if grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo && [ -n "$k_default" ]; then
  expect_cmd "blas kernels, the fallback on a CPU with AVX2: runs" 0 "" -- env -u OPENBLAS_CORETYPE \
    HENCKY_BLAS_TEST_CHOSEN=Prescott "$bin" run "$la_dir/case.yaml" -o "$la_dir/restart.out" --quiet
  expect_cmd "blas kernels, the fallback: hencky started again with better kernels, and says so" 0 \
    "^BLAS: OpenBLAS took its 'Prescott' kernels for this CPU \(a model it does not know\); hencky started again with OPENBLAS_CORETYPE=(SkylakeX|Haswell) \(now '(SkylakeX|Haswell)'" \
    -- cat "$la_dir/restart.out/hencky.log"
  ex_check "blas kernels, the fallback: the summary names the kernels of the second start" \
    "$la_dir/restart.out/summary.json" 's["linear_solver"]["blas_kernels"] in ("SkylakeX", "Haswell")'
else
  ok "blas kernels: no AVX2 or not OpenBLAS here, the restart is not checked"
fi
expect_cmd "blas kernels, keep: runs" 0 "" -- env HENCKY_BLAS_KERNELS=keep \
  "$bin" run "$la_dir/case.yaml" -o "$la_dir/keep.out" --quiet
if grep -q "^BLAS: " "$la_dir/keep.out/hencky.log"; then
  bad "blas kernels, keep: the log says it started again"
else
  ok "blas kernels, keep: not started again"
fi
expect_cmd "blas kernels, OPENBLAS_CORETYPE=Haswell: runs" 0 "" -- env OPENBLAS_CORETYPE=Haswell \
  "$bin" run "$la_dir/case.yaml" -o "$la_dir/haswell.out" --quiet
if ! grep -qw avx2 /proc/cpuinfo || [ -z "$k_default" ]; then
  ok "blas kernels: the user's OPENBLAS_CORETYPE (not checked here: no AVX2 or not OpenBLAS)"
else
  ex_check "blas kernels: the user's OPENBLAS_CORETYPE is kept" "$la_dir/haswell.out/summary.json" \
    's["linear_solver"]["blas_kernels"].lower() == "haswell"'
fi
