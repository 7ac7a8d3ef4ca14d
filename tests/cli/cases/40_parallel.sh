# Sourced by run_cli_tests.sh: the PETSc back end, serial and under mpirun (issue 5). The same
# coarse example is run with the serial direct solver, with PETSc on one process, and on 2, 3
# and 4 MPI ranks; every step's displacement, stress and (with contact) contact pressure must
# agree: to 1e-10 relative for the direct solvers (CHOLMOD and MUMPS), to the Newton tolerance
# for CG + GAMG. Then the outputs are written once, and an error on one rank stops every rank.
# (its helpers, mpi to parallel_suite, are in 05_helpers.sh: 50, 55 and 60 use them too)

# --- Elastic: Lame cylinder (10-node tetrahedra).
ex_copy lame-cylinder
d="$work/examples/lame-cylinder"
ex_set "$d/cylinder.geo" '^h = [0-9.e-]+;' 'h = 0.02;'
parallel_suite "parallel lame-cylinder" "$d" displacement,stress
mpi_expect "parallel lame-cylinder: auto (the default) on 2 ranks is CG + GAMG, and says why" 0 \
  "linear solver \(solver.linear: auto\): PETSc CG \+ GAMG; 2 MPI ranks" 2 -- \
  run "$d/case.yaml" -o "$d/auto2"
same "parallel lame-cylinder: auto on 2 ranks = serial direct to 1e-7" "$d/direct" "$d/auto2" 1e-7 \
  displacement,stress
ex_check "parallel lame-cylinder: summary says 2 ranks and MUMPS" "$d/mumps2/summary.json" \
  's["ranks"] == 2 and "mumps" in s["linear_solver"]["method"] and s["peak_memory_bytes_all_ranks"] >= s["peak_memory_bytes"]'
ex_check "parallel lame-cylinder: history.csv written once (a header and 2 steps)" \
  "$d/mumps2/history.csv" 'len(h) == 2'
pieces "parallel lame-cylinder: 3 ranks write a .pvtu a step, with 3 pieces that hold each cell once" \
  "$d/mumps3" 3
pieces "parallel lame-cylinder: 2 ranks, 2 pieces" "$d/gamg2" 2
pieces "parallel lame-cylinder: 4 ranks, 4 pieces" "$d/mumps4" 4
# The mesh is distributed on ranks (issue 21): root reads and splits it, each rank holds its
# part. HENCKY_REPLICATED=1 keeps the whole mesh on every rank (docs/development.md), which must
# give the same answers.
mpi_expect "parallel lame-cylinder: 3 ranks hold a distributed mesh" 0 "distributed mesh: 3 ranks" \
  3 -- run "$d/case-direct.yaml" -o "$d/dist3"
export HENCKY_REPLICATED=1  # mpirun's ranks on this machine inherit its environment
mpi_expect "parallel lame-cylinder: HENCKY_REPLICATED=1 holds the whole mesh on each rank" 0 \
  "partition: 2 ranks" 2 -- run "$d/case-direct.yaml" -o "$d/replicated2"
unset HENCKY_REPLICATED
same "parallel lame-cylinder: ... and gives the serial answer to 1e-8" "$d/direct" "$d/replicated2" \
  1e-8 displacement,stress
ex_check "parallel lame-cylinder: GAMG iterates (more than one iteration a solve)" \
  "$d/gamg2/summary.json" 's["linear_solver"]["iterations"] > 2 * s["linear_solver"]["solves"]'
# The solve's tolerance adapts to the Newton residual unless -ksp_rtol is given: then the
# user's tolerance stands (more CG iterations than the adaptive default, closer to the direct
# solution than the 1e-7 a default run is held to).
expect "parallel lame-cylinder: -ksp_rtol 1e-12 given" 0 "" -- \
  run "$d/case-petsc.yaml" -o "$d/rtol12" --quiet --petsc "-ksp_rtol 1e-12"
ex_check "parallel lame-cylinder: -ksp_rtol given fixes the tolerance (more CG iterations than the default)" \
  "$d/rtol12/summary.json" \
  's["linear_solver"]["iterations"] > json.load(open(sys.argv[1].replace("rtol12", "petsc1")))["linear_solver"]["iterations"]'
same "parallel lame-cylinder: -ksp_rtol 1e-12 = serial direct to 1e-9" "$d/direct" "$d/rtol12" 1e-9 \
  displacement,stress
expect "parallel lame-cylinder: --petsc options reach PETSc (hypre)" 0 "" -- \
  run "$d/case-petsc.yaml" -o "$d/hypre1" --quiet --petsc "-pc_type hypre -ksp_rtol 1e-10"
ex_check "parallel lame-cylinder: summary names hypre" "$d/hypre1/summary.json" \
  '"hypre" in s["linear_solver"]["method"]'
same "parallel lame-cylinder: serial hypre = serial direct to 1e-7" "$d/direct" "$d/hypre1" 1e-7 \
  displacement,stress

# --- A mesh that Gmsh partitioned and saved in one file (gmsh -part 3) is the whole mesh: hencky
# splits it its own way on the ranks, and the order conversion (order: 2) goes through the Gmsh
# library, which must leave the boundaries between Gmsh's partitions out as the reader does.
# One file of a mesh split into files (-part_split) holds a part only: refused, naming it.
pd="$work/partitioned"
rm -rf "$pd" && mkdir -p "$pd" && cp "$d/cylinder.geo" "$pd/"
gmsh -3 "$pd/cylinder.geo" -format msh41 -o "$pd/plain.msh" >/dev/null 2>&1 &&
  gmsh -3 -part 3 "$pd/cylinder.geo" -format msh41 -o "$pd/parts.msh" >/dev/null 2>&1 &&
  gmsh -3 -part 3 -part_split "$pd/cylinder.geo" -format msh41 -o "$pd/split.msh" >/dev/null 2>&1 ||
  bad "partitioned: gmsh could not write the meshes"
for m in plain parts split_2; do
  sed -E "s#^  file: cylinder.geo.*#  file: $m.msh#" "$d/case-direct.yaml" >"$pd/$m.yaml"
done
expect "partitioned: the unpartitioned mesh, serial" 0 "" -- run "$pd/plain.yaml" -o "$pd/plain" --quiet
mpi_expect "partitioned: the mesh in 3 partitions, on 2 ranks" 0 "distributed mesh: 2 ranks" 2 -- \
  run "$pd/parts.yaml" -o "$pd/parts"
same "partitioned: ... = the unpartitioned mesh's answer to 1e-10" "$pd/plain" "$pd/parts" 1e-10 \
  displacement,stress
ex_bad "partitioned: one file of a split mesh is refused" \
  "split_2\.msh:[0-9]+: not a valid Gmsh mesh file: the file holds 1 of the 3 partitions of a mesh split into files" \
  "$pd/split_2.yaml"

# --- A mesh split into files (mesh.split, gmsh -part 3 -part_split): on 3 ranks each rank reads
# its own file and no rank the whole mesh; on one rank and on 2 the files are read together,
# numbered as the ranks' parts number them, so that checkpoints pass between the ways. The
# answers are those of the same mesh in one file. The whole model's checks are made by the
# ranks together, with the serial messages.
sd="$work/split"
rm -rf "$sd" && mkdir -p "$sd" && cp "$d/cylinder.geo" "$sd/"
gmsh -3 -order 2 "$sd/cylinder.geo" -format msh41 -o "$sd/plain.msh" >/dev/null 2>&1 &&
  gmsh -3 -order 2 -part 3 -part_split "$sd/cylinder.geo" -format msh41 -o "$sd/cyl.msh" \
    >/dev/null 2>&1 || bad "split: gmsh could not write the meshes"
sed -E -e "s#^  file: cylinder.geo.*#  file: plain.msh#" -e "/^  order: 2/d" "$d/case-direct.yaml" \
  >"$sd/plain.yaml"
sed -E -e "s#^  file: cylinder.geo.*#  file: cyl.msh\n  split: true#" -e "/^  order: 2/d" \
  "$d/case-direct.yaml" >"$sd/split.yaml"
expect "split: the mesh in one file, serial" 0 "" -- run "$sd/plain.yaml" -o "$sd/plain" --quiet
mpi_expect "split: 3 files on 3 ranks, each reads its own" 0 \
  "distributed mesh: 3 ranks, each read its file of the split mesh" 3 -- run "$sd/split.yaml" -o "$sd/own3"
same "split: ... = the mesh in one file to 1e-10" "$sd/plain" "$sd/own3" 1e-10 displacement,stress
same_history "split: ... and its history.csv to 1e-10" "$sd/plain" "$sd/own3" 1e-10 \
  '^reaction\.top\.'
if grep -q "mesh: $(sed -n 's/^mesh: //p' "$sd/plain/hencky.log")" "$sd/own3/hencky.log"; then
  ok "split: ... and the log describes the whole mesh as the serial run does"
else bad "split: the 3-rank log's mesh line is not the serial one" "$(grep '^mesh' "$sd"/*/hencky.log)"; fi
expect "split: the files read together on one rank" 0 "" -- run "$sd/split.yaml" -o "$sd/one" --quiet
same "split: ... = the mesh in one file to 1e-10" "$sd/plain" "$sd/one" 1e-10 displacement,stress
mpi_expect "split: 3 files on 2 ranks: root reads them" 0 "split mesh: root read its 3 files" 2 -- \
  run "$sd/split.yaml" -o "$sd/two"
same "split: ... = the mesh in one file to 1e-10" "$sd/plain" "$sd/two" 1e-10 displacement,stress
expect "split: the 3-rank run's checkpoint restarts on one rank" 0 "restart: from" -- \
  run "$sd/split.yaml" -o "$sd/own3-from1" --restart "$sd/own3" --from 0.5
same "split: ... = the 3-rank run to 1e-10" "$sd/own3" "$sd/own3-from1" 1e-10 displacement,stress
mpi_expect "split: the serial run's checkpoint restarts on 3 ranks, each reading its file" 0 "" 3 -- \
  run "$sd/split.yaml" -o "$sd/one-from3" --quiet --restart "$sd/one" --from 0.5
same "split: ... = the serial run to 1e-10" "$sd/one" "$sd/one-from3" 1e-10 displacement,stress
mpi_expect "split: a checkpoint of the mesh in one file is not the split mesh's (numbered otherwise)" \
  1 "is not the mesh the checkpoint was written with" 3 -- \
  run "$sd/split.yaml" -o "$sd/plain-from3" --quiet --restart "$sd/plain" --from 0.5
sed 's/point: \[0.2, 0.0, 0.01\]/point: [0.3, 0.0, 0.01]/' "$sd/split.yaml" >"$sd/outside.yaml"
mpi_expect "split: a probe outside every rank's part: the serial message" 1 \
  "^error: .*outside.yaml:[0-9]+:[0-9]+: 'output.probes\[1\].point': probe 'outer' at \(0.3, 0, 0.01\) is outside the mesh$" \
  3 -- run "$sd/outside.yaml" -o "$sd/outside"
[ -e "$sd/outside" ] && bad "split: the refused case wrote $sd/outside" || ok "split: ... and wrote nothing"
"$ex_py" - "$sd/split.yaml" "$sd/free.yaml" <<'PY'
import sys
s = open(sys.argv[1]).read()
i, j = s.index("  - region: symmetry_x"), s.index("solver:")
open(sys.argv[2], "w").write(s[:i] + "\n" + s[j:].replace("  reactions: [symmetry_x, symmetry_y, bottom]\n", ""))
PY
mpi_expect "split: no support on any rank: the serial message" 1 \
  "^error: .*free.yaml: 'boundary': no displacement condition: the body is free to move" 3 -- \
  run "$sd/free.yaml" -o "$sd/free"
mkdir -p "$sd/gap" && cp "$sd/cyl_1.msh" "$sd/cyl_3.msh" "$sd/gap/" && cp "$sd/split.yaml" "$sd/gap/"
ex_bad "split: a missing file (cyl_2.msh) is named by what the first says" \
  "cyl_1\.msh: the file holds partition 1 of 3, but as file 1 of the 1 files of the split mesh" \
  "$sd/gap/split.yaml"
expect "split: hencky check reads the files together" 0 "mesh: [0-9]+ nodes, [0-9]+ elements" -- check "$sd/split.yaml"

# --- Plastic: strip with a hole, overloaded and unloaded (20-node hexahedra, newton).
ex_copy plate-hole-overload
d="$work/examples/plate-hole-overload"
ex_set "$d/plate.geo" '^n = [0-9]+;' 'n = 6;'
# Each rank holds its own cells' integration points only: the fields recovered from them
# (nodal averages across the ranks' boundaries, cell means, the plastic zone) must not change.
parallel_suite "parallel plate-hole-overload" "$d" \
  displacement,stress,von_mises,plastic_strain,equivalent_plastic_strain,plastic_zone
ex_check "parallel plate-hole-overload: same steps, iterations and points on 2 ranks" "$d/mumps2/summary.json" \
  '(r := json.load(open(sys.argv[1].replace("mumps2", "direct")))) and s["steps"] == 10 and s["iterations"] == r["iterations"] and s["integration_points"] == r["integration_points"]'

# --- Contact: rigid ball pressed into a block and released.
ex_copy ball-indentation
d="$work/examples/ball-indentation"
ex_set "$d/block.geo" '^hc = a / [0-9]+;' 'hc = a / 2;'
# The refined ball of the coarse mesh these checks were measured on (551 contact nodes).
ex_set "$d/block.geo" '^rf = [0-9.]+ \* a;' 'rf = 1.1 * a;'
parallel_suite "parallel ball-indentation" "$d" displacement,stress,contact_pressure
mpi_expect "parallel ball-indentation: 2 ranks hold a distributed mesh" 0 "distributed mesh: 2 ranks" \
  2 -- run "$d/case-direct.yaml" -o "$d/dist2"
if grep -q "contact 'ball': 551 nodes of 'top'" "$d/dist2/hencky.log"; then
  ok "parallel ball-indentation: ... and the log names the whole model's contact nodes"
else bad "parallel ball-indentation: the log does not name the 551 contact nodes"; fi
ex_check "parallel ball-indentation: the contact force on 3 ranks = serial to 1e-8" \
  "$d/mumps3/history.csv" \
  'close(at(1.0)["contact.ball.resultant.z"], [float(r["contact.ball.resultant.z"]) for r in csv.DictReader(open(sys.argv[1].replace("mumps3", "direct"))) if float(r["time"]) == 1.0][0], 1e-8)'
# Contact on a mesh split into files, each rank reading its own: the ranks bind the contact
# points together (a node's faces may all be in another rank's file), and a checkpoint's
# contact states pass to one rank reading the files together.
sd="$work/split-contact"
rm -rf "$sd" && mkdir -p "$sd" && cp "$d/block.geo" "$sd/"
gmsh -3 -order 2 "$sd/block.geo" -format msh41 -o "$sd/plain.msh" >/dev/null 2>&1 &&
  gmsh -3 -order 2 -part 3 -part_split "$sd/block.geo" -format msh41 -o "$sd/b.msh" \
    >/dev/null 2>&1 || bad "split contact: gmsh could not write the meshes"
sed -E "s#^mesh: .*#mesh: {file: plain.msh}#" "$d/case-direct.yaml" >"$sd/plain.yaml"
sed -E "s#^mesh: .*#mesh: {file: b.msh, split: true}#" "$d/case-direct.yaml" >"$sd/split.yaml"
expect "split contact: the mesh in one file, serial" 0 "" -- run "$sd/plain.yaml" -o "$sd/plain" --quiet
mpi_expect "split contact: 3 files on 3 ranks, each reads its own" 0 \
  "contact 'ball': 551 nodes of 'top' \(1 touching at t = 0, 401 mid-edge\)" 3 -- \
  run "$sd/split.yaml" -o "$sd/own3"
same "split contact: ... = the mesh in one file to 1e-10" "$sd/plain" "$sd/own3" 1e-10 \
  displacement,stress,contact_pressure
same_history "split contact: ... and its history.csv to 1e-10" "$sd/plain" "$sd/own3" 1e-10 \
  '^$'
expect "split contact: the 3-rank run's checkpoint at t = 1 restarts on one rank" 0 "restart: from" -- \
  run "$sd/split.yaml" -o "$sd/own3-from1" --restart "$sd/own3" --from 1.0
same "split contact: ... = the 3-rank run to 1e-10" "$sd/own3" "$sd/own3-from1" 1e-10 \
  displacement,stress,contact_pressure

# --- Anderson mixing on ranks (acceleration: auto): the least squares of initial-stress works on
# the displacements, whole on every rank; that of initial-strain on the points' initial strains,
# each rank's own, summed over the ranks, and with contact (unload-contact) on each contact
# node's augmented force too, which every rank holds (weighted 1/ranks). All must take the
# ranks' run to the serial one. So must variable-stiffness's line search (line_search: auto),
# whose decisions (the residual's work along the correction) root takes for every rank.
# The two schemes with a stiffness update (initial-stress-stiffness, initial-strain-stiffness)
# complete the set: every scheme on ranks against its serial run (issue 21).
for run in heated-bar:initial-stress heated-bar:initial-strain unload-contact:initial-strain \
           epp-cylinder:variable-stiffness heated-bar:initial-stress-stiffness \
           heated-bar:initial-strain-stiffness; do
  case_="${run%%:*}" scheme="${run#*:}"
  d="$work/parallel-anderson-$case_-$scheme"
  rm -rf "$d" && mkdir -p "$d" && cp "$src/tests/cli/inputs/issue16/$case_"/* "$d/"
  sed -i -E "s/^  scheme: newton$/  scheme: $scheme/" "$d/case.yaml"
  # variable-stiffness's path depends on the last bits of its iterates: on the perfectly plastic
  # cylinder a point at the yield surface whose increment turns its stress is plastic by a λ of
  # second order in the increment (the iterate takes its trial's direction), and its matrix
  # along Z switches between 0 and 3G with it. The ranks' CG + GAMG and the serial CHOLMOD then
  # take different paths (measured at the case's tolerance 1e-8: 53 and 56 iterations, 1.5e-8
  # apart; with MUMPS on the ranks 54 and 56, 5.7e-9). It is run at 1e-10, where the two answers
  # are 8e-11 apart, and its iterations are not compared.
  [ "$scheme" = variable-stiffness ] && sed -i -E "s/^  tolerance: 1e-8$/  tolerance: 1e-10/" "$d/case.yaml"
  expect "parallel anderson, $case_, $scheme: serial" 0 "" -- run "$d/case.yaml" -o "$d/r1" --quiet
  mpi_expect "parallel anderson, $case_, $scheme: 2 ranks" 0 "" 2 -- run "$d/case.yaml" -o "$d/r2" --quiet
  same "parallel anderson, $case_, $scheme: 2 ranks = serial to 1e-8" "$d/r1" "$d/r2" 1e-8 \
    displacement,stress,equivalent_plastic_strain
  [ "$scheme" = variable-stiffness ] && continue
  ex_check "parallel anderson, $case_, $scheme: the same iterations on 2 ranks" "$d/r2/summary.json" \
    's["iterations"] == json.load(open(sys.argv[1].replace("/r2/", "/r1/")))["iterations"]'
done

# --- formulation: report (issue 46) on 2 ranks: the report's initial stresses on the plastic
# cylinder, the same iterates as serial (its Z(t) and its measures are per point; the sums over
# the ranks decide alike).
d="$work/parallel-report"
rm -rf "$d" && mkdir -p "$d" && cp -r "$src/tests/cli/inputs/issue16/epp-cylinder/." "$d/"
sed -i -E 's/^([[:space:]]*)scheme:[[:space:]]*newton[[:space:]]*$/\1scheme: initial-stress\n\1formulation: report/' "$d/case.yaml"
expect "parallel report, epp-cylinder, initial-stress: serial" 0 "" -- run "$d/case.yaml" -o "$d/r1" --quiet
mpi_expect "parallel report, epp-cylinder, initial-stress: 2 ranks" 0 "" 2 -- run "$d/case.yaml" -o "$d/r2" --quiet
same "parallel report, epp-cylinder, initial-stress: 2 ranks = serial to 1e-8" "$d/r1" "$d/r2" 1e-8 \
  displacement,stress,equivalent_plastic_strain
ex_check "parallel report: the same iterations and yield excess on 2 ranks" "$d/r2/summary.json" \
  's["iterations"] == json.load(open(sys.argv[1].replace("/r2/", "/r1/")))["iterations"] and close(s["report"]["largest_yield_excess"]["value"], json.load(open(sys.argv[1].replace("/r2/", "/r1/")))["report"]["largest_yield_excess"]["value"], 1e-8) and s["formulation"] == "report"'

# --- More ranks than cells: a fully prescribed single hexahedron (NAFEMS NL1, issue 23) on 2
# ranks, one of which holds no cell. Its checkpoint used to stop the distributed run with an
# internal error and hang the replicated one (the points' tangents record, written by the rank
# with points only).
d="$work/parallel-nl1"
rm -rf "$d" && mkdir -p "$d" && cp "$src/tests/cli/inputs/nl1/"* "$d/"
sed -i -E "s/^  steps: 80$/  steps: 16/" "$d/case.yaml"
expect "more ranks than cells: serial" 0 "" -- run "$d/case.yaml" -o "$d/r1" --quiet
mpi_expect "more ranks than cells: 2 ranks, one without a cell" 0 "" 2 -- \
  run "$d/case.yaml" -o "$d/r2" --quiet
same "more ranks than cells: ... = serial to 1e-12" "$d/r1" "$d/r2" 1e-12 displacement,stress
mpi_expect "more ranks than cells: ... and restarts from its checkpoint at t = 4" 0 "" 2 -- \
  run "$d/case.yaml" -o "$d/r2-from4" --quiet --restart "$d/r2" --from 4
same "more ranks than cells: ... = serial to 1e-12" "$d/r1" "$d/r2-from4" 1e-12 displacement,stress

# --- An Abaqus deck (issue 22) under mpirun: Gmsh's export of the 20-node box, whose sets share
# their names across kinds (NSET and ELSET "fixed"), on 2 ranks and restarted from its
# checkpoint on 3; rank 0 reads the deck.
d="$work/inp-parallel"
rm -rf "$d" && mkdir -p "$d"
cp "$src/tests/cli/inputs/inp/box-hex.geo" "$d/"
if gmsh -3 "$d/box-hex.geo" -order 2 -string "Mesh.SecondOrderIncomplete=1;" -o "$d/box.msh" \
  >/dev/null 2>&1 && gmsh "$d/box.msh" -0 -string "Mesh.SaveGroupsOfNodes=1;" -format inp \
  -o "$d/box.inp" >/dev/null 2>&1; then
  sed -E -e 's|file: box.msh|file: box.inp|' -e 's|^solver: \{steps: 1\}|solver: {steps: 2}|' \
    -e 's|^  reactions: \[fixed\]|  reactions: [fixed]\n  checkpoint: 1|' \
    "$src/tests/cli/inputs/inp/box.yaml" >"$d/case.yaml"
  expect "inp deck: serial" 0 "" -- run "$d/case.yaml" -o "$d/r1" --quiet
  mpi_expect "inp deck: 2 ranks" 0 "" 2 -- run "$d/case.yaml" -o "$d/r2" --quiet
  same "inp deck: 2 ranks (MUMPS) = serial to 1e-10" "$d/r1" "$d/r2" 1e-10 displacement,stress
  mpi_expect "inp deck: restarted on 3 ranks from the 2 ranks' checkpoint at t = 0.5" 0 "" 3 -- \
    run "$d/case.yaml" -o "$d/r3" --quiet --restart "$d/r2" --from 0.5
  same "inp deck: ... = serial to 1e-10" "$d/r1" "$d/r3" 1e-10 displacement,stress
else
  bad "inp deck: gmsh failed"
fi

# --- Errors under mpirun.
d="$work/examples/lame-cylinder"
sed -E 's/^  steps: 2/  stepz: 2/' "$d/case.yaml" >"$d/broken.yaml"
mpi_expect "parallel: a bad case is reported once, by rank 0, with exit 1" 1 \
  "^error: .*broken.yaml.*'solver.stepz'" 2 -- run "$d/broken.yaml" --quiet
out="$(timeout 120 mpirun --oversubscribe --bind-to none -x OMP_NUM_THREADS=1 \
  -np 1 "$bin" run "$d/case.yaml" -o "$d/mpmd" --quiet : -np 1 "$bin" run "$d/broken.yaml" --quiet 2>&1)"
rc=$?
if [ "$rc" -eq 1 ] && grep -Eq "^rank 1: error: .*'solver.stepz'" <<<"$out" && [ ! -e "$d/mpmd" ]; then
  ok "parallel: an error on rank 1 alone names the rank, stops both ranks (exit 1), writes nothing"
else
  bad "parallel: an error on rank 1 alone (exit $rc)" "$out"
fi
cp "$d/case.yaml" "$d/other.yaml"
ex_set "$d/other.yaml" '^  file: cylinder.geo' '  file: other.geo'
sed -E 's/^h = [0-9.e-]+;/h = 0.03;/' "$d/cylinder.geo" >"$d/other.geo"
out="$(timeout 120 mpirun --oversubscribe --bind-to none -x OMP_NUM_THREADS=1 \
  -np 1 "$bin" run "$d/case.yaml" -o "$d/mixed" --quiet : -np 1 "$bin" run "$d/other.yaml" -o "$d/mixed" --quiet 2>&1)"
rc=$?
if [ "$rc" -eq 1 ] && grep -Eq "the ranks read different models" <<<"$out"; then
  ok "parallel: ranks that read different meshes stop with an error"
else
  bad "parallel: ranks that read different meshes (exit $rc)" "$out"
fi
# An option PETSc reads but cannot set the solver up with (an algorithm the serial matrix type
# does not have) is an input error naming the options, not a body that is not held; on 2 ranks
# the same option works.
expect "parallel: an option PETSc cannot set up with is an input error naming solver.petsc_options" 1 \
  "'solver.petsc_options'.*allatonce" -- run "$d/case-petsc.yaml" -o "$d/badopt" --quiet \
  --petsc "-matptap_via allatonce"
[ ! -e "$d/badopt" ] && ok "parallel: ... and nothing is written" || bad "parallel: $d/badopt written"
mpi_expect "parallel: -matptap_via allatonce works on 2 ranks" 0 "" 2 -- \
  run "$d/case-petsc.yaml" -o "$d/allatonce2" --quiet --petsc "-matptap_via allatonce"
same "parallel: ... and gives the serial answer to 1e-7" "$d/direct" "$d/allatonce2" 1e-7 displacement,stress
# A body that is not held: refused on 2 ranks as on one, before anything is solved, naming
# its free motions (Model::check_held).
ex_copy cantilever
d="$work/examples/cantilever"
ex_set "$d/beam.geo" '^n = [0-9]+;' 'n = 4;'
ex_set "$d/case.yaml" 'displacement: \{x: 0, y: 0, z: 0\}' 'displacement: {x: 0}'
with_petsc "$d/case.yaml"
mpi_expect "parallel: a body not held, 2 ranks: exit 1 naming its free motions" 1 \
  "'boundary': the body is not held: its displacement conditions leave 3 rigid motions free: translation along y; translation along z; rotation about .* along x" \
  2 -- run "$d/case-petsc.yaml" --quiet
# A body that contact alone may hold, which the surface does not touch in the first step: the
# direct solve (MUMPS factors the singular matrix without complaint; its residual gives it
# away) stops with the input error.
g="$work/parallel-gap"
rm -rf "$g" && mkdir -p "$g" && cp "$src/tests/cli/inputs/held/block.geo" "$g/"
sed -e 's/point: \[0, 0, 0\]/point: [0, 0, -1e-3]/' -e 's/^contact:/solver: {linear: direct}\ncontact:/' \
  "$src/tests/cli/inputs/held/contact-held.yaml" >"$g/gap.yaml"
mpi_expect "parallel: a body the surface does not reach, MUMPS on 2 ranks: exit 1 naming the cause" 1 \
  "'boundary'.*relative residual.*not held against rigid-body motion" 2 -- run "$g/gap.yaml" --quiet
# Issue 14 under mpirun: the refusals and the safety net are collective (every rank stops with
# the same status, rank 0 reports).
printf '%s\n' "mesh: {file: beam.geo}" "materials: [{E: 2.1e11, nu: 0.3, alpha: 1.2e-5}]" \
  "boundary:" "  - {region: clamp, displacement: {x: 0, y: 0, z: 0}}" >"$d/clamped.yaml"
mpi_expect "parallel: -o /proc/x on 2 ranks: exit 1 from rank 0's check, before solving" 1 \
  "^rank 0: error: '-o': cannot create the output directory /proc/x" 2 -- \
  run "$d/clamped.yaml" -o /proc/x --quiet
{ cat "$d/clamped.yaml"; echo "temperature: {reference: 20, field: \"t > 0.6 ? 1e308 : 20 + 100*t\"}"
  echo "solver: {steps: 2}"; } >"$d/hot.yaml"
mpi_expect "parallel: a temperature that overflows at step 2 on 2 ranks: exit 1, reported once" 1 \
  "^error: .*'temperature\.field': the temperature 1e\+308 at element [0-9]+ \(material 'material0', t = 1\)" 2 -- \
  run "$d/hot.yaml" -o "$d/hot.out" --quiet
[ ! -e "$d/hot.out" ] && ok "parallel: ... and nothing is written" || bad "parallel: $d/hot.out written"
{ cat "$d/clamped.yaml"; echo "  - {region: tip, displacement: {z: \"t > 0.6 ? 1e308 : -0.001*t\"}}"
  echo "solver: {steps: 2, cutback: 1}"; } >"$d/nan.yaml"
mpi_expect "parallel: a NaN in the solve on 2 ranks fails the step (exit 2)" 2 "" 2 -- \
  run "$d/nan.yaml" -o "$d/nan.out" --quiet
ex_check "parallel: ... saying where, and step 1 is kept" "$d/nan.out/summary.json" \
  's["status"] == "not-converged" and s["steps"] == 1 and "a NaN or an infinity appeared in the stress at element" in s["failure"]'
