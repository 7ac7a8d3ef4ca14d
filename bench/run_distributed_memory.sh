#!/usr/bin/env bash
# Per-rank peak memory of a contact case and a heat case on 1, 2 and 4 MPI ranks, on the
# distributed mesh and with the whole mesh on every rank (HENCKY_REPLICATED=1), one run per cell
# (issue 21). Memory does not depend on the machine's load; the seconds do (4 ranks share the 2
# cores), and are recorded for orientation only.
#
#   bench/run_distributed_memory.sh [HENCKY_BINARY]      (default: build/hencky)
#
# The cases, built in bench/work/distributed-memory/ from the repository's own inputs:
#   contact  examples/ball-indentation refined (hmax = L/14, g = 0.1): 142,032 unknowns, 10-node
#            tetrahedra, times 0.5, 1, 2 (pressed in and released), `solver.linear: petsc`.
#   heat     tests/cli/inputs/heat (transient, k(T), c(T), radiation, a source of T) on a block of
#            40 x 20 x 10 20-node hexahedra: 101,460 unknowns, 4 heat and 4 mechanical steps,
#            `solver.linear: petsc` (CG + GAMG for both systems).
# Both with `output.checkpoint: 0`, so that the figures are the model's and PETSc's, not the
# checkpoint gathered on root. Results: bench/results/distributed-memory-<date>.md.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="$(realpath "${1:-$here/build/hencky}")"
work="$here/bench/work/distributed-memory"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
cp "$here/examples/ball-indentation/block.geo" .
# The contact mesh these figures were measured on (the example refined its ball later).
sed -i -E 's#^hmax = L / 4;#hmax = L / 14;#; s#^g = 0.25;#g = 0.1;#; s#^hc = a / 6;#hc = a / 5;#; s#^rf = 1.6 \* a;#rf = 1.1 * a;#' block.geo
sed -E 's/^solver:.*/&\n  linear: petsc/; s/^  times: .*/  times: [0.5, 1.0, 2.0]/; s/^output:$/output:\n  checkpoint: 0/' \
  "$here/examples/ball-indentation/case.yaml" >contact.yaml
cp "$here/tests/cli/inputs/heat/block.geo" heatblock.geo
sed -i -E 's/^n = 6;/n = 40;/; s/Layers\{2\}/Layers{10}/' heatblock.geo
sed -E 's/block.geo/heatblock.geo/; s/^  steps: 12$/  steps: 4/; s/^solver:.*/&\n  linear: petsc/; s/^output:$/output:\n  checkpoint: 0/' \
  "$here/tests/cli/inputs/heat/case.yaml" >heat.yaml
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=PASSIVE
out="$here/bench/results/distributed-memory-$(date +%Y%m%d-%H%M%S).md"
{
  echo "# Per-rank peak memory, distributed mesh against replicated (issue 21)"
  echo
  echo "Binary: $bin ($(git -C "$here" rev-parse --short HEAD)); $(nproc) cores; $(date -u)."
  echo
  echo "| case | mesh | ranks | status | wall s | largest rank MiB | all ranks MiB | iterations | unknowns |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
} >"$out"
for c in contact heat; do
  for np in 1 2 4; do
    for mode in distributed replicated; do
      [ "$np" = 1 ] && [ "$mode" = replicated ] && continue
      dir="out-$c-$mode-$np"
      env_=()
      [ "$mode" = replicated ] && env_=(HENCKY_REPLICATED=1)
      t0=$(date +%s.%N)
      rc=0
      if [ "$np" = 1 ]; then
        env "${env_[@]}" OMP_NUM_THREADS=1 "$bin" run "$c.yaml" -o "$dir" --quiet --threads 1 \
          >"$dir.log" 2>&1 || rc=$?
      else
        env "${env_[@]}" timeout 1800 mpirun -np "$np" --oversubscribe --bind-to none \
          -x OMP_NUM_THREADS=1 "$bin" run "$c.yaml" -o "$dir" --quiet >"$dir.log" 2>&1 || rc=$?
      fi
      t1=$(date +%s.%N)
      /usr/bin/python3 "$here/bench/memory_row.py" "$dir/summary.json" "$rc" "$t0" "$t1" \
        wall,largest,all,iterations,dofs "$c" "$mode" "$np" >>"$out"
    done
  done
done
cat "$out"
