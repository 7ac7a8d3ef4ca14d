#!/usr/bin/python3
"""Two WORK_DIRs of bench/run_issue16_table.sh, run by run: are the outputs byte-identical?

    cmp_issue16_runs.py BEFORE_DIR AFTER_DIR

For every BEFORE_DIR/<case>/<variant>/out (and the same folder under AFTER_DIR) compares
history.csv and every step_*.vtu byte for byte (as `cmp`; the sets of step files must be the
same too); summary.json, hencky.log and checkpoints/ are not compared (timings). Prints one line
per run: "same" or what differs, and for a run that differs the iterations before/after
(summary.json "iterations") and the largest difference of the final nodal displacement and
stress, each relative to BEFORE's largest value of that field over its run (the "vs" column of
run_issue16_table.sh), when both runs wrote steps. Standard library + numpy.
"""
import filecmp
import json
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../tests/tools"))


def steps(out):
    try:
        return sorted(p for p in os.listdir(out) if re.fullmatch(r"step_\d+\.vtu", p))
    except OSError:
        return []


def iterations(out):
    try:
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        return s.get("iterations", "-"), s.get("failure", "")
    except (OSError, ValueError):
        return "-", "no summary.json"


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    before, after = sys.argv[1:]
    n_same = n_diff = n_none = 0
    for case in sorted(os.listdir(before)):
        cdir = os.path.join(before, case)
        if not os.path.isdir(cdir):
            continue
        for variant in sorted(os.listdir(cdir)):
            a, b = os.path.join(cdir, variant, "out"), os.path.join(after, case, variant, "out")
            what = []
            ha, hb = os.path.join(a, "history.csv"), os.path.join(b, "history.csv")
            if os.path.exists(ha) != os.path.exists(hb):
                what.append("history.csv present in one only")
            elif os.path.exists(ha) and not filecmp.cmp(ha, hb, shallow=False):
                what.append("history.csv")
            sa, sb = steps(a), steps(b)
            if sa != sb:
                what.append(f"steps {len(sa)} vs {len(sb)} files")
            bad = [p for p in sa if p in sb and not filecmp.cmp(os.path.join(a, p), os.path.join(b, p), shallow=False)]
            if bad:
                what.append(f"{len(bad)} of {len(sa)} step files ({bad[0]} first)")
            name = f"{case}/{variant}"
            if not what and not sa and not os.path.exists(ha):
                n_none += 1
                print(f"{name}: no outputs in either (the run wrote neither history.csv nor steps)")
                continue
            if not what:
                n_same += 1
                print(f"{name}: same (history.csv + {len(sa)} step files)")
                continue
            n_diff += 1
            (ia, fa_), (ib, fb_) = iterations(a), iterations(b)
            line = f"{name}: DIFFERS: {'; '.join(what)}; iterations {ia} -> {ib}"
            if fa_ or fb_:
                line += f"; failure before: {fa_!r}, after: {fb_!r}"
            if sa and sb:
                import numpy as np
                from compare_results import read_vtu
                runs = [read_vtu(os.path.join(a, p)) for p in sa]
                last_b = read_vtu(os.path.join(b, sb[-1]))
                parts = []
                for field in ("displacement", "stress"):
                    ref = max(np.abs(r[field]).max() for r in runs)
                    d = np.abs(runs[-1][field] - last_b[field]).max()
                    parts.append(f"{field} {d / ref if ref > 0 else d:.1e}")
                line += "; final fields, largest difference / before's largest: " + ", ".join(parts)
            print(line)
    print(f"{n_same} runs byte-identical, {n_diff} differ, {n_none} without outputs in either")


if __name__ == "__main__":
    main()
