# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# A point law declared in material/ alone (issue 44, material/point_law.hpp): Prager's linear
# kinematic hardening, read from its keys, run by newton, carried by the checkpoints, written
# by name; the report's schemes refuse it. Closed forms in the case file.

d="$work/point_laws/prager-cube"
mkdir -p "$work/point_laws"
cp -r "$src/tests/cli/inputs/point_laws/prager-cube" "$d"
expect "point law: the Prager cube runs its strain cycle" 0 "" -- run "$d/case.yaml" --quiet
h="$d/case.out/history.csv"
s="$d/case.out/summary.json"
E=2.0e11; SY=250e6; HK=2e10
ex_check "point law: Prager, the peak stress (sigma_y + H_k eps)/(1 + H_k/E) to 1e-6" "$h" \
  "close(at(1)['centre.stress.zz'], ($SY + $HK*0.01)/(1 + $HK/$E), 1e-6)"
# The Bauschinger effect: at t = 1.2 (-100 MPa) the cube flows again in compression, where an
# isotropic law would still be elastic (inside +-409 MPa).
ex_check "point law: Prager, the compression branch (H_k eps - sigma_y)/(1 + H_k/E) at t = 1.2 and 2 to 1e-6" "$h" \
  "close(at(1.2)['centre.stress.zz'], ($HK*0.007 - $SY)/(1 + $HK/$E), 1e-6) and close(at(2)['centre.stress.zz'], ($HK*(-0.005) - $SY)/(1 + $HK/$E), 1e-6)"
ex_check "point law: Prager, the back stress alpha_zz = (2/3) H_k eps_p at the end, to 1e-6" "$s" \
  "close(s['probes']['centre']['back_stress']['zz'], 2/3*$HK*(-0.005 - s['probes']['centre']['stress']['zz']/$E), 1e-6)"
ex_check "point law: Prager, newton converges in at most 3 iterations a step (consistent tangent)" "$h" \
  "max(r['iterations'] for r in h) <= 3"
if grep -aq 'Name="back_stress" NumberOfComponents="6"' "$d/case.out/step_0009.vtu"; then
  ok "point law: the VTU files carry back_stress (6 components)"
else bad "point law: no back_stress field in step_0009.vtu"; fi
# The back stress is in the checkpoints: a restart from t = 1 ends on the same bits.
restart_same "point law: Prager" "$d/case.yaml" "$d/case.out" 1 step_0009.vtu

# Refusals, each naming what to do.
bad_case() {  # bad_case NAME SED-EXPRESSION PATTERN
  local c="$work/point_laws/bad-$1"
  rm -rf "$c"; cp -r "$src/tests/cli/inputs/point_laws/prager-cube" "$c"
  sed -E -i "$2" "$c/case.yaml"
  expect "point law: $1 is refused" 1 "$3" -- check "$c/case.yaml"
}
bad_case "a report scheme" 's/scheme: newton/scheme: initial-stress/' \
  "material 'steel' has kinematic hardening, which solver.scheme 'initial-stress' cannot run.*use scheme: newton"
bad_case "gamma > 0" 's/gamma: 0/gamma: 100/' "gamma = 100: only linear kinematic hardening"
bad_case "unloading-curve" 's/^( +)kinematic: /\1unloading: curve\n\1kinematic: /' "kinematic hardening needs elastic unloading"
bad_case "a misspelt key" 's/kinematic: /kinematik: /' "unknown key 'kinematik'; did you mean 'kinematic'"
bad_case "a group without C" 's/\{C: 2e10, gamma: 0\}/{gamma: 0}/' "kinematic\[0\].*C"
