# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 23: a model whose every degree of freedom is prescribed is a valid case. NAFEMS NL1
# (tests/cli/inputs/nl1): one hexahedron driven through a plane-strain strain history; no
# linear solve, the point laws converge on the prescribed displacements and the reactions are
# the internal forces. Checked against the exactly integrated rate equations
# (tests/tools/nl1_reference.py) at the end of each leg: exact on the proportional legs 1-3,
# first-order in the step on the turning legs 4-8 (the error halves with the step), with
# newton and three of the report's schemes, perfectly plastic and hardening.

nd="$work/nl1"
rm -rf "$nd" && mkdir -p "$nd"
cp "$src/tests/cli/inputs/nl1/"* "$nd/"
for h in 0 62.5e9; do
  "$ex_py" "$src/tests/tools/nl1_reference.py" "$h" >"$nd/reference-$h.txt" ||
    bad "nl1: the reference script failed"
done
# nl1_check NAME DIR_COARSE DIR_FINE H: legs 1-3 to 1e-8 sigma_y; legs 4-8 within 2.5 % of
# sigma_y at 10 steps a leg, and the largest error halved (1.7 .. 2.3) at 20; the reactions of
# the unit faces x1 and y1 are sigma_xx and sigma_yy at every step.
nl1_check() {
  local out
  if out="$("$ex_py" - "$2/history.csv" "$3/history.csv" "$nd/reference-$4.txt" 2>&1 <<'PY'
import csv, sys
ref = {round(float(l.split()[0])): [float(v) for v in l.split()[1:5]] for l in open(sys.argv[3])}
sy = 5e6
def errors(path):
    rows = list(csv.DictReader(open(path)))
    for r in rows:
        for face, c in (("x1.x", "xx"), ("y1.y", "yy")):
            d = abs(float(r["reaction." + face]) - float(r["centre.stress." + c]))
            assert d <= 1e-12 * sy, "reaction %s off its stress by %.3g at t = %s" % (face, d, r["time"])
    e = {}
    for r in rows:
        t = float(r["time"])
        if abs(t - round(t)) < 1e-9:
            got = [float(r["centre." + k]) for k in ("von_mises", "stress.xx", "stress.yy", "stress.zz")]
            e[round(t)] = max(abs(a - b) for a, b in zip(got, ref[round(t)])) / sy
    assert sorted(e) == list(range(1, 9)), "legs ending at %s" % sorted(e)
    return e
c, f = errors(sys.argv[1]), errors(sys.argv[2])
for leg in (1, 2, 3):
    assert c[leg] <= 1e-8 and f[leg] <= 1e-8, "proportional leg %d off by %.3g, %.3g sigma_y" % (leg, c[leg], f[leg])
worst_c, worst_f = max(c[k] for k in range(4, 9)), max(f[k] for k in range(4, 9))
assert worst_c <= 0.025, "turning legs off by %.3g sigma_y at 10 steps a leg" % worst_c
assert 1.7 <= worst_c / worst_f <= 2.3, "error %.3g -> %.3g sigma_y: not first order" % (worst_c, worst_f)
print("legs 4-8: %.2e -> %.2e sigma_y" % (worst_c, worst_f))
PY
)"; then ok "$1 ($out)"; else bad "$1" "$out"; fi
}
for h in 0 62.5e9; do
  for scheme in newton initial-stress variable-stiffness initial-strain; do
    # initial-strain iterates on the strain form, which a perfectly plastic curve has not
    [ "$h" = 0 ] && [ "$scheme" = initial-strain ] && continue
    for steps in 80 160; do
      d="$nd/$scheme-$h-$steps"
      sed -E -e "s/^  scheme: newton$/  scheme: $scheme/" -e "s/^  steps: 80$/  steps: $steps/" \
        "$nd/case.yaml" >"$d.yaml"
      [ "$h" = 0 ] || sed -i -E "s/plasticity: \{perfect: \{yield: 5e6\}\}/plasticity: {linear: {yield: 5e6, hardening: $h}}/" "$d.yaml"
      expect "nl1, H = $h, $scheme, $steps steps: runs with no linear solve" 0 \
        "linear solver: none, every degree of freedom is prescribed" -- run "$d.yaml" -o "$d"
    done
    ex_check "nl1, H = $h, $scheme: no factorization" "$nd/$scheme-$h-80/summary.json" \
      's["factorizations"] == 0'
    nl1_check "nl1, H = $h, $scheme: the exactly integrated stresses" "$nd/$scheme-$h-80" \
      "$nd/$scheme-$h-160" "$h"
  done
done
# The run's report: |u| is largest at the corner (1, 1, z) at t = 4, 5e-5 sqrt(2); von Mises
# reaches sigma_y first at t = 1; no load, so the reactions balance to round-off of the forces.
ex_check "nl1: report, the largest displacement and von Mises stress, where and when" \
  "$nd/newton-0-80/summary.json" \
  'close(s["report"]["displacement"]["value"], 5e-5 * 2 ** 0.5, 1e-12) and s["report"]["displacement"]["time"] == 4 and s["report"]["displacement"]["position"][:2] == [1, 1] and close(s["report"]["von_mises"]["value"], 5e6, 1e-12) and s["report"]["von_mises"]["time"] == 1 and s["report"]["balance"]["imbalance"] < 1e-12'
# On MPI ranks: tests/cli/cases/40_parallel.sh ("more ranks than cells").
