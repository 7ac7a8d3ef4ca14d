# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 48, item 1: `hencky run MODEL.inp` runs a CalculiX/Abaqus deck as it is, model and
# history data, with no case file. Checked against CalculiX's own test decks (Debian's
# calculix-ccx-test) and their .dat.ref, and against ccx 2.20 itself (calculix-ccx) on variants
# of them; both packages are installed by scripts/packages.txt.
cd_="$work/ccx-decks"
rm -rf "$cd_" && mkdir -p "$cd_"
suite=/usr/share/doc/calculix-ccx-test/examples/test
if [ ! -f "$suite/beam10p.inp.gz" ] || ! command -v ccx >/dev/null; then
  bad "ccx decks: calculix-ccx-test or calculix-ccx is missing (scripts/setup.sh installs them)"
  return 0
fi
for d in beam8p beam10p beamd beam20t beampiso; do zcat "$suite/$d.inp.gz" >"$cd_/$d.inp"; done
# Each deck against its .dat.ref (the last step's displacements of every node), to a bound set
# by what the two codes do differently (measured 2026-11-28; docs/verification.md, section 20):
# - beam10p (C3D10, *CLOAD, single-label *BOUNDARY): the same element: 5.7e-8, the .dat.ref's
#   7 printed digits;
# - beam20t (C3D20, temperature tables of E and alpha, *TEMPERATURE on node sets): 2.2e-7, with
#   the temperatures projected onto trilinear functions as ccx's C3D20 takes them (9.4e-2 with
#   the quadratic field);
# - beamd (C3D20R, *DLOAD P2): ccx's reduced integration against hencky's full one: 3.5e-3
#   (1.3e-7 when ccx runs it as C3D20, below);
# - beam8p (C3D8, *CLOAD): hencky's B-bar against ccx's plain full integration: 3.2e-2;
# - beampiso (C3D20R, *PLASTIC, NLGEOM, two steps, the load reversed): 3.4e-2, the two codes'
#   finite-strain plasticity (2.5e-7 without NLGEOM, below).
for case in "beam10p 2e-7" "beam20t 1e-6" "beamd 5e-3" "beam8p 4e-2" "beampiso 4e-2"; do
  set -- $case
  expect "ccx decks: $1.inp runs as given" 0 "" -- run "$cd_/$1.inp" --quiet
  out="$("$ex_py" "$src/tests/tools/ccx_dat.py" "$cd_/$1.out" "$suite/$1.dat.ref.gz" "$cd_/$1.inp" "$2" 2>&1)" &&
    ok "ccx decks: $1's displacements are its .dat.ref's to $2 ($out)" ||
    bad "ccx decks: $1's displacements are not its .dat.ref's to $2" "$out"
done
# MODEL.dat (item 3): the *NODE PRINT and *EL PRINT blocks in ccx's layout, compared block by
# block with the .dat.ref (tests/tools/dat_compare.py reads both alike): beam10p's every line,
# its stresses at the 4 points of each C3D10 in ccx's order; beam20t's stresses at the 27
# points of each C3D20 (its ENER block is not written).
datcmp() {  # datcmp WHAT A.dat B.dat BOUND [--blocks N]
  local out
  out="$("$ex_py" "$src/tests/tools/dat_compare.py" "$2" "$3" "$4" "${@:5}" 2>&1)" &&
    ok "ccx decks: $1 ($(tr '\n' ';' <<<"$out"))" || bad "ccx decks: $1" "$out"
}
datcmp "beam10p.dat: U, RF and S at the points are the .dat.ref's to 1e-6" \
  "$cd_/beam10p.out/beam10p.dat" "$suite/beam10p.dat.ref.gz" 1e-6
datcmp "beam20t.dat: U, and S at the 27 points in ccx's order, are the .dat.ref's to 1e-6" \
  "$cd_/beam20t.out/beam20t.dat" "$suite/beam20t.dat.ref.gz" 1e-6 --blocks 2
# The variants, run through ccx as well: the same element in both codes.
peer() {  # peer NAME BOUND WHAT [dat]: NAME.inp through ccx and hencky, displacements compared
  (cd "$cd_" && ccx -i "$1" >"$1.ccx.log" 2>&1) || { bad "ccx decks: ccx failed on $1" "$(tail -5 "$cd_/$1.ccx.log")"; return; }
  expect "ccx decks: $1.inp runs" 0 "" -- run "$cd_/$1.inp" --quiet
  local out
  out="$("$ex_py" "$src/tests/tools/ccx_dat.py" "$cd_/$1.out" "$cd_/$1.dat" "$cd_/$1.inp" "$2" 2>&1)" &&
    ok "ccx decks: $3 as ccx's to $2 ($out)" || bad "ccx decks: $3 not as ccx's to $2" "$out"
  [ "${4:-}" = dat ] && datcmp "... $1.dat: every block and increment as ccx's .dat" \
    "$cd_/$1.out/$1.dat" "$cd_/$1.dat" "$2"
}
sed -e 's/C3D20R/C3D20 /' "$cd_/beamd.inp" >"$cd_/beamd20.inp"
peer beamd20 1e-6 "beamd as C3D20: the face pressure P2" dat
# beampiso without NLGEOM: isotropic hardening, the load reversed in the second step (OP=MOD
# replaces each node's value; the second step ramps from the first one's end).
sed -e 's/^\*STEP,NLGEOM/*STEP/' "$cd_/beampiso.inp" >"$cd_/beampiso-small.inp"
peer beampiso-small 1e-6 "beampiso without NLGEOM: plastic, loaded and reversed over two steps"
# An amplitude, a second step with OP=NEW and a *BOUNDARY with a value: beam10p's load follows
# the amplitude to half its value in step 1 (of time 2: an elastic step is solved once at its
# end, as ccx solves a linear one, DIRECT or not), with its tip node 12 held along z;
# step 2 removes the load and pulls node 12 by 0.01 along z instead.
awk '/^\*STEP/ && !done {print "*BOUNDARY\n12,3,3\n*AMPLITUDE,NAME=HALF\n0.,0.,2.,0.5"; done=1} {print}' "$cd_/beam10p.inp" |
  sed -e 's/^\*STATIC$/*STATIC,DIRECT\n1.,2./' -e 's/^\*CLOAD$/*CLOAD,AMPLITUDE=HALF/' >"$cd_/beam10p-history.inp"
cat >>"$cd_/beam10p-history.inp" <<'DECK'
*STEP
*STATIC
*CLOAD,OP=NEW
*BOUNDARY
12,3,3,0.01
*NODE PRINT,NSET=NALL
U
*END STEP
DECK
awk '{print} /^\*END STEP/{exit}' "$cd_/beam10p-history.inp" >"$cd_/beam10p-amplitude.inp"
peer beam10p-amplitude 1e-6 "the first step alone: the load at half its value by the amplitude" dat
peer beam10p-history 1e-6 "an amplitude, OP=NEW and a prescribed displacement over two steps" dat
ex_check "ccx decks: ... 2 steps of the deck, 2 of hencky (a linear step is solved once)" \
  "$cd_/beam10p-history.out/summary.json" 's["steps"] == 2 and s["title"] == "beam10p-history"'
# *PLASTIC, HARDENING=KINEMATIC (two lines: Prager's linear kinematic hardening, C the slope
# between them): beampkin's first step without NLGEOM, as C3D20, against ccx (on loading a
# beam's points load nearly proportionally, where linear kinematic and isotropic hardening of one
# modulus agree: this checks the modulus read from the two lines). (Its second step
# reverses the load; ccx diverges there without NLGEOM, so the reversed branch is checked on
# case.yaml's cube against the closed form, 85_point_laws.sh.)
zcat "$suite/beampkin.inp.gz" | sed -e 's/^\*STEP,NLGEOM/*STEP/' -e 's/C3D20R/C3D20 /' |
  awk '{print} /^\*END STEP/{exit}' >"$cd_/beampkin-step1.inp"
peer beampkin-step1 1e-6 "beampkin's kinematic hardening, its loading step" dat
# HARDENING=COMBINED with *CYCLIC HARDENING (the isotropic part's curve): beampik's first step.
zcat "$suite/beampik.inp.gz" | sed -e 's/^\*STEP,NLGEOM/*STEP/' -e 's/C3D20R/C3D20 /' |
  awk '{print} /^\*END STEP/{exit}' >"$cd_/beampik-step1.inp"
peer beampik-step1 1e-6 "beampik's combined hardening, its loading step" dat
sed -e '/^\*CYCLIC HARDENING/,+2d' "$cd_/beampik-step1.inp" >"$cd_/beampik-nocyclic.inp"
expect "ccx decks: COMBINED without *CYCLIC HARDENING is refused" 1 \
  "beampik-nocyclic.inp:[0-9]+: \*PLASTIC, HARDENING=COMBINED without \*CYCLIC HARDENING" -- \
  check "$cd_/beampik-nocyclic.inp"
# E at the points: the total strain with ccx's tensor shears, in ccx's point order (C3D10).
sed -e 's/^S$/S,E/' "$cd_/beam10p.inp" >"$cd_/beam10p-strain.inp"
peer beam10p-strain 1e-6 "beam10p with E at the 4 points of each C3D10" dat
# The output directory is MODEL.out beside the deck; -o moves it.
[ -f "$cd_/beam10p.out/results.pvd" ] && ok "ccx decks: the outputs are in MODEL.out beside the deck" ||
  bad "ccx decks: no beam10p.out/results.pvd beside the deck"
expect "ccx decks: check lists the regions the history made" 0 "BOUNDARY-1 \(0D\).*CLOAD-1 \(0D\)" -- \
  check "$cd_/beam10p.inp"
# What hencky cannot do is refused before solving: every keyword with its file and line, nothing
# written.
sed -e 's/^\*STEP$/*STEP\n*FREQUENCY\n10/' -e 's/^\*CLOAD$/*CLOAD,FOLLOWER/' "$cd_/beam10p.inp" >"$cd_/refused.inp"
printf '*STEP\n*HEAT TRANSFER\n*CFLUX\n1,5,5.\n*END STEP\n' >>"$cd_/refused.inp"
out="$("$bin" run "$cd_/refused.inp" --quiet 2>&1)"
rc=$?
[ "$rc" -eq 1 ] &&
  grep -Eq "^error: .*refused\.inp:[0-9]+: the deck asks for 4 things hencky cannot do; nothing was solved:$" <<<"$out" &&
  grep -Eq "^  refused\.inp:[0-9]+: \*FREQUENCY: " <<<"$out" &&
  grep -Eq "^  refused\.inp:[0-9]+: \*CLOAD, FOLLOWER: " <<<"$out" &&
  grep -Eq "^  refused\.inp:[0-9]+: \*CFLUX on degree of freedom 5: " <<<"$out" &&
  grep -Eq "^  refused\.inp:[0-9]+: a deck that mixes \*STATIC, \*HEAT TRANSFER" <<<"$out" &&
  ok "ccx decks: a deck asking what hencky cannot do is refused (exit 1), each keyword with its line" ||
  bad "ccx decks: the refused deck's exit or message (exit $rc)" "$out"
[ ! -e "$cd_/refused.out" ] && ok "ccx decks: ... and nothing is written" || bad "ccx decks: a refused deck wrote refused.out"
# The .dat's other blocks against ccx on the same deck: beam20t with NT of every node, RF of the
# supports CN7 as TOTALS=ONLY and of GIBO as TOTALS=YES (its ENER and ELSE blocks are not
# written: 6 blocks of ccx's 8).
awk '/^\*NODE PRINT,NSET=NALL$/ {print "*NODE PRINT,NSET=NALL\nU,NT\n*NODE PRINT,NSET=CN7,TOTALS=ONLY\nRF\n*NODE PRINT,NSET=GIBO,TOTALS=YES\nRF"; getline; next} {print}' \
  "$cd_/beam20t.inp" >"$cd_/beam20t-prints.inp"
(cd "$cd_" && ccx -i beam20t-prints >beam20t-prints.ccx.log 2>&1) || bad "ccx decks: ccx failed on beam20t-prints"
expect "ccx decks: beam20t-prints.inp runs" 0 "" -- run "$cd_/beam20t-prints.inp" --quiet
datcmp "... NT, and RF with TOTALS=ONLY and YES, as ccx's .dat (6 blocks)" \
  "$cd_/beam20t-prints.out/beam20t-prints.dat" "$cd_/beam20t-prints.dat" 1e-6 --blocks 6
# The print frequency, as ccx keeps it: beampiso without NLGEOM, as C3D20, in increments of 0.25
# and then 0.5 (DIRECT), FREQUENCY=2 on step 1's *NODE PRINT only: both codes print at t = 0.5,
# 1 and 2 (the frequency carried into step 2, whose other increment, 1.5, is not printed), and
# the plastic strains and stresses at the 27 points of each element as well.
sed -e 's/^\*STEP,NLGEOM/*STEP/' -e 's/C3D20R/C3D20 /' "$cd_/beampiso.inp" |
  awk '/^\*EL PRINT/ {getline; next}
       /^\*STATIC,DIRECT/ {n++; print; getline; print (n == 1 ? "0.25,1." : "0.5,1."); next}
       /^\*NODE PRINT/ && !m {m = 1; print "*EL PRINT,ELSET=EALL\nPEEQ,S,E\n*NODE PRINT,NSET=NALL,FREQUENCY=2"; next}
       {print}' >"$cd_/beampiso-frequency.inp"
peer beampiso-frequency 1e-6 "the frequency carried into step 2, PEEQ, S and E of a plastic C3D20" dat
grep -c "^ displacements" "$cd_/beampiso-frequency.out/beampiso-frequency.dat" | grep -qx 3 &&
  ok "ccx decks: ... 3 displacement blocks of the 6 increments" ||
  bad "ccx decks: the frequency did not leave 3 displacement blocks"
# Restarted from t = 0.75 (step 1's third increment, not printed): the .dat is the uninterrupted
# run's, its blocks up to the restart copied and the frequency counted on over both steps.
expect "ccx decks: beampiso-frequency restarted from t = 0.75" 0 "" -- \
  run "$cd_/beampiso-frequency.inp" --restart "$cd_/beampiso-frequency.out" --from 0.75 \
  -o "$cd_/beampiso-restart.out" --quiet
cmp -s "$cd_/beampiso-restart.out/beampiso-frequency.dat" "$cd_/beampiso-frequency.out/beampiso-frequency.dat" &&
  ok "ccx decks: ... its .dat is the uninterrupted run's" ||
  bad "ccx decks: the restarted run's .dat differs from the uninterrupted run's" \
    "$(diff "$cd_/beampiso-restart.out/beampiso-frequency.dat" "$cd_/beampiso-frequency.out/beampiso-frequency.dat" | head -5)"
# `hencky ccx -i JOB`, as a front end calls ccx: JOB.dat beside the deck, in the working folder.
mkdir -p "$cd_/job" && cp "$cd_/beam10p.inp" "$cd_/job/"
expect_cmd "ccx decks: hencky ccx -i beam10p runs in the deck's folder" 0 "" -- \
  bash -c "cd '$cd_/job' && '$(readlink -f "$bin")' ccx -i beam10p --quiet"
datcmp "... and writes beam10p.dat there, the .dat.ref's to 1e-6" "$cd_/job/beam10p.dat" \
  "$suite/beam10p.dat.ref.gz" 1e-6
# MODEL.frd: *NODE FILE U, RF and *EL FILE S, E on beam10p, beside ccx's own .frd of the deck:
# the same node and element blocks (ccx's node order in each element), the same displacements
# and forces, and nodal stresses and strains (the points' values extrapolated to the nodes and
# averaged; ccx's tensor shears) within 1e-5, the resolution of the format's 12.5E fields.
sed -e 's/^\*END STEP/*NODE FILE\nU,RF\n*EL FILE\nS,E\n*END STEP/' "$cd_/beam10p.inp" >"$cd_/beam10p-frd.inp"
(cd "$cd_" && ccx -i beam10p-frd >beam10p-frd.ccx.log 2>&1) || bad "ccx decks: ccx failed on beam10p-frd"
mkdir -p "$cd_/frd" && cp "$cd_/beam10p-frd.inp" "$cd_/frd/"
expect_cmd "ccx decks: hencky ccx -i beam10p-frd writes beam10p-frd.frd" 0 "" -- \
  bash -c "cd '$cd_/frd' && '$(readlink -f "$bin")' ccx -i beam10p-frd --quiet && test -s beam10p-frd.frd"
out="$("$ex_py" "$src/tests/tools/frd_compare.py" "$cd_/frd/beam10p-frd.frd" "$cd_/beam10p-frd.frd" 1e-5 DISP FORC STRESS TOSTRAIN 2>&1)" &&
  ok "ccx decks: ... its mesh, DISP, FORC, STRESS and TOSTRAIN are ccx's .frd's ($(tr '\n' ';' <<<"$out"))" ||
  bad "ccx decks: ... its .frd is not ccx's" "$out"
# CalculiX GraphiX reads it (batch mode, no display): its datasets, the beam's volume 1 x 1 x 8.
if command -v cgx >/dev/null; then
  printf 'read beam10p-frd.frd\nds 1 e 1\nvolu all\nquit\n' >"$cd_/frd/read.fbd"
  out="$(cd "$cd_/frd" && timeout 60 cgx -bg read.fbd 2>&1)"
  grep -q "reading Dataset No:4" <<<"$out" && grep -q "VOLUME:8.000000e+00" <<<"$out" &&
    ! grep -qi "error" <<<"$out" && ok "ccx decks: ... cgx -bg reads it: 4 datasets, volume 8" ||
    bad "ccx decks: cgx did not read beam10p-frd.frd" "$(tail -20 <<<"$out")"
else
  bad "ccx decks: cgx is missing (scripts/setup.sh installs calculix-cgx)"
fi
# As ccx, a *SOLID SECTION may name a material the deck defines after it, and FREQUENCY=0 drops
# a print request (ccx's elprints.f): beam10p with its *MATERIAL moved below the section and
# FREQUENCY=0 on its *EL PRINT writes its U and RF blocks, no stress block.
awk '/^\*MATERIAL/ {skip = 3} skip > 0 {held = held $0 "\n"; skip--; next}
     {print} /^\*SOLID SECTION/ {printf "%s", held}' "$cd_/beam10p.inp" |
  sed -e 's/^\*EL PRINT,ELSET=EALL$/*EL PRINT,ELSET=EALL,FREQUENCY=0/' >"$cd_/late-material.inp"
grep -q "^\*SOLID SECTION" "$cd_/late-material.inp" && [ "$(grep -n '^\*SOLID SECTION' "$cd_/late-material.inp" | cut -d: -f1)" -lt "$(grep -n '^\*MATERIAL' "$cd_/late-material.inp" | cut -d: -f1)" ] ||
  bad "ccx decks: the material was not moved below the section in late-material.inp"
expect "ccx decks: a material defined after its section runs" 0 "" -- run "$cd_/late-material.inp" --quiet
datcmp "... U and RF are beam10p's .dat.ref's, and there is no stress block" \
  "$cd_/late-material.out/late-material.dat" "$suite/beam10p.dat.ref.gz" 1e-6 --blocks 2
grep -q "stresses" "$cd_/late-material.out/late-material.dat" &&
  bad "ccx decks: FREQUENCY=0 on *EL PRINT still wrote stresses" || ok "ccx decks: ... FREQUENCY=0: no stresses"
