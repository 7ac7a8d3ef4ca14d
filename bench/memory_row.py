"""One row of a per-rank memory table from a run's summary.json (bench/run_*_memory.sh).

    memory_row.py SUMMARY STATUS T0 T1 COLUMNS LABEL...

LABEL...: the row's first cells; STATUS: the run's exit status; T0, T1: its start and end
(seconds); COLUMNS: the summary's figures after them, comma-separated, from: wall, largest
(MiB of the largest rank), all (MiB over the ranks), iterations, dofs. A run without a
summary gets dashes.
"""
import json
import sys

summary, status, t0, t1, columns, *labels = sys.argv[1:]
columns = columns.split(",")
try:
    s = json.load(open(summary))
except OSError:
    print("| " + " | ".join(labels + [status] + ["–"] * len(columns)) + " |")
    sys.exit()
mib = 2.0 ** 20
value = {
    "wall": lambda: f"{float(t1) - float(t0):.1f}",
    "largest": lambda: f"{s['peak_memory_bytes'] / mib:.0f}",
    "all": lambda: f"{s.get('peak_memory_bytes_all_ranks', s['peak_memory_bytes']) / mib:.0f}",
    "iterations": lambda: str(s["iterations"]),
    "dofs": lambda: str(s["dofs"]),
}
print("| " + " | ".join(labels + [status] + [value[c]() for c in columns]) + " |")
