#!/usr/bin/env bash
# Per-rank peak memory when each rank reads its own file of a split mesh (mesh.split) against
# root reading the mesh in one file and sending the parts, with and without checkpoints, on 2
# and 4 MPI ranks (issue 21). One run per cell; memory does not depend on the machine's load.
#
#   bench/run_split_memory.sh [HENCKY_BINARY]      (default: build/hencky)
#
# The case: tests/cli/inputs/heat (transient, k(T), c(T), radiation, a source of T) on a block
# of 40 x 20 x 10 20-node hexahedra (101,460 unknowns), 4 heat and 4 mechanical steps,
# `solver.linear: petsc`. Gmsh writes the mesh (serendipity second order) in one file and split
# into 2 and 4 files. Checkpoints: every step (the default) or none (`output.checkpoint: 0`).
# Results: bench/results/split-memory-<date>.md.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="$(realpath "${1:-$here/build/hencky}")"
work="$here/bench/work/split-memory"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
cp "$here/tests/cli/inputs/heat/block.geo" heatblock.geo
sed -i -E 's/^n = 6;/n = 40;/; s/Layers\{2\}/Layers{10}/' heatblock.geo
serendipity=(-order 2 -string "Mesh.SecondOrderIncomplete=1;" -format msh41)
gmsh -3 "${serendipity[@]}" heatblock.geo -o whole.msh >/dev/null
for np in 2 4; do
  gmsh -3 "${serendipity[@]}" -part "$np" -part_split heatblock.geo -o "split$np.msh" >/dev/null
done
for ck in every none; do
  extra=""
  [ "$ck" = none ] && extra='s/^output:$/output:\n  checkpoint: 0/;'
  for mesh in whole split2 split4; do
    spec="{file: $mesh.msh}"
    [ "$mesh" != whole ] && spec="{file: $mesh.msh, split: true}"
    sed -E "s#^mesh: .*#mesh: $spec#; s/^  steps: 12\$/  steps: 4/; s/^solver:.*/&\n  linear: petsc/; $extra" \
      "$here/tests/cli/inputs/heat/case.yaml" >"$mesh-$ck.yaml"
  done
done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=PASSIVE
out="$here/bench/results/split-memory-$(date +%Y%m%d-%H%M%S).md"
{
  echo "# Per-rank peak memory: each rank reading its file of a split mesh (issue 21)"
  echo
  echo "Binary: $bin ($(git -C "$here" rev-parse --short HEAD)); $(nproc) cores; $(date -u)."
  echo
  echo "| mesh input | checkpoints | ranks | status | wall s | largest rank MiB | all ranks MiB | unknowns |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|"
} >"$out"
for ck in every none; do
  for np in 1 2 4; do
    for input in whole split; do
      [ "$np" = 1 ] && [ "$input" = split ] && continue
      c="whole-$ck"
      [ "$input" = split ] && c="split$np-$ck"
      dir="out-$c-$np"
      t0=$(date +%s.%N)
      rc=0
      if [ "$np" = 1 ]; then
        OMP_NUM_THREADS=1 "$bin" run "$c.yaml" -o "$dir" --quiet --threads 1 >"$dir.log" 2>&1 || rc=$?
      else
        timeout 1800 mpirun -np "$np" --oversubscribe --bind-to none -x OMP_NUM_THREADS=1 \
          "$bin" run "$c.yaml" -o "$dir" --quiet >"$dir.log" 2>&1 || rc=$?
      fi
      t1=$(date +%s.%N)
      label="one file, root sends the parts"
      [ "$input" = split ] && label="$np files, each rank its own"
      [ "$np" = 1 ] && label="one file"
      /usr/bin/python3 "$here/bench/memory_row.py" "$dir/summary.json" "$rc" "$t0" "$t1" \
        wall,largest,all,dofs "$label" "$ck" "$np" >>"$out"
    done
  done
done
cat "$out"
