#!/usr/bin/python3
"""hencky plasticity benchmark: the six iteration schemes and CalculiX on the Hill cylinder.

An elastic-perfectly-plastic thick cylinder a = 0.1 m < r < b = 0.2 m under internal pressure,
von Mises, plane strain: a slice of a quarter ring (symmetry rollers on x = 0 and y = 0, both end
faces held axially), meshed by Gmsh with 10-node tetrahedra at increasing sizes. The pressure is
ramped to 0.9 of the limit pressure p_L = 2 sigma_y / sqrt(3) ln(b/a) in 20 equal increments.
The very same .msh is solved by hencky with each `solver.scheme` and, converted to an .inp
(C3D10, *ELASTIC + *PLASTIC, *STATIC, DIRECT with 20 fixed increments, *DLOAD on the bore's
element faces), by CalculiX (ccx).

The slice is meshed in its plane with size h and extruded by --layers (2) layers of thickness h,
so it stays two elements thick at every size: the unknowns grow as h^-2 and the factor's fill as
for a 2D mesh (at ~100k unknowns 6x fewer flops than run_bench's 3D cylinder), which keeps the
~500k size within hours. --layers 0 --thickness T meshes an unstructured slice of fixed thickness
T instead (3D fill: at ~500k unknowns a factorization costs about as much as run_bench's ~400k
cylinder, ~1 min for hencky and ~6 min for ccx, times 40-140 factorizations).

The strain-form schemes (initial-strain, initial-strain-stiffness) need F = eps(sigma), which
does not exist above the yield stress of a perfectly plastic material: they are run on the
perfect material all the same (their failure is recorded), and the benchmark has a second
material, the same with a small linear hardening (--hardening, default E/100), on which they
are run together with newton and ccx (the like-for-like comparison). Their relaxation omega:
initial-strain iterates with the elastic matrix everywhere, where the error of a flowing point
shrinks by 1 - omega (1 + E/H): omega = 0.01 ~ 1/(1 + E/H). initial-strain-stiffness has the
tangent at points that flowed at the start of the step (factor 1 - omega) and the elastic
matrix at points that start to yield (1 - omega (1 + E/H)): one omega cannot make both small;
0.015 converges (~600 iterations a step at H = E/100), 0.01 stalls at 0.99 per iteration and
0.0196 (the uniaxial optimum) diverges at first yield.

For every run: end-to-end wall time and peak memory (/usr/bin/time -v), iterations and
factorizations (hencky's summary.json; ccx's output), converged or not, and the radial
displacement of the outer radius u(b) at 0.9 p_L against
  - Hill's closed form (The Mathematical Theory of Plasticity, 1950, ch. V: exact for nu -> 1/2,
    an approximation of the plane-strain von Mises solution for nu = 0.3: 0.28 % low here), and
  - a 1D reference: the same problem (same 20 increments, same material) solved along the
    radius with 200 quadratic elements, radial return and Newton (converged to ~1e-5; it also
    gives the hardening variant, which has no closed form).

    /usr/bin/python3 bench/run_plastic_bench.py                       # ~20k, ~100k, ~500k unknowns
    /usr/bin/python3 bench/run_plastic_bench.py --sizes 20000         # the small size only
    /usr/bin/python3 bench/run_plastic_bench.py --report bench/results/plastic-<stamp>.json

Results: bench/results/plastic-<timestamp>.json and .md (one table per size; both rewritten
after every size). Meshes and runs go to bench/work/ (meshes reused). A run that exceeds
--timeout (default 1800 s) is killed and recorded as a timeout, with the load it had reached.
The problem, the runs and the conversion for ccx are in the henckybench package
(bench/henckybench/: problems, runs, calculix, gmsh). Standard library + numpy only.
"""
from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path

from henckybench import calculix, gmsh, report, runner
from henckybench.problems import A_IN, B_OUT, E, NU, SY, limit_pressure, plastic_problem
from henckybench.report import fmt_s, mib, pct
from henckybench.runs import plastic_ccx_row, plastic_hencky_row, references, rel_error, variants

SCHEMES = ["newton", "variable-stiffness", "initial-strain", "initial-strain-stiffness",
           "initial-stress", "initial-stress-stiffness"]
# A scheme name with "+anderson" runs that scheme with `solver.acceleration: anderson`, "+auto"
# with hencky's default acceleration, "+updated" with `solver.geometry: updated`.
TAGS = ["anderson", "auto", "updated"]
ACCELERATED = ["initial-stress+anderson", "initial-stress-stiffness+anderson"]


# ----------------------------------------------------------------------------------------------
# Benchmark
# ----------------------------------------------------------------------------------------------
def bench_size(problem: str, target: int, args, work: Path, exe: Path, refs: dict) -> dict:
    msh, gmsh_seconds, h = gmsh.size_for(problem, target, work, args.threads)
    run_dir, mesh = gmsh.size_run_dir(msh, work, "plastic")
    n_nodes, n_elems = int(len(mesh["node_tags"])), int(len(mesh["tets"]))
    size = dict(target_dofs=target, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds, nodes=n_nodes,
                elements=n_elems, runs=[])
    ccx_inputs = {}  # written first, so that the mesh is not held in memory during the runs
    for v in variants(args):
        if v["ccx"]:
            job = f"ccx-{v['name']}"
            ccx_inputs[v["name"]] = (job, calculix.write_plastic_inp(mesh, run_dir / f"{job}.inp", v, args))
    del mesh
    print(f"[~{target / 1000:.0f}k unknowns] h = {h:g}: {msh.name}, {n_nodes} nodes, {n_elems} tetrahedra", flush=True)
    for v in variants(args):
        ref = refs[v["name"]]
        programs = (["ccx"] if v["ccx"] else []) + list(v["schemes"])
        for prog in programs:
            runner.quiet(args)
            if prog == "ccx":
                row = plastic_ccx_row(run_dir, *ccx_inputs[v["name"]], v, args)
            else:
                row = plastic_hencky_row(exe, run_dir, run_dir / msh.name, prog, v, args)
            row["error_hill"] = rel_error(row.get("u_outer"), ref["hill"])
            row["error_ref"] = rel_error(row.get("u_outer"), ref["u_outer"])
            if row.get("dofs"):
                size["dofs"] = row["dofs"]
            size["runs"].append(row)
            if row.get("u_outer") is None or row["status"] != "converged":
                err = ""
            else:
                err = (f"  u(b) {row['u_outer']:.6e} ("
                       + (f"Hill {row['error_hill']:+.2%}, " if row["error_hill"] is not None else "")
                       + f"1D {row['error_ref']:+.2%})")
            print(f"    {v['name']:9s} {prog:26s} {row['status']:13s} wall {row['wall']:8.2f} s  peak {row['peak_rss'] / 2**20:6.0f} MiB"
                  f"  it {row.get('iterations')} fact {row.get('factorizations')}{err}; others {row['others']:.2f} cores"
                  + (f"\n        {row['failure']}" if row.get("failure") else ""), flush=True)
    size.setdefault("dofs", 3 * n_nodes)
    return size


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
def status_text(r: dict) -> str:
    s = r["status"]
    if s == "converged":
        return "converged"
    reached = r.get("reached")
    where = f" at p = {reached:.2f}·p_end" if reached is not None else ""
    if s == "timeout":
        return f"**timeout**{where}"
    return f"**{'stopped' if s == 'not-converged' else s}**{where}"


def size_table(size: dict, res: dict) -> str:
    p = res["parameters"]
    out = [f"### ~{size['target_dofs'] / 1000:.0f}k: {size['dofs']:,} unknowns, {size['elements']:,} tetrahedra "
           f"(h = {size['h']:g} m)\n"]
    ls = next((r["linear_solver"] for r in size["runs"] if r.get("linear_solver")), None)
    if ls and ls.get("factor_nonzeros"):
        out.append(f"hencky's factor: {ls['factor_nonzeros'] / 1e6:.1f} M nonzeros, {ls['factor_flops'] / 1e9:.1f} "
                   f"Gflop per factorization ({ls['method']}).\n")
    out.append("| material | program / scheme | status | time s | iterations | factorizations | peak MiB | "
               "u(b) error vs Hill | vs 1D | ccx time / time | memory / ccx | others |")
    out.append("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ccx = {r["material"]: r for r in size["runs"] if r["program"] == "ccx"}
    notes = []
    for r in size["runs"]:
        c = ccx.get(r["material"])
        ok = r["status"] == "converged"
        both = ok and c is not None and c["status"] == "converged" and r is not c
        mat = "perfect" if r["material"] == "perfect" else f"H = {p['hardening']:.3g}"
        name = "**ccx**" if r["program"] == "ccx" else f"hencky {r['scheme']}"
        its = r.get("iterations")
        its = "–" if its is None else (f"≥ {its}" if r["status"] == "timeout" else f"{its}")
        out.append(
            f"| {mat} | {name} | {status_text(r)} | {fmt_s(r['wall'])} | {its} | "
            f"{'–' if r.get('factorizations') is None else r['factorizations']} | {mib(r['peak_rss'])} | "
            + (pct(r.get("error_hill")) if ok else "–") + " | " + (pct(r.get("error_ref")) if ok else "–") + " | "
            + (f"{c['wall'] / r['wall']:.2f}×" if both else "–") + " | "
            + (f"{r['peak_rss'] / c['peak_rss']:.2f}" if both else "–") + f" | {r['others']:.2f} |")
        if r.get("failure") and not ok:
            notes.append(f"- {name} ({r['material']}): {r['failure']}")
    out.append("")
    if notes:
        out.append("Failures, as the programs report them:\n")
        out += notes
        out.append("")
    return "\n".join(out)


def render(res: dict) -> str:
    p, refs, m = res["parameters"], res["references"], res["machine"]
    rp, rh = refs["perfect"], refs.get("hardening")
    out = [f"## Plasticity benchmark run {res['timestamp']}\n"]
    out.append(f"- machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; "
               f"{m['os']}; CalculiX {m['ccx']}; Gmsh {m['gmsh']}")
    out.append(f"- hencky {res['hencky_version']} (git {res['git']}), `{res['hencky']}`, {res['threads']} threads; "
               f"{res['seconds'] / 60:.1f} min; `{report.in_repository(res['command'])}`")
    out.append("")
    out.append(
        f"**Problem.** Thick cylinder a = {A_IN} m < r < b = {B_OUT} m, plane strain: a slice of a quarter "
        f"ring (rollers on x = 0 and y = 0, both end faces held axially), "
        + (f"meshed in its plane with size h and extruded by {p['layers']} layers of thickness h (Gmsh "
           "splits the prisms into tetrahedra), so the slice is "
           f"{p['layers']} elements thick at every size and the factor's fill grows as in 2D; "
           if p.get("layers") else f"{p['thickness']} m thick, meshed unstructured (fill as in 3D); ")
        + f"10-node tetrahedra (ccx C3D10). E = {E:.3g} Pa, ν = {NU}, von Mises, σ_y = {SY:.3g} Pa. "
        f"Internal pressure ramped to {p['load_factor']} p_L = {p['p_end']:.6g} Pa (p_L = 2σ_y/√3·ln(b/a) = "
        f"{p['p_limit']:.6g} Pa) in {p['steps']} equal increments. hencky: tolerance {p['tolerance']:g}, "
        f"max_iterations {p['max_iterations']}, cutback {p['cutback']}, relaxation ω = {p['relaxation']} "
        f"(initial-strain) and {p.get('relaxation_stiffness', p['relaxation'])} (initial-strain-stiffness), "
        f"`linear: {p['linear']}`; fields written at the last step only; time limit {p['timeout'] or 0:g} s "
        f"per run (ccx {p['ccx_timeout'] or 0:g} s; 0: none). ccx: *STATIC, DIRECT (fixed increments), "
        "its default convergence controls; .frd at the last increment only.\n")
    out.append(
        "**Materials.** `perfect`: elastic-perfectly plastic (all six schemes; the strain-form schemes "
        "initial-strain and initial-strain-stiffness need F = ε(σ), undefined above σ_y: they are run and "
        f"their failure recorded). `hardening`: the same with linear hardening H = {p['hardening']:.4g} Pa "
        f"(= E/{E / p['hardening']:.0f}; ccx: *PLASTIC ({SY:.3g}, 0), ({SY + p['hardening']:.4g}, 1)), the "
        f"variant that the strain-form schemes can run, with {', '.join(p['hardening_schemes'])} and ccx "
        "on it for comparison.\n" if rh else
        "**Material.** elastic-perfectly plastic; no hardening variant in this run.\n")
    out.append(
        f"**Accuracy.** u(b) = radial displacement of the outer node (b, 0, 0) at the end of the ramp. "
        f"Hill's closed form (exact for ν → ½; the plastic front at c = {rp['hill_front']:.5f} m): "
        f"u(b) = {rp['hill']:.6e} m. 1D reference (the same increments along the radius, "
        f"{rp['elements']} quadratic elements, radial return; {rp['elements'] // 2} elements differ by "
        f"{abs(rp['u_outer_half_mesh'] / rp['u_outer'] - 1):.0e}): u(b) = {rp['u_outer']:.6e} m, "
        f"{pct(rp['u_outer'] / rp['hill'] - 1)} from Hill's, which is the closed form's own error for ν = {NU}"
        + (f"; with hardening u(b) = {rh['u_outer']:.6e} m (no closed form)." if rh else ".") + "\n")
    out.append(
        "**Columns.** Time: wall time of the whole process (`/usr/bin/time -v`), one run each. "
        "Iterations: hencky's total over the steps (summary.json); ccx's \"iteration\" lines (cut-back "
        "attempts included). Factorizations: hencky's summary.json; ccx's \"Factoring the system of "
        "equations\" lines. ccx time / time > 1: hencky faster; memory / ccx < 1: hencky smaller (both "
        "against ccx on the same material). Others: cores used by other programs during the run "
        "(/proc/stat; above ~0.2 the time is disturbed). Errors only for runs that reached the end of "
        "the ramp.\n")
    for size in res["sizes"]:
        out.append(size_table(size, res))
    return "\n".join(out)


# ----------------------------------------------------------------------------------------------
def or_auto(convert):
    """An argparse type: `convert(text)`, or the word auto (hencky's default of the key)."""
    def parse(text: str):
        return "auto" if text == "auto" else convert(text)
    parse.__name__ = f"{convert.__name__} or auto"  # argparse's "invalid float or auto value"
    return parse


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None,
                    help="hencky binary (default: the first of build-bench, build-f, build-release, build under the repository)")
    ap.add_argument("--sizes", default="20000,100000,500000",
                    help="target unknowns, comma separated (default 20000,100000,500000); those above --max-dofs are skipped")
    ap.add_argument("--max-dofs", type=float, default=550000, help="skip target sizes above this (default 550000)")
    ap.add_argument("--schemes", default=",".join(SCHEMES + ACCELERATED),
                    help="hencky schemes on the perfectly plastic material (default: all six, and initial-stress(-stiffness) with +anderson)")
    ap.add_argument("--hardening", type=float, default=E / 100,
                    help="linear hardening modulus H (Pa) of the variant for the strain-form schemes (default E/100; 0: no variant)")
    ap.add_argument("--hardening-schemes", default="newton,initial-strain,initial-strain-stiffness",
                    help="hencky schemes run on the hardening variant (default newton,initial-strain,initial-strain-stiffness; '' for none)")
    ap.add_argument("--relaxation", type=or_auto(float), default=0.01,
                    help="solver.relaxation ω of initial-strain (default 0.01 ≈ 1/(1 + E/H) for H = E/100: elastic matrix everywhere; 'auto': hencky's default)")
    ap.add_argument("--relaxation-stiffness", type=or_auto(float), default=0.015,
                    help="solver.relaxation ω of initial-strain-stiffness (default 0.015; see the module notes; 'auto': hencky's default)")
    ap.add_argument("--layers", type=int, default=2,
                    help="the slice is this many elements thick at every size (default 2); 0: unstructured slice of --thickness")
    ap.add_argument("--thickness", type=float, default=0.02,
                    help="with --layers 0: axial length of the unstructured slice, m (default 0.02)")
    ap.add_argument("--load-factor", type=float, default=0.9, help="end of the ramp as a fraction of p_L (default 0.9)")
    ap.add_argument("--steps", type=int, default=20, help="load increments (default 20)")
    ap.add_argument("--tolerance", type=float, default=1e-6, help="hencky solver.tolerance (default 1e-6, the case default)")
    ap.add_argument("--max-iterations", type=or_auto(int), default=1000,
                    help="hencky solver.max_iterations per step (default 1000: the fixed-matrix schemes need many near the limit load; 'auto': hencky's default)")
    ap.add_argument("--cutback", type=int, default=4, help="hencky solver.cutback (default 4, the case default)")
    ap.add_argument("--linear", choices=("auto", "direct", "iterative", "petsc"), default="auto",
                    help="hencky solver.linear (default auto, hencky's default)")
    ap.add_argument("--timeout", type=float, default=1800, help="time limit of one hencky run, s (default 1800); 0: none")
    ap.add_argument("--ccx-timeout", type=float, default=None, help="time limit of one ccx run, s (default: --timeout)")
    ap.add_argument("--ref-elements", type=int, default=200, help="quadratic elements of the 1D reference (default 200)")
    runner.add_common_arguments(ap)
    args = ap.parse_args()

    if args.report:
        print(render(json.loads(args.report.read_text())))
        return

    args.schemes = [s for s in args.schemes.split(",") if s]
    args.hardening_schemes = [s for s in args.hardening_schemes.split(",") if s]
    for s in args.schemes + args.hardening_schemes:
        base, *tags = s.split("+")
        if base not in SCHEMES or any(t not in TAGS for t in tags):
            raise SystemExit(f"unknown scheme {s!r}; the schemes are {', '.join(SCHEMES)}, each with "
                             f"any of the tags {', '.join('+' + t for t in TAGS)}")
    if args.ccx_timeout is None:
        args.ccx_timeout = args.timeout
    args.timeout = args.timeout or None
    args.ccx_timeout = args.ccx_timeout or None
    args.p_limit = limit_pressure()
    args.p_end = args.load_factor * args.p_limit
    if not args.no_ccx and not shutil.which("ccx"):
        raise SystemExit("ccx not found (Debian package calculix-ccx), or pass --no-ccx")
    if args.timeout and not shutil.which("timeout"):
        raise SystemExit("coreutils' timeout not found")

    exe, work, stamp = runner.prepare_run(args)
    problem = plastic_problem(args.layers, args.thickness)

    m = runner.machine_info()
    print(runner.machine_line(m, exe), flush=True)
    refs = references(args)
    rp = refs["perfect"]
    print(f"p_L = {args.p_limit:.6g} Pa, ramp to {args.p_end:.6g} Pa in {args.steps} increments; u(b): Hill "
          f"{rp['hill']:.6e} m, 1D reference {rp['u_outer']:.6e} m"
          + (f", with hardening {refs['hardening']['u_outer']:.6e} m" if "hardening" in refs else ""), flush=True)

    sizes = runner.parse_sizes(args.sizes)
    sizes = [x for x in sizes if x <= args.max_dofs]
    t_start = time.perf_counter()
    result = dict(
        timestamp=stamp, machine=m, **runner.program_facts(exe),
        command=" ".join([sys.executable] + sys.argv), threads=args.threads, hencky_env=args.hencky_env,
        parameters=dict(E=E, nu=NU, yield_stress=SY, a=A_IN, b=B_OUT, layers=args.layers,
                        thickness=None if args.layers > 0 else args.thickness,
                        p_limit=args.p_limit, load_factor=args.load_factor, p_end=args.p_end,
                        steps=args.steps, hardening=args.hardening, schemes=args.schemes,
                        hardening_schemes=args.hardening_schemes, relaxation=args.relaxation,
                        relaxation_stiffness=args.relaxation_stiffness,
                        tolerance=args.tolerance, max_iterations=args.max_iterations,
                        cutback=args.cutback, linear=args.linear, timeout=args.timeout,
                        ccx_timeout=args.ccx_timeout),
        references=refs, sizes=[], seconds=0.0)
    jpath = args.results / f"plastic-{stamp}.json"
    mdpath = args.results / f"plastic-{stamp}.md"
    for target in sizes:
        result["sizes"].append(bench_size(problem, target, args, work, exe, refs))
        result["seconds"] = time.perf_counter() - t_start
        # written after every size: a long run that is stopped keeps what it measured
        report.write_results(jpath, mdpath, result, render(result))
    result["seconds"] = time.perf_counter() - t_start
    md = render(result)
    report.write_results(jpath, mdpath, result, md)
    report.print_written(jpath, mdpath, md)


if __name__ == "__main__":
    main()
