#!/usr/bin/env bash
# End-to-end tests of the command line: exit statuses, messages and outputs of the contract.
# Usage: run_cli_tests.sh HENCKY_BINARY SOURCE_DIR [only|except CASE...]
#   CASE: names of tests/cli/cases/*.sh without .sh; `only` runs those, `except` all others
#   (ctest runs the suite as two such halves side by side). 05_helpers is always read.
#   HENCKY_CLI_SKIP (environment): case names left out as well.
#   HENCKY_CLI_TIMES (environment): a file to which each command's wall seconds are appended,
#   "seconds<TAB>case<TAB>check" (to find what makes the suite slow).
#   HENCKY_CLI_KEEP (environment): a folder to run in and keep (it must not exist), so that the
#   outputs of two binaries can be compared (tests/tools/compare_trees.py); else a temporary one.
set -u
bin="$1"; src="$2"
part_mode="${3:-}"; part_cases=" ${*:4} "
case "$part_mode" in
  ""|only|except) ;;
  *) echo "run_cli_tests.sh: the third argument is 'only' or 'except', not '$part_mode'" >&2; exit 2 ;;
esac
if [ -n "${HENCKY_CLI_KEEP:-}" ]; then
  mkdir "$HENCKY_CLI_KEEP" || exit 2
  work="$(cd "$HENCKY_CLI_KEEP" && pwd)"
else
  work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fi
pass=0; fail=0
ok()   { pass=$((pass+1)); echo "ok   $1"; }
bad()  { fail=$((fail+1)); echo "FAIL $1"; [ -n "${2:-}" ] && echo "$2" | sed 's/^/     /'; }

# expect_cmd NAME STATUS PATTERN -- COMMAND... : runs the command, checks exit status and that
# the combined output matches the extended regular expression.
expect_cmd() {
  local name="$1" status="$2" pattern="$3"; shift 4
  local out rc t0="${EPOCHREALTIME/./}"
  out="$("$@" 2>&1)"; rc=$?
  if [ -n "${HENCKY_CLI_TIMES:-}" ]; then
    local us=$(( ${EPOCHREALTIME/./} - t0 ))
    printf '%d.%02d\t%s\t%s\n' $((us / 1000000)) $((us % 1000000 / 10000)) "${case_name:-}" "$name" \
      >> "$HENCKY_CLI_TIMES"
  fi
  if [ "$rc" -ne "$status" ]; then bad "$name: exit $rc, expected $status" "$out"; return; fi
  if [ -n "$pattern" ] && ! grep -Eq -- "$pattern" <<<"$out"; then
    bad "$name: output does not match /$pattern/" "$out"; return
  fi
  ok "$name"
}
# expect NAME STATUS PATTERN -- ARGS... : expect_cmd on the hencky binary.
expect() { expect_cmd "$1" "$2" "$3" -- "$bin" "${@:5}"; }

# HENCKY_CLI_SKIP: case files to leave out, by name without .sh ("10_examples 40_parallel"):
# the sanitizer stage of CI leaves out the slowest (scripts/sanitize.sh).
for f in "$src"/tests/cli/cases/*.sh; do
  [ -e "$f" ] || continue
  case_name="$(basename "$f" .sh)"
  if [ "$case_name" != 05_helpers ]; then
    if [ "$part_mode" = only ] && [[ "$part_cases" != *" $case_name "* ]]; then continue; fi
    if [ "$part_mode" = except ] && [[ "$part_cases" == *" $case_name "* ]]; then continue; fi
  fi
  if [[ " ${HENCKY_CLI_SKIP:-} " == *" $case_name "* ]]; then echo "skip $case_name.sh"; continue; fi
  case_t0=$SECONDS
  # shellcheck disable=SC1090
  . "$f"
  echo "# $case_name.sh: $((SECONDS - case_t0)) s"
done

echo "$pass passed, $fail failed"
# No check at all (every case file of this part skipped, or a misspelt CASE): ctest reports the
# test as skipped (SKIP_RETURN_CODE in CMakeLists.txt), not as passed.
if [ $((pass + fail)) -eq 0 ]; then echo "no check was run"; exit 77; fi
[ "$fail" -eq 0 ]
