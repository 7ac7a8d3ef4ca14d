# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 22: Abaqus/CalculiX .inp meshes (input/inp_reader.hpp). One Gmsh mesh, read from its
# .msh and from two decks, gives the same results to 1e-10 (the .inp holds 14 digits):
#   - Gmsh's own export (gmsh -format inp: faces as CPS elements in ELSETs, NSETs);
#   - that deck rewritten as Abaqus/CAE writes decks (tests/tools/inp_surfaces.py: faces as
#     element-based *SURFACEs S1..S6, names in upper case where the case has lower case,
#     GENERATE sets, elements continued over lines);
# for 10- and 4-node tetrahedra (the Lamé cylinder), 20- and 8-node hexahedra and 6-node wedges
# (a box loaded on each face but the clamped one). Then the decks the CalculiX bench writes for
# ccx (tests/tools/bench_deck.py), and bad decks: each stops with its file and line and
# changes nothing on disk.

id="$work/inp"
rm -rf "$id" && mkdir -p "$id"
cp "$src/tests/cli/inputs/inp/"* "$src/examples/lame-cylinder/cylinder.geo" "$id/"
sed -E -e 's|file: cylinder.geo.*|file: cyl.msh|' -e '/^  order: 2/d' \
  "$src/examples/lame-cylinder/case.yaml" >"$id/cyl.yaml"

# inp_same NAME GEO ORDER CASE MESH: meshes GEO at ORDER into $id/MESH.msh, writes it as Gmsh's
# deck and as the CAE-style deck, and runs CASE (whose mesh.file is MESH.msh) on all three.
inp_same() {
  local name="$1" geo="$2" order="$3" case="$4" mesh="$5" d="$id/$1" m
  mkdir -p "$d"
  if ! gmsh -3 "$id/$geo" -order "$order" -string "Mesh.SecondOrderIncomplete=1;" \
    -o "$d/$mesh.msh" >"$d/gmsh.log" 2>&1 ||
    ! gmsh "$d/$mesh.msh" -0 -string "Mesh.SaveGroupsOfNodes=1;" -format inp \
      -o "$d/$mesh-gmsh.inp" >>"$d/gmsh.log" 2>&1; then
    bad "inp $name: gmsh failed" "$(tail -5 "$d/gmsh.log")"
    return
  fi
  "$ex_py" "$src/tests/tools/inp_surfaces.py" "$d/$mesh-gmsh.inp" "$d/$mesh-cae.inp" \
    --upper --generate --split-lines || bad "inp $name: inp_surfaces.py failed"
  cp "$id/$case" "$d/msh.yaml"
  for m in gmsh cae; do
    sed -E "s|file: $mesh.msh|file: $mesh-$m.inp|" "$id/$case" >"$d/$m.yaml"
  done
  expect "inp $name: the .msh runs" 0 "converged" -- run "$d/msh.yaml" -o "$d/msh"
  expect "inp $name: Gmsh's deck runs" 0 "converged" -- run "$d/gmsh.yaml" -o "$d/gmsh"
  expect "inp $name: the CAE-style deck runs, skipping its material and step" 0 \
    "skipped what is not mesh data.*\*MATERIAL, \*ELASTIC, \*STEP, \*STATIC, \*END STEP" \
    -- run "$d/cae.yaml" -o "$d/cae"
  for m in gmsh cae; do
    if out="$("$ex_py" "$src/tests/tools/compare_results.py" "$d/msh" "$d/$m" 1e-10 \
      --fields displacement,stress 2>&1)"; then
      ok "inp $name: $m deck = .msh to 1e-10"
    else
      bad "inp $name: $m deck differs from the .msh" "$out"
    fi
  done
}
inp_same "tet10 cylinder" cylinder.geo 2 cyl.yaml cyl
inp_same "tet4 cylinder" cylinder.geo 1 cyl.yaml cyl
inp_same "hex20 box" box-hex.geo 2 box.yaml box
inp_same "hex8 box" box-hex.geo 1 box.yaml box
inp_same "wedge6 box" box-wedge.geo 1 box.yaml box

# The decks bench/henckybench/calculix.py writes for ccx (C3D10, NSETs, the loaded faces as a
# *SURFACE, *MATERIAL .. *END STEP skipped), with the bench's own hencky cases.
for problem in cylinder cantilever; do
  d="$id/bench-$problem"
  if ! out="$("$ex_py" "$src/tests/tools/bench_deck.py" "$problem" 0.03 "$d" 2>&1)"; then
    bad "inp bench $problem: bench_deck.py failed" "$out"
    continue
  fi
  expect "inp bench $problem: the .msh runs" 0 "converged" -- run "$d/msh.yaml" -o "$d/msh"
  expect "inp bench $problem: the ccx deck runs" 0 "converged" -- run "$d/inp.yaml" -o "$d/inp"
  if out="$("$ex_py" "$src/tests/tools/compare_results.py" "$d/msh" "$d/inp" 1e-10 \
    --fields displacement,stress 2>&1)"; then
    ok "inp bench $problem: ccx deck = .msh to 1e-10"
  else
    bad "inp bench $problem: the ccx deck differs from the .msh" "$out"
  fi
done

# Bad decks and cases: the line, and nothing written.
b="$id/hex20 box"
bd="$id/bad"
mkdir -p "$bd"
inp_bad() { # NAME PATTERN SED-EXPRESSION: the CAE-style box deck edited by SED-EXPRESSION
  sed -E "$3" "$b/box-cae.inp" >"$bd/box.inp"
  sed -E "s|file: box.msh|file: box.inp|" "$id/box.yaml" >"$bd/$1.yaml"
  ex_bad "inp: $1" "$2" "$bd/$1.yaml"
}
inp_bad unknown-type "box.inp:[0-9]+: unknown element type 'C3X20'" 's/TYPE=C3D20/TYPE=C3X20/'
inp_bad missing-node "box.inp:[0-9]+: NSET 'FIXED' names node 99999, which no \*NODE defines" \
  '/^\*NSET, NSET=FIXED/{n;s/^/99999, /}'
inp_bad set-before "box.inp:[0-9]+: 'NOSUCH' is neither a label nor an ELSET defined before" \
  '/^\*ELSET, ELSET=SOLID/{n;s/^/NOSUCH, /}'
inp_bad bad-face "box.inp:[0-9]+: .*face S1 .. S6" 's/^(_FIXED_S6), S6/\1, S9/'
# Cut short in the middle of the elements: after the first line of the element on line 150.
head -n 150 "$b/box-cae.inp" >"$bd/box.inp"
sed -E "s|file: box.msh|file: box.inp|" "$id/box.yaml" >"$bd/truncated.yaml"
ex_bad "inp: a deck cut short" "box.inp:150: element [0-9]+ has 7 nodes, and C3D20 has 20: .*cut short" \
  "$bd/truncated.yaml"
cp "$b/box-cae.inp" "$bd/box.inp"
sed -E -e "s|file: box.msh|file: box.inp|" -e 's|mesh: \{(.*)\}|mesh: {\1, order: 2}|' \
  "$id/box.yaml" >"$bd/order.yaml"
ex_bad "inp: mesh.order on a deck" "mesh.order converts Gmsh meshes only" "$bd/order.yaml"
sed -E -e "s|file: box.msh|file: box.inp|" -e 's|region: load$|region: lod|' \
  "$id/box.yaml" >"$bd/region.yaml"
ex_bad "inp: a region the deck has not, in a deck's words" \
  "region 'lod' is not a \*SURFACE \(element faces, or an ELSET of face elements\) of the mesh box\.inp; did you mean 'LOAD'\? valid \*SURFACEs and ELSETs of faces:.*LOAD" \
  "$bd/region.yaml"
