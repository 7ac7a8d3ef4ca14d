#!/usr/bin/env bash
# Regenerates the issue-16 table: every case of tests/cli/inputs/issue16 with every scheme, on
# the case's own (default) settings.
#
# Usage: run_issue16_table.sh HENCKY_BINARY OUTPUT.md [CASE ...]
#   CASE: names of case folders (default: all folders with a case.yaml).
# Environment:
#   CASES_DIR  folder of the cases   (default tests/cli/inputs/issue16 of this repository)
#   WORK_DIR   scratch folder        (default /tmp/issue16/work-<binary name>; the folders of
#              the cases run are replaced)
#   TIMEOUT    seconds per run       (default 300; a run killed by it shows status 124)
#   THREADS    --threads of the runs (default: hencky's default)
#   SCHEMES    space-separated list of variants (default: the seven below; without newton
#              under FORMULATION=report)
#   FORMULATION  when set (hencky or report), each copy gets a line `formulation: <value>`
#              after its scheme line; under `report` newton is skipped (the reader refuses it)
#   VS_DIR     another WORK_DIR: the "vs" column then compares each run with the same case and
#              variant there (VS_DIR/<case>/<variant>/out, e.g. the runs of the other
#              formulation) instead of with this run's newton
#              (the reference's largest values over its run are cached in its out/largest.json)
#
# Columns of rows.tsv (WORK_DIR/rows.tsv): case, unknowns, variant, exit, steps (planned), t,
# iterations, cut-backs, factorizations, plastic points, wall s, stopped because, vs, and
# summary.json's report.largest_yield_excess.value (the largest σ̃/σ_y − 1 over the run; "-"
# if the binary does not write it).
#
# Every case file sets `scheme: newton` on a line of its own in `solver:`; the per-scheme copy
# replaces that line (variable-stiffness/strain adds `curve_form: strain` under it). The copy
# goes into WORK_DIR/<case>/<variant>/ with the case's other files, its results in .../out.
set -u
bin="$(readlink -f "${1:?usage: run_issue16_table.sh HENCKY_BINARY OUTPUT.md [CASE ...]}")"
md="${2:?usage: run_issue16_table.sh HENCKY_BINARY OUTPUT.md [CASE ...]}"
shift 2
cases_dir="${CASES_DIR:-$(cd "$(dirname "$0")/.." && pwd)/tests/cli/inputs/issue16}"
work="${WORK_DIR:-/tmp/issue16/work-$(basename "$bin")}"
timeout_s="${TIMEOUT:-300}"
schemes="${SCHEMES:-newton initial-stress initial-stress-stiffness initial-strain initial-strain-stiffness variable-stiffness variable-stiffness/strain}"
formulation="${FORMULATION:-}"
vs_dir="${VS_DIR:-}"
vs_label="newton"; [ -n "$vs_dir" ] && vs_label="$(basename "$vs_dir")"
threads_opt=()
[ -n "${THREADS:-}" ] && threads_opt=(--threads "$THREADS")

[ -x "$bin" ] || { echo "not an executable: $bin" >&2; exit 1; }
if [ "$#" -gt 0 ]; then cases=("$@"); else
  # the issue's findings in order, then any other case folder
  cases=()
  for c in unload-force unload-pressure unload-displacement unload-temperature \
           unload-temperature-wall unload-contact unload-all multilinear-cube heated-bar \
           epp-cylinder epp-cylinder-tet indentation-unload indentation-half; do
    [ -f "$cases_dir/$c/case.yaml" ] && cases+=("$c")
  done
  for d in "$cases_dir"/*/; do
    c="$(basename "$d")"
    [ -f "$d/case.yaml" ] && [[ " ${cases[*]} " != *" $c "* ]] && cases+=("$c")
  done
fi
mkdir -p "$work"
rows="$work/rows.tsv"; : >"$rows"

for c in "${cases[@]}"; do
  src="$cases_dir/$c"
  [ -f "$src/case.yaml" ] || { echo "no case.yaml in $src" >&2; exit 1; }
  grep -Eq '^[[:space:]]*scheme:[[:space:]]*newton[[:space:]]*(#.*)?$' "$src/case.yaml" ||
    { echo "$src/case.yaml: no line 'scheme: newton' to replace" >&2; exit 1; }
  planned="$("$bin" check "$src/case.yaml" 2>/dev/null | sed -n 's/^ *steps: //p')"
  dofs="$("$bin" check "$src/case.yaml" 2>/dev/null | sed -n 's/^ *unknowns: //p')"
  rm -rf "${work:?}/$c"
  for v in $schemes; do
    [ "$formulation" = report ] && [ "$v" = newton ] && continue
    s="${v%%/*}"; form=""; [ "$v" != "$s" ] && form="${v#*/}"
    d="$work/$c/${v//\//-}"; mkdir -p "$d"
    cp -r "$src"/. "$d"/
    if [ -n "$form" ]; then
      sed -E -i "s/^([[:space:]]*)scheme:[[:space:]]*newton[[:space:]]*(#.*)?\$/\1scheme: $s\n\1curve_form: $form/" "$d/case.yaml"
    else
      sed -E -i "s/^([[:space:]]*)scheme:[[:space:]]*newton[[:space:]]*(#.*)?\$/\1scheme: $s/" "$d/case.yaml"
    fi
    [ -n "$formulation" ] &&
      sed -E -i "s/^([[:space:]]*)scheme:[[:space:]]*$s[[:space:]]*\$/&\n\1formulation: $formulation/" "$d/case.yaml"
    t0=$(date +%s.%N)
    timeout "$timeout_s" "$bin" run "$d/case.yaml" -o "$d/out" --quiet "${threads_opt[@]}" >"$d/terminal.txt" 2>&1
    rc=$?
    t1=$(date +%s.%N)
    wall=$(/usr/bin/python3 -c "print(f'{$t1 - $t0:.2f}')")
    ref_out="$work/$c/newton/out"; [ -n "$vs_dir" ] && ref_out="$vs_dir/$c/${v//\//-}/out"
    /usr/bin/python3 - "$c" "$v" "$rc" "$wall" "$d" "$planned" "$dofs" "$ref_out" \
      "$(dirname "$0")/../tests/tools" >>"$rows" <<'EOF'
import csv, json, os, re, sys
case, variant, rc, wall, d, planned, dofs, newton_out, tools = sys.argv[1:]
sys.path.insert(0, tools)
out = os.path.join(d, "out")
summ = {}
try:
    with open(os.path.join(out, "summary.json")) as f:
        summ = json.load(f)
except Exception:
    pass
log = ""
try:
    with open(os.path.join(out, "hencky.log"), errors="replace") as f:
        log = f.read()
except Exception:
    pass
cutbacks = log.count("cutting back")
t_reached, max_pp = "0", 0
try:
    with open(os.path.join(out, "history.csv")) as f:
        for row in csv.DictReader(f):
            t_reached = row["time"]
            max_pp = max(max_pp, int(row.get("plastic_points") or 0))
except Exception:
    pass
failure = summ.get("failure", "")
if not failure and rc not in ("0",):
    with open(os.path.join(d, "terminal.txt"), errors="replace") as f:
        lines = [l.strip() for l in f if l.strip()]
    failure = lines[-1] if lines else ("timeout" if rc == "124" else "")
# a short reason: what follows the last ': ' of the usual message
short = re.sub(r"^step to t = \S+ did not converge after \d+ cut-backs: ", "", failure)
short = short.replace("|", "/")
if len(short) > 110:
    short = short[:107] + "..."
try:
    t_reached = f"{float(t_reached):.6g}"
except ValueError:
    pass

def steps_of(out_dir):
    # the steps' .vtu files of a run that reached the end time, else []
    try:
        with open(os.path.join(out_dir, "summary.json")) as f:
            s = json.load(f)
        if s.get("failure"):
            return []
        return [os.path.join(out_dir, p) for p in
                sorted(p for p in os.listdir(out_dir) if re.fullmatch(r"step_\d+\.vtu", p))]
    except Exception:
        return []


# against newton: the largest difference of the nodal displacement and of the nodal stress at
# the end, each relative to newton's largest value of that field over the run (the end of an
# unloading is near zero stress); both runs on the same mesh, nodes in one order
vs_newton = "-"
a, b = steps_of(newton_out), steps_of(out)
if a and b and os.path.realpath(newton_out) != os.path.realpath(out):
    from compare_results import read_vtu
    import numpy as np
    fa, fb = read_vtu(a[-1]), read_vtu(b[-1])
    # newton's largest values over its run, read from its steps once per case (every variant
    # compares against them)
    cache = os.path.join(newton_out, "largest.json")
    try:
        with open(cache) as f:
            largest = json.load(f)
    except (OSError, ValueError):
        runs = [read_vtu(p) for p in a]
        largest = {n: float(max(np.abs(r[n]).max() for r in runs)) for n in ("displacement", "stress")}
        with open(cache, "w") as f:
            json.dump(largest, f)
    worst = 0.0
    for name, ref in largest.items():
        if ref > 0:
            worst = max(worst, np.abs(fa[name] - fb[name]).max() / ref)
    vs_newton = f"{worst:.1e}"
excess = summ.get("report", {}).get("largest_yield_excess", {}).get("value")
excess = "-" if excess is None else f"{excess:.1e}"
fields = [case, dofs, variant, rc, f"{summ.get('steps', '-')} ({planned})", t_reached,
          str(summ.get("iterations", "-")), str(cutbacks), str(summ.get("factorizations", "-")),
          str(max_pp), wall, short, vs_newton, excess]
print("\t".join(fields))
EOF
    tail -n 1 "$rows" | awk -F'\t' '{printf "%-24s %-26s exit %s  steps %-8s t %-6s it %-5s cb %-2s fact %-5s %ss  vs %s  excess %s  %s\n", $1, $3, $4, $5, $6, $7, $8, $9, $11, $13, $14, $12}' >&2
  done
done

{
  echo "# issue 16: cases x schemes"
  echo
  echo "binary: \`$bin\` ($("$bin" --version 2>&1 | head -n 1)); cases: \`$cases_dir\`;"
  echo "generated $(date -u '+%Y-%m-%d %H:%M UTC') on $(nproc) cores by bench/run_issue16_table.sh; every run on the case's settings"
  echo "(solver defaults except what the case sets), only \`scheme\` (and \`curve_form\`) changed${formulation:+, \`formulation: $formulation\` added}."
  echo
  echo "Columns: exit status (0 converged, 2 not converged, 124 killed after ${timeout_s} s); steps converged"
  echo "(planned steps); last converged time; iterations (all attempts, cut-back attempts included);"
  echo "cut-backs (\"cutting back\" lines of hencky.log); factorizations (summary.json); the largest"
  echo "number of plastic points in a step; wall time of the process; why it stopped; against"
  echo "$vs_label: the largest difference of the nodal displacement and of the nodal stress at the end,"
  echo "each relative to $vs_label's largest value of that field over the run; the largest yield"
  echo "excess σ̃/σ_y − 1 of the run (summary.json report.largest_yield_excess)."
  echo
  echo "| case | unknowns | scheme | exit | steps | t | iterations | cut-backs | factorizations | plastic pts | wall s | stopped because | vs $vs_label | yield excess |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
  awk -F'\t' '{printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14}' "$rows"
  echo
  echo "At a glance: exit status / iterations / cut-backs, one row per case (vs = variable-stiffness)."
  echo
  /usr/bin/python3 - "$rows" <<'GLANCE'
import sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
cases, variants, cell = [], [], {}
for r in rows:
    if r[0] not in cases: cases.append(r[0])
    if r[2] not in variants: variants.append(r[2])
    cell[(r[0], r[2])] = f"{'**' + r[3] + '**' if r[3] != '0' else r[3]} / {r[6]} / {r[7]}"
short = lambda v: v.replace("variable-stiffness", "vs").replace("initial-", "i-")
print("| case | " + " | ".join(short(v) for v in variants) + " |")
print("|---|" + "---|" * len(variants))
for c in cases:
    print(f"| {c} | " + " | ".join(cell.get((c, v), "") for v in variants) + " |")
GLANCE
} >"$md"
echo "wrote $md" >&2
