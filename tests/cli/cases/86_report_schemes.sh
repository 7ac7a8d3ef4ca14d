# Sourced by run_cli_tests.sh ($bin, $src, $work, expect, ok, bad; helpers in 05_helpers.sh).
# solver.formulation: report (issue 46): the five schemes iterate as the report writes them.
# One hexahedron with every degree of freedom prescribed is one material point; its iterates
# (output.iterations: iterations.csv) are compared with an independent program written from
# the report's equations (tests/tools/report_schemes.py): every iterate's measures, stress and
# eps~ to 1e-12 for the first five iterations of each step and at its last, on four strain
# paths (proportional with unloading, turning as NAFEMS NL1, first yield deep in a step, and
# the temperature rising during every step) for each scheme and both forms of scheme 1.

rs="$src/tests/tools/report_schemes.py"
d="$work/report_schemes"
mkdir -p "$d"
cp "$src/tests/cli/inputs/nl1/cube.geo" "$d/"
# The log lines of hencky's additions, none of which may appear under report.
additions='held|Anderson|mixing|line search|begins again|released|goes on, up to|extrapolat|elastic start|stress form|3G'
for path in proportional turning deep thermal; do
  for v in variable-stiffness variable-stiffness-strain initial-strain initial-strain-stiffness \
           initial-stress initial-stress-stiffness; do
    c="$d/$path-$v"
    "$ex_py" "$rs" case "$path" "$v" > "$c.yaml"
    # The strain form's secant iteration (2.34) diverges at a first yield early in a step with
    # the strain held (its factor 1 - tan b*/tan b is below -1): the reference and hencky stop
    # at the same iterate of step 2 (status 2).
    status=0
    [ "$v" = variable-stiffness-strain ] && [ "$path" != deep ] && status=2
    "$bin" run "$c.yaml" --quiet -o "$c.out" > "$c.run.txt" 2>&1
    rc=$?
    if [ "$rc" -ne "$status" ]; then
      bad "report: $path, $v: exit $rc, expected $status" "$(tail -5 "$c.run.txt")"
      continue
    fi
    if out="$("$ex_py" "$rs" compare "$path" "$v" "$c.out/iterations.csv" 2>&1)"; then
      ok "report: $path, $v: every iterate as the report's equations give it ($(tail -1 <<<"$out" | sed 's/.*: //'))"
    else
      bad "report: $path, $v: hencky's iterates differ from the reference" "$out"
    fi
    # The log's paths left out first: the run's folder is a random temporary name, which once
    # held "3g" (tmp.njQYx3g6iG) and matched, case-insensitively, the pattern of the 3G line.
    if sed "s|$work|WORK|g" "$c.out/hencky.log" | grep -Eiq -- "$additions"; then
      bad "report: $path, $v: the log shows one of hencky's additions" \
        "$(sed "s|$work|WORK|g" "$c.out/hencky.log" | grep -Ei -- "$additions" | head -3)"
    else
      ok "report: $path, $v: no line of hencky's additions in the log"
    fi
  done
done

# The defaults' answer differs from the report's where the path turns: the report's Z(t)
# (2.10) keeps the step's stress across Z elastic (NL1's kind of path, 1/3 of the leg a step).
c="$d/turning-hencky"
sed -e 's/^  formulation: report$/  formulation: hencky/' -e '/^  relaxation:/d' \
  "$d/turning-initial-stress.yaml" > "$c.yaml"
"$bin" run "$c.yaml" --quiet -o "$c.out" > /dev/null 2>&1
ex_check "report: on the turning path the report's answer differs from hencky's (von Mises at t = 2 by more than 1 %)" \
  "$d/turning-initial-stress.out/history.csv" \
  "abs(at(2)['c.von_mises'] / [float(r['c.von_mises']) for r in __import__('csv').DictReader(open('$c.out/history.csv')) if abs(float(r['time']) - 2) < 1e-9][0] - 1) > 0.01"

# ... and the report's map leaves its points above the yield surface there: the log says so at
# every such step and the summary gives the largest excess (measured: 31 % in the first step
# of the shear leg).
if grep -q "the report's map leaves [0-9]* points above their yield stress" \
     "$d/turning-initial-stress.out/hencky.log"; then
  ok "report: the log says where the report's map leaves points above the yield stress"
else bad "report: no line about points above the yield stress on the turning path"; fi
ex_check "report: on the turning path the largest yield excess is above 1e-3 (the report's Z(t))" \
  "$d/turning-initial-stress.out/summary.json" \
  "s['report']['largest_yield_excess']['value'] > 1e-3 and s['formulation'] == 'report'"

# A report run restarts as it ran: ε̃^{e+p} and its largest value, the report's state, are in the
# checkpoints.
c="$d/turning-initial-strain"
restart_same "report: turning, initial-strain" "$c.yaml" "$c.out" 1 step_0009.vtu

# Settings that would add one of hencky's strategies are refused by name.
refuse() {  # refuse NAME SED-EXPRESSION PATTERN
  local c="$d/refuse-$1"
  sed -E "$2" "$d/proportional-initial-strain.yaml" > "$c.yaml"
  expect "report: $1 is refused" 1 "$3" -- check "$c.yaml"
}
refuse newton 's/scheme: initial-strain/scheme: newton/' \
  "solver.scheme.*newton, hencky's reference scheme, is not one of them.*formulation: hencky"
refuse anderson 's/^(  relaxation: .*)$/\1\n  acceleration: anderson/' \
  "solver.acceleration.*without Anderson's mixing"
refuse "line search" 's/^(  relaxation: .*)$/\1\n  line_search: auto/' \
  "solver.line_search.*without a line search"
refuse "automatic relaxation" 's/^  relaxation: .*$/  relaxation: auto/' \
  "solver.relaxation.*give ω as a number"
refuse "updated geometry" 's/^(  relaxation: .*)$/\1\n  geometry: updated/' \
  "solver.geometry.*not implemented"
refuse "a misspelt formulation" 's/formulation: report/formulation: reprot/' \
  "formulation.*report"
