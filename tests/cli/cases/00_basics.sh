# Sourced by run_cli_tests.sh: $bin, $src, $work, expect, ok, bad are defined.
expect "version" 0 "^hencky [0-9]+\.[0-9]+\.[0-9]+" -- --version
expect "no subcommand" 1 "" --
expect "missing case file" 1 "no-such-case.yaml" -- run "$work/no-such-case.yaml"
