# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 48, item 2: regions named by the mesh's labels in case.yaml (mesh.regions): nodes,
# volume elements, and element faces numbered as the Abaqus and CalculiX manuals number them.
# Checked on decks of CalculiX's test suite (calculix-ccx-test), whose conditions name single
# labels and element faces.
lr="$work/label-regions"
rm -rf "$lr" && mkdir -p "$lr"
suite=/usr/share/doc/calculix-ccx-test/examples/test
if [ ! -f "$suite/beam10p.inp.gz" ]; then
  bad "label regions: calculix-ccx-test is missing (scripts/setup.sh installs it)"
  return 0
fi
zcat "$suite/beam10p.inp.gz" >"$lr/beam10p.inp"
zcat "$suite/beamd.inp.gz" >"$lr/beamd.inp"
# beam10p's *BOUNDARY names nodes 1 (x, y) and 3 (x) by their labels; its one material takes
# the elements by theirs (every element of the deck).
# (A C3D10 record is 11 numbers over two lines: the label is every 11th number.)
elements="$(awk '/^\*ELEMENT/ {f = 1; next} /^\*/ {f = 0} f {gsub(/,/, " "); for (i = 1; i <= NF; ++i) if (n++ % 11 == 0) {printf "%s%d", sep, $i; sep = ", "}}' "$lr/beam10p.inp")"
cat >"$lr/beam10p.yaml" <<YAML
mesh:
  file: beam10p.inp
  regions:
    - {name: n1, nodes: [1]}
    - {name: n3, nodes: [3]}
    - {name: all, elements: [$elements]}
materials:
  - {name: EL, regions: [all], E: 210000, nu: 0.3}
boundary:
  - {region: n1, displacement: {x: 0, y: 0}}
  - {region: n3, displacement: {x: 0}}
  - {region: FIX, displacement: {z: 0}}
  - {region: LOAD, nodal_force: [0, 1, 0]}
YAML
expect "label regions: beam10p's single-label supports and its elements by label run" 0 "" -- \
  run "$lr/beam10p.yaml" -o "$lr/beam10p.out" --quiet
out="$("$ex_py" "$src/tests/tools/ccx_dat.py" "$lr/beam10p.out" "$suite/beam10p.dat.ref.gz" "$lr/beam10p.inp" 2e-7 2>&1)" &&
  ok "label regions: ... its displacements are the .dat.ref's to 2e-7 ($out)" ||
  bad "label regions: ... not the .dat.ref's" "$out"
# beamd's *DLOAD LAST,P2 is face 2 of elements 29 .. 32: the same faces by label, the same
# pressure, give the deck's own run to round-off.
cat >"$lr/beamd.yaml" <<'YAML'
mesh:
  file: beamd.inp
  regions:
    - {name: end, faces: [[29, 2], [30, 2], [31, 2], [32, 2]]}
materials:
  - {name: EL, E: 210000, nu: 0.3}
boundary:
  - {region: CN7, displacement: {x: 0, y: 0, z: 0}}
  - {region: end, pressure: -1}
YAML
expect "label regions: beamd's loaded faces by element and face number run" 0 "" -- \
  run "$lr/beamd.yaml" -o "$lr/beamd-yaml.out" --quiet
expect "label regions: ... and the deck itself" 0 "" -- run "$lr/beamd.inp" -o "$lr/beamd-deck.out" --quiet
out="$("$ex_py" "$src/tests/tools/compare_results.py" "$lr/beamd-yaml.out" "$lr/beamd-deck.out" 1e-10 --fields displacement,stress 2>&1)" &&
  ok "label regions: ... the two agree to 1e-10" || bad "label regions: the faces by label differ from the deck's *DLOAD" "$out"
# Bad labels and names, each named where it is written.
sed -e 's/nodes: \[3\]/nodes: [3, 99999]/' "$lr/beam10p.yaml" >"$lr/bad-node.yaml"
expect "label regions: a node label the mesh lacks is an error at its place" 1 \
  "bad-node\.yaml:[0-9]+:[0-9]+: 'mesh\.regions\[1\]\.nodes\[1\]': node 99999 is not a node of the mesh's body" \
  -- check "$lr/bad-node.yaml"
sed -e 's/\[32, 2\]/[32, 7]/' "$lr/beamd.yaml" >"$lr/bad-face.yaml"
expect "label regions: a face number outside 1 .. 6 is an error" 1 \
  "bad-face\.yaml:[0-9]+:[0-9]+: 'mesh\.regions\[0\]\.faces\[3\]\[1\]': a face number is 1 \.\. 6" \
  -- check "$lr/bad-face.yaml"
sed -e 's/name: end, faces/name: LAST, faces/' -e 's/region: end,/region: LAST,/' "$lr/beamd.yaml" >"$lr/taken.yaml"
expect "label regions: a name the mesh already has is an error" 1 \
  "taken\.yaml:[0-9]+:[0-9]+: 'mesh\.regions\[0\]': the mesh already has a region 'LAST'" \
  -- check "$lr/taken.yaml"
