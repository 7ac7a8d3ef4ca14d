# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad): helpers for the example,
# output and bad-input cases (10_examples.sh, 20_outputs.sh, 30_bad_input.sh). JSON is read with
# the system Python (/usr/bin/python3, which has numpy: Debian's python3-numpy).
ex_py=/usr/bin/python3

# ex_check NAME FILE EXPR: evaluates the Python expression EXPR with close(value, expected,
# relative_tolerance) and FILE's content: a .csv (history.csv) as h = its rows (numbers) with
# at(t) = the row nearest time t and np = numpy, anything else as s = its JSON (summary.json).
# ok when EXPR is true.
ex_check() {
  local name="$1" file="$2" expr="$3" out
  if out="$("$ex_py" - "$file" "$expr" 2>&1 <<'PY'
import csv, json, os, sys
def close(v, e, rel):
    if abs(v - e) <= rel * abs(e):
        return True
    print("got %r, expected %r within %g relative (off by %.3g)" % (v, e, rel, abs(v - e) / abs(e)))
    return False
if sys.argv[1].endswith(".csv"):
    import numpy as np
    h = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(sys.argv[1]))]
    def at(t):
        return min(h, key=lambda r: abs(r["time"] - t))
else:
    s = json.load(open(sys.argv[1]))
sys.exit(0 if eval("(" + sys.argv[2] + "\n)") else 1)
PY
)"; then ok "$name"; else bad "$name" "check: $expr"$'\n'"$out"; fi
}

# ex_copy EXAMPLE: a fresh copy of examples/EXAMPLE in $work/examples/EXAMPLE, without results.
ex_copy() {
  mkdir -p "$work/examples"
  rm -rf "$work/examples/$1"
  cp -r "$src/examples/$1" "$work/examples/$1"
  rm -rf "$work/examples/$1"/*.out "$work/examples/$1"/*.png
}

# ex_set FILE PATTERN REPLACEMENT: sed -E 's|PATTERN|REPLACEMENT|' in FILE, and a failed check
# when the pattern is not there (so that a renamed .geo parameter is not silently ignored) or the
# file is unchanged. '|' delimits: patterns hold '/' ("hc = a / 3").
ex_set() {
  if grep -Eq -- "$2" "$1"; then
    local before
    before="$(cat "$1")"
    sed -E -i "s|$2|$3|" "$1" || bad "$(basename "$1"): sed failed on /$2/"
    [ "$before" != "$(cat "$1")" ] || [ "$2" = "$3" ] || bad "$(basename "$1"): /$2/ changed nothing"
  else
    bad "$(basename "$1"): no line matches /$2/ to coarsen the example"
  fi
}

# ex_snapshot DIR: a listing of DIR (names, sizes, times, checksums; DIR's own time, not its
# parent's) and of DIR.* siblings.
ex_snapshot() {
  (cd "$(dirname "$1")" && ls -la --time-style=full-iso "$(basename "$1")" 2>&1 | grep -v ' \.\.$' &&
    find "$(basename "$1")" -type f -exec md5sum {} + 2>&1 | sort &&
    ls -d "$(basename "$1")"* 2>&1)
}

# ex_bad NAME PATTERN CASE [ARGS...]: `hencky run CASE ARGS` must exit 1 with an error matching
# the extended regular expression PATTERN, must not mention NaN (unless EX_ALLOW_NAN=1), and
# must leave the output directory that exists before the run (CASE without .yaml, plus .out,
# holding a marker file) exactly as it was, with no partial or old copies next to it.
ex_bad() {
  local name="$1" pattern="$2" case="$3"; shift 3
  local dir="${case%.yaml}.out" before after out rc
  rm -rf "$dir" "$dir".*
  mkdir -p "$dir"
  echo "results of an earlier run" >"$dir/marker"
  echo '{"status": "converged"}' >"$dir/summary.json"   # so that hencky may replace it
  touch -d "2020-01-01 00:00:00" "$dir/marker" "$dir/summary.json" "$dir"
  before="$(ex_snapshot "$dir")"
  out="$("$bin" run "$case" "$@" 2>&1)"; rc=$?
  after="$(ex_snapshot "$dir")"
  if [ "$rc" -ne 1 ]; then bad "$name: exit $rc, expected 1" "$out"
  elif ! grep -Eq -- "$pattern" <<<"$out"; then bad "$name: output does not match /$pattern/" "$out"
  elif [ -z "${EX_ALLOW_NAN:-}" ] && grep -Eqi -- "(^|[^a-z])nan([^a-z]|$)" <<<"${out//$work/}"; then
    bad "$name: the message mentions NaN" "$out"
  elif [ "$before" != "$after" ]; then
    bad "$name: the existing output directory changed" "$(diff <(echo "$before") <(echo "$after"))"
  else ok "$name"; fi
}
