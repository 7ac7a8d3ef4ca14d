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

# Armstrong-Frederick (gamma > 0): the same cycle, the back stress saturating at C/gamma. With
# eps_p = eps - sigma/E of the probe, the closed forms on each branch (af-cube/case.yaml).
a="$work/point_laws/af-cube"
rm -rf "$a"; cp -r "$src/tests/cli/inputs/point_laws/af-cube" "$a"
cp "$src/tests/cli/inputs/point_laws/prager-cube/block.geo" "$a/"  # the same cube
expect "point law: the Armstrong-Frederick cube runs its strain cycle" 0 "" -- run "$a/case.yaml" --quiet
ha="$a/case.out/history.csv"
CG=2e10; GA=100
# Backward Euler's own update at every step (the back stress X = (3/2) alpha_zz of the probe,
# eps_p = eps - sigma/E): X_k+1 (1 + gamma |d eps_p|) = X_k + C d eps_p, and on the yield surface
# |sigma - X| = sigma_y wherever it flowed; the strain at step k is the z1 displacement over 10 mm.
ex_check "point law: AF, every step is backward Euler's X(1 + gamma |dep|) = X0 + C dep, on the surface, to 1e-6" "$ha" \
  "(lambda eps: all(close(1.5*b['centre.back_stress.zz']*(1 + $GA*abs(eps(b) - eps(a))), 1.5*a['centre.back_stress.zz'] + $CG*(eps(b) - eps(a)), 1e-6) for a, b in zip([dict((k, 0.0) for k in h[0])] + h[:-1], h)) and all(abs(r['centre.back_stress.zz']) < 1 or close(abs(r['centre.stress.zz'] - 1.5*r['centre.back_stress.zz']), $SY, 1e-6) for r in h))(lambda r: (1e-2*r['time'] if r['time'] <= 1 else 1e-2*(1 - 1.5*(r['time'] - 1))) - r['centre.stress.zz']/$E)"
# Against the closed form of the ODE, X = (C/gamma)(1 - exp(-gamma eps_p)) at eps = 1 %: the
# error of the 4 steps to t = 1 (2.9 % of sigma_y) falls as backward Euler's, first order: to
# 0.29 of itself with 16 steps (0.25 in the limit).
python3 - "$a/case.yaml" <<'PY'
import sys
p = sys.argv[1]
s = open(p).read()
s = s.replace("times: [0.25, 0.5, 0.75, 1, 1.2, 1.4, 1.6, 1.8, 2]", "times: [" + ", ".join(str(k / 16) for k in range(1, 17)) + "]")
open(p.replace("case.yaml", "fine.yaml"), "w").write(s)
PY
expect "point law: AF, 16 steps to t = 1" 0 "" -- run "$a/fine.yaml" --quiet
ex_check "point law: AF, the closed form's error at eps = 1 % falls to 0.2 .. 0.32 of itself with 4 times the steps" "$ha" \
  "(lambda err: 0.2 < err('$a/fine.out/history.csv') / err('$a/case.out/history.csv') < 0.32 and err('$a/case.out/history.csv') < 0.05)(lambda p: (lambda r: abs(r['centre.stress.zz'] - ($SY + $CG/$GA*(1 - np.exp(-$GA*(0.01 - r['centre.stress.zz']/$E))))) / $SY)([x for x in ({k: float(v) for k, v in r.items()} for r in csv.DictReader(open(p))) if abs(x['time'] - 1) < 1e-12][0]))"
# The same cube as an Abaqus deck (*PLASTIC, HARDENING=COMBINED, DATATYPE=PARAMETERS): the
# homogeneous stress at every point of its one element is the case's at t = 1 and 2, to 1e-6 (the
# .dat's 7 digits).
expect "point law: AF from an Abaqus deck's parameters runs" 0 "" -- run "$a/af-abaqus.inp" --quiet
szz() { awk -v t="$2" '/stresses/ {on = ($NF + 0 == t)} on && $1 == 1 && $2 == 1 {print $5}' "$1"; }
ex_check "point law: ... its stress is the case's at t = 1 and 2" "$ha" \
  "close(at(1)['centre.stress.zz'], $(szz "$a/af-abaqus.out/af-abaqus.dat" 1), 1e-6) and close(at(2)['centre.stress.zz'], $(szz "$a/af-abaqus.out/af-abaqus.dat" 2), 1e-6)"
ex_check "point law: AF, the back stress alpha_zz = (2/3)(sigma - sigma_y) on the compression branch, to 1e-6" "$a/case.out/summary.json" \
  "close(s['probes']['centre']['back_stress']['zz'], 2/3*(s['probes']['centre']['stress']['zz'] + $SY), 1e-6)"
ex_check "point law: AF, newton converges in at most 5 iterations a step (the tangent's symmetric part)" "$ha" \
  "max(r['iterations'] for r in h) <= 5"

# Refusals, each naming what to do.
bad_case() {  # bad_case NAME SED-EXPRESSION PATTERN
  local c="$work/point_laws/bad-$1"
  rm -rf "$c"; cp -r "$src/tests/cli/inputs/point_laws/prager-cube" "$c"
  sed -E -i "$2" "$c/case.yaml"
  expect "point law: $1 is refused" 1 "$3" -- check "$c/case.yaml"
}
bad_case "a report scheme" 's/scheme: newton/scheme: initial-stress/' \
  "material 'steel' has kinematic hardening, which solver.scheme 'initial-stress' cannot run.*use scheme: newton"
bad_case "gamma < 0" 's/gamma: 0/gamma: -1/' "gamma = -1: expected a rate >= 0"
nine="$(printf '{C: 2e10, gamma: 1}, %.0s' 1 2 3 4 5 6 7 8){C: 2e10, gamma: 1}"
bad_case "nine back stresses" "s/\\[\\{C: 2e10, gamma: 0\\}\\]/[$nine]/" "9 back stresses: hencky takes at most 8"
bad_case "unloading-curve" 's/^( +)kinematic: /\1unloading: curve\n\1kinematic: /' "kinematic hardening needs elastic unloading"
bad_case "a misspelt key" 's/kinematic: /kinematik: /' "unknown key 'kinematik'; did you mean 'kinematic'"
bad_case "a group without C" 's/\{C: 2e10, gamma: 0\}/{gamma: 0}/' "kinematic\[0\].*C"
