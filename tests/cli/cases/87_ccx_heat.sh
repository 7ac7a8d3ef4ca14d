# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 48, item 1: a deck's heat transfer. *HEAT TRANSFER (steady and transient) and *COUPLED
# TEMPERATURE-DISPLACEMENT with the temperatures of *BOUNDARY's degree of freedom 11, *FILM,
# *RADIATE, *DFLUX and *PHYSICAL CONSTANTS, checked against CalculiX's own test decks
# (calculix-ccx-test) and their .dat.ref, and against ccx 2.20 on variants of them.
hd_="$work/ccx-heat"
rm -rf "$hd_" && mkdir -p "$hd_"
suite=/usr/share/doc/calculix-ccx-test/examples/test
if [ ! -f "$suite/beamth.inp.gz" ] || ! command -v ccx >/dev/null; then
  bad "ccx heat: calculix-ccx-test or calculix-ccx is missing (scripts/setup.sh installs them)"
  return 0
fi
# The package keeps the small decks as they are and gzips the others.
ref() { if [ -f "$suite/$1.dat.ref" ]; then echo "$suite/$1.dat.ref"; else echo "$suite/$1.dat.ref.gz"; fi; }
for d in oneel20fi oneel8ra oneel20df oneel20cf beamth beamhtbo; do
  if [ -f "$suite/$d.inp" ]; then cp "$suite/$d.inp" "$hd_/"; else zcat "$suite/$d.inp.gz" >"$hd_/$d.inp"; fi
done
hdat() {  # hdat WHAT A.dat B.dat BOUND [--blocks N]
  local out
  out="$("$ex_py" "$src/tests/tools/dat_compare.py" "$2" "$3" "$4" "${@:5}" 2>&1)" &&
    ok "ccx heat: $1 ($(tr '\n' ';' <<<"$out"))" || bad "ccx heat: $1" "$out"
}
# Steady heat transfer alone, every deck's NT against its .dat.ref (7 printed digits; the RFL
# and HFL blocks are not written): a film on one face of a C3D20R cube (h = 10, sink -12), a
# flux into one face (-100, *DFLUX), heat flows into single nodes (*CFLUX: 10 into each corner
# of one face, -40 out of two others), radiation from one face of a C3D8 (emissivity 1, sink
# -12, *PHYSICAL CONSTANTS' absolute zero and Stefan-Boltzmann constant), and beamhtbo's
# conductivity that steps from 50 to 100 at 52 degrees (a table over temperature).
for d in oneel20fi oneel20df oneel20cf oneel8ra beamhtbo; do
  expect "ccx heat: $d.inp runs as given" 0 "" -- run "$hd_/$d.inp" --quiet
  hdat "$d's temperatures are its .dat.ref's to 1e-6" "$hd_/$d.out/$d.dat" "$(ref "$d")" 1e-6 --blocks 1
done
expect "ccx heat: check counts a heat analysis alone's temperatures" 0 "unknowns: 20 temperatures" -- \
  check "$hd_/oneel20fi.inp"
# A transient (beamth: 100 degrees on one end from t = 0, initial 20, 10 s in ccx's automatic
# increments from 1e-3, FREQUENCY=10): hencky takes the increments ccx takes when each converges
# at once (two of 1e-3, then 1.5 times the last), 23 of them, and prints at the same three. As
# C3D20 the two codes integrate alike: ccx's temperatures to their printed digits; as given
# (C3D20R) ccx's reduced integration of the capacity and the conductivity differs from hencky's
# full one by 1.1e-3 of the range at the first print (t = 0.076, the steepest gradients), 1e-7
# at the end.
sed -e 's/TYPE=C3D20R/TYPE=C3D20/' "$hd_/beamth.inp" >"$hd_/beamth20.inp"
(cd "$hd_" && ccx -i beamth20 >beamth20.ccx.log 2>&1) || bad "ccx heat: ccx failed on beamth20"
expect "ccx heat: beamth20.inp (transient) runs" 0 "" -- run "$hd_/beamth20.inp" --quiet
hdat "the transient's temperatures at its three prints are ccx's to 1e-6" \
  "$hd_/beamth20.out/beamth20.dat" "$hd_/beamth20.dat" 1e-6 --blocks 3
ex_check "ccx heat: ... in ccx's 23 increments" "$hd_/beamth20.out/summary.json" 's["steps"] == 23'
# The temperatures in MODEL.frd as well (*NODE FILE NT every 10th increment): ccx's NDTEMP.
sed -e 's/^\*NODE PRINT,NSET=Nall,FREQUENCY=10$/*NODE FILE,FREQUENCY=10\nNT\n&/' "$hd_/beamth20.inp" >"$hd_/beamth-frd.inp"
(cd "$hd_" && ccx -i beamth-frd >beamth-frd.ccx.log 2>&1) || bad "ccx heat: ccx failed on beamth-frd"
expect "ccx heat: beamth-frd.inp runs" 0 "" -- run "$hd_/beamth-frd.inp" --quiet
out="$("$ex_py" "$src/tests/tools/frd_compare.py" "$hd_/beamth-frd.out/beamth-frd.frd" "$hd_/beamth-frd.frd" 1e-6 NDTEMP 2>&1)" &&
  grep -c "^NDTEMP block" <<<"$out" | grep -qx 3 &&
  ok "ccx heat: ... its .frd holds ccx's NDTEMP at the same 3 increments" || bad "ccx heat: the .frd's NDTEMP" "$out"
# A restart from the 15th increment (t = 0.582859, as the checkpoints' list shows it) writes
# the same MODEL.dat and MODEL.frd as the run that was not stopped: the blocks before the
# restart copied, the print frequency counted on (the next print is the 20th increment).
expect "ccx heat: a restart of the deck run from t = 0.582859" 0 "" -- \
  run "$hd_/beamth-frd.inp" --restart "$hd_/beamth-frd.out" --from 0.582859 -o "$hd_/restart.out" --quiet
cmp -s "$hd_/restart.out/beamth-frd.dat" "$hd_/beamth-frd.out/beamth-frd.dat" &&
  diff <(grep -v UTIME "$hd_/restart.out/beamth-frd.frd") <(grep -v UTIME "$hd_/beamth-frd.out/beamth-frd.frd") >/dev/null &&
  ok "ccx heat: ... its .dat and .frd are the uninterrupted run's (the .frd's time of writing aside)" ||
  bad "ccx heat: the restarted run's .dat or .frd differ from the uninterrupted run's"
expect "ccx heat: beamth.inp runs as given" 0 "" -- run "$hd_/beamth.inp" --quiet
hdat "beamth (C3D20R) against its .dat.ref to 2e-3 (reduced against full integration)" \
  "$hd_/beamth.out/beamth.dat" "$(ref beamth)" 2e-3 --blocks 3
# Coupled temperature-displacement: beamhtbo's beam as C3D20 with a constant conductivity, an
# elastic material that expands, held at its cool end; steady and transient (0.5 in 20 s,
# automatic increments). hencky solves the heat step and then the stresses it causes, ccx both
# together: without heat made by deformation the answers are the same, U and NT to their printed
# digits, S at the 27 points of every element to 1.6e-5 of the block's largest: a stress here is
# the small difference of E·ε and E·α·ΔT (about 200 against the largest stress, 7.2), and the
# two codes' sums of the temperatures at the points differ in their last bits (the same deck as a
# *STATIC step with the printed temperatures shows the same 6.3e-6 between the two codes).
awk '/^\*MATERIAL/ {print "*MATERIAL,NAME=EL\n*ELASTIC\n210000.,.3\n*EXPANSION\n12.E-6\n*CONDUCTIVITY\n50.\n*DENSITY\n7.8E-9\n*SPECIFIC HEAT\n4.6E8"; skip=1; next}
     skip && /^\*SOLID SECTION/ {skip=0}
     skip {next}
     /^\*STEP/ {exit}
     {sub(/TYPE=C3D20R/, "TYPE=C3D20"); sub(/^Nall,0\.$/, "Nall,20."); print}' "$hd_/beamhtbo.inp" >"$hd_/beam-coupled.model"
for kind in steady transient; do
  { cat "$hd_/beam-coupled.model"
    if [ "$kind" = steady ]; then printf '*STEP\n*COUPLED TEMPERATURE-DISPLACEMENT,STEADY STATE\n1.,1.\n'
    else printf '*STEP\n*COUPLED TEMPERATURE-DISPLACEMENT\n0.5,20.\n'; fi
    printf '*BOUNDARY\nCN7,1,3\nGIBO,11,11,100.\nCN7,11,11,20.\n*NODE PRINT,NSET=Nall\nU,NT\n*EL PRINT,ELSET=Eall\nS\n*END STEP\n'
  } >"$hd_/coupled-$kind.inp"
  (cd "$hd_" && ccx -i "coupled-$kind" >"coupled-$kind.ccx.log" 2>&1) || bad "ccx heat: ccx failed on coupled-$kind"
  expect "ccx heat: coupled-$kind.inp runs" 0 "" -- run "$hd_/coupled-$kind.inp" --quiet
  hdat "coupled, $kind: U, NT and S at the points are ccx's to 3e-5 in every increment" \
    "$hd_/coupled-$kind.out/coupled-$kind.dat" "$hd_/coupled-$kind.dat" 3e-5
done
# A flux through one face of a steel cube held at 200° on its bottom (C3D8, transient to 5 s in
# ccx's increments with a largest one of 2): as *HEAT TRANSFER, ccx's temperatures in every
# increment; as *COUPLED TEMPERATURE-DISPLACEMENT with α = 0 as well; with α = 1.2e-5 ccx's
# coupled step conducts the heat in the deformed cube, and its temperatures move by 0.45 % of
# the differences (3.75e-5 of the range; docs/ccx-decks.md).
cat >"$hd_/cube-mesh.inp" <<'DECK'
*NODE, NSET=NALL
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=EALL
1, 1, 2, 3, 4, 5, 6, 7, 8
*NSET, NSET=BOTTOM
1, 2, 3, 4
*NSET, NSET=TOP
5, 6, 7, 8
DECK
{ cat "$hd_/cube-mesh.inp"; cat <<'DECK'
*MATERIAL, NAME=STEEL
*ELASTIC
210000., .3
*EXPANSION
ALPHA
*CONDUCTIVITY
50.
*DENSITY
7.8E-9
*SPECIFIC HEAT
4.6E8
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*INITIAL CONDITIONS, TYPE=TEMPERATURE
NALL, 20.
*STEP
DECK
} >"$hd_/cube.model"
for v in "heat 0 0" "coupled 0 0" "coupled 1.2E-5 3.75e-5"; do
  set -- $v
  { sed "s/^ALPHA$/$2/" "$hd_/cube.model"
    if [ "$1" = heat ]; then printf '*HEAT TRANSFER
0.5, 5., , 2.
*BOUNDARY
'
    else printf '*COUPLED TEMPERATURE-DISPLACEMENT
0.5, 5., , 2.
*BOUNDARY
BOTTOM, 1, 3
'; fi
    printf 'BOTTOM, 11, 11, 200.
*DFLUX
1, S4, -100.
*NODE PRINT, NSET=NALL
NT
*END STEP
'
  } >"$hd_/cube-$1-$2.inp"
  (cd "$hd_" && ccx -i "cube-$1-$2" >"cube-$1-$2.ccx.log" 2>&1) || bad "ccx heat: ccx failed on cube-$1-$2"
  expect "ccx heat: cube-$1-$2.inp runs" 0 "" -- run "$hd_/cube-$1-$2.inp" --quiet
  # Bound 1: every block of ccx's there (the same 6 increments), the largest difference judged here.
  out="$("$ex_py" "$src/tests/tools/dat_compare.py" "$hd_/cube-$1-$2.out/cube-$1-$2.dat" "$hd_/cube-$1-$2.dat" 1 2>&1)" &&
    worst="$(grep -o 'largest difference [0-9.e+-]*' <<<"$out" | awk '{print $3}' | sort -g | tail -1)" &&
    [ "$(grep -c '^temperatures' <<<"$out")" -eq 6 ] &&
    awk -v w="$worst" -v e="$3" 'BEGIN {exit !(w != "" && (e == 0 ? w == 0 : w > 0.5 * e && w < 2 * e))}' &&
    ok "ccx heat: ... its temperatures in the 6 increments differ from ccx's by $worst (expected $3)" ||
    bad "ccx heat: cube-$1-$2's temperatures differ from ccx's by '$worst', expected $3" "$out"
done
# heat.boundary's nodal_flux in case.yaml (the meaning of *CFLUX): 25 W into each corner of the
# top of a unit cube (k = 50) held at 0 on its bottom is the consistent load of a uniform
# 100 W/m²: the top reaches q L / k = 2 exactly, 100 W flows in, and the bottom takes it out.
mkdir -p "$hd_/nodal"
cp "$hd_/cube-mesh.inp" "$hd_/nodal/cube.inp"
cat >"$hd_/nodal/case.yaml" <<'YAML'
mesh: {file: cube.inp}
materials: [{E: 2.0e11, nu: 0.3, alpha: 0, conductivity: 50}]
temperature: {reference: 0, from: heat}
boundary:
  - {region: BOTTOM, displacement: {x: 0, y: 0, z: 0}}
heat:
  boundary:
    - {region: BOTTOM, temperature: 0}
    - {region: TOP, nodal_flux: 25}
output:
  heat_flows: [TOP]
  reactions: [BOTTOM]
  probes: [{name: top, point: [0.5, 0.5, 1]}]
YAML
expect "ccx heat: nodal_flux on a cube's top runs" 0 "" -- run "$hd_/nodal/case.yaml" --quiet
ex_check "ccx heat: ... its top is at q L / k = 2, 100 W flow in and out" "$hd_/nodal/case.out/history.csv" \
  'close(h[-1]["top.temperature"], 2.0, 1e-12) and close(h[-1]["heat_flow.TOP"], 100.0, 1e-12) and close(h[-1]["reaction.BOTTOM.heat"], -100.0, 1e-12)'
# What a deck's heat transfer may not ask is refused by name: initial temperatures that differ
# between nodes, and steady and transient steps in one deck.
sed -e 's/^Nall,20\.$/Nall,20.\n1,30./' "$hd_/coupled-steady.inp" >"$hd_/refused-initial.inp"
expect "ccx heat: initial temperatures that differ are refused" 1 \
  "refused-initial.inp:[0-9]+: \*INITIAL CONDITIONS: initial temperatures from 30 to 20" -- \
  check "$hd_/refused-initial.inp"
{ cat "$hd_/coupled-steady.inp"
  printf '*STEP\n*COUPLED TEMPERATURE-DISPLACEMENT\n0.5,1.\n*END STEP\n'
} >"$hd_/refused-mix.inp"
expect "ccx heat: steady and transient steps in one deck are refused" 1 \
  "refused-mix.inp:[0-9]+: steady and transient heat steps in one deck" -- check "$hd_/refused-mix.inp"
# A steady step with heat flows alone has no temperature level: refused, not left to a singular
# matrix.
sed -e 's/^GIBO,11,11,100\.$//' -e 's/^CN7,11,11,20\.$/*CFLUX\nGIBO,11,5./' "$hd_/coupled-steady.inp" >"$hd_/refused-level.inp"
expect "ccx heat: a steady step with heat flows alone is refused" 1 \
  "refused-level.inp:[0-9]+: a steady heat step needs a temperature \(\*BOUNDARY on 11\), \*FILM or \*RADIATE" -- \
  check "$hd_/refused-level.inp"
# On several MPI ranks the nodes and points are spread over the ranks: MODEL.dat and MODEL.frd
# are not written (a warning says so), the other outputs are.
if with_mpi; then
  mpi_expect "ccx heat: on 2 ranks the deck runs, and says its .dat and .frd are not written" 0 \
    "beamth-frd.dat is and beamth-frd.frd is written by a run on one MPI rank only" 2 -- \
    run "$hd_/beamth-frd.inp" -o "$hd_/mpi.out"
  [ -f "$hd_/mpi.out/results.pvd" ] && [ ! -e "$hd_/mpi.out/beamth-frd.dat" ] &&
    ok "ccx heat: ... the fields are written, the .dat is not" ||
    bad "ccx heat: on 2 ranks, the fields or the .dat are not as said"
  # `hencky ccx -i JOB` on 2 ranks: an earlier JOB.dat beside the deck is removed, not left to
  # be read as this run's.
  mkdir -p "$hd_/job" && cp "$hd_/beamth-frd.inp" "$hd_/job/" && echo stale >"$hd_/job/beamth-frd.dat"
  mpi_expect "ccx heat: hencky ccx -i on 2 ranks says the earlier .dat is removed" 0 \
    "beamth-frd.dat of an earlier run removed: this run wrote none" 2 -- ccx -i "$hd_/job/beamth-frd"
  [ ! -e "$hd_/job/beamth-frd.dat" ] && ok "ccx heat: ... and it is gone" ||
    bad "ccx heat: the earlier beamth-frd.dat is still beside the deck"
  # A steady step ramps its temperatures from 0: at t = 0 the answer is T = 0, whose residual
  # has no magnitudes to be measured against (CG + GAMG stalled at 2e-2 of them before the first
  # iterate's magnitudes were kept as the floor). On 2 ranks, the serial run's fields.
  mpi_expect "ccx heat: the steady coupled beam on 2 ranks (CG + GAMG) converges" 0 "" 2 -- \
    run "$hd_/coupled-steady.inp" -o "$hd_/coupled-mpi.out" --quiet
  same "ccx heat: ... its displacements and temperatures are the serial run's to 1e-6" \
    "$hd_/coupled-mpi.out" "$hd_/coupled-steady.out" 1e-6 displacement,temperature
fi
