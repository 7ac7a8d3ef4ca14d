#!/usr/bin/python3
"""hencky performance benchmark: hencky vs CalculiX on the same quadratic tetrahedral meshes.

Two linear-elastic problems with closed-form answers, meshed once by Gmsh (10-node tetrahedra)
at increasing sizes; the very same .msh is solved by hencky and, converted to an .inp, by
CalculiX (ccx). For every size it records hencky's phase times (summary.json), the end-to-end
wall time and peak memory of both programs (/usr/bin/time -v), the accuracy of both against
the closed form, and the flop rate of CHOLMOD's factorization next to the machine's dense
matrix-multiply rate (numpy, same OpenBLAS) and one core's memory bandwidth (numpy triad). hencky
runs with its default `solver.linear: auto`; --compare runs the solvers it chooses between as
well, for the table of its choice.

    /usr/bin/python3 bench/run_bench.py                    # default sizes, up to ~400k unknowns
    /usr/bin/python3 bench/run_bench.py --compare direct,petsc  # and both solvers auto chooses from
    /usr/bin/python3 bench/run_bench.py --max-dofs 1100000 # add the ~1M size
    /usr/bin/python3 bench/run_bench.py --help

Results: bench/results/<timestamp>.json and .md; --write-docs regenerates the generated part of
docs/performance.md (the text outside the GENERATED markers is kept).
Standard library + numpy only.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
from pathlib import Path

from henckybench import BENCH, ROOT, calculix, gmsh, problems, report, runner
from henckybench.problems import PROBLEMS
from henckybench.report import fmt_s, mib
from henckybench.runs import probe_value

LINEAR = ("auto", "direct", "iterative", "petsc")


# ----------------------------------------------------------------------------------------------
# Benchmark
# ----------------------------------------------------------------------------------------------
def bench_one(problem, target, args, work, exe, linear=None, compare=False) -> dict:
    """One problem at one size with solver.linear = `linear` (default args.linear). `compare`:
    a --compare run, once, without ccx."""
    linear = linear or args.linear
    spec = PROBLEMS[problem]
    msh, gmsh_seconds, h = gmsh.size_for(problem, target, work, args.threads)
    run_dir = gmsh.mesh_run_dir(msh, work)
    local_msh = run_dir / msh.name
    case = run_dir / ("case.yaml" if linear == "direct" else f"case-{linear}.yaml")
    case.write_text(problems.elastic_case(problem, local_msh, linear))
    exact = spec["exact"]()
    comp, sign = spec["sign"]
    row = dict(problem=problem, target_dofs=target, linear=linear, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds,
               exact=exact, reference=spec["reference"], quantity=spec["quantity"])
    print(f"[{problem} ~{target / 1000:.0f}k, linear: {linear}] h = {h:g}: {msh.name}", flush=True)

    ccx_ok = (not compare and not args.no_ccx and shutil.which("ccx")
              and (args.ccx_max_dofs <= 0 or target <= args.ccx_max_dofs))
    inp_info = None
    if ccx_ok:
        t0 = time.perf_counter()
        mesh = gmsh.read_msh4(msh)
        inp_info = calculix.write_elastic_inp(problem, mesh, run_dir / "job.inp", args.ccx_solver)
        row["ccx_solver"] = args.ccx_solver
        row["ccx_input"] = dict(inp_info, convert_seconds=time.perf_counter() - t0,
                                elements=int(len(mesh["tets"])), nodes=int(len(mesh["node_tags"])))
        del mesh

    hencky_runs, ccx_runs = [], []
    repeats = 1 if compare else max(1, args.repeat)
    k = 0
    while k < repeats:
        runner.quiet(args)
        r = runner.run_hencky(exe, case, run_dir / "hencky.out", args.threads, getattr(args, "hencky_environ", None))
        hencky_runs.append(r)
        s = r["summary"]
        print(f"    hencky  {s['dofs']:>8d} dofs  wall {r['wall']:7.2f} s  peak {r['peak_rss'] / 2**20:7.0f} MiB"
              f"  (mesh {s['wall_seconds']['mesh']:.2f}, setup {s['wall_seconds']['setup']:.2f},"
              f" assembly {s['wall_seconds']['assembly']:.2f}, factor {s['wall_seconds']['factorization']:.2f},"
              f" solve {s['wall_seconds']['solve']:.2f}, output {s['wall_seconds']['output']:.2f});"
              f" others {r['others']:.2f} cores", flush=True)
        if ccx_ok:
            if args.wait_quiet > 0:
                runner.wait_quiet(args.wait_quiet)
            c = calculix.run_ccx(run_dir, "job", args.threads)
            c["u"] = calculix.parse_ccx_dat(run_dir / "job.dat", inp_info["probe_node"])
            ccx_runs.append(c)
            print(f"    ccx              wall {c['wall']:7.2f} s  peak {c['peak_rss'] / 2**20:7.0f} MiB"
                  f"  SPOOLES on {c['cpus'].get('spooles', '?')} threads; others {c['others']:.2f} cores", flush=True)
        k += 1
        slowest = max([r["wall"]] + ([c["wall"]] if ccx_ok else []))
        if k == 1 and slowest > args.repeat_below and not compare:
            repeats = max(1, args.repeat_large)  # large sizes: fewer runs
    # Runs during which other programs took more than --disturbed cores are left out of the
    # statistics when at least one undisturbed run exists (all runs are kept in *_all).
    hencky_all, ccx_all = hencky_runs, ccx_runs
    hencky_runs, ccx_runs = runner.undisturbed(hencky_all, args.disturbed), runner.undisturbed(ccx_all, args.disturbed)
    s = hencky_runs[-1]["summary"]
    value_h = probe_value(problem, s)
    phases = ("mesh", "setup", "assembly", "factorization", "solve", "material", "output", "total")
    row["hencky"] = dict(
        runs=len(hencky_runs),
        dofs=s["dofs"], nodes=s["nodes"], elements=s["elements"],
        wall=runner.median([r["wall"] for r in hencky_runs]),
        wall_all=[r["wall"] for r in hencky_all],
        others_all=[r["others"] for r in hencky_all],
        cpu=runner.median([r["cpu"] for r in hencky_runs]),
        peak_rss=runner.median([r["peak_rss"] for r in hencky_runs]),
        peak_memory_bytes=runner.median([r["summary"]["peak_memory_bytes"] for r in hencky_runs]),
        phases={p: runner.median([r["summary"]["wall_seconds"][p] for r in hencky_runs]) for p in phases},
        factor_flops=s["linear_solver"]["factor_flops"],
        factor_nonzeros=s["linear_solver"].get("factor_nonzeros"),
        matrix_nonzeros=s["linear_solver"].get("matrix_nonzeros"),
        factor_gflops=runner.median([r["summary"]["linear_solver"].get("factor_gflops_per_second") for r in hencky_runs]),
        method=s["linear_solver"]["method"],
        iterations=s["linear_solver"].get("iterations"),
        threads=s.get("threads"),
        load=runner.median([r["load_before"] for r in hencky_runs]),
        others=runner.median([r["others"] for r in hencky_runs]),
        value=value_h,
        error=(value_h - exact) / exact,
    )
    if ccx_runs:
        value_c = sign * ccx_runs[-1]["u"][comp]
        row["ccx"] = dict(
            runs=len(ccx_runs),
            wall=runner.median([c["wall"] for c in ccx_runs]),
            wall_all=[c["wall"] for c in ccx_all],
            others_all=[c["others"] for c in ccx_all],
            cpu=runner.median([c["cpu"] for c in ccx_runs]),
            peak_rss=runner.median([c["peak_rss"] for c in ccx_runs]),
            reported_seconds=runner.median([c["ccx_reported_seconds"] for c in ccx_runs]),
            cpus=ccx_runs[-1]["cpus"],
            solver=ccx_runs[-1]["solver"],
            phases={k: runner.median([c["phases"].get(k) for c in ccx_runs])
                    for k in ("input_structure", "assembly", "factor_solve", "stress_output")},
            load=runner.median([c["load_before"] for c in ccx_runs]),
            others=runner.median([c["others"] for c in ccx_runs]),
            value=value_c,
            error=(value_c - exact) / exact,
        )
        row["ratio"] = dict(
            time=row["ccx"]["wall"] / row["hencky"]["wall"],            # > 1: hencky faster
            memory=row["hencky"]["peak_rss"] / row["ccx"]["peak_rss"],  # < 1: hencky smaller
            hencky_vs_ccx=(value_h - value_c) / value_c,
        )
        print(f"    speed-up {row['ratio']['time']:.2f}x, memory {row['ratio']['memory']:.2f}, "
              f"errors hencky {row['hencky']['error']:+.3e} ccx {row['ccx']['error']:+.3e}", flush=True)
    if not args.keep_output:
        shutil.rmtree(run_dir / "hencky.out", ignore_errors=True)
        for ext in (".frd",):
            (run_dir / ("job" + ext)).unlink(missing_ok=True)
    return row


# ----------------------------------------------------------------------------------------------
# Reports
# ----------------------------------------------------------------------------------------------
def solver_name(h: dict) -> str:
    m = h.get("method", "")
    return "CHOLMOD" if "CHOLMOD" in m else "CG + GAMG" if "gamg" in m else m


# Fine-level matrix products per CG + GAMG iteration: CG's own, two Chebyshev steps before and two
# after the coarse correction, and the residual passed down (PETSc's V-cycle defaults).
PRODUCTS_PER_ITERATION = 6


def physical_limit(h: dict, blas: dict) -> float | None:
    """The time the solver's own work would take at the machine's measured rates: a
    factorization's flops at dgemm's rate on all cores; CG + GAMG's iterations as
    PRODUCTS_PER_ITERATION fine-level products, each streaming the matrix (8-byte value +
    4-byte column index per entry) at one core's triad bandwidth (coarser levels, vectors and
    the set-up left out: a lower bound)."""
    if "CHOLMOD" in h.get("method", "") and h.get("factor_flops"):
        return h["factor_flops"] / (blas["gflops_all"] * 1e9)
    if "gamg" in h.get("method", "") and h.get("matrix_nonzeros") and blas.get("stream_1"):
        return h["iterations"] * PRODUCTS_PER_ITERATION * h["matrix_nonzeros"] * 12 / (blas["stream_1"] * 1e9)
    return None


def choice_table(rows: dict, blas: dict) -> str:
    """solver.linear: auto against both solvers it chooses between, on the same mesh."""
    out = ["### `solver.linear: auto` against both solvers\n",
           "The same mesh solved with `linear: direct` (CHOLMOD, 2 threads) and `linear: petsc` "
           "(CG + GAMG, one process), one run each, beside the default `auto`. `Mflop/unknown`: "
           "the factorization's flops per unknown, which auto predicts from 150,000 unknowns "
           "on and compares with its crossover, 3.6 × (unknowns / 100k)^0.4 (it also takes CG + "
           "GAMG when the factor would need more than 70 % of the memory available). Physical limit: the factorization's flops "
           "at dgemm's rate (all cores); CG's iterations at 6 fine-level matrix products each, "
           "streamed at one core's triad bandwidth (a lower bound).\n",
           "| problem | unknowns | Mflop/unknown | direct s | direct MiB | direct limit s | CG + GAMG s | CG MiB | CG iterations | CG limit s | faster | auto chose | auto s |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|"]
    keys = sorted({(p, t) for (p, t, lin) in rows}, key=lambda k: (k[0], k[1]))
    n = 0
    for p, t in keys:
        d, g, a = rows.get((p, t, "direct")), rows.get((p, t, "petsc")), rows.get((p, t, "auto"))
        if not (d and g):
            continue
        dh, gh = d["hencky"], g["hencky"]
        fast = "direct" if dh["wall"] <= gh["wall"] else "CG + GAMG"
        lim_d, lim_g = physical_limit(dh, blas), physical_limit(gh, blas)
        out.append(f"| {p} | {dh['dofs']:,} | {dh['factor_flops'] / dh['dofs'] / 1e6:.2f} | {fmt_s(dh['wall'])} | "
                   f"{mib(dh['peak_rss'])} | {fmt_s(lim_d) if lim_d else '–'} | {fmt_s(gh['wall'])} | "
                   f"{mib(gh['peak_rss'])} | {gh.get('iterations', '–')} | {fmt_s(lim_g) if lim_g else '–'} | {fast} | "
                   + (f"{solver_name(a['hencky'])} | {fmt_s(a['hencky']['wall'])} |" if a else "– | – |"))
        n += 1
    out.append("")
    return "\n".join(out) if n else ""


def markdown_tables(rows: list[dict], blas: dict) -> str:
    rows = sorted(rows, key=lambda r: (r["problem"], r["hencky"]["dofs"]))
    both = [r for r in rows if r.get("ccx")]
    out = []
    out.append("### hencky vs CalculiX, end to end\n")
    out.append("Wall time of the whole process (start to exit: reading the mesh, writing the "
               "results and, for hencky, loading its shared libraries included) and its peak "
               "resident memory (`/usr/bin/time -v`); median of `n` runs (hencky/ccx), the two "
               "programs alternating; runs disturbed by other programs (> 0.25 cores) are left "
               "out when an undisturbed one exists. Speed-up = ccx time / hencky time (target ≥ 10); memory "
               "ratio = hencky peak / ccx peak (target ≤ 0.5). Error = (computed − closed form) "
               "/ closed form at the probe node; Δ = (hencky − ccx) / ccx on the same mesh. "
               "Others h/c = CPU used by other programs during the hencky/ccx runs (cores, median; "
               "/proc/stat busy + steal time minus the benchmarked process's own): the machine "
               "is shared, and above ~0.2 the timings are disturbed.\n")
    out.append("Solver: what hencky ran (`solver.linear: auto` chooses; the log says why). Physical "
               "limit: the time that solver's own work would take at the machine's measured rates "
               "(the factorization's flops at dgemm's rate on all cores, or CG's iterations at one "
               "core's memory bandwidth; `physical_limit` in the script).\n")
    out.append("| problem | unknowns | n | solver | hencky s | physical limit s | ccx s | speed-up | hencky MiB | ccx MiB | mem. ratio | hencky error | ccx error | Δ | others h/c |")
    out.append("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        h, c, q = r["hencky"], r.get("ccx"), r.get("ratio")
        oth = f"{h['others']:.2f}" if h.get("others") is not None else "–"
        if c and c.get("others") is not None:
            oth += f"/{c['others']:.2f}"
        out.append(
            f"| {r['problem']} | {h['dofs']:,} | {h['runs']}"
            + (f"/{c['runs']}" if c else "")
            + f" | {solver_name(h)} | {fmt_s(h['wall'])} | "
            + (fmt_s(physical_limit(h, blas)) if physical_limit(h, blas) else "–")
            + f" | {fmt_s(c['wall']) if c else '–'} | "
            + (f"**{q['time']:.2f}×**" if q else "–")
            + f" | {mib(h['peak_rss'])} | {mib(c['peak_rss']) if c else '–'} | "
            + (f"{q['memory']:.2f}" if q else "–")
            + f" | {h['error']:+.2e} | " + (f"{c['error']:+.2e}" if c else "–")
            + " | " + (f"{q['hencky_vs_ccx']:+.1e}" if q else "–")
            + f" | {oth} |")
    out.append("")
    if both:
        out.append("### Against the target (10× faster end to end, ≤ ½ the peak memory, same accuracy)\n")
        out.append("| problem | unknowns | speed-up | needed hencky s for 10× | time target | memory ratio | memory target | same accuracy (abs. Δ < 1e-4) |")
        out.append("|---|---:|---:|---:|---|---:|---|---|")
        for r in both:
            q = r["ratio"]
            out.append(f"| {r['problem']} | {r['hencky']['dofs']:,} | {q['time']:.2f}× | "
                       f"{fmt_s(r['ccx']['wall'] / 10)} | {'met' if q['time'] >= 10 else 'not met'} | "
                       f"{q['memory']:.2f} | {'met' if q['memory'] <= 0.5 else 'not met'} | "
                       f"{'yes' if abs(q['hencky_vs_ccx']) < 1e-4 else 'no'} |")
        out.append("")
    keys = ("mesh", "setup", "assembly", "factorization", "solve", "material", "output", "total")
    out.append("### hencky phases (seconds, median; `summary.json` `wall_seconds`)\n")
    out.append("`factorization` includes CHOLMOD's symbolic analysis (fill-reducing ordering: "
               "METIS nested dissection of the node graph), or with CG + GAMG the preconditioner's "
               "set-up (then `solve` is CG's iterations). `setup` includes `auto`'s prediction of the "
               "factor from 150,000 unknowns on. `material` is the "
               "stress update and internal forces at the integration points (twice for a linear "
               "step: before the solve and for the equilibrium check). CPU = (user + system) / "
               "wall of the process: 2.0 is both cores busy.\n")
    out.append("| problem | unknowns | elements | mesh read | setup | assembly | factorization | solve | material | output | total | process wall | CPU |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        h = r["hencky"]
        p = h["phases"]
        out.append(
            f"| {r['problem']} | {h['dofs']:,} | {h['elements']:,} | "
            + " | ".join(fmt_s(p[k]) for k in keys)
            + f" | {fmt_s(h['wall'])} | {h['cpu'] / h['wall']:.2f} |")
    out.append("")
    out.append("### Share of hencky's process wall time\n")
    out.append("| problem | unknowns | mesh read | setup | assembly | factorization | solve | material | output | other (process start-up, exit) |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        h = r["hencky"]
        p = h["phases"]
        w = h["wall"]
        known = sum(p[k] for k in keys[:-1])
        out.append(f"| {r['problem']} | {h['dofs']:,} | "
                   + " | ".join(f"{100 * p[k] / w:.0f} %" for k in keys[:-1])
                   + f" | {100 * (w - known) / w:.0f} % |")
    out.append("")
    if both:
        out.append("### CalculiX phases (seconds, median)\n")
        out.append("From the time ccx's progress lines appear (stdout line-buffered): input + "
                   "matrix structure (up to \"symmetric stiffness\"), element stiffness (up to "
                   "\"Factoring\"), SPOOLES factorization + solve (up to the stress calculation), "
                   "stresses + .frd/.dat output (to exit). Compare with hencky's mesh+setup, "
                   "assembly, factorization+solve, material+output+other.\n")
        out.append("| problem | unknowns | input + structure | assembly | factor + solve | stresses + output | wall | CPU | hencky factor + solve | ccx/hencky factor + solve | ccx/hencky rest |")
        out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in both:
            c, h = r["ccx"], r["hencky"]
            cp = c.get("phases") or {}
            hf = h["phases"]["factorization"] + h["phases"]["solve"]
            if cp.get("factor_solve") is None:
                continue
            c_rest = c["wall"] - cp["factor_solve"]
            h_rest = h["wall"] - hf
            out.append(f"| {r['problem']} | {h['dofs']:,} | {fmt_s(cp['input_structure'])} | "
                       f"{fmt_s(cp['assembly'])} | {fmt_s(cp['factor_solve'])} | {fmt_s(cp['stress_output'])} | "
                       f"{fmt_s(c['wall'])} | {c['cpu'] / c['wall']:.2f} | {fmt_s(hf)} | "
                       f"{cp['factor_solve'] / hf:.1f}× | {c_rest / h_rest:.1f}× |")
        out.append("")
    out.append("### Factorization flop rate vs dense matrix multiply\n")
    out.append(f"dgemm: numpy `a @ b`, n = {blas['n']}, same OpenBLAS, best of the measurements at "
               f"the start and the end of the run (median of 3 products each): **{blas['gflops_all']:.1f} GFLOP/s** on all cores, "
               f"{blas['gflops_1']:.1f} GFLOP/s on one. CHOLMOD's rate = its flop count of one "
               "numeric factorization / hencky's `factorization` time (which includes the "
               "ordering, so the numeric kernel alone runs faster than this).\n")
    out.append("| problem | unknowns | factor nonzeros (M) | factor Gflop | factorization s | CHOLMOD GFLOP/s | % of dgemm | ordering |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        h = r["hencky"]
        if "CHOLMOD" not in h.get("method", ""):
            continue
        rate = h["factor_gflops"] or 0
        out.append(f"| {r['problem']} | {h['dofs']:,} | {(h['factor_nonzeros'] or 0) / 1e6:.1f} | "
                   f"{h['factor_flops'] / 1e9:.1f} | {fmt_s(h['phases']['factorization'])} | {rate:.1f} | "
                   f"{100 * rate / blas['gflops_all']:.0f} % | {h['method'].replace('CHOLMOD ', '')} |")
    out.append("")
    return "\n".join(out)


def iterative_table(rows: list[dict], direct: dict) -> str:
    """hencky with solver.linear = iterative, against ccx (and hencky direct) on the same mesh."""
    out = ["### hencky with the iterative solver (`solver.linear: iterative`)\n",
           "Conjugate gradients with Eigen's incomplete Cholesky preconditioner. ccx and hencky "
           "direct columns: the direct-solver rows of the same mesh above.\n",
           "| problem | unknowns | n | hencky CG s | CG iterations | hencky direct s | ccx s | speed-up vs ccx | hencky CG MiB | ccx MiB | mem. ratio | error | Δ vs direct |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in sorted(rows, key=lambda r: (r["problem"], r["hencky"]["dofs"])):
        h = r["hencky"]
        d = direct.get((r["problem"], r["target_dofs"]))
        c = (d or {}).get("ccx") or r.get("ccx")
        dh = d["hencky"] if d else None
        out.append(
            f"| {r['problem']} | {h['dofs']:,} | {h['runs']} | {fmt_s(h['wall'])} | {h.get('iterations', '–')} | "
            + (fmt_s(dh["wall"]) if dh else "–") + " | " + (fmt_s(c["wall"]) if c else "–") + " | "
            + (f"{c['wall'] / h['wall']:.2f}×" if c else "–") + f" | {mib(h['peak_rss'])} | "
            + (mib(c["peak_rss"]) if c else "–") + " | "
            + (f"{h['peak_rss'] / c['peak_rss']:.2f}" if c else "–") + f" | {h['error']:+.2e} | "
            + (f"{(h['value'] - dh['value']) / dh['value']:+.1e}" if dh else "–") + " |")
    out.append("")
    return "\n".join(out)


def render(results: list[dict]) -> tuple[str, str]:
    """Markdown for a list of result files (later ones win for the same problem, size and
    linear solver). Returns (machine and run description, tables)."""
    rows = {}
    for res in results:
        for r in res["rows"]:
            rows[(r["problem"], r["target_dofs"], r.get("linear", "direct"))] = r
    direct = {(p, t): r for (p, t, lin), r in rows.items() if lin == "direct"}
    # The main tables: hencky's default (auto) where it was run, else the direct solver.
    main_rows = {(p, t): r for (p, t, lin), r in rows.items() if lin == "auto"} or direct
    iterative = [r for (p, t, lin), r in rows.items() if lin == "iterative"]
    main = results[-1]
    head = report.machine_markdown(main["machine"], main["blas"]) + "\n\n" + "\n".join(
        f"- run `{res['timestamp']}`: hencky {res['hencky_version']} (git {res['git']}), "
        f"{res['threads']} threads, {res['seconds'] / 60:.1f} min; dgemm then "
        f"{res['blas']['gflops_all']:.1f} GFLOP/s; `{report.in_repository(res['command'])}`"
        + (f"; hencky environment {res['hencky_env']}" if res.get("hencky_env") else "")
        for res in results)
    tables = markdown_tables(list(main_rows.values()), main["blas"]) if main_rows else ""
    tables += "\n" + choice_table(rows, main["blas"])
    if iterative:
        tables += "\n" + iterative_table(iterative, direct)
    return head, tables


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None, help="hencky binary (default: the first of build-bench, build-f, build-release, build under the repository)")
    ap.add_argument("--problems", default="cantilever,cylinder")
    ap.add_argument("--sizes", default="10000,30000,100000,400000,1000000",
                    help="target unknowns (comma separated); those above --max-dofs are skipped")
    ap.add_argument("--max-dofs", type=float, default=450000, help="skip target sizes above this (default 450000: up to ~400k)")
    ap.add_argument("--min-dofs", type=float, default=0, help="skip target sizes below this")
    ap.add_argument("--repeat", type=int, default=3, help="runs per size (median reported)")
    ap.add_argument("--repeat-below", type=float, default=20.0,
                    help="repeat only sizes whose first run took less than this many seconds")
    ap.add_argument("--repeat-large", type=int, default=1, help="runs per size for the sizes not repeated by --repeat-below")
    ap.add_argument("--wait-quiet", type=float, default=120.0,
                    help="before each run wait up to this many seconds for other programs to leave the CPU (0: never wait)")
    ap.add_argument("--disturbed", type=float, default=0.25,
                    help="leave runs during which other programs used more than this many cores out of the medians (when an undisturbed run exists)")
    ap.add_argument("--linear", choices=LINEAR, default="auto",
                    help="hencky's linear solver (solver.linear of the case; default auto, hencky's default)")
    ap.add_argument("--compare", default="",
                    help="other solver.linear values run once more per size, without ccx (e.g. direct,petsc: the "
                         "table of auto's choice)")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="threads for hencky and ccx (default: all cores)")
    ap.add_argument("--hencky-env", action="append", default=[], metavar="NAME=VALUE",
                    help="extra environment for hencky (experiments, e.g. OMP_WAIT_POLICY=passive)")
    ap.add_argument("--no-ccx", action="store_true", help="do not run CalculiX")
    ap.add_argument("--ccx-solver", choices=("spooles", "iterative-cholesky"), default="spooles",
                    help="ccx's solver: SPOOLES (its default) or *STATIC, SOLVER=ITERATIVE CHOLESKY")
    ap.add_argument("--ccx-max-dofs", type=float, default=0, help="run ccx only up to this target size (0: always)")
    ap.add_argument("--work", type=Path, default=BENCH / "work", help="meshes and runs (default bench/work)")
    ap.add_argument("--results", type=Path, default=BENCH / "results")
    ap.add_argument("--merge", type=Path, nargs="*", default=[], help="earlier results .json whose rows are added to the report (rows of this run win)")
    ap.add_argument("--report", type=Path, nargs="+", help="run nothing: render these results .json (later files win)")
    ap.add_argument("--write-docs", action="store_true", help="regenerate the generated part of docs/performance.md")
    ap.add_argument("--keep-output", action="store_true", help="keep hencky's VTU output and ccx's .frd")
    ap.add_argument("--blas-n", type=int, default=4000)
    args = ap.parse_args()

    if args.report:
        results = [json.loads(p.read_text()) for p in args.report]
        sources = [str(p) for p in args.report]
    else:
        exe, work, stamp = runner.prepare_run(args)

        m = runner.machine_info()
        print(runner.machine_line(m, exe), flush=True)
        def measure_blas():
            if args.wait_quiet > 0:
                runner.wait_quiet(args.wait_quiet)
            b = dict(gflops_all=runner.dgemm_rate(args.blas_n, None), gflops_1=runner.dgemm_rate(args.blas_n, 1),
                     stream_1=runner.stream_rate())
            print(f"dgemm n={args.blas_n}: {b['gflops_all']:.1f} GFLOP/s all cores, {b['gflops_1']:.1f} one core;"
                  f" triad {b['stream_1']:.1f} GB/s one core", flush=True)
            return b
        blas_runs = [measure_blas()]

        sizes = [float(x) for x in args.sizes.split(",")]
        sizes = [x for x in sizes if args.min_dofs <= x <= args.max_dofs]
        rows = []
        t_start = time.perf_counter()
        for problem in args.problems.split(","):
            for target in sizes:
                rows.append(bench_one(problem, int(target), args, work, exe))
                for other in [x for x in args.compare.split(",") if x and x != args.linear]:
                    rows.append(bench_one(problem, int(target), args, work, exe, other, compare=True))
        blas_runs.append(measure_blas())
        # The machine's capability: the best of the measurements (other programs only slow it).
        blas = dict(n=args.blas_n, runs=blas_runs,
                    gflops_all=max(b["gflops_all"] for b in blas_runs),
                    gflops_1=max(b["gflops_1"] for b in blas_runs),
                    stream_1=max(b["stream_1"] for b in blas_runs))
        result = dict(
            timestamp=stamp, machine=m, blas=blas, **runner.program_facts(exe),
            command=" ".join([sys.executable] + sys.argv), threads=args.threads,
            hencky_env=args.hencky_env, seconds=time.perf_counter() - t_start, rows=rows)
        jpath = args.results / f"{stamp}.json"
        jpath.write_text(json.dumps(result, indent=1))
        results = [json.loads(p.read_text()) for p in args.merge] + [result]
        sources = [str(p) for p in args.merge] + [str(jpath)]
        head, tables = render(results)
        mdpath = args.results / f"{stamp}.md"
        mdpath.write_text(f"## Benchmark run {stamp}\n\n{head}\n\n{tables}")
        print(f"\nwrote {jpath} and {mdpath}\n")

    head, tables = render(results)
    print(tables)
    if args.write_docs:
        rel = [os.path.relpath(x, ROOT) for x in sources]
        gen = (f"Generated by `bench/run_bench.py` from {', '.join(f'`{x}`' for x in rel)}.\n\n"
               f"### Machine and runs\n\n{head}\n\n{tables}")
        report.write_docs(ROOT / "docs" / "performance.md", gen)
        print("updated docs/performance.md")


if __name__ == "__main__":
    main()
