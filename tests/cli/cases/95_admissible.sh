# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Every accepted state admissible (issue 46): each plastic run of this part of the suite (the
# case files before this one; ctest runs it in both halves, so the examples are scanned too)
# reports report.largest_yield_excess, and under formulation: hencky no converged step left an
# integration point above its yield stress by more than 1e-6 (docs/schemes.md, "Every accepted
# state admissible"). Under formulation: report the excess is the report's map's, reported only.
# The guard at work: initial-strain stopped at a loose tolerance (1e-3) leaves its points off
# the curve by ω's last correction (the strain defect times 3G, 2e-4 of the yield stress on
# NL1's hardening variant): such an iterate is not accepted and the iteration goes on.
d="$work/admissible"
mkdir -p "$d"
cp "$src/tests/cli/inputs/nl1/cube.geo" "$d/"
sed -e 's/perfect: {yield: 5e6}/linear: {yield: 5e6, hardening: 62.5e9}/' \
    -e 's/scheme: newton/scheme: initial-strain\n  tolerance: 1e-3\n  relaxation: 0.3/' \
    "$src/tests/cli/inputs/nl1/case.yaml" > "$d/loose.yaml"
expect "admissible: initial-strain at a loose tolerance runs NL1's path" 0 "" -- run "$d/loose.yaml" --quiet
if grep -q "converged, but [0-9]* points lie above their yield stress, the largest by .*: the iteration goes on" "$d/loose.out/hencky.log"; then
  ok "admissible: a converged iterate above the yield stress is not accepted, and the log names the point"
else bad "admissible: the guard did not act on the loose initial-strain run" "$(grep -c iteration "$d/loose.out/hencky.log") iteration lines"; fi
ex_check "admissible: ... and the accepted states lie within 1e-6 of it" "$d/loose.out/summary.json" \
  "0 <= s['report']['largest_yield_excess']['value'] <= 1e-6"

# The points' own stresses in the report (issue 47: the recovered nodal von Mises can stand far
# above them): NL1's perfectly plastic point carries σ_y exactly.
sed -E "s/^  steps: 80$/  steps: 16/" "$src/tests/cli/inputs/nl1/case.yaml" > "$d/nl1.yaml"
expect "admissible: NL1, perfectly plastic" 0 "report: largest von Mises stress at an integration point 5e\+06" \
  -- run "$d/nl1.yaml" -o "$d/nl1.out"
ex_check "admissible: ... report.point_von_mises is sigma_y to 1e-12" "$d/nl1.out/summary.json" \
  "close(s['report']['point_von_mises']['value'], 5e6, 1e-12)"

if out="$("$ex_py" - "$work" <<'PY'
import json, os, sys
plastic = hencky = 0
problems, worst = [], (0.0, "")
for root, dirs, files in os.walk(sys.argv[1]):
    if "summary.json" not in files:
        continue
    path = os.path.join(root, "summary.json")
    try:
        s = json.load(open(path))
    except ValueError:
        continue
    report = s.get("report", {})
    if "equivalent_plastic_strain" not in report:
        continue  # no plastic material, or no converged step
    plastic += 1
    e = report.get("largest_yield_excess")
    if e is None:
        problems.append(path + ": a plastic run without report.largest_yield_excess")
        continue
    if s.get("formulation", "hencky") != "hencky":
        continue
    hencky += 1
    if e["value"] > worst[0]:
        worst = (e["value"], path)
    if not 0 <= e["value"] <= 1e-6:
        problems.append("%s: largest_yield_excess %.3g at node %s, t = %g" %
                        (path, e["value"], e["node"], e["time"]))
for p in problems[:10]:
    print(p)
print("%d plastic runs, %d under formulation: hencky; the largest excess %.2g (%s)" %
      (plastic, hencky, worst[0], os.path.relpath(worst[1], sys.argv[1]) if worst[1] else "-"))
sys.exit(1 if problems or plastic == 0 else 0)
PY
)"; then
  ok "admissible: every plastic run reports its largest yield excess, none above 1e-6 under hencky ($(tail -1 <<<"$out"))"
else
  bad "admissible: a converged state above its yield stress, or an excess missing" "$out"
fi
