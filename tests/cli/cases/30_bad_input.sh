# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Bad input: exit status 1, a message naming the file, the line (where there is one) and the
# key, with a suggestion where one exists; nothing is solved and an existing output directory
# is left exactly as it was (ex_bad checks all of that, see 05_helpers.sh).
bd="$work/bad"
mkdir -p "$bd"
cp "$src/examples/cantilever/beam.geo" "$bd/beam.geo"
ex_set "$bd/beam.geo" '^n = [0-9]+;' 'n = 4;'   # 4 hexahedra; regions beam, clamp, tip

# The valid base case; every bad case below changes one thing in it. Line numbers matter.
cat >"$bd/good.yaml" <<'EOF'
title: bad-input base case
mesh: {file: beam.geo, order: 2}
materials:
  - name: steel
    E: 2.1e11
    nu: 0.3
    alpha: 1.2e-5
boundary:
  - region: clamp
    displacement: {x: 0, y: 0, z: 0}
  - region: tip
    force: [0, 0, "-1000*t"]
solver: {steps: 2}
output:
  probes:
    - {name: A, point: [1.0, 0.025, 0.05]}
  reactions: [clamp]
EOF
expect "bad input: the base case itself is valid" 0 "good\.yaml: ok" -- check "$bd/good.yaml"

# ex_variant NAME SED-SCRIPT: $bd/NAME.yaml = the base case edited by sed -E.
ex_variant() { sed -E "$2" "$bd/good.yaml" >"$bd/$1.yaml"; }

# --- keys
ex_variant materails 's/^materials:/materails:/'
ex_bad "bad input: unknown key, with suggestion" \
  "materails\.yaml:3:1: 'materails': unknown key 'materails'; did you mean 'materials'\?" "$bd/materails.yaml"
ex_variant stpes 's/^solver: \{steps: 2\}/solver: {stpes: 2}/'
ex_bad "bad input: unknown key in a section, with suggestion" \
  "stpes\.yaml:13:[0-9]+: 'solver\.stpes': unknown key 'stpes'; did you mean 'steps'\?" "$bd/stpes.yaml"

# --- mesh
ex_variant missing-mesh 's/file: beam\.geo/file: nosuch.msh/'
ex_bad "bad input: missing mesh file" \
  "missing-mesh\.yaml:2:[0-9]+: 'mesh\.file': mesh file not found: .*/bad/nosuch\.msh" "$bd/missing-mesh.yaml"
"$ex_py" -c 'import random, sys; random.seed(1); open(sys.argv[1], "wb").write(bytes(random.getrandbits(8) for _ in range(4096)))' "$bd/garbage.msh"
ex_variant garbage-msh 's/file: beam\.geo/file: garbage.msh/'
ex_bad "bad input: a .msh file that is garbage (4 kB of fixed pseudo-random bytes)" \
  "garbage\.msh:1: not a valid Gmsh mesh file: the file does not start with \\\$MeshFormat" "$bd/garbage-msh.yaml"
printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\nthis is not a node block\n$EndNodes\n' >"$bd/broken.msh"
ex_variant broken-msh 's/file: beam\.geo/file: broken.msh/'
ex_bad "bad input: a .msh file with a valid header and a garbage node block" \
  "broken\.msh:5: not a valid Gmsh mesh file: the number of node blocks \(a non-negative integer\) expected, found .this." "$bd/broken-msh.yaml"

# --- regions (the message lists the regions the mesh has)
ex_variant region 's/region: tip$/region: tipp/'
ex_bad "bad input: unknown region name, with suggestion and the mesh's regions" \
  "region\.yaml:11:[0-9]+: 'boundary\[1\]\.region': region 'tipp' is not a physical surface of the mesh beam\.geo; did you mean 'tip'\? valid physical surfaces: 'clamp', 'tip'" \
  "$bd/region.yaml"
ex_variant volume 's/^  - name: steel/  - name: steel\n    regions: [bean]/'
ex_bad "bad input: unknown material region, with suggestion and the mesh's volumes" \
  "volume\.yaml:5:[0-9]+: 'materials\[0\]\.regions\[0\]': region 'bean' is not a physical volume .*did you mean 'beam'\? valid physical volumes: 'beam'" \
  "$bd/volume.yaml"

# --- values
ex_variant wrong-type 's/^    E: 2\.1e11/    E: "abc"/'
ex_bad "bad input: wrong type (E: \"abc\")" \
  "wrong-type\.yaml:5:[0-9]+: 'materials\[0\]\.E': expected a number, found 'abc'" "$bd/wrong-type.yaml"
ex_variant expression 's/"-1000\*t"/"100e6*t +"/'
ex_bad "bad input: malformed expression" \
  "expression\.yaml:12:[0-9]+: 'boundary\[1\]\.force\[2\]': invalid expression \"100e6\*t \+\"" "$bd/expression.yaml"
ex_variant nu-half 's/^    nu: 0\.3/    nu: 0.5/'
ex_bad "bad input: nu = 0.5" \
  "nu-half\.yaml:6:[0-9]+: 'materials\[0\]\.nu': nu must satisfy -1 < nu < 0\.5.*found 0\.5" "$bd/nu-half.yaml"
ex_variant table-order 's/^    E: 2\.1e11/    E: {temperature: [20, 300, 200], value: [2.1e11, 1.9e11, 2.0e11]}/; s/^solver:/temperature: {reference: 20, field: "20 + 100*t"}\nsolver:/'
ex_bad "bad input: temperature table out of order" \
  "table-order\.yaml:5:[0-9]+: 'materials\[0\]\.E\.temperature\[2\]': temperatures must be strictly increasing, found 200 after 300" \
  "$bd/table-order.yaml"
ex_variant scheme 's/^solver: \{steps: 2\}/solver: {steps: 2, scheme: newtn}/'
ex_bad "bad input: unknown scheme name, with suggestion" \
  "scheme\.yaml:13:[0-9]+: 'solver\.scheme': unknown scheme 'newtn'; did you mean 'newton'\?" "$bd/scheme.yaml"

# --- hardening curves: a valid one passes the check; a bad one is named by table and point
ex_variant plasticity 's/^    alpha: 1\.2e-5/    alpha: 1.2e-5\n    plasticity:\n      perfect: {yield: 240e6}/'
expect "plasticity: a valid curve passes the check" 0 "plasticity\.yaml: ok" -- check "$bd/plasticity.yaml"
ex_variant bad-curve 's/^    alpha: 1\.2e-5/    alpha: 1.2e-5\n    plasticity:\n      curve:\n        kind: uniaxial\n        table:\n          - {temperature: 20, strain: [0.00114286, 0.002, 0.003], stress: [240e6, 260e6, 500e6]}/'
ex_bad "bad input: a uniaxial curve whose plastic strain does not increase" \
  "bad-curve\.yaml:12:59: 'materials\[0\]\.plasticity\.curve\.table\[0\]': point 2 \(strain 0\.003, stress 5e\+08\): its plastic strain .* does not increase" \
  "$bd/bad-curve.yaml"
expect "bad input: hencky check reports the bad curve too" 1 \
  "bad-curve\.yaml:12:59: 'materials\[0\]\.plasticity\.curve\.table\[0\]': point 2" -- check "$bd/bad-curve.yaml"

# --- contact
cp "$bd/good.yaml" "$bd/contact.yaml"
printf 'contact:\n  - name: floor\n    nodes: clamp\n    surface:\n      plane: {point: [0, 0, 0.5], normal: [0, 0, 1]}\n' >>"$bd/contact.yaml"
ex_bad "bad input: a contact node that starts inside the rigid surface" \
  "contact\.yaml:2[0-9]:[0-9]+: 'contact\[0\]\.surface': contact 'floor': node [0-9]+ of region 'clamp' .* starts inside the rigid surface" "$bd/contact.yaml"
# A tetrahedron with one face missing: not a closed rigid body.
printf 'solid open\n' >"$bd/open.stl"
for f in "0 0 0|0 1 0|1 0 0" "0 0 0|1 0 0|0 0 1" "0 0 0|0 0 1|0 1 0"; do
  IFS='|' read -r a b c <<<"$f"
  printf ' facet normal 0 0 0\n  outer loop\n   vertex %s\n   vertex %s\n   vertex %s\n  endloop\n endfacet\n' "$a" "$b" "$c" >>"$bd/open.stl"
done
printf 'endsolid open\n' >>"$bd/open.stl"
cp "$bd/good.yaml" "$bd/open-stl.yaml"
printf 'contact:\n  - name: punch\n    nodes: clamp\n    surface:\n      mesh: {file: open.stl}\n' >>"$bd/open-stl.yaml"
ex_bad "bad input: an STL rigid body that is not closed names the file" \
  "open\.stl:[0-9]+: the surface is not closed" "$bd/open-stl.yaml"

# --- YAML syntax
ex_variant yaml-flow 's/^mesh: \{file: beam\.geo, order: 2\}/mesh: {file: beam.geo, order: 2/'
ex_bad "bad input: malformed YAML (unclosed {)" \
  "yaml-flow\.yaml:[0-9]+:[0-9]+: YAML syntax error" "$bd/yaml-flow.yaml"
ex_variant yaml-tab 's/^    nu: 0\.3/\tnu: 0.3/'
ex_bad "bad input: malformed YAML (tab indentation), with a hint" \
  "yaml-tab\.yaml:[0-9]+:[0-9]+: YAML syntax error.*line 6 is indented with a tab" "$bd/yaml-tab.yaml"

# --- probes
ex_variant probe 's/point: \[1\.0, 0\.025, 0\.05\]/point: [2.0, 0.025, 0.05]/'
ex_bad "bad input: probe outside the mesh" \
  "probe\.yaml:16:[0-9]+: 'output\.probes\[0\]\.point': probe 'A' at \(2, 0\.025, 0\.05\) is outside the mesh" \
  "$bd/probe.yaml"

# --- supports
cat >"$bd/no-support.yaml" <<'EOF'
mesh: {file: beam.geo, order: 2}
materials:
  - {name: steel, E: 2.1e11, nu: 0.3}
boundary:
  - region: tip
    force: [0, 0, "-1000*t"]
EOF
ex_bad "bad input: a body with no displacement condition at all" \
  "no-support\.yaml: 'boundary': no displacement condition" "$bd/no-support.yaml"
# Refused before any solve, naming the free motions (Model::check_held, issue 47), whatever
# the linear solver.
ex_variant support 's/displacement: \{x: 0, y: 0, z: 0\}/displacement: {z: 0}/'
ex_bad "bad input: only z fixed on one face: the free rigid motions named" \
  "support\.yaml: 'boundary': the body is not held: its displacement conditions leave 4 rigid motions free: translation along x; translation along y; rotation about the axis through \(0, 0\.025, 0\.05\) along y; rotation about the axis through \(0\.5, 0\.025, 0\.05\) along z" \
  "$bd/support.yaml"
ex_variant support-cg 's/displacement: \{x: 0, y: 0, z: 0\}/displacement: {z: 0}/; s/^solver: \{steps: 2\}/solver: {steps: 2, linear: iterative}/'
ex_bad "bad input: only z fixed on one face, iterative solver: the same" \
  "support-cg\.yaml: 'boundary': the body is not held: .* 4 rigid motions free" "$bd/support-cg.yaml"
# A body that contact alone may hold passes that check; where the surface does not touch it in
# the first step, the first factorization finds it free: the solver's diagnosis.
cp "$src/tests/cli/inputs/held/block.geo" "$bd/"
sed 's/point: \[0, 0, 0\]/point: [0, 0, -1e-3]/' "$src/tests/cli/inputs/held/contact-held.yaml" >"$bd/gap.yaml"
ex_bad "bad input: held by a surface that does not touch it: the factorization says so" \
  "gap\.yaml: 'boundary': the stiffness matrix is (singular|not positive definite).*not held against rigid-body motion" \
  "$bd/gap.yaml"

# --- the existing directory given with -o is left alone too
ex_variant with-o 's/^materials:/materails:/'
mkdir -p "$bd/given"
echo "keep me" >"$bd/given/marker"
before="$(ex_snapshot "$bd/given")"
expect "bad input with -o DIR: exit 1" 1 "unknown key 'materails'" -- run "$bd/with-o.yaml" -o "$bd/given"
if [ "$before" = "$(ex_snapshot "$bd/given")" ]; then ok "bad input with -o DIR: DIR untouched"
else bad "bad input with -o DIR: DIR changed" "$(ls -la "$bd/given" "$bd"/given.* 2>&1)"; fi

# --- an expression that is fine at first and not finite at a later step: exit 1, and the
#     steps already solved do not replace the existing results.
ex_variant late-nan 's/"-1000\*t"/"t > 0.6 ? sqrt(-1) : -1000*t"/'
EX_ALLOW_NAN=1 ex_bad "bad input: expression not finite at step 2 (after step 1 was solved)" \
  "late-nan\.yaml:12:[0-9]+: 'boundary\[1\]\.force\[2\]': force: \"t > 0\.6 \? sqrt\(-1\) : -1000\*t\" gives -?nan at .*t=1; expected a finite value" \
  "$bd/late-nan.yaml"
# No pointer to partial results that were deleted with the bad input.
out="$("$bin" run "$bd/late-nan.yaml" 2>&1)"
if ! grep -q "results so far are in" <<<"$out"; then ok "bad input: no pointer to deleted partial results"
else bad "bad input: points at deleted partial results" "$out"; fi

# --- γ chosen per step (solver.correction, an expression of t) must be >= 0 at every step: the
#     planned steps' times are checked when the case is read, a cut-back's when its step begins
#     (here the first step cannot converge in one iteration at a tolerance below round-off and
#     is halved to t = 0.25, where γ is -1); either way an input error, nothing written.
ex_variant gamma-planned 's/^solver: \{steps: 2\}/solver: {steps: 2, correction: "t > 0.75 ? -1 : 1"}/'
ex_bad "bad input: correction < 0 at a planned step" \
  "gamma-planned\.yaml:[0-9]+:[0-9]+: 'solver\.correction': expected a number or an expression of t >= 0 .*found -1 at t = 1" \
  "$bd/gamma-planned.yaml"
ex_variant gamma-cutback 's/^solver: \{steps: 2\}/solver: {steps: 2, tolerance: 1e-30, max_iterations: 1, correction: "abs(t - 0.25) < 1e-9 ? -1 : 1"}/'
ex_bad "bad input: correction < 0 at a cut-back's time" \
  "gamma-cutback\.yaml:[0-9]+:[0-9]+: 'solver\.correction': the correction γ = .* is -1 at t = 0\.25 \(a step cut back\)" \
  "$bd/gamma-cutback.yaml"
