# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# Issue 22: `hencky plot DIR` draws history.csv's columns (scripts/plot_history.py, matplotlib)
# into DIR/plot.png and DIR/plot.svg; bad columns and directories are errors naming them that
# write nothing.

pd="$work/plot"
rm -rf "$pd" && mkdir -p "$pd"
cp "$src/tests/cli/inputs/nl1/"* "$pd/"
sed -i -E "s/^  steps: 80$/  steps: 16/" "$pd/case.yaml"
expect "plot: a run to plot" 0 "" -- run "$pd/case.yaml" -o "$pd/out" --quiet
# png_svg NAME PREFIX: PREFIX.png starts with the PNG signature and holds an image header,
# PREFIX.svg is an SVG document.
png_svg() {
  local out
  if out="$("$ex_py" - "$2" 2>&1 <<'PY'
import struct, sys
png = open(sys.argv[1] + ".png", "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG: %r" % png[:8]
assert png[12:16] == b"IHDR", "no IHDR chunk"
w, h = struct.unpack(">II", png[16:24])
assert w >= 400 and h >= 300, "a %dx%d image" % (w, h)
svg = open(sys.argv[1] + ".svg").read()
assert "<svg" in svg and svg.rstrip().endswith("</svg>"), "not an SVG document"
print("%dx%d" % (w, h))
PY
)"; then ok "$1 ($out)"; else bad "$1" "$out"; fi
}
expect "plot: the defaults (reactions and probes against time)" 0 \
  "wrote .*plot.png and .*plot.svg \(10 curves against time\)" -- plot "$pd/out"
png_svg "plot: ... a PNG and an SVG" "$pd/out/plot"
expect "plot: the stress path, sigma_yy against sigma_xx, into a named file" 0 \
  "1 curves against centre.stress.xx" -- \
  plot "$pd/out" --x centre.stress.xx --y centre.stress.yy -o "$pd/path"
png_svg "plot: ... a PNG and an SVG" "$pd/path"
expect "plot: convergence measures on a log axis, by pattern" 0 "4 curves against time" -- \
  plot "$pd/out" --y iterations 'reaction.x1.?' --log-y -o "$pd/conv"
expect "plot: a column that is not there is named" 1 \
  "error: --y 'centre.strain.qq': no column of history.csv matches it" -- \
  plot "$pd/out" --y centre.strain.qq -o "$pd/bad"
[ -e "$pd/bad.png" ] && bad "plot: the refused plot wrote $pd/bad.png" || ok "plot: ... and wrote nothing"
expect "plot: a bad --x is named" 1 "error: --x 'tme': not a column of" -- plot "$pd/out" --x tme
expect "plot: a directory without history.csv is named" 1 \
  "error: .*/nowhere/history.csv: cannot be read" -- plot "$pd/nowhere"
