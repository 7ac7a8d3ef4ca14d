# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 47: a step whose iteration diverges stops within a few iterations, for every scheme
# (IterationLimit::diverges).

d="$work/diverging"
rm -rf "$d" && mkdir -p "$d" && cp -r "$src/tests/cli/inputs/issue16/unload-all/." "$d/"
# The report's initial strains with ω = 1 on unload-all: from t = 0.5 the step to 0.625 grows
# without bound (before the rule: 90 iterations to a force of 3.6e153 and a NaN).
sed -i -E -e 's/^([[:space:]]*)scheme:[[:space:]]*newton[[:space:]]*$/\1scheme: initial-strain\n\1formulation: report/' \
  -e 's/^([[:space:]]*)times: .*$/\1times: [0.5, 0.625]/' -e 's/^([[:space:]]*)cutback: .*$/\1cutback: 0/' \
  "$d/case.yaml"
grep -q "cutback: 0" "$d/case.yaml" || sed -i -E 's/^([[:space:]]*)formulation: report$/&\n\1cutback: 0/' "$d/case.yaml"
expect "diverging: the step that diverges stops with status 2, saying so" 2 \
  "the iteration diverges: the residual grew to .* of the step's force scale in iteration [0-9]+, more than 1e\+06 times its best in the step" \
  -- run "$d/case.yaml" -o "$d/out"
ex_check "diverging: ... within 10 iterations of the step (the first step's answer kept)" "$d/out/summary.json" \
  "s['steps'] == 1 and int(__import__('re').search(r'in iteration (\\d+)', s['failure']).group(1)) <= 10"

# A model whose supports leave a rigid motion free is refused before anything is solved, by
# `check` and `run`, naming the motion; the test is exact (Model::check_held), whatever the
# factorization's pivots (before: the bar with an axial force "converged", with a lateral one it
# ran 250 iterations; with 25 elements CHOLMOD happened to refuse it).
h="$work/held"
rm -rf "$h" && cp -r "$src/tests/cli/inputs/held" "$h"
for cmd in check run; do
  expect "held: a bar free to turn about its axis: $cmd refuses it" 1 \
    "'boundary': the body is not held: its displacement conditions leave 1 rigid motion free: rotation about the axis through \(0.05, 0, 0\) along x" \
    -- $cmd "$h/rotation-free.yaml"
done
[ -e "$h/rotation-free.out" ] && bad "held: the refused run wrote an output directory" || ok "held: the refused run wrote nothing"
sed -e 's/{region: x0, displacement: {x: 0}}/{region: x0, displacement: {x: 0, y: 0}}/' "$h/rotation-free.yaml" > "$h/held.yaml"
expect "held: the same bar with u_y held at its end runs" 0 "" -- run "$h/held.yaml" --quiet
# A free motion about no coordinate axis: the turned block may tip over the bottom edge of its
# oblique side, along (-1, 1, 0)/sqrt(2) through the origin (the nearest point of that axis to the
# block's centre is (-0.354, 0.354, 0)). Before, this input crashed `check` (SIGSEGV in the
# description of such a motion).
expect "held: a block free to tip over an oblique edge is refused, naming that axis" 1 \
  "leave 1 rigid motion free: rotation about the axis through \(-0\.35[0-9]*, 0\.35[0-9]*, 0\) along \((-0\.7071, 0\.7071|0\.7071, -0\.7071), 0\)\." \
  -- check "$h/tilt-free.yaml"
# The thick-cylinder slice held by its x symmetry plane alone (a regression: it had run 250
# iterations for 165 s since the node-graph ordering, and stopped with status 2).
c="$h/slice"
mkdir -p "$c" && cp "$src/tests/cli/inputs/issue16/epp-cylinder/"* "$c/"
sed -i -E '/region: (ysym|bottom|top), displacement/d' "$c/case.yaml"
expect "held: the cylinder slice held by one plane is refused, naming its free motions" 1 \
  "leave 3 rigid motions free: translation along y; translation along z; rotation about the axis through .* along x" \
  -- check "$c/case.yaml"
# A body that contact alone holds runs, with a warning naming the motion contact must stop.
expect "held: a cube held vertically by a rigid plane alone runs, with a warning" 0 \
  "warning: the body is held by contact alone against translation along z" \
  -- run "$h/contact-held.yaml" -o "$h/contact-held.out"
ex_check "held: ... and the plane carries the load (1e4 N to 1e-9)" "$h/contact-held.out/summary.json" \
  "close(s['contact']['plane']['force'], 1e4, 1e-9)"

# --- The same check on a mesh split into files, each rank reading its own (no rank holds the
#     whole mesh): the ranks' pieces of the bar are joined into one body, whose free rotation
#     is named as on one rank. The 25 x 2 x 2 bar split in two across its length.
if with_mpi; then
  s="$h/split"
  mkdir -p "$s"
  gmsh -3 -part 2 -part_split "$h/bar.geo" -format msh41 -o "$s/bar.msh" >/dev/null 2>&1 ||
    bad "held, split: gmsh could not split the bar"
  sed -e 's#^mesh: {file: bar.geo}$#mesh: {file: bar.msh, split: true}#' "$h/rotation-free.yaml" \
    >"$s/rotation-free.yaml"
  grep -q "split: true" "$s/rotation-free.yaml" || bad "held, split: the case's mesh line was not replaced"
  # (`check` reads the files together as the whole mesh; `run` on 2 ranks is the split way,
  # which ran this bar to the end before.)
  mpi_expect "held, split into 2 files on 2 ranks: run refuses the free rotation, named as on one rank" 1 \
    "the body is not held: its displacement conditions leave 1 rigid motion free: rotation about the axis through \(0.05, 0, 0\) along x" \
    2 -- run "$s/rotation-free.yaml" -o "$s/refused.out"
  [ -e "$s/refused.out" ] && bad "held, split: the refused run wrote an output directory" ||
    ok "held, split: the refused run wrote nothing"
  sed -e 's/{region: x0, displacement: {x: 0}}/{region: x0, displacement: {x: 0, y: 0}}/' \
    "$s/rotation-free.yaml" >"$s/held.yaml"
  mpi_expect "held, split: ... and runs once u_y is held at its end" 0 "" 2 -- run "$s/held.yaml" --quiet
fi
