#!/usr/bin/python3
"""NAFEMS NL1 (tests/cli/inputs/nl1): the error of the probe's stress against the exact answer,
per scheme and formulation, as the steps halve (issue 46).

    report_nl1_order.py HENCKY_BINARY WORK_DIR OUTPUT.md [--table-only]

Runs, one at a time, every combination of
  material   hardening (`linear: {yield: 5e6, hardening: 62.5e9}` in place of the case's
             `perfect: {yield: 5e6}`) and perfect (the case as it is; only the stress-form
             schemes: the strain-form ones need a hardening curve)
  formulation report (`formulation: report`; the initial strains with `relaxation: 0.3`: with
             the report's default ω = 1 they diverge under the held strain) and hencky (the
             default, nothing added: hencky's own defaults, newton too)
  scheme     variable-stiffness (stress and strain form), initial-strain(-stiffness),
             initial-stress(-stiffness), newton (hencky only)
  steps      solver.steps 10 20 40 80 160 320 (end 8)
into WORK_DIR/<material>/<formulation>/<variant>/<steps>/ (out/ = the results), then writes the
table: the largest error of sigma_xx, sigma_yy, sigma_zz of the probe `centre` at t = 2, 4, 6, 8
against tests/tools/nl1_reference.py (run with 62.5e9 for the hardening variant), relative to
sigma_y = 5e6; at 10 steps (dt = 0.8) only t = 4 and 8 are step ends, so that error, and the
order 10 -> 20, are on t = 4, 8 only. Order: log2 of the ratio of successive errors.
--table-only re-reads WORK_DIR without running. Environment: TIMEOUT (s per run, default 150),
THREADS (--threads, default 1). Standard library only (+ the reference, which uses numpy).
"""
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CASE = os.path.join(ROOT, "tests/cli/inputs/nl1")
REFERENCE = os.path.join(ROOT, "tests/tools/nl1_reference.py")
SIGMA_Y = 5e6
STEPS = [10, 20, 40, 80, 160, 320]
TIMES = [2, 4, 6, 8]
MATERIALS = {"hardening": "{linear: {yield: 5e6, hardening: 62.5e9}}", "perfect": None}
HARDENING = {"hardening": "62.5e9", "perfect": None}
STRESS_FORM = ["variable-stiffness", "initial-stress", "initial-stress-stiffness"]
ALL = ["variable-stiffness", "variable-stiffness/strain", "initial-strain",
       "initial-strain-stiffness", "initial-stress", "initial-stress-stiffness"]


def variants(material, formulation):
    v = ALL if material == "hardening" else STRESS_FORM
    return v + (["newton"] if formulation == "hencky" else [])


def case_text(material, formulation, variant, steps):
    text = open(os.path.join(CASE, "case.yaml")).read()
    if MATERIALS[material]:
        text = text.replace("{perfect: {yield: 5e6}}", MATERIALS[material])
    scheme, _, form = variant.partition("/")
    lines = [f"  scheme: {scheme}"]
    if formulation == "report":
        lines.append("  formulation: report")
        if scheme.startswith("initial-strain"):
            lines.append("  relaxation: 0.3")
    if form:
        lines.append(f"  curve_form: {form}")
    text, n = re.subn(r"(?m)^  scheme: newton$", "\n".join(lines), text)
    assert n == 1
    text, n = re.subn(r"(?m)^  steps: 80$", f"  steps: {steps}", text)
    assert n == 1
    return text


def run_all(binary, work, timeout, threads):
    for material in MATERIALS:
        for formulation in ("report", "hencky"):
            for variant in variants(material, formulation):
                for steps in STEPS:
                    d = os.path.join(work, material, formulation, variant.replace("/", "-"), str(steps))
                    shutil.rmtree(d, ignore_errors=True)
                    os.makedirs(d)
                    shutil.copy(os.path.join(CASE, "cube.geo"), d)
                    with open(os.path.join(d, "case.yaml"), "w") as f:
                        f.write(case_text(material, formulation, variant, steps))
                    t0 = time.monotonic()
                    with open(os.path.join(d, "terminal.txt"), "w") as term:
                        try:
                            rc = subprocess.run([binary, "run", os.path.join(d, "case.yaml"), "-o",
                                                 os.path.join(d, "out"), "--quiet", "--threads",
                                                 str(threads)], stdout=term, stderr=term,
                                                timeout=timeout).returncode
                        except subprocess.TimeoutExpired:
                            rc = 124
                    wall = time.monotonic() - t0
                    with open(os.path.join(d, "run.json"), "w") as f:
                        json.dump({"rc": rc, "wall": wall}, f)
                    print(f"{material:9s} {formulation:6s} {variant:26s} {steps:4d}  exit {rc}  "
                          f"{wall:.2f}s", file=sys.stderr, flush=True)


def reference(material):
    args = ["/usr/bin/python3", REFERENCE] + ([HARDENING[material]] if HARDENING[material] else [])
    ref = {}
    for line in subprocess.run(args, capture_output=True, text=True, check=True).stdout.split("\n"):
        if line.strip():
            v = line.split()
            ref[int(float(v[0]))] = [float(x) for x in v[1:5]]  # von Mises, sxx, syy, szz
    return ref


def result(d, ref):
    """exit, stop reason, iterations, yield excess, {t: largest component error / sigma_y}."""
    r = {"rc": None, "why": "", "iterations": "-", "excess": None, "err": {}, "vm": {}}
    try:
        r["rc"] = json.load(open(os.path.join(d, "run.json")))["rc"]
    except (OSError, ValueError):
        return r
    try:
        s = json.load(open(os.path.join(d, "out", "summary.json")))
        r["why"] = s.get("failure", "")
        r["iterations"] = s.get("iterations", "-")
        r["excess"] = s.get("report", {}).get("largest_yield_excess", {}).get("value")
    except (OSError, ValueError):
        pass
    if r["rc"] not in (0, None) and not r["why"]:
        lines = [l.strip() for l in open(os.path.join(d, "terminal.txt"), errors="replace") if l.strip()]
        r["why"] = lines[-1] if lines else ("timeout" if r["rc"] == 124 else "")
    r["why"] = re.sub(r"^step to t = (\S+) did not converge after (\d+) cut-backs: ",
                      r"t = \1, \2 cut-backs: ", r["why"]).replace("|", "/")
    try:
        with open(os.path.join(d, "out", "history.csv")) as f:
            for row in csv.DictReader(f):
                t = float(row["time"])
                for T in TIMES:
                    if abs(t - T) < 1e-9:
                        got = [float(row[f"centre.stress.{c}"]) for c in ("xx", "yy", "zz")]
                        r["err"][T] = max(abs(g - e) for g, e in zip(got, ref[T][1:])) / SIGMA_Y
                        r["vm"][T] = abs(float(row["centre.von_mises"]) - ref[T][0]) / SIGMA_Y
    except (OSError, ValueError, KeyError):
        pass
    return r


def largest(r, times):
    if not all(t in r["err"] for t in times):
        return None
    return max(r["err"][t] for t in times)


def fmt(x, f="{:.2e}"):
    return "-" if x is None else f.format(x)


def table(work, md, binary, header):
    out = [header]
    summary = {}
    for material in MATERIALS:
        ref = reference(material)
        out += [f"## {material} ({'plastic modulus 62.5 GPa' if material == 'hardening' else 'perfectly plastic'})",
                "",
                "Reference (nl1_reference.py" + (f" {HARDENING[material]}" if HARDENING[material] else "")
                + "), Pa: " + "; ".join(f"t = {t}: sxx {ref[t][1]:.6e}, syy {ref[t][2]:.6e}, szz {ref[t][3]:.6e}"
                                       for t in TIMES), ""]
        rows = {}
        for formulation in ("report", "hencky"):
            for variant in variants(material, formulation):
                rows[(formulation, variant)] = [
                    result(os.path.join(work, material, formulation, variant.replace("/", "-"), str(n)), ref)
                    for n in STEPS]
        out += ["Largest error of the stress components at t = 2, 4, 6, 8, relative to sigma_y "
                "(10 steps: t = 4, 8 only); a run that stopped early shows its exit status.", "",
                "| formulation | scheme | " + " | ".join(f"{n} steps" for n in STEPS) + " | "
                + " | ".join(f"order {a}->{b}" for a, b in zip(STEPS, STEPS[1:])) + " |",
                "|---|---|" + "---:|" * (2 * len(STEPS) - 1)]
        for (formulation, variant), rs in rows.items():
            errs = [largest(r, [4, 8] if n == 10 else TIMES) for r, n in zip(rs, STEPS)]
            cells = [fmt(e) if r["rc"] == 0 else f"exit {r['rc']}" for e, r in zip(errs, rs)]
            orders = []
            for i in range(len(STEPS) - 1):
                ts = [4, 8] if i == 0 else TIMES
                a, b = largest(rs[i], ts), largest(rs[i + 1], ts)
                ok = rs[i]["rc"] == 0 and rs[i + 1]["rc"] == 0 and a and b
                orders.append(f"{math.log2(a / b):.2f}" if ok else "-")
            summary[(material, formulation, variant)] = (errs, orders, rs)
            out.append(f"| {formulation} | {variant} | " + " | ".join(cells) + " | " + " | ".join(orders) + " |")
        out += ["", "Largest yield excess sigma~/sigma_y - 1 of each run (summary.json "
                "report.largest_yield_excess.value) / iterations of the run:", "",
                "| formulation | scheme | " + " | ".join(f"{n} steps" for n in STEPS) + " |",
                "|---|---|" + "---:|" * len(STEPS)]
        for (formulation, variant), rs in rows.items():
            out.append(f"| {formulation} | {variant} | "
                       + " | ".join(f"{fmt(r['excess'], '{:.1e}')} / {r['iterations']}" for r in rs) + " |")
        out += ["", "Error at each time (largest component error / sigma_y at t = 2, 4, 6, 8; "
                "von Mises error at t = 8 in brackets):", "",
                "| formulation | scheme | " + " | ".join(f"{n} steps" for n in STEPS) + " |",
                "|---|---|" + "---|" * len(STEPS)]
        for (formulation, variant), rs in rows.items():
            out.append(f"| {formulation} | {variant} | " + " | ".join(
                " ".join(fmt(r["err"].get(t), "{:.1e}") for t in TIMES) + f" ({fmt(r['vm'].get(8), '{:.1e}')})"
                for r in rs) + " |")
        failed = [(f, v, n, r) for (f, v), rs in rows.items() for n, r in zip(STEPS, rs) if r["rc"] != 0]
        if failed:
            out += ["", "Runs that did not reach t = 8:", ""]
            out += [f"- {f} {v}, {n} steps: exit {r['rc']}: {r['why']}" for f, v, n, r in failed]
        out.append("")
    with open(md, "w") as f:
        f.write("\n".join(out) + "\n")
    return summary


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 3:
        sys.exit(__doc__)
    binary, work, md = os.path.abspath(args[0]), os.path.abspath(args[1]), args[2]
    timeout, threads = float(os.environ.get("TIMEOUT", 150)), int(os.environ.get("THREADS", 1))
    if "--table-only" not in sys.argv:
        run_all(binary, work, timeout, threads)
    version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.strip()
    date = subprocess.run(["date", "-u"], capture_output=True, text=True).stdout.strip()
    header = "\n".join([
        "# issue 46: NAFEMS NL1, the error of the stress and its order as the steps halve", "",
        f"Generated by `/usr/bin/python3 bench/report_nl1_order.py {args[0]} {args[1]} {md}` "
        f"(TIMEOUT={timeout:g}, THREADS={threads}); binary `{binary}` ({version}); {date}; "
        f"machine: {os.cpu_count()} cores (nproc), shared with another process, runs one at a time.", "",
        "Case: tests/cli/inputs/nl1/case.yaml (one 8-node hexahedron, every dof prescribed, end 8), "
        "solver.steps set to 10 ... 320. `report`: `formulation: report` added, the initial strains "
        "with `relaxation: 0.3`; `hencky`: the case's settings, hencky's defaults, only `scheme` "
        "(and `curve_form`) changed. The error is the largest |sigma_ij - exact| over "
        "xx, yy, zz of the probe `centre` (history.csv) at t = 2, 4, 6, 8, over sigma_y = 5e6; "
        "exact: tests/tools/nl1_reference.py.", ""])
    table(work, md, binary, header)
    print(f"wrote {md}", file=sys.stderr)


if __name__ == "__main__":
    main()
