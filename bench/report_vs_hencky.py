#!/usr/bin/python3
"""The issue-46 table: the issue-16 cases under `formulation: hencky` and `formulation: report`.

    report_vs_hencky.py HENCKY_ROWS.tsv REPORT_ROWS.tsv OUTPUT.md [HEADER_FILE]

The rows are the rows.tsv of bench/run_issue16_table.sh, run once with FORMULATION=hencky and
once with FORMULATION=report VS_DIR=<the hencky WORK_DIR> (so the report rows' "vs" column is
the difference from hencky's run of the same case and variant). HEADER_FILE, if given, is
copied to the top of the output (how it was generated). Standard library only.
"""
import statistics
import sys

VARIANTS = ["variable-stiffness", "variable-stiffness/strain", "initial-strain",
            "initial-strain-stiffness", "initial-stress", "initial-stress-stiffness"]
# fields of a row of run_issue16_table.sh
CASE, DOFS, VAR, RC, STEPS, T, IT, CB, FACT, PP, WALL, WHY, VS, EXCESS = range(14)


def read(path):
    rows = {}
    for line in open(path):
        if line.strip():
            r = line.rstrip("\n").split("\t")
            r += ["-"] * (14 - len(r))
            rows[(r[CASE], r[VAR])] = r
    return rows


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    hencky, report = read(sys.argv[1]), read(sys.argv[2])
    cases = []
    for c, _ in list(hencky) + list(report):
        if c not in cases:
            cases.append(c)
    out = [open(sys.argv[4]).read().rstrip("\n"), ""] if len(sys.argv) > 4 else []

    # at a glance
    n = {"hencky": [0, 0], "report": [0, 0]}
    diffs, bad = [], []
    for c in cases:
        for v in VARIANTS:
            for name, rows in (("hencky", hencky), ("report", report)):
                r = rows.get((c, v))
                if r:
                    n[name][0] += 1
                    n[name][1] += r[RC] == "0"
            r = report.get((c, v))
            if r and r[VS] not in ("-", ""):
                diffs.append((float(r[VS]), c, v))
    out += ["## At a glance", ""]
    for name in ("hencky", "report"):
        out.append(f"- `formulation: {name}`: {n[name][1]} of {n[name][0]} runs reached the end.")
    if diffs:
        d = sorted(x[0] for x in diffs)
        big = [x for x in diffs if x[0] > 1e-6]
        out.append(f"- report vs hencky, the {len(d)} pairs where both reached the end: largest nodal "
                   f"difference (displacement or stress, relative to hencky's largest) median "
                   f"{statistics.median(d):.1e}, range {d[0]:.1e} to {d[-1]:.1e}; above 1e-6: "
                   + (", ".join(f"{c} {v} {x:.1e}" for x, c, v in sorted(big, reverse=True)) or "none") + ".")
    out += ["", "Exit status / iterations / cut-backs per case and variant, hencky → report "
            "(**bold**: not 0; vs = variable-stiffness, i- = initial-):", "",
            "| case | " + " | ".join(v.replace("variable-stiffness", "vs").replace("initial-", "i-")
                                  for v in VARIANTS) + " |",
            "|---|" + "---|" * len(VARIANTS)]

    def cell(r):
        if not r:
            return ""
        rc = r[RC] if r[RC] == "0" else f"**{r[RC]}**"
        return f"{rc}/{r[IT]}/{r[CB]}"
    for c in cases:
        out.append(f"| {c} | " + " | ".join(f"{cell(hencky.get((c, v)))} → {cell(report.get((c, v)))}"
                                          for v in VARIANTS) + " |")

    out += ["", "## Every run", "",
            "Columns: exit status (0 reached the end, 1 input refused, 2 not converged, 124 killed by the "
            "timeout); steps converged (planned; cut-back steps count); iterations (all attempts); cut-backs; "
            "wall time of the process; why it stopped; report vs hencky (on the report row): the largest "
            "difference of the final nodal displacement and of the final nodal stress, each relative to "
            "hencky's largest value of that field over its run, where both reached the end; yield excess: "
            "summary.json report.largest_yield_excess.value (largest σ̃/σ_y − 1 over the run).", "",
            "| case | unknowns | scheme | formulation | exit | steps | iterations | cut-backs | wall s | "
            "stopped because | report vs hencky | yield excess |",
            "|---|---:|---|---|---:|---:|---:|---:|---:|---|---:|---:|"]
    for c in cases:
        for v in VARIANTS:
            for name, rows in (("hencky", hencky), ("report", report)):
                r = rows.get((c, v))
                if not r:
                    continue
                vs = r[VS] if name == "report" else ""
                out.append(f"| {c} | {r[DOFS]} | {v} | {name} | {r[RC]} | {r[STEPS]} | {r[IT]} | {r[CB]} | "
                           f"{r[WALL]} | {r[WHY]} | {vs} | {r[EXCESS]} |")
    open(sys.argv[3], "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
