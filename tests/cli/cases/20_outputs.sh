# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# The outputs of the contract (CASE_FORMAT.md, "Outputs in the output directory") and the
# command-line options: -o DIR, --quiet, --threads, output.dir, output.every, hencky check,
# exit status 2.
od="$work/outputs"
mkdir -p "$od"
cp "$src/examples/cantilever/beam.geo" "$od/beam.geo"
ex_set "$od/beam.geo" '^n = [0-9]+;' 'n = 4;'   # 4 hexahedra: fast
cat >"$od/case.yaml" <<'EOF'
title: outputs of the contract
mesh: {file: beam.geo, order: 2}
materials:
  - {name: steel, E: 2.1e11, nu: 0.3, alpha: 1.2e-5}
temperature: {reference: 20, field: "20 + 10*t*x"}
boundary:
  - region: clamp
    displacement: {x: 0, y: 0, z: 0}
  - region: tip
    force: [0, 0, "-1000*t"]
solver: {steps: 2}
output:
  probes:
    - {name: A, point: [1.0, 0.025, 0.05]}
    - {name: mid, point: [0.5, 0.025, 0.1]}
  reactions: [clamp]
EOF

# --- run -o DIR --quiet: nothing on the terminal, everything in DIR, nothing elsewhere.
o="$work/outputs/custom dir"   # a space in the name on purpose
out="$("$bin" run "$od/case.yaml" -o "$o" --quiet 2>&1)"; rc=$?
if [ "$rc" -eq 0 ] && [ -z "$out" ]; then ok "run --quiet: exit 0 and prints nothing"
else bad "run --quiet: exit $rc (expected 0) with output (expected none)" "$out"; fi
missing=""
for f in results.pvd step_0001.vtu step_0002.vtu history.csv summary.json hencky.log; do
  [ -s "$o/$f" ] || missing="$missing $f"
done
if [ -z "$missing" ]; then ok "run -o DIR: results.pvd, step_*.vtu, history.csv, summary.json, hencky.log in DIR"
else bad "run -o DIR: missing or empty in DIR:$missing" "$(ls -la "$o" 2>&1)"; fi
if [ ! -e "$od/case.out" ] && [ -z "$(ls -d "$o".* "$od"/*.partial-* "$od"/*.old-* 2>/dev/null)" ]; then
  ok "run -o DIR: no default case.out, no partial or old directories left"
else bad "run -o DIR: unexpected directories" "$(ls -la "$od")"; fi

# --- results.pvd: one data set per step, with its time.
ex_pvd() {  # ex_pvd NAME PVD "t1:file1 t2:file2 ..."
  local got
  got="$("$ex_py" -c 'import re, sys
print(" ".join("%g:%s" % (float(t), f) for t, f in re.findall(r"<DataSet[^>]*timestep=\"([^\"]*)\"[^>]*file=\"([^\"]*)\"", open(sys.argv[1]).read())))' "$2" 2>&1)"
  if [ "$got" = "$3" ]; then ok "$1"; else bad "$1" "expected: $3"$'\n'"got:      $got"; fi
}
ex_pvd "results.pvd lists step_0001.vtu at t = 0.5 and step_0002.vtu at t = 1" "$o/results.pvd" \
  "0.5:step_0001.vtu 1:step_0002.vtu"

# --- step_*.vtu: the arrays of the contract, with their component counts.
ex_vtu_arrays() {  # ex_vtu_arrays VTU -> "PointData:name:ncomp ..." sorted
  "$ex_py" -c 'import re, sys
x = open(sys.argv[1], "rb").read().split(b"<AppendedData")[0].decode()
out = []
for sec, body in re.findall(r"<(PointData|CellData)>(.*?)</\1>", x, re.S):
    for a in re.findall(r"<DataArray ([^>]*)>", body):
        n = re.search(r"Name=\"([^\"]*)\"", a).group(1)
        c = re.search(r"NumberOfComponents=\"(\d+)\"", a)
        out.append("%s:%s:%s" % (sec, n, c.group(1) if c else "1"))
print(" ".join(sorted(out)))' "$1" 2>&1
}
arrays="$(ex_vtu_arrays "$o/step_0002.vtu")"
missing=""
for a in PointData:displacement:3 PointData:stress:6 PointData:von_mises:1 PointData:temperature:1 \
         CellData:material:1 CellData:region:1 CellData:stress:6 CellData:von_mises:1; do
  grep -qw -- "$a" <<<"$arrays" || missing="$missing $a"
done
if [ -z "$missing" ]; then ok "step_0002.vtu: displacement, stress, von_mises, temperature; cell material, region, stress, von_mises"
else bad "step_0002.vtu: missing arrays:$missing" "$arrays"; fi
missing=""
for a in PointData:plastic_strain:6 PointData:equivalent_plastic_strain:1 \
         PointData:contact_pressure:1 PointData:contact_state:1; do
  grep -qw -- "$a" <<<"$arrays" || missing="$missing $a"
done
if [ -z "$missing" ]; then ok "step_0002.vtu: plastic and contact arrays of the contract"
else bad "step_0002.vtu: missing arrays:$missing" "$arrays"; fi
missing=""
for a in PointData:strain:6 PointData:elastic_strain:6 PointData:thermal_strain:6 \
         PointData:equivalent_elastoplastic_strain:1; do
  grep -qw -- "$a" <<<"$arrays" || missing="$missing $a"
done
if [ -z "$missing" ]; then ok "step_0002.vtu: the strains (total, elastic, thermal, ε̃^{e+p})"
else bad "step_0002.vtu: missing arrays:$missing" "$arrays"; fi

# --- history.csv: the header of the contract (plus hencky's columns at the end), one row per
# step, final row = summary.
cols="step,time,iterations,residual"
for p in A mid; do
  cols="$cols,$p.displacement.x,$p.displacement.y,$p.displacement.z"
  cols="$cols,$p.stress.xx,$p.stress.yy,$p.stress.zz,$p.stress.xy,$p.stress.yz,$p.stress.xz"
  cols="$cols,$p.von_mises,$p.equivalent_plastic_strain,$p.temperature"
done
cols="$cols,reaction.clamp.x,reaction.clamp.y,reaction.clamp.z"
# hencky's own columns after the contract's: the scheme's measures and counts per step
cols="$cols,delta_sigma,delta_epsilon,factorizations,plastic_points"
# then each probe's strains (issue 17): total, elastic, plastic, thermal (tensor components), ε̃^{e+p}
for p in A mid; do
  for f in strain elastic_strain plastic_strain thermal_strain; do
    for c in xx yy zz xy yz xz; do cols="$cols,$p.$f.$c"; done
  done
  cols="$cols,$p.equivalent_elastoplastic_strain"
done
header="$(head -n 1 "$o/history.csv" 2>/dev/null)"
if [ "$header" = "$cols" ]; then ok "history.csv: header step,time,iterations,residual, probe, reaction and scheme columns"
else bad "history.csv: wrong header" "expected: $cols"$'\n'"got:      $header"; fi
ex_check "history.csv: 2 numeric rows (steps 1, 2 at t = 0.5, 1); the last one matches summary.json" "$o/summary.json" '
(rows := [l.split(",") for l in open(sys.argv[1].replace("summary.json", "history.csv")).read().split("\n")[1:] if l]) is not None
and len(rows) == 2 and all(len(r) == 85 for r in rows) and all(float(v) == float(v) for r in rows for v in r)
and [int(r[0]) for r in rows] == [1, 2] and [float(r[1]) for r in rows] == [0.5, 1.0]
and close(float(rows[1][6]), s["probes"]["A"]["displacement"]["z"], 1e-12)
and close(float(rows[1][30]), s["reactions"]["clamp"]["z"], 1e-12)'

# --- summary.json: the keys of the contract.
ex_check "summary.json: status, steps, iterations, dofs, elements, wall_seconds.*, peak_memory_bytes" "$o/summary.json" '
s["status"] == "converged" and s["steps"] == 2 and s["iterations"] >= 2 and s["dofs"] > 0
and s["elements"] == 4 and s["peak_memory_bytes"] > 0
and all(s["wall_seconds"][k] >= 0 for k in ("assembly", "factorization", "solve", "material", "output"))'
ex_check "summary.json: probes.A.{displacement,stress,von_mises,equivalent_plastic_strain,temperature}, reactions, contact" "$o/summary.json" '
set(s["probes"]) == {"A", "mid"}
and set(s["probes"]["A"]["stress"]) == {"xx", "yy", "zz", "xy", "yz", "xz"}
and set(s["probes"]["A"]["displacement"]) == {"x", "y", "z"}
and all(isinstance(s["probes"]["A"][k], float) for k in ("von_mises", "equivalent_plastic_strain", "temperature"))
and close(s["probes"]["A"]["temperature"], 30.0, 1e-9) and isinstance(s["probes"]["A"]["stress"]["xx"], float)
and close(s["reactions"]["clamp"]["z"], 1000.0, 1e-6) and s["contact"] == {}'
ex_check "summary.json: probes.A.{strain,elastic_strain,plastic_strain,thermal_strain}.*, equivalent_elastoplastic_strain" "$o/summary.json" '
all(set(s["probes"]["A"][f]) == {"xx", "yy", "zz", "xy", "yz", "xz"}
    for f in ("strain", "elastic_strain", "plastic_strain", "thermal_strain"))
and isinstance(s["probes"]["A"]["equivalent_elastoplastic_strain"], float)'

# --- hencky.log: the progress lines, also with --quiet.
if grep -q "step    2" "$o/hencky.log" 2>/dev/null && grep -q "converged" "$o/hencky.log"; then
  ok "hencky.log: progress of both steps and the final line"
else bad "hencky.log: no step lines" "$(cat "$o/hencky.log" 2>&1)"; fi

# --- without --quiet the terminal shows the progress; running again into the same DIR works.
# (hencky replaces the whole DIR, unrelated files in it included; deliberately not asserted.)
touch -d "2020-01-01 00:00:00" "$o/summary.json"
expect "run (not quiet): prints the steps and 'converged'" 0 "step +2 .*t = 1(.|$)" -- run "$od/case.yaml" -o "$o"
if [ "$(stat -c %Y "$o/summary.json" 2>/dev/null || echo 0)" -gt 1600000000 ] &&
   [ -z "$(ls -d "$o".* 2>/dev/null)" ]; then
  ok "run into an existing -o DIR: new results, no partial or old copies left"
else bad "run into an existing -o DIR: old results or leftovers" "$(ls -la --time-style=full-iso "$o" "$o".* 2>&1)"; fi
echo "precious" >"$od/a-file"
expect "run -o FILE: refused (exit 1)" 1 "a-file" -- run "$od/case.yaml" -o "$od/a-file" --quiet
if [ "$(cat "$od/a-file" 2>/dev/null)" = "precious" ]; then ok "run -o FILE: the file is kept"
else bad "run -o FILE: the file was replaced" "$(ls -la "$od/a-file" 2>&1)"; fi

# --- --threads 1 gives the same numbers.
expect "run --threads 1" 0 "" -- run "$od/case.yaml" -o "$od/one-thread" --threads 1 --quiet
ex_check "run --threads 1: same tip displacement and reaction as with all threads" "$od/one-thread/summary.json" '
(t := json.load(open(sys.argv[1].replace("one-thread", "custom dir")))) is not None
and close(s["probes"]["A"]["displacement"]["z"], t["probes"]["A"]["displacement"]["z"], 1e-9)
and close(s["reactions"]["clamp"]["z"], t["reactions"]["clamp"]["z"], 1e-9)'

# --- output.dir (relative to the case file) and output.every (the last step is always written).
sed -e 's/^solver: {steps: 2}/solver: {steps: 3}/' -e 's/^output:/output:\n  dir: every2\n  every: 2/' \
  "$od/case.yaml" >"$od/every.yaml"
expect "run with output.dir and output.every: 2" 0 "" -- run "$od/every.yaml" --quiet
ex_pvd "output.every: 2 of 3 steps writes steps 2 and 3 (the last) into output.dir" "$od/every2/results.pvd" \
  "0.666667:step_0002.vtu 1:step_0003.vtu"
if [ ! -e "$od/every2/step_0001.vtu" ] && [ "$(($(wc -l <"$od/every2/history.csv")))" -eq 4 ] && [ ! -e "$od/every.out" ]; then
  ok "output.every: no step_0001.vtu, history.csv still has every step, no every.out"
else bad "output.every: wrong files" "$(ls -la "$od/every2" 2>&1; cat "$od/every2/history.csv" 2>&1 | cut -c1-40)"; fi

# --- hencky check: validates (mesh, regions, probes) and solves nothing.
rm -rf "$od/case.out"
expect "check: a valid case exits 0 and says ok" 0 "case\.yaml: ok" -- check "$od/case.yaml"
if [ ! -e "$od/case.out" ] && [ -z "$(ls -d "$od"/case.out.* 2>/dev/null)" ]; then
  ok "check: creates no output directory"
else bad "check: created an output directory" "$(ls -la "$od")"; fi
sed 's/region: tip/region: tpi/' "$od/case.yaml" >"$od/check-bad.yaml"
expect "check: an unknown region is found without solving (exit 1)" 1 \
  "check-bad\.yaml:[0-9]+:[0-9]+: 'boundary\[1\]\.region': region 'tpi' .*did you mean 'tip'" -- check "$od/check-bad.yaml"

# --- exit status 2: a step that does not converge; the converged steps before it are kept.
# Step 1 has no load (zero residual, converged); step 2 cannot reach tolerance 1e-30.
cat >"$od/stuck.yaml" <<'EOF'
mesh: {file: beam.geo, order: 2}
materials:
  - {E: 2.1e11, nu: 0.3}
boundary:
  - region: clamp
    displacement: {x: 0, y: 0, z: 0}
  - region: tip
    force: [0, 0, "t > 0.5 ? -1000 : 0"]
solver: {steps: 2, tolerance: 1.0e-30, max_iterations: 2, cutback: 1}
EOF
expect "exit 2 when a step does not converge" 2 "did not converge" -- run "$od/stuck.yaml"
ex_check "exit 2: status not-converged, step 1 written and kept" "$od/stuck.out/summary.json" '
s["status"] == "not-converged" and s["steps"] == 1 and "failure" in s
and os.path.exists(sys.argv[1].replace("summary.json", "step_0001.vtu"))
and "step_0001.vtu" in open(sys.argv[1].replace("summary.json", "results.pvd")).read()'

# The first step cannot converge: status 2 and a summary that still has its three groups.
sed -e 's/"t > 0.5 ? -1000 : 0"/"-1000*t"/' "$od/stuck.yaml" >"$od/stuck-first.yaml"
expect "exit 2 when the first step does not converge" 2 "did not converge" -- run "$od/stuck-first.yaml"
ex_check "exit 2 at step 1: summary with steps 0 and empty probes, reactions, contact" "$od/stuck-first.out/summary.json" '
s["status"] == "not-converged" and s["steps"] == 0 and s["probes"] == {} and s["reactions"] == {} and s["contact"] == {}'

# --- -o naming an existing folder that is not a hencky output: refused, left alone.
mkdir -p "$od/not-results"; echo "precious" >"$od/not-results/thesis.tex"
expect "run -o on an unrelated folder: refused (exit 1)" 1 "not a hencky output directory" -- run "$od/case.yaml" -o "$od/not-results" --quiet
if [ "$(cat "$od/not-results/thesis.tex" 2>/dev/null)" = "precious" ] && [ -z "$(ls -d "$od"/not-results.* 2>/dev/null)" ]; then
  ok "run -o on an unrelated folder: its files are kept"
else bad "run -o on an unrelated folder: changed" "$(ls -la "$od/not-results" 2>&1)"; fi

# --- The strains (issue 17) against the closed form of a bar held axially, heated by 180 K past
# yield and cooled back (tests/cli/inputs/issue16/unload-temperature; uniaxial stress, linear
# hardening): at t = 1 eps_p_zz = -(E*alpha*dT - sigma_y)/(E + h) = -9.0099e-4 and
# sigma_zz = -251.80 MPa; the thermal strain is alpha*dT on the diagonal, the total strain along
# the bar is zero, the elastic one is sigma/E along it and -nu*sigma/E across it, the plastic one
# across it half that along it with the sign reversed; eps~^{e+p} = eps~^p + sigma~/3G. Cooled
# back (t = 3) the thermal strain is zero and the elastic strain balances the plastic one.
d="$work/strains"
rm -rf "$d" && mkdir -p "$d" && cp "$src/tests/cli/inputs/issue16/unload-temperature"/* "$d/"
expect "strains: the restrained bar runs" 0 "" -- run "$d/case.yaml" --quiet
ex_check "strains at t = 1: thermal, total, elastic, plastic and eps~^{e+p} match the closed form" \
  "$d/case.out/history.csv" '
(E := 2e11, nu := 0.3, ep := -(2e11 * 2.16e-3 - 250e6) / (2e11 + 2e9)) is not None
and (sz := -(250e6 + 2e9 * abs(ep))) is not None
and (r := at(1)) is not None and (c := "centre.") is not None
and all(close(r[c + "thermal_strain." + k], 2.16e-3, 1e-12) for k in ("xx", "yy", "zz"))
and abs(r[c + "strain.zz"]) < 1e-12
and close(r[c + "elastic_strain.zz"], sz / E, 1e-5) and close(r[c + "elastic_strain.xx"], -nu * sz / E, 1e-5)
and close(r[c + "plastic_strain.zz"], ep, 1e-5) and close(r[c + "plastic_strain.yy"], -ep / 2, 1e-5)
and close(r[c + "strain.xx"], 2.16e-3 - nu * sz / E - ep / 2, 1e-5)
and close(r[c + "equivalent_elastoplastic_strain"], abs(ep) + abs(sz) / (3 * E / (2 * (1 + nu))), 1e-5)'
ex_check "strains at t = 3: no thermal strain, elastic = -plastic along the bar, total = e + p + th" \
  "$d/case.out/history.csv" '
(r := at(3)) is not None and (c := "centre.") is not None
and all(abs(r[c + "thermal_strain." + k]) < 1e-12 for k in ("xx", "yy", "zz"))
and close(r[c + "elastic_strain.zz"], -r[c + "plastic_strain.zz"], 1e-6)
and all(abs(r[c + "strain." + k] - r[c + "elastic_strain." + k] - r[c + "plastic_strain." + k]
            - r[c + "thermal_strain." + k]) < 1e-12 * 2.16e-3
        for k in ("xx", "yy", "zz", "xy", "yz", "xz"))'
