# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh,
# the mpirun ones among them). Issue 18: heat conduction. The case is
# tests/cli/inputs/heat/case.yaml (a transient with every kind of condition, k(T), c(T) and a
# source of T); its outputs, the same run on the PETSc back end and on MPI ranks, a heat
# analysis that stops, and bad input.
hd="$work/heat"
rm -rf "$hd"
mkdir -p "$hd"
cp "$src/tests/cli/inputs/heat"/* "$hd/"
# The 12 heat steps of 5 s, the first in two backward-Euler halves: 13 heat steps.
expect "heat: the heated block runs" 0 "heat   13  t = 60 .*iterations" -- run "$hd/case.yaml"
h="$hd/case.out/history.csv"
s="$hd/case.out/summary.json"
ex_check "heat: history.csv has heat_flow.<region> and reaction.x0.heat (W into the body)" "$h" \
  'all(k in h[0] for k in ("heat_flow.x0", "heat_flow.x1", "heat_flow.top", "heat_flow.y0", "reaction.x0.heat", "reaction.bottom.z", "middle.temperature"))'
ex_check "heat: the x0 reaction is its temperature condition's flow; y0 brings its 2e4 W/m2 over 0.1 x 0.02 m" "$h" \
  'all(r["reaction.x0.heat"] == r["heat_flow.x0"] and close(r["heat_flow.y0"], 40.0, 1e-12) for r in h)'
ex_check "heat: convection and radiation take heat out, the heated end puts it in at the end" "$h" \
  'at(60)["heat_flow.x1"] < 0 and at(60)["heat_flow.top"] < 0 and at(60)["heat_flow.x0"] > 0'
ex_check "heat: summary.json has heat_flows, reactions.x0.heat and the heat solver's counts" "$s" \
  's["heat_flows"]["y0"] == s["reactions"]["x0"]["heat"] - s["reactions"]["x0"]["heat"] + 40.0 and s["heat"]["steps"] == 13 and s["wall_seconds"]["heat"] > 0'
ex_check "heat: the probe warms (middle of the block, above 20 degrees at t = 60)" "$h" \
  'at(60)["middle.temperature"] > 25 and all(h[i]["middle.temperature"] < h[i + 1]["middle.temperature"] for i in range(len(h) - 1))'
if grep -q '"heat_flux"' "$hd/case.out/step_0004.vtu"; then ok "heat: the VTU has a heat_flux field"
else bad "heat: no heat_flux field in step_0004.vtu"; fi

# --- The same case on the PETSc back end and on MPI ranks: the temperatures, heat fluxes and
# stresses agree with the serial direct run (the heat matrix goes through the same back ends).
# The block carries no load: the net reaction of its held bottom is round-off (below 1e-9 N),
# which the ranks' sums need not reproduce.
parallel_suite "heat" "$hd" "displacement,stress,temperature,heat_flux" '^reaction\.bottom\.'
# On ranks the heat analysis runs on the distributed mesh (issue 21): each rank holds its part
# and its temperatures. A restart at t = 30 on 3 ranks is the uninterrupted 3-rank run; the
# serial run's checkpoint restarted on 2 ranks gives the serial run.
mpi_expect "heat: on 2 ranks the mesh is distributed" 0 "distributed mesh: 2 ranks" 2 -- \
  run "$hd/case-direct.yaml" -o "$hd/dist2"
mpi_expect "heat: restarted at t = 30 on 3 ranks" 0 "" 3 -- \
  run "$hd/case-direct.yaml" --quiet --restart "$hd/mumps3" --from 30 -o "$hd/from30-3"
same "heat: ... = the uninterrupted run on 3 ranks to 1e-12" "$hd/mumps3" "$hd/from30-3" 1e-12 \
  displacement,stress,temperature,heat_flux
same_history "heat: ... and its history.csv to 1e-12" "$hd/mumps3" "$hd/from30-3" 1e-12
mpi_expect "heat: the serial run's checkpoint restarted at t = 30 on 2 ranks" 0 "" 2 -- \
  run "$hd/case-direct.yaml" --quiet --restart "$hd/direct" --from 30 -o "$hd/from30-s2"
same "heat: ... = the serial run to 1e-8" "$hd/direct" "$hd/from30-s2" 1e-8 \
  displacement,stress,temperature,heat_flux
same_history "heat: ... and its history.csv to 1e-8" "$hd/direct" "$hd/from30-s2" 1e-8 \
  '^reaction\.bottom\.'

# The heated block in 3 files (mesh.split, 20-node hexahedra made before Gmsh splits the mesh):
# on 3 ranks each reads its own file; the temperatures and heat fluxes are those of the same
# mesh in one file, and the 3-rank checkpoint restarts on one rank.
hs="$hd/split"
mkdir -p "$hs" && cp "$hd/block.geo" "$hs/"
serendipity=(-order 2 -string "Mesh.SecondOrderIncomplete=1;")
gmsh -3 "${serendipity[@]}" "$hs/block.geo" -format msh41 -o "$hs/plain.msh" >/dev/null 2>&1 &&
  gmsh -3 "${serendipity[@]}" -part 3 -part_split "$hs/block.geo" -format msh41 -o "$hs/blk.msh" \
    >/dev/null 2>&1 || bad "heat: gmsh could not write the split meshes"
sed -E 's#^mesh: .*#mesh: {file: plain.msh}#' "$hd/case-direct.yaml" >"$hs/plain.yaml"
sed -E 's#^mesh: .*#mesh: {file: blk.msh, split: true}#' "$hd/case-direct.yaml" >"$hs/split.yaml"
expect "heat: the block's mesh in one file, serial" 0 "" -- run "$hs/plain.yaml" -o "$hs/plain" --quiet
mpi_expect "heat: the block in 3 files on 3 ranks, each reading its own" 0 \
  "each read its file of the split mesh" 3 -- run "$hs/split.yaml" -o "$hs/own3"
same "heat: ... = the mesh in one file to 1e-10" "$hs/plain" "$hs/own3" 1e-10 \
  displacement,stress,temperature,heat_flux
same_history "heat: ... and its history.csv to 1e-10" "$hs/plain" "$hs/own3" 1e-10 \
  '^reaction\.bottom\.'
expect "heat: ... its checkpoint at t = 30 restarts on one rank" 0 "" -- \
  run "$hs/split.yaml" -o "$hs/own3-from1" --quiet --restart "$hs/own3" --from 30
same "heat: ... = the 3-rank run to 1e-8" "$hs/own3" "$hs/own3-from1" 1e-8 \
  displacement,stress,temperature,heat_flux

# --- A heat analysis that does not converge stops with status 2 and keeps what converged:
# radiation from surroundings at 1500 degrees switched on at t = 30, two Newton iterations
# allowed (a step without radiation needs two: the solve, and the check of its correction).
sed -E -e 's/^  steps: 12$/  steps: 12\n  max_iterations: 2/' \
  -e 's/emissivity: 0.8, ambient: 20/emissivity: "t > 30 ? 0.8 : 0", ambient: 1500/' \
  -e 's/^  source: .*$/  source: 0/' -e 's/\{temperature: \[20, 600\], value: \[50, 30\]\}/50/' \
  -e 's/\{temperature: \[20, 600\], value: \[450, 700\]\}/450/' -e 's/^  theta: 0.5$/  theta: 1/' \
  "$hd/case.yaml" >"$hd/stops.yaml"
expect "heat: a heat step that does not converge stops the run with status 2" 2 \
  "heat: the step to t = 35 did not converge after 4 cut-backs" -- run "$hd/stops.yaml" --quiet
ex_check "heat: the run that stopped kept its converged steps (t = 15, 30)" "$hd/stops.out/history.csv" \
  'len(h) == 2 and at(30)["time"] == 30'

# --- Bad input: a clear error at the key, nothing written.
hb() {  # hb NAME PATTERN SED_SCRIPT: the case edited by the sed script must be refused
  sed -E "$3" "$hd/case.yaml" >"$hd/bad.yaml"
  ex_bad "heat, bad input: $1" "$2" "$hd/bad.yaml"
}
hb "a material without conductivity" "materials\[0\]\.conductivity.*needs 'conductivity'" \
  '/^    conductivity:/d'
hb "a transient without density" "materials\[0\]\.density.*needs 'density'" '/^    density:/d'
hb "a negative film coefficient" "heat\.boundary\[1\]\.convection\.h.*must be >= 0" 's/h: 200/h: -5/'
hb "a film coefficient that turns negative at run time" \
  "heat\.boundary\[1\]\.convection\.h.*gives the film coefficient h = -.*h must be >= 0" \
  's/h: 200/h: "200 - 10*t"/'
hb "an emissivity above 1" "heat\.boundary\[2\]\.radiation\.emissivity.*in 0 \.\. 1" \
  's/emissivity: 0.8/emissivity: 1.5/'
hb "radiation without the absolute zero" "heat\.boundary\[2\]\.radiation\.emissivity.*absolute_zero" \
  '/^  absolute_zero:/d'
hb "a convection on a region with no faces (a volume)" "heat\.boundary\[1\]\.region.*physical surface" \
  's/region: x1, convection/region: body, convection/; s/heat_flows: .*/heat_flows: [x0]/'
hb "a region that does not exist" "heat\.boundary\[3\]\.region.*'y9'.*y0" 's/region: y0, flux/region: y9, flux/; s/heat_flows: .*/heat_flows: [x0]/'
hb "from: heat without a heat section" "temperature\.from.*needs a 'heat' section" \
  '/^heat:/,/^boundary:/{/^boundary:/!d}'
hb "a heat section with a temperature field" "temperature\.field.*from: heat" \
  's/^temperature: .*/temperature: {reference: 20, field: 100}/'
hb "theta below 1/2" "heat\.theta.*0\.5 \.\. 1" 's/^  theta: 0.5$/  theta: 0.2/'
hb "a steady analysis with fluxes only" "heat\.boundary.*steady heat analysis needs a temperature" \
  's/^  analysis: transient$/  analysis: steady/; s/^  theta: 0.5$//; /region: x[01],|region: top,/d'
hb "heat steps ending before the mechanical ones" "heat\.times.*before the mechanical steps" \
  's/^  steps: 12$/  times: [10, 20]/'
hb "an unknown heat key, with a suggestion" "heat.*'sourse'.*source" 's/^  source:/  sourse:/'
hb "heat_flows of a region without a heat condition" "output\.heat_flows.*'bottom' has no heat condition" \
  's/heat_flows: \[x0, x1, top, y0\]/heat_flows: [x0, bottom]/'

# --- Every scheme and contact take the heat analysis's temperatures. The block made plastic
# (linear hardening from 100 MPa, H = E/10; the middle yields), run with each scheme: every run
# converges on the same temperatures. Every scheme takes the flow direction of the iterate's
# trial stress and solves the same step equations: each agrees with newton to the tolerance
# (within 1e-5 of the yield stress). The initial strains kept the report's flow direction of
# the step's start before: they differed from newton by O(dt) (4.5e-2 of the yield stress at
# these 4 steps; docs/schemes.md).
sed -E 's/^    specific_heat: (.*)$/    specific_heat: \1\n    plasticity: {linear: {yield: 100e6, hardening: 2.0e10}}/' \
  "$hd/case.yaml" >"$hd/plastic.yaml"
hist_py() { echo "[{k: float(v) for k, v in r.items()} for r in __import__('csv').DictReader(open('$1'))]"; }
same_stress() { # $1 the reference history.csv, $2 the largest difference / yield stress
  echo "(v := $(hist_py "$1")) and len(v) == len(h) == 4 and all(a['middle.temperature'] == b['middle.temperature'] and max(abs(a['middle.stress.' + c] - b['middle.stress.' + c]) for c in ('xx', 'yy', 'zz', 'xy', 'yz', 'xz')) < $2 * 100e6 for a, b in zip(h, v))"
}
for scheme in newton variable-stiffness initial-stress initial-stress-stiffness initial-strain \
  initial-strain-stiffness; do
  sed -E "s/^solver:$/solver:\n  scheme: $scheme/" "$hd/plastic.yaml" >"$hd/plastic-$scheme.yaml"
  expect "heat: the plastic block, scheme $scheme" 0 "" -- run "$hd/plastic-$scheme.yaml" --quiet
  [ "$scheme" = newton ] || ex_check "heat: $scheme = newton: same temperatures, stresses within 1e-5 of the yield stress" \
    "$hd/plastic-$scheme.out/history.csv" "$(same_stress "$hd/plastic-newton.out/history.csv" 1e-5)"
done
ex_check "heat: the middle of the plastic block yields (newton)" \
  "$hd/plastic-newton.out/history.csv" "h[-1]['middle.equivalent_plastic_strain'] > 0"
# Contact: a rigid lid on the top face coming down while the block heats: it presses every top
# node, and its force balances the bottom's reaction.
sed -E 's/^boundary:$/contact:\n  - {name: lid, nodes: top, surface: {plane: {point: [0, 0, 0.02], normal: [0, 0, -1]}}, motion: [0, 0, "-2.0e-7*t"]}\nboundary:/' \
  "$hd/plastic.yaml" >"$hd/contact.yaml"
expect "heat: the plastic block heated under a rigid lid" 0 "" -- run "$hd/contact.yaml" --quiet
ex_check "heat: the lid presses every top node (73), its force grows and balances the bottom's reaction to 1e-6" \
  "$hd/contact.out/history.csv" \
  'all(r["contact.lid.nodes"] == 73 and close(r["reaction.bottom.z"], -r["contact.lid.resultant.z"], 1e-6) for r in h) and all(h[i]["contact.lid.force"] < h[i + 1]["contact.lid.force"] for i in range(3))'
