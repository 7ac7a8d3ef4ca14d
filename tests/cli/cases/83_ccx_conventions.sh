# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 48, item 5: ccx's conventions where hencky's differ. `temperature.interpolation: linear`
# takes the temperatures of a 20-node hexahedron's integration points as ccx's C3D20 does: the
# quadratic field projected onto the trilinear functions (tests/cli/inputs/ccx/linear-temperature.yaml
# says what each gives, in closed form; beam20t of ccx's suite, in 84_ccx_decks.sh, matches ccx
# to 2e-7 with it and differs by 9 % without).
cc="$work/ccx-conventions"
rm -rf "$cc" && cp -r "$src/tests/cli/inputs/ccx" "$cc"
expect "ccx conventions: linear temperatures in a 20-node hexahedron run" 0 "" -- \
  run "$cc/linear-temperature.yaml" -o "$cc/linear" --quiet
ex_check "ccx conventions: ... the points take x^2 projected on trilinear functions: 1/3 at the centre" \
  "$cc/linear/summary.json" \
  'all(close(s["probes"]["c"]["stress"][k], -2.0e11 * 1.0e-5 / 3 / 0.5, 1e-12) for k in ("xx", "yy", "zz"))'
sed -e 's/, interpolation: linear//' "$cc/linear-temperature.yaml" >"$cc/element.yaml"
expect "ccx conventions: the cell's own functions (the default) run" 0 "" -- \
  run "$cc/element.yaml" -o "$cc/element" --quiet
ex_check "ccx conventions: ... the points take x^2: the centre's fit is 0.35, sigma = -1.4e6 Pa" \
  "$cc/element/summary.json" \
  'all(close(s["probes"]["c"]["stress"][k], -2.0e11 * 1.0e-5 * 0.35 / 0.5, 1e-12) for k in ("xx", "yy", "zz"))'
sed -e 's/interpolation: linear/interpolation: corners/' "$cc/linear-temperature.yaml" >"$cc/bad.yaml"
expect "ccx conventions: an unknown interpolation is an input error naming the key and the choices" 1 \
  "bad\.yaml:[0-9]+:[0-9]+: 'temperature\.interpolation': .*'element', 'linear'" -- check "$cc/bad.yaml"
