# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Meshes that crashed hencky through Gmsh 4.8 (shared/crashes/geo-mesh-error-abort,
# msh4-bad-node-tag-segv, msh4-count-too-small): each is now an input error (exit 1) that names
# the file, the line and what is wrong, for `check` and for `run`, and a refused run leaves
# the output directory as it was (ex_bad).
bm="$work/bad-meshes"
mkdir -p "$bm"
cp "$src"/tests/cli/inputs/crashes/* "$bm/"
# bad_mesh NAME FILE PATTERN: `check` and `run` of a case on FILE exit 1 matching PATTERN.
bad_mesh() {
  printf 'mesh: {file: %s}\nmaterials: [{E: 2.1e11, nu: 0.3}]\n' "$2" >"$bm/$1.yaml"
  printf 'boundary: [{region: "1", displacement: {x: 0, y: 0, z: 0}}]\n' >>"$bm/$1.yaml"
  expect "bad mesh: $1 (check)" 1 "$3" -- check "$bm/$1.yaml"
  ex_bad "bad mesh: $1 (run)" "$3" "$bm/$1.yaml"
}
bad_mesh geo-mesh-error transfinite-mismatch.geo \
  "transfinite-mismatch\.geo: Gmsh cannot mesh this geometry: Surface 1 cannot be meshed using the transfinite algo \(divisions 10 != 2\)"
bad_mesh node-minus-one node-minus-one.msh \
  "node-minus-one\.msh:19: not a valid Gmsh mesh file: element 1 has node -1, which \\\$Nodes does not define"
bad_mesh node-2-31 node-2-31.msh \
  "node-2-31\.msh:19: not a valid Gmsh mesh file: element 1 has node 2147483648, which \\\$Nodes does not define"
bad_mesh nodes-count-small nodes-count-small.msh \
  "nodes-count-small\.msh:6: not a valid Gmsh mesh file: the node blocks hold more nodes than the \\\$Nodes header announces \(1\)"
bad_mesh elements-count-small elements-count-small.msh \
  "elements-count-small\.msh:20: not a valid Gmsh mesh file: the element blocks hold more elements than the \\\$Elements header announces \(0\)"
bad_mesh v2-body-under-4.0 v2-body-under-4.0.msh \
  "v2-body-under-4\.0\.msh:6: not a valid Gmsh mesh file: the \\\$Nodes header announces 6 nodes, its blocks hold 0"
# The same files with an order conversion, which goes through the Gmsh library: hencky's
# reader refuses them first.
printf 'mesh: {file: node-minus-one.msh, order: 2}\nmaterials: [{E: 2.1e11, nu: 0.3}]\n' >"$bm/convert.yaml"
expect "bad mesh: a malformed file is refused before Gmsh converts its order" 1 \
  "node-minus-one\.msh:19: not a valid Gmsh mesh file" -- check "$bm/convert.yaml"
# A $PhysicalNames line of dimension 4 (shared/crashes/msh-physical-dim4-*): read, it crashed the
# Gmsh library once a case set mesh.order (1 or 2); now hencky's reader refuses it first.
for order in 1 2; do
  printf 'mesh: {file: physical-dim4.msh, order: %s}\nmaterials: [{E: 2.1e11, nu: 0.3}]\n' "$order" \
    >"$bm/dim4-order$order.yaml"
  expect "bad mesh: a physical name of dimension 4, mesh.order $order, is an input error" 1 \
    "physical-dim4\.msh:6: not a valid Gmsh mesh file: physical name 'clamp' has dimension 4 \(0 to 3\)" \
    -- check "$bm/dim4-order$order.yaml"
done
