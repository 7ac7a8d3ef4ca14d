#!/usr/bin/python3
"""hencky parallel benchmark: the PETSc back end (CG + GAMG, MUMPS) on 1 and 2 MPI ranks, against
hencky's serial CHOLMOD and CalculiX, on the Gmsh meshes of the other benchmarks.

Five parts, each selectable with --parts (default: all, run in this order):

  gamg      GAMG iterations against problem size. run_bench.py's Lamé cylinder (quarter ring,
            internal pressure, plane strain; 10-node tetrahedra) at increasing sizes (--gamg-sizes,
            default ~25k, 100k, 400k, 1.6M unknowns; --max-dofs caps every part's sizes), hencky
            `solver.linear: petsc` (CG + GAMG, rigid-body near null space) on 1 rank and on 2
            ranks. Recorded: unknowns, CG iterations per solve (linear_solver.iterations /
            solves), GAMG set-up and solve seconds (wall_seconds.factorization and .solve), the
            process wall time, peak memory (largest rank and the sum over the ranks), and the
            error of the bore's radial displacement against Lamé (run_bench.py's measure).
  scaling   Strong scaling at one size (--scaling-dofs, default the ~400k cylinder): CHOLMOD
            (`linear: direct`) on 2 threads and on 1, PETSc CG + GAMG on 1 rank and on 2, PETSc
            MUMPS Cholesky on 1 rank (`linear: petsc` with --petsc "-ksp_type preonly -pc_type
            cholesky -pc_factor_mat_solver_type mumps") and on 2 (`linear: direct` under mpirun).
            Each configuration --repeat times (default 3), the configurations alternating;
            medians, speed-ups as ratios of this run's medians, phases from summary.json.
  ccx       Side by side with CalculiX on the same meshes, one moderate size per problem
            (--ccx-cases, default: run_bench's cylinder and cantilever at ~100k, the plastic
            cylinder of run_plastic_bench.py (newton, 20 increments to 0.9 p_L) at ~60k, the Hertz
            contact of run_contact_bench.py at ~40k): hencky serial CHOLMOD (--threads threads),
            hencky PETSc GAMG on 2 ranks, hencky MUMPS on 2 ranks, and ccx (OMP_NUM_THREADS and
            CCX_NPROC_* = --threads, as those scripts run it). Time, peak memory and each script's
            own accuracy measure (closed form; Hill and the 1D reference; Hertz), one run each
            (--ccx-repeat), all in this run.
  largest   The largest cylinder solved here with GAMG on 2 ranks: --largest-dofs (default ~3M
            unknowns). When the gamg part measured 2-rank memory and time, the run is first
            estimated from them (bytes per unknown and seconds per unknown at its largest size);
            a size whose estimate exceeds 90 % of the available memory or --largest-timeout is not
            started, and a run that fails (killed, timed out, not converged) is recorded with the
            reason; then the next smaller size (x --largest-shrink, default 0.7) is tried, at most
            --largest-attempts times.
  memory    Per-rank peak memory: how much of the model every rank still holds whole. Two problems
            at --memory-sizes (default ~100k and ~400k unknowns) and --memory-plastic-sizes (default
            ~50k and ~100k): `elastic`, the gamg part's Lamé
            cylinder and case, and `plastic`, the ccx part's plastic cylinder (run_plastic_bench.py,
            newton, 20 increments to 0.9 p_L) with `solver.linear: petsc` instead of direct, so that
            both rank counts run CG + GAMG; each on 1 rank (no mpirun, one core, as in the gamg part)
            and on 2 ranks (mpirun -np 2), one run each; --memory-ranks 1,2,4 adds 4 ranks (mpirun -np
            4 --oversubscribe on 2 cores: the time is then shared, the memory is not). Recorded:
            unknowns, wall time, the largest rank's peak (summary.json peak_memory_bytes), the sum
            over the ranks, the status, CG iterations per solve (linear_solver.iterations / solves)
            and the preconditioner's set-up seconds (wall_seconds.factorization: GAMG's). With
            --baseline-hencky PATH every run is repeated with that binary as well (same case files,
            its own output folder and log), to compare two builds in one run; each row names its
            binary. Derived: ratio = largest rank on 2 ranks / 1 rank (0.5: nothing held twice), and
            "held whole per rank" = (2 × largest rank on 2 ranks − 1 rank) / unknowns, in bytes per
            unknown: if a process holds R replicated (whole model) and D distributable bytes, 1 rank
            peaks at R + D and each of 2 ranks at about R + D/2, so the estimate is R per unknown (on
            N ranks, R + D/N each: (N × largest rank − 1 rank) / (N − 1) / unknowns). It
            also counts what a process of 2 holds beyond a serial one (MPI buffers, halo, ghost
            copies) and the 2-rank imbalance (the largest rank is taken), and the fixed start-up
            memory of a process (libraries), which weighs on small models; the notes under the
            table give the same difference between two sizes per added unknown, where it cancels.

How the programs are run (the exact command of every run is recorded and shown):
  - serial:   hencky run case.yaml -o OUT --quiet --threads T        (T = --threads, or 1; with
              1, OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 as well, so CHOLMOD's BLAS is serial too)
  - 1 rank:   the same command with the case's `linear: petsc` (PETSc starts without mpirun), on one
              core (--rank-threads, default 1): the base of the rank speed-ups
  - N ranks:  mpirun -np N --bind-to none -x OMP_NUM_THREADS=1 hencky run case.yaml -o OUT --quiet
              (OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 when run as root;
              --oversubscribe only for N above the core count). Under mpirun `linear: direct`
              becomes PETSc MUMPS and `linear: petsc` CG + GAMG.
Each configuration has its own case file, case.<configuration>.yaml, next to the mesh in
bench/work/parallel-<mesh>/ (plastic-/contact- for the problems of those scripts, written by them).
Wall time and peak memory come from /usr/bin/time -v (runner.timed) around the whole command
(for mpirun: the largest process); the per-rank peak (summary.json peak_memory_bytes) and the
sum over the ranks (peak_memory_bytes_all_ranks) from hencky itself. For the comparison with ccx
the memory of an MPI run is the sum over its ranks (mpirun's own process not included). Before
every timed run the script waits (--wait-quiet, up to 30 s) for other programs to leave the CPU
and records the cores they used during the run ("others"); runs disturbed by more than
--disturbed cores are left out of the medians when an undisturbed run exists.

    /usr/bin/python3 bench/run_parallel_bench.py                          # everything, ~30 min here
    /usr/bin/python3 bench/run_parallel_bench.py --parts gamg,scaling --max-dofs 60000 --repeat 1
    /usr/bin/python3 bench/run_parallel_bench.py --parts memory --baseline-hencky OTHER/build/hencky
    /usr/bin/python3 bench/run_parallel_bench.py --parts memory --memory-sizes 400000 --memory-plastic-sizes "" \
        --memory-ranks 1,2,4 --memory-petsc "-pc_gamg_repartition true"
    /usr/bin/python3 bench/run_parallel_bench.py --report bench/results/parallel-<stamp>.json

Results: bench/results/parallel-<stamp>.json and .md (rewritten after every part, so a stopped
run keeps what it measured). Meshes and runs go to bench/work/ (meshes reused). Needs a Release
build with PETSc (bash bench/setup.sh: build-bench/hencky), Open MPI's mpirun, Gmsh, ccx for the
ccx part, /usr/bin/time. The problems, their cases, ccx inputs and result readers, the meshing,
the runs and the machine's facts are in the henckybench package (bench/henckybench/), as for
the other scripts.
Standard library + numpy only.
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import re
import shlex
import shutil
import sys
import time
from pathlib import Path
from types import SimpleNamespace

from henckybench import ROOT, calculix, gmsh, problems, report, runner
from henckybench.problems import DELTA, PROBLEMS, Hertz, R, contact_problem, lame_bore_displacement, limit_pressure, plastic_problem
from henckybench.report import fmt_err, fmt_s, mib, pct, ratio, sci, status_cell
from henckybench.runs import (RunHencky, contact_ccx_row, contact_hencky_row, plastic_ccx_row, plastic_hencky_row,
                              probe_value, references, rel_error, variants)

PARTS = ("gamg", "scaling", "ccx", "largest", "memory")
MUMPS_OPTIONS = "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps"


# ----------------------------------------------------------------------------------------------
# Solver configurations
# ----------------------------------------------------------------------------------------------
def configuration(key: str, args) -> dict:
    """What a configuration key means: the case's solver.linear, ranks, threads per rank and the
    --petsc options. Keys: cholmod-<T>t (serial CHOLMOD on T threads), gamg-<N> (CG + GAMG on N
    ranks), mumps-<N> (MUMPS Cholesky on N ranks), jacobi-<N> (CG + point Jacobi on N ranks: no
    multigrid set-up, so that the memory part sees hencky's own share)."""
    m = re.fullmatch(r"(cholmod|gamg|mumps|jacobi)-(\d+)(t?)", key)
    if not m:
        raise SystemExit(f"unknown configuration {key!r}")
    kind, n = m.group(1), int(m.group(2))
    if kind == "cholmod":
        return dict(key=key, label=f"CHOLMOD, {n} thread{'s' if n > 1 else ''}", kind=kind, ranks=1,
                    threads=n, linear="direct", petsc=None)
    rt = args.rank_threads if n == 1 else 1
    where = f"{n} rank{'s' if n > 1 else ''}" + (f" × {rt} threads" if rt > 1 else "")
    if kind == "gamg":
        return dict(key=key, label=f"PETSc CG + GAMG, {where}", kind=kind, ranks=n, threads=rt,
                    linear="petsc", petsc=None)
    if kind == "jacobi":
        return dict(key=key, label=f"PETSc CG + Jacobi, {where}", kind=kind, ranks=n, threads=rt,
                    linear="petsc", petsc="-pc_type jacobi -ksp_max_it 100000")
    # MUMPS: on one rank through --petsc, under mpirun what `linear: direct` becomes
    return dict(key=key, label=f"PETSc MUMPS Cholesky, {where}", kind=kind, ranks=n, threads=rt,
                linear="petsc" if n == 1 else "direct", petsc=MUMPS_OPTIONS if n == 1 else None)


def hencky_command(exe: Path, case: Path, out: Path, cfg: dict) -> tuple[list[str], dict]:
    """The command (paths relative to the case's folder, where it runs) and the environment it
    needs beyond the inherited one."""
    here = case.parent
    run = [os.path.relpath(exe, here), "run", case.name, "-o", os.path.relpath(out, here), "--quiet"]
    if cfg["petsc"]:
        run += ["--petsc", cfg["petsc"]]
    if cfg["ranks"] == 1:
        env = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"} if cfg["threads"] == 1 else {}
        return run + ["--threads", str(cfg["threads"])], env
    mpi = ["mpirun", "-np", str(cfg["ranks"]), "--bind-to", "none", "-x", "OMP_NUM_THREADS=1"]
    if cfg["ranks"] > (os.cpu_count() or 1):
        mpi.append("--oversubscribe")
    env = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"} if os.geteuid() == 0 else {}
    return mpi + run, env


def shell_line(cwd: Path, cmd: list[str], env: dict) -> str:
    """The command as one shell line, to be pasted in the repository's root."""
    return (f"cd {os.path.relpath(cwd, ROOT)} && "
            + "".join(f"{k}={shlex.quote(v)} " for k, v in env.items()) + shlex.join(cmd))


def run_config(exe: Path, case: Path, out: Path, key: str, args, timeout: float | None = None,
               tag: str = "", petsc: str = "") -> dict:
    """hencky on `case` in configuration `key`: the case is copied to case.<key>.yaml with its
    solver.linear set for the configuration, and run under /usr/bin/time -v (runner.hencky_timed).
    Returns runner.run_hencky's fields (rc, wall, peak_rss, cpu, others, load_before,
    timed_out, log, summary) and the configuration, the command and a summary of the run.
    tag: the log is case.<key>.<tag>.hencky.log instead of case.<key>.hencky.log (a part that
    runs the same case files as another keeps its own logs). petsc: PETSc options added after the
    configuration's own."""
    cfg = configuration(key, args)
    if petsc:
        cfg["petsc"] = f"{cfg['petsc']} {petsc}" if cfg["petsc"] else petsc
        cfg["label"] += f" ({petsc})"
    text, n = re.subn(r"\blinear: \w+", f"linear: {cfg['linear']}", case.read_text())
    if n != 1:
        raise SystemExit(f"{case}: expected one `linear:` entry, found {n}")
    run_case = case.parent / f"{case.stem}.{key}.yaml"
    run_case.write_text(text)
    cmd, env = hencky_command(exe, run_case, out, cfg)
    log = case.parent / f"{run_case.stem}{'.' + tag if tag else ''}.hencky.log"
    r = runner.hencky_timed(cmd, case, out, env=dict(args.hencky_environ, **env), log=log, timeout=timeout)
    r["tail"] = [line for _, line in r.pop("lines")[-6:]]
    r["config"] = cfg
    r["command"] = shell_line(case.parent, cmd, env)
    r["record"] = run_record(r, timeout)
    return r


def run_record(r: dict, timeout: float | None) -> dict:
    """The figures of one hencky run kept in the results (summary.json and /usr/bin/time)."""
    s = r["summary"] or {}
    ls = s.get("linear_solver") or {}
    cfg = r["config"]
    rec = dict(config=cfg["key"], label=cfg["label"], ranks=cfg["ranks"], threads=cfg["threads"],
               rc=r["rc"], wall=r["wall"], cpu=r["cpu"], peak_rss=r["peak_rss"], others=r["others"],
               load_before=r["load_before"], command=r["command"], log=r["log"],
               status=s.get("status") or ("timeout" if r["timed_out"] else "error"),
               failure=s.get("failure"), dofs=s.get("dofs"), nodes=s.get("nodes"), elements=s.get("elements"),
               method=ls.get("method"), linear_iterations=ls.get("iterations"), solves=ls.get("solves"),
               setups=ls.get("factorizations"), iterations=s.get("iterations"),
               factorizations=s.get("factorizations"), phases=s.get("wall_seconds"),
               peak_rank=s.get("peak_memory_bytes"),
               peak_sum=s.get("peak_memory_bytes_all_ranks", s.get("peak_memory_bytes")),
               summary_ranks=s.get("ranks"), summary_threads=s.get("threads"))
    if not s:
        killed = {137: "killed (SIGKILL: out of memory?)", -9: "killed (SIGKILL: out of memory?)"}
        why = (f"killed after the time limit of {timeout:g} s" if r["timed_out"]
               else killed.get(r["rc"], f"exit status {r['rc']} without summary.json"))
        rec["failure"] = why + "; last output: " + " | ".join(x.strip() for x in r["tail"] if x.strip())
    if rec["linear_iterations"] is not None and rec["solves"]:
        rec["iterations_per_solve"] = rec["linear_iterations"] / rec["solves"]
    return rec


def configured_run(key: str, args, records: list) -> RunHencky:
    """A stand-in for runner.run_hencky (same arguments and result) that runs hencky in
    configuration `key` (run_config) and appends the record of each run to `records`: how the
    ccx part runs the plastic and contact problems' hencky rows (henckybench.runs) in its
    configurations."""

    def run(exe, case, out, threads, env=None, timeout=None, check=True):
        r = run_config(exe, case, out, key, args, timeout)
        records.append(r["record"])
        if check and r["rc"] != 0:
            raise SystemExit(f"hencky failed (exit {r['rc']}), see {r['log']}")
        return r

    return run


# ----------------------------------------------------------------------------------------------
# Helpers
# ----------------------------------------------------------------------------------------------
def write_elastic_case(problem: str, run_dir: Path, msh: Path) -> Path:
    case = run_dir / "case.yaml"
    case.write_text(problems.elastic_case(problem, run_dir / msh.name, "direct"))
    return case


def elastic_run(exe, problem: str, run_dir: Path, case: Path, key: str, args, timeout=None, show=True) -> dict:
    """One elastic hencky run in configuration `key`, with the probe value and its error against
    the closed form (run_bench.py's measure)."""
    exact = PROBLEMS[problem]["exact"]()
    out = run_dir / f"out-{key}"
    r = run_config(exe, case, out, key, args, timeout)
    rec = r["record"]
    s = r["summary"]
    if s and rec["status"] == "converged":
        rec["value"] = probe_value(problem, s)
        rec["error"] = (rec["value"] - exact) / exact
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
    if not show:
        return rec
    print(f"    {rec['label']:38s} {rec['status']:10s} {rec['dofs'] or 0:>9d} dofs  wall {rec['wall']:8.2f} s  "
          f"peak {mib(rec['peak_rank'] or rec['peak_rss']):>6s} MiB/rank {mib(rec['peak_sum'] or rec['peak_rss']):>6s} all"
          + (f"  its/solve {rec['iterations_per_solve']:.1f}" if rec.get("iterations_per_solve") and rec["config"].startswith("gamg") else "")
          + (f"  error {rec['error']:+.3e}" if rec.get("error") is not None else "")
          + f"; others {rec['others']:.2f}" + (f"\n        {rec['failure']}" if rec.get("failure") else ""), flush=True)
    return rec


def combine(runs: list[dict], limit: float) -> dict:
    """One row from repeated runs of a configuration: the last converged run's figures with the
    medians of the times and memory over the undisturbed converged runs."""
    ok = [r for r in runs if r["status"] == "converged"]
    use = runner.undisturbed(ok or runs, limit)
    row = dict(use[-1])
    for k in ("wall", "cpu", "peak_rss", "peak_rank", "peak_sum", "others", "load_before"):
        row[k] = runner.median([r.get(k) for r in use])
    if use[-1].get("phases"):
        row["phases"] = {p: runner.median([(r.get("phases") or {}).get(p) for r in use]) for p in use[-1]["phases"]}
    row.update(n=len(use), runs=len(runs), wall_all=[r["wall"] for r in runs],
               others_all=[r["others"] for r in runs], status_all=[r["status"] for r in runs])
    return row


def capped(target: float, args) -> int:
    return int(min(target, args.max_dofs))


# ----------------------------------------------------------------------------------------------
# Parts
# ----------------------------------------------------------------------------------------------
def part_gamg(exe, work, args) -> dict:
    sizes = [int(float(x)) for x in args.gamg_sizes.split(",") if x]
    sizes = [x for x in sizes if x <= args.max_dofs]
    rows = []
    for target in sizes:
        msh, gmsh_seconds, h = gmsh.size_for("cylinder", target, work, args.threads)
        run_dir = gmsh.mesh_run_dir(msh, work, "parallel")
        case = write_elastic_case("cylinder", run_dir, msh)
        print(f"[gamg ~{target / 1000:.0f}k] h = {h:g}: {msh.name}", flush=True)
        for key in ("gamg-1", "gamg-2"):
            runs = []
            for _ in range(max(1, args.gamg_repeat)):
                runner.quiet(args)
                runs.append(elastic_run(exe, "cylinder", run_dir, case, key, args, args.timeout))
            rows.append(dict(combine(runs, args.disturbed), target_dofs=target, h=h, msh=str(msh),
                             gmsh_seconds=gmsh_seconds))
    return dict(problem="cylinder", exact=lame_bore_displacement(), rows=rows)


def part_scaling(exe, work, args) -> dict:
    target = capped(args.scaling_dofs, args)
    msh, gmsh_seconds, h = gmsh.size_for("cylinder", target, work, args.threads)
    run_dir = gmsh.mesh_run_dir(msh, work, "parallel")
    case = write_elastic_case("cylinder", run_dir, msh)
    keys = [k for k in args.scaling_configs.split(",") if k]
    print(f"[scaling ~{target / 1000:.0f}k] h = {h:g}: {msh.name}; {', '.join(keys)} x {args.repeat}", flush=True)
    runs = {k: [] for k in keys}
    for rep in range(max(1, args.repeat)):
        print(f"  repetition {rep + 1}", flush=True)
        for key in keys:
            runner.quiet(args)
            runs[key].append(elastic_run(exe, "cylinder", run_dir, case, key, args, args.timeout))
    rows = [dict(combine(runs[k], args.disturbed), target_dofs=target) for k in keys]
    return dict(problem="cylinder", target_dofs=target, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds,
                exact=lame_bore_displacement(), repeat=args.repeat, rows=rows)


def part_largest(exe, work, args, gamg: dict | None) -> dict:
    """GAMG on 2 ranks at --largest-dofs, smaller when it cannot run (see the module notes)."""
    ref = None
    if gamg:
        two = [r for r in gamg["rows"] if r["config"] == "gamg-2" and r["status"] == "converged" and r.get("peak_sum")]
        if two:
            ref = max(two, key=lambda r: r["dofs"])
    attempts = []
    target = capped(args.largest_dofs, args)
    for _ in range(max(1, args.largest_attempts)):
        att = dict(target_dofs=target)
        attempts.append(att)
        if ref:
            att["estimate"] = dict(
                from_dofs=ref["dofs"], memory_bytes=ref["peak_sum"] / ref["dofs"] * target * 1.1,
                wall=ref["wall"] * (target / ref["dofs"]) ** 1.15, available_bytes=runner.mem_available())
            est = att["estimate"]
            print(f"[largest ~{target / 1e6:.2f}M] estimated from {ref['dofs']:,} unknowns: "
                  f"{est['memory_bytes'] / 2**30:.1f} GiB (available {est['available_bytes'] / 2**30:.1f} GiB), "
                  f"{est['wall']:.0f} s", flush=True)
            why = None
            if est["memory_bytes"] > 0.9 * est["available_bytes"]:
                why = (f"not run: estimated memory {est['memory_bytes'] / 2**30:.1f} GiB > 90 % of the "
                       f"available {est['available_bytes'] / 2**30:.1f} GiB")
            elif args.largest_timeout and est["wall"] > args.largest_timeout:
                why = f"not run: estimated time {est['wall']:.0f} s > --largest-timeout {args.largest_timeout:g} s"
            if why:
                att.update(status="not-run", failure=why)
                print(f"    {why}", flush=True)
                target = int(target * args.largest_shrink)
                continue
        t0 = time.perf_counter()
        msh, gmsh_seconds, h = gmsh.size_for("cylinder", target, work, args.threads)
        att.update(h=h, msh=str(msh), gmsh_seconds=gmsh_seconds, mesh_seconds_here=time.perf_counter() - t0)
        run_dir = gmsh.mesh_run_dir(msh, work, "parallel")
        case = write_elastic_case("cylinder", run_dir, msh)
        print(f"[largest ~{target / 1e6:.2f}M] h = {h:g}: {msh.name}", flush=True)
        runner.quiet(args)
        rec = elastic_run(exe, "cylinder", run_dir, case, "gamg-2", args, args.largest_timeout or None)
        att.update(rec)
        if rec["status"] == "converged":
            break
        target = int(target * args.largest_shrink)
    return dict(problem="cylinder", exact=lame_bore_displacement(), attempts=attempts,
                estimated_from=ref["dofs"] if ref else None)


def ccx_cases(args) -> list[tuple[str, int]]:
    out = []
    for item in args.ccx_cases.split(","):
        if not item:
            continue
        name, _, size = item.partition("=")
        if name not in ("cylinder", "cantilever", "plastic", "contact"):
            raise SystemExit(f"--ccx-cases: unknown problem {name!r} (cylinder, cantilever, plastic, contact)")
        out.append((name, capped(float(size or 1e5), args)))
    return out


CCX_CONFIGS = ("cholmod-{threads}t", "gamg-2", "mumps-2")


def merge_record(row: dict, records: list, key: str) -> dict:
    """The plastic or contact problem's row of a hencky run (henckybench.runs), with this script's record
    of the same run (configuration, command, per-rank memory, linear iterations)."""
    rec = records[-1] if records else {}
    out = dict(row)
    out.update({k: v for k, v in rec.items() if row.get(k) is None})
    out.update(config=key, label=out.get("label") or rec.get("label") or key, program="hencky")
    return out


def side_by_side(size: dict, args, hencky_row, ccx_row, measure) -> dict:
    """The runs of one problem of the ccx part, --ccx-repeat times: hencky in each of CCX_CONFIGS
    (hencky_row(key, run) -> row; run: configured_run for the configuration, for the rows of
    henckybench.runs that take it), then ccx (ccx_row() -> row). measure(row) sets a converged row's
    `errors` (one per entry of size["measures"]) and `compare` (the value compared between the
    programs), and returns a short text for the progress line."""
    for _ in range(max(1, args.ccx_repeat)):
        for key in [k.format(threads=args.threads) for k in CCX_CONFIGS] + ["ccx"]:
            runner.quiet(args)
            if key == "ccx":
                row = ccx_row()
                row.update(config="ccx", label=f"CalculiX ccx, {args.threads} threads", program="ccx",
                           peak_sum=row["peak_rss"])
            else:
                records = []
                row = merge_record(hencky_row(key, configured_run(key, args, records)), records, key)
            text = measure(row) if row["status"] == "converged" else ""
            row.setdefault("errors", [None] * len(size["measures"]))
            size["rows"].append(row)
            its = row.get("iterations_per_solve") if key.startswith("gamg") else None
            print(f"    {row['label']:38s} {row['status']:10s} wall {row['wall']:8.2f} s  peak "
                  f"{mib(row.get('peak_sum') or row['peak_rss']):>6s} MiB  it {row.get('iterations')} "
                  f"fact {row.get('factorizations')}" + (f"  its/solve {its:.1f}" if its else "")
                  + f"  {text}; others {row['others']:.2f}"
                  + (f"\n        {row['failure']}" if row.get("failure") and row["status"] != "converged" else ""),
                  flush=True)
    size["dofs"] = next((r["dofs"] for r in size["rows"] if r.get("dofs")), 3 * size["nodes"])
    return size


def ccx_elastic(problem, target, exe, work, args) -> dict:
    """run_bench.py's problem: the probe displacement against the closed form."""
    spec = PROBLEMS[problem]
    comp, sign = spec["sign"]
    exact = spec["exact"]()
    msh, gmsh_seconds, h = gmsh.size_for(problem, target, work, args.threads)
    run_dir, mesh = gmsh.size_run_dir(msh, work, "parallel")
    info = calculix.write_elastic_inp(problem, mesh, run_dir / "job.inp")
    size = dict(problem=problem, target_dofs=target, h=h, msh=str(msh), nodes=int(len(mesh["node_tags"])),
                elements=int(len(mesh["tets"])), measures=[spec["quantity"] + " vs " + spec["reference"]],
                exact=exact, rows=[])
    del mesh
    case = write_elastic_case(problem, run_dir, msh)
    print(f"[ccx {problem} ~{target / 1000:.0f}k] h = {h:g}: {msh.name}", flush=True)

    def ccx_row():
        c = calculix.run_ccx(run_dir, "job", args.threads, timeout=args.ccx_timeout, check=False)
        row = {k: c[k] for k in ("wall", "cpu", "peak_rss", "others", "load_before", "cpus", "rc")}
        row.update(status="converged" if c["ok"] else ("timeout" if c["timed_out"] else "error"),
                   failure="; ".join(c.get("errors") or []) or None,
                   command=calculix.ccx_shell_line(run_dir, "job", args.threads))
        if c["ok"]:
            row["value"] = sign * calculix.parse_ccx_dat(run_dir / "job.dat", info["probe_node"])[comp]
        if not args.keep_output:
            (run_dir / "job.frd").unlink(missing_ok=True)
        return row

    def measure(row):
        row["errors"] = [(row["value"] - exact) / exact]
        row["compare"] = row["value"]
        return f"error {row['errors'][0]:+.3e}"

    return side_by_side(size, args, lambda key, run: elastic_run(exe, problem, run_dir, case, key, args, args.timeout, show=False),
                        ccx_row, measure)


def plastic_args(args, linear: str = "direct") -> SimpleNamespace:
    """run_plastic_bench.py's options for its cylinder (perfect plasticity, newton, its default
    controls), with hencky's solver.linear `linear`: the ccx and memory parts' plastic case."""
    pargs = SimpleNamespace(
        steps=20, tolerance=1e-6, max_iterations=1000, cutback=4, linear=linear, relaxation=0.01,
        relaxation_stiffness=0.015, load_factor=0.9, hardening=0.0, schemes=["newton"], hardening_schemes=[],
        no_ccx=False, ref_elements=200, timeout=args.timeout, ccx_timeout=args.ccx_timeout,
        threads=args.threads, keep_output=args.keep_output, hencky_environ=args.hencky_environ)
    pargs.p_limit = limit_pressure()
    pargs.p_end = pargs.load_factor * pargs.p_limit
    return pargs


def ccx_plastic(target, exe, work, args) -> dict:
    """run_plastic_bench.py's cylinder (perfect plasticity, newton, its default controls): u(b)
    against its 1D reference and Hill."""
    pargs = plastic_args(args)
    refs = references(pargs)["perfect"]
    variant = variants(pargs)[0]
    problem = plastic_problem(2, 0.02)
    msh, gmsh_seconds, h = gmsh.size_for(problem, target, work, args.threads)
    run_dir, mesh = gmsh.size_run_dir(msh, work, "plastic")
    job = "ccx-perfect"
    info = calculix.write_plastic_inp(mesh, run_dir / f"{job}.inp", variant, pargs)
    size = dict(problem="plastic", target_dofs=target, h=h, msh=str(msh), nodes=int(len(mesh["node_tags"])),
                elements=int(len(mesh["tets"])), references=refs,
                measures=["u(b) vs the 1D reference", "u(b) vs Hill"], rows=[],
                parameters=dict(steps=pargs.steps, tolerance=pargs.tolerance, p_end=pargs.p_end,
                                scheme="newton", layers=2))
    del mesh
    print(f"[ccx plastic ~{target / 1000:.0f}k] h = {h:g}: {msh.name}; u(b) 1D {refs['u_outer']:.6e}, "
          f"Hill {refs['hill']:.6e}", flush=True)

    def ccx_row():
        row = plastic_ccx_row(run_dir, job, info, variant, pargs)
        row["command"] = calculix.ccx_shell_line(run_dir, job, args.threads)
        return row

    def measure(row):
        if row.get("u_outer") is None:
            return ""
        row["errors"] = [rel_error(row["u_outer"], refs["u_outer"]), rel_error(row["u_outer"], refs["hill"])]
        row["compare"] = row["u_outer"]
        return f"u(b) vs 1D {pct(row['errors'][0], 3)}"

    return side_by_side(size, args, lambda key, run: plastic_hencky_row(exe, run_dir, run_dir / msh.name, "newton",
                                                                        variant, pargs, run=run), ccx_row, measure)


def ccx_contact(target, exe, work, args) -> dict:
    """run_contact_bench.py's Hertz problem (its defaults): the force and the p² fit's p0
    against Hertz."""
    cargs = SimpleNamespace(steps=4, block=100.0, penetration=None, ccx_stiffness=10.0, timeout=args.timeout,
                            ccx_timeout=args.ccx_timeout, threads=args.threads, keep_output=args.keep_output,
                            hencky_environ=args.hencky_environ)
    hz = Hertz(R)
    P0, p00 = hz.force(DELTA), hz.peak(DELTA)
    problem = contact_problem(cargs.block)
    msh, gmsh_seconds, hc = gmsh.size_for(problem, target, work, args.threads)
    run_dir, mesh = gmsh.size_run_dir(msh, work, "contact")
    info = calculix.write_contact_inp(mesh, run_dir / "job.inp", hc, cargs)
    size = dict(problem="contact", target_dofs=target, h=hc, msh=str(msh), nodes=int(len(mesh["node_tags"])),
                elements=int(len(mesh["tets"])), hertz=dict(P=P0, p0=p00, a=hz.radius(DELTA)),
                measures=["P vs Hertz", "p0 (p² fit) vs Hertz"], rows=[],
                parameters=dict(steps=cargs.steps, block=cargs.block, ccx_stiffness=cargs.ccx_stiffness))
    del mesh
    print(f"[ccx contact ~{target / 1000:.0f}k] h_c = {hc:g}: {msh.name}; Hertz P = {P0:.6g} N", flush=True)

    def ccx_row():
        row = contact_ccx_row(run_dir, info, cargs, hz)
        row["command"] = calculix.ccx_shell_line(run_dir, "job", args.threads)
        return row

    def measure(row):
        if row.get("P") is None:
            return ""
        row["errors"] = [rel_error(row["P"], P0), rel_error((row.get("fit") or {}).get("p0"), p00)]
        row["compare"] = row["P"]
        return f"P {fmt_err(row, 'P', P0)}"

    return side_by_side(size, args, lambda key, run: contact_hencky_row(exe, run_dir, run_dir / msh.name, cargs, hz, run=run),
                        ccx_row, measure)


def part_ccx(exe, work, args) -> dict:
    if not shutil.which("ccx"):
        return dict(sizes=[], skipped="ccx not found (Debian package calculix-ccx)")
    sizes = []
    for name, target in ccx_cases(args):
        if name in ("cylinder", "cantilever"):
            sizes.append(ccx_elastic(name, target, exe, work, args))
        elif name == "plastic":
            sizes.append(ccx_plastic(target, exe, work, args))
        else:
            sizes.append(ccx_contact(target, exe, work, args))
    return dict(sizes=sizes)


def memory_sizes(args, problem: str) -> list[int]:
    """--memory-sizes (elastic) or --memory-plastic-sizes, each capped at --max-dofs (duplicates
    after the cap dropped)."""
    out = []
    for x in (args.memory_sizes if problem == "elastic" else args.memory_plastic_sizes).split(","):
        if x and capped(float(x), args) not in out:
            out.append(capped(float(x), args))
    return out


def memory_run(exe: Path, binary: str, problem: str, target: int, run_dir: Path, case: Path, key: str, args) -> dict:
    """One run of the memory part: `exe` (binary "hencky" or "baseline") on `case` in configuration
    `key`, with its own output folder (out-memory[-baseline]-<key>) and log
    (case.<key>.memory[-baseline].hencky.log), so the other parts' files on the same mesh and the
    other binary's stay apart. The record gets the compared value: the bore displacement
    (elastic) or u(b) (plastic), the final state of the run."""
    tag = "memory" if binary == "hencky" else f"memory-{binary}"
    out = run_dir / f"out-{tag}-{key}"
    r = run_config(exe, case, out, key, args, args.timeout, tag=tag, petsc=args.memory_petsc)
    rec = dict(r["record"], problem=problem, target_dofs=target, binary=binary, exe=str(exe))
    s = r["summary"]
    if s and rec["status"] == "converged":
        probes = s.get("probes") or {}
        if problem == "elastic":
            rec["value"] = probe_value("cylinder", s)
        elif probes.get("outer"):
            rec["value"] = probes["outer"]["displacement"]["x"]
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
    print(f"    {binary:8s} {rec['label']:26s} {rec['status']:10s} {rec['dofs'] or 0:>9d} dofs  wall {rec['wall']:8.2f} s  "
          f"peak {mib(rec['peak_rank']):>6s} MiB/rank {mib(rec['peak_sum']):>6s} all"
          + (f"  its/solve {rec['iterations_per_solve']:.1f}" if rec.get("iterations_per_solve") else "")
          + (f"  set-up {rec['phases']['factorization']:.2f} s" if (rec.get("phases") or {}).get("factorization") is not None else "")
          + f"; others {rec['others']:.2f}"
          + (f"\n        {rec['failure']}" if rec.get("failure") and rec["status"] != "converged" else ""), flush=True)
    return rec


def memory_ranks(args) -> list[int]:
    """--memory-ranks: the rank counts of the memory part (default 1,2)."""
    ranks = [int(x) for x in args.memory_ranks.split(",") if x]
    if not ranks or min(ranks) < 1:
        raise SystemExit(f"--memory-ranks: rank counts >= 1, comma separated (got {args.memory_ranks!r})")
    return ranks


def part_memory(exe, work, args) -> dict:
    """Per-rank peak memory on 1 and 2 ranks (--memory-ranks), elastic and plastic, for this
    binary and the baseline (see the module notes)."""
    binaries = [("hencky", exe)] + ([("baseline", args.baseline_hencky)] if args.baseline_hencky else [])
    pargs = plastic_args(args, "petsc")
    variant = variants(pargs)[0]
    ring = plastic_problem(2, 0.02)
    info = {b: runner.binary_info(path) for b, path in binaries}  # before the runs: a rebuild meanwhile is noticed
    runs = []
    for problem in ("elastic", "plastic"):
        for target in memory_sizes(args, problem):
            if problem == "elastic":
                msh, gmsh_seconds, h = gmsh.size_for("cylinder", target, work, args.threads)
                run_dir = gmsh.mesh_run_dir(msh, work, "parallel")
                case = write_elastic_case("cylinder", run_dir, msh)
            else:
                # run_plastic_bench's case file (as runs.plastic_hencky_row writes it), linear: petsc
                msh, gmsh_seconds, h = gmsh.size_for(ring, target, work, args.threads)
                run_dir = gmsh.mesh_run_dir(msh, work, "plastic")
                case = run_dir / f"case-{variant['name']}-newton.yaml"
                case.write_text(problems.plastic_case(run_dir / msh.name, "newton", variant, pargs))
            print(f"[memory {problem} ~{target / 1000:.0f}k] h = {h:g}: {msh.name}", flush=True)
            for key in (f"{args.memory_solver}-{n}" for n in memory_ranks(args)):
                for binary, path in binaries:
                    runner.quiet(args)
                    runs.append(dict(memory_run(path, binary, problem, target, run_dir, case, key, args),
                                     h=h, msh=str(msh), gmsh_seconds=gmsh_seconds))
    return dict(binaries=info, exact=lame_bore_displacement(), solver=args.memory_solver,
                petsc=args.memory_petsc, ranks=memory_ranks(args),
                plastic=dict(steps=pargs.steps, tolerance=pargs.tolerance, p_end=pargs.p_end, scheme="newton",
                             layers=2, linear=pargs.linear),
                runs=runs)


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
def delta(a, b, same_code=True):
    """Relative difference of two answers on the same mesh; between two hencky solvers it is
    marked when it exceeds what their tolerances allow (1e-6)."""
    if a is None or b is None or b == 0:
        return "–"
    d = (a - b) / b
    return f"**{d:+.1e}**" if same_code and abs(d) > 1e-6 else f"{d:+.1e}"


def part_command(res: dict, part: str) -> str:
    """The bench command line of this run restricted to one part."""
    argv, out, skip = res["argv"], [], False
    for a in argv:
        if skip:
            skip = False
            continue
        if a == "--parts":
            skip = True
            continue
        if a.startswith("--parts="):
            continue
        out.append(a)
    return "/usr/bin/python3 bench/run_parallel_bench.py " + shlex.join(out + ["--parts", part])


def reproduce(res: dict, part: str, rows: list[dict]) -> str:
    """The commands under a table: the bench command of the part, and the run command of the
    first row of each configuration (hencky serial, 1 rank, mpirun; ccx)."""
    out = ["Reproduce (from the repository's root; the bench command meshes and writes the case "
           "files first):\n", f"- this table: `{part_command(res, part)}`"]
    seen = set()
    for r in rows:
        cmd = r.get("command")
        if not cmd or r.get("config") in seen:
            continue
        seen.add(r.get("config"))
        out.append(f"- row \"{r['label']}\": `{cmd}`")
    return "\n".join(out) + "\n"


def others_cell(r):
    return "–" if r.get("others") is None else f"{r['others']:.2f}"


def render_gamg(res: dict) -> str:
    g = res["parts"]["gamg"]
    rows = sorted(g["rows"], key=lambda r: (r.get("dofs") or r["target_dofs"], r["ranks"]))
    out = ["### 1. GAMG iterations against problem size\n",
           f"run_bench.py's thick cylinder (Lamé, plane strain; exact bore displacement u(a) = {g['exact']:.6e} m), "
           "hencky `solver.linear: petsc` (CG + GAMG, rigid-body near null space, relative tolerance 1e-10), one "
           "linear solve. 1 rank: `hencky run` without mpirun on one core; 2 ranks: `mpirun -np 2`, one thread "
           "each. Iterations per solve = linear_solver.iterations / solves. GAMG set-up = wall_seconds."
           "factorization (the preconditioner's set-up), solve = wall_seconds.solve, hencky total = wall_seconds."
           "total; process wall and CPU (user + system, all ranks) from /usr/bin/time -v. Peak memory: the largest "
           "rank's and the sum over the ranks (summary.json). Error = (u(a) − Lamé) / Lamé at the bore node; Δ = "
           "(2 ranks − 1 rank) / 1 rank on the same mesh. One run per row unless n says otherwise.\n",
           "| unknowns | elements | ranks | n | status | iterations / solve | GAMG set-up s | solve s | assembly s | "
           "hencky total s | process wall s | CPU s | peak MiB (max rank) | peak MiB (all ranks) | error vs Lamé | Δ 2 vs 1 rank | others |",
           "|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    one = {r["target_dofs"]: r for r in rows if r["ranks"] == 1}
    for r in rows:
        p = r.get("phases") or {}
        base = one.get(r["target_dofs"]) if r["ranks"] > 1 else None
        its = r.get("iterations_per_solve")
        out.append(
            f"| {r['dofs'] or 0:,} | {r['elements'] or 0:,} | {r['ranks']} | {r['n']} | {status_cell(r)} | "
            + (f"{its:.1f}" if its is not None else "–")
            + f" | {fmt_s(p.get('factorization'))} | {fmt_s(p.get('solve'))} | {fmt_s(p.get('assembly'))} | "
            f"{fmt_s(p.get('total'))} | {fmt_s(r['wall'])} | {fmt_s(r['cpu'])} | {mib(r.get('peak_rank'))} | "
            f"{mib(r.get('peak_sum'))} | {sci(r.get('error'))} | "
            + (delta(r.get("value"), base.get("value")) if base else "–") + f" | {others_cell(r)} |")
    out.append("")
    conv = [r for r in rows if r["status"] == "converged" and r.get("iterations_per_solve")]
    for ranks in (1, 2):
        rr = [r for r in conv if r["ranks"] == ranks]
        if len(rr) >= 2:
            a, b = rr[0], rr[-1]
            out.append(f"- {ranks} rank{'s' if ranks > 1 else ''}: iterations per solve "
                       + " → ".join(f"{r['iterations_per_solve']:.0f}" for r in rr)
                       + f" from {a['dofs']:,} to {b['dofs']:,} unknowns (×{b['dofs'] / a['dofs']:.0f} unknowns, "
                       f"×{b['iterations_per_solve'] / a['iterations_per_solve']:.2f} iterations); solve time per "
                       f"unknown and iteration {1e9 * a['phases']['solve'] / a['dofs'] / a['iterations_per_solve']:.1f} → "
                       f"{1e9 * b['phases']['solve'] / b['dofs'] / b['iterations_per_solve']:.1f} ns; peak memory per "
                       f"unknown (all ranks) {(a.get('peak_sum') or 0) / a['dofs']:.0f} → {(b.get('peak_sum') or 0) / b['dofs']:.0f} bytes.")
    if conv:
        out.append("")
    out.append(reproduce(res, "gamg", rows))
    return "\n".join(out)


def render_scaling(res: dict) -> str:
    s = res["parts"]["scaling"]
    rows = s["rows"]
    by = {r["config"]: r for r in rows}
    dofs = next((r["dofs"] for r in rows if r.get("dofs")), s["target_dofs"])
    direct = next((r for r in rows if r["config"].startswith("cholmod") and r.get("value") is not None), None)
    ref_key = f"cholmod-{res['threads']}t"
    ref = by.get(ref_key)
    out = [f"### 2. Strong scaling at {dofs:,} unknowns (cylinder)\n",
           f"Every configuration {s['repeat']} times, the configurations alternating; medians of the undisturbed "
           "runs (n of runs). 1 rank and 1 thread = one core; `mpirun -np 2` = both cores, one thread per rank; "
           f"CHOLMOD on {res['threads']} threads = hencky's default serial run (assembly threads and OpenBLAS). "
           "Speed-ups are ratios of this table's medians. Memory: largest rank and sum over the ranks "
           "(summary.json; for a serial run both are the process's peak). Δ = (value − CHOLMOD's) / CHOLMOD's "
           "on the same mesh; error against Lamé.\n",
           "| configuration | n | status | process wall s (min–max) | speed-up vs 1 core | speed-up vs "
           f"CHOLMOD {res['threads']} threads | CPU s | peak MiB (max rank) | peak MiB (all ranks) | "
           "iterations / solve | error vs Lamé | Δ vs CHOLMOD | others |",
           "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        one = by.get({"cholmod": "cholmod-1t", "gamg": "gamg-1", "mumps": "mumps-1"}[r["config"].split("-")[0]])
        ok = [w for w, st in zip(r["wall_all"], r["status_all"]) if st == "converged"]
        its = r.get("iterations_per_solve")
        out.append(
            f"| {r['label']} | {r['n']}/{r['runs']} | {status_cell(r)} | {fmt_s(r['wall'])}"
            + (f" ({fmt_s(min(ok))}–{fmt_s(max(ok))})" if len(ok) > 1 else "")
            + f" | {ratio(one['wall'], r['wall']) if one and one is not r and one['status'] == 'converged' else '–'}"
            f" | {ratio(ref['wall'], r['wall']) if ref and ref['status'] == 'converged' else '–'} | {fmt_s(r['cpu'])} | "
            f"{mib(r.get('peak_rank'))} | {mib(r.get('peak_sum'))} | "
            + (f"{its:.1f}" if its is not None and r["config"].startswith("gamg") else "–")
            + f" | {sci(r.get('error'))} | {delta(r.get('value'), direct.get('value')) if direct and r is not direct else '–'}"
            f" | {others_cell(r)} |")
    out.append("")
    pairs = [("cholmod-1t", ref_key, f"CHOLMOD 1 → {res['threads']} threads"), ("gamg-1", "gamg-2", "GAMG 1 → 2 ranks"),
             ("mumps-1", "mumps-2", "MUMPS 1 → 2 ranks")]
    lines = []
    for a, b, name in pairs:
        ra, rb_ = by.get(a), by.get(b)
        if ra and rb_ and ra["status"] == rb_["status"] == "converged":
            pa, pb_ = ra.get("phases") or {}, rb_.get("phases") or {}
            lines.append(f"- {name}: process wall {fmt_s(ra['wall'])} → {fmt_s(rb_['wall'])} s, **{ra['wall'] / rb_['wall']:.2f}×**"
                         + "; " + ", ".join(f"{k} {fmt_s(pa.get(k))} → {fmt_s(pb_.get(k))} s" for k in ("assembly", "factorization", "solve")
                                            if pa.get(k) is not None and pb_.get(k) is not None)
                         + f"; memory (all ranks) {mib(ra.get('peak_sum'))} → {mib(rb_.get('peak_sum'))} MiB")
    if lines:
        out.append("Speed-ups (`factorization` = CHOLMOD's ordering and factorization, PETSc's preconditioner set-up, "
                   "MUMPS's analysis and factorization):\n")
        out += lines
        out.append("")
    keys = ("mesh", "setup", "assembly", "factorization", "solve", "material", "output", "total")
    out.append("Phases (seconds, medians; summary.json `wall_seconds` of rank 0; `factorization` = ordering + "
               "factorization for CHOLMOD and MUMPS, GAMG's set-up for CG + GAMG; the process wall includes "
               "start-up, PETSc/MPI initialisation and exit):\n")
    out.append("| configuration | method (summary.json) | " + " | ".join(keys) + " | process wall |")
    out.append("|---|---|" + "---:|" * (len(keys) + 1))
    for r in rows:
        p = r.get("phases") or {}
        out.append(f"| {r['label']} | {r.get('method') or '–'} | " + " | ".join(fmt_s(p.get(k)) for k in keys)
                   + f" | {fmt_s(r['wall'])} |")
    out.append("")
    out.append(reproduce(res, "scaling", rows))
    return "\n".join(out)


def render_largest(res: dict) -> str:
    L = res["parts"]["largest"]
    out = ["### 3. The largest cylinder solved here (CG + GAMG, 2 ranks)\n",
           "Attempts from the largest size down"
           + (f"; each estimated first from the gamg part's 2-rank run at {L['estimated_from']:,} unknowns "
              "(memory ∝ unknowns × 1.1, time ∝ unknowns^1.15)" if L.get("estimated_from") else "")
           + ". Mesh = Gmsh's time for this mesh (not in the wall time).\n",
           "| target | unknowns | elements | status | process wall s | hencky total s | GAMG set-up s | solve s | "
           "iterations / solve | peak MiB (max rank) | peak MiB (all ranks) | estimated MiB / s | error vs Lamé | mesh s | others | note |",
           "|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for a in L["attempts"]:
        p = a.get("phases") or {}
        est = a.get("estimate")
        its = a.get("iterations_per_solve")
        size = f"{a['dofs']:,} | {a['elements']:,}" if a.get("dofs") else "– | –"
        out.append(f"| {a['target_dofs']:,} | {size} | {status_cell(a)} | {fmt_s(a.get('wall'))} | "
                   f"{fmt_s(p.get('total'))} | {fmt_s(p.get('factorization'))} | {fmt_s(p.get('solve'))} | "
                   + (f"{its:.1f}" if its else "–") + f" | {mib(a.get('peak_rank'))} | {mib(a.get('peak_sum'))} | "
                   + (f"{mib(est['memory_bytes'])} / {est['wall']:.0f}" if est else "–")
                   + f" | {sci(a.get('error'))} | {fmt_s(a.get('gmsh_seconds'))} | "
                   f"{others_cell(a) if a.get('wall') else '–'} | {a.get('failure') or ''} |")
    out.append("")
    out.append(reproduce(res, "largest", [a for a in L["attempts"] if a.get("command")]))
    return "\n".join(out)


def render_ccx_size(size: dict, res: dict) -> str:
    prob = size["problem"]
    title = {"cylinder": "elastic thick cylinder (run_bench.py, Lamé)",
             "cantilever": "elastic cantilever (run_bench.py, Timoshenko)",
             "plastic": "plastic thick cylinder (run_plastic_bench.py, newton, 20 increments to 0.9 p_L)",
             "contact": "Hertz contact (run_contact_bench.py, rigid sphere, 4 steps)"}[prob]
    out = [f"#### {title}: {size['dofs']:,} unknowns, {size['elements']:,} tetrahedra\n"]
    if prob == "plastic":
        rf = size["references"]
        out.append(f"u(b) of the 1D reference {rf['u_outer']:.6e} m, Hill {rf['hill']:.6e} m (Hill is 0.28 % low for ν = 0.3). "
                   "Iterations: hencky's Newton iterations (summary.json), ccx's \"iteration\" lines; factorizations: "
                   "hencky's (PETSc: preconditioner set-ups), ccx's \"Factoring\" lines.\n")
    elif prob == "contact":
        hz = size["hertz"]
        out.append(f"Hertz P = {hz['P']:.5g} N, p0 = {hz['p0']:.4g} Pa; the finite block and a/R make the model "
                   "~+1 % stiffer than Hertz on P (run_contact_bench.py). ccx: meshed rigid cap, face-to-face penalty. "
                   "Iterations/factorizations as in that script.\n")
    else:
        out.append(f"Closed form: {size['exact']:.6e} m.\n")
    cc = next((r for r in size["rows"] if r["config"] == "ccx" and r["status"] == "converged"), None)
    direct = next((r for r in size["rows"] if r["config"].startswith("cholmod") and r.get("compare") is not None), None)
    m = size["measures"]
    out.append("| program | status | wall s | ccx time / time | peak MiB (all ranks) | peak MiB (max rank) | memory / ccx | "
               "iterations | factorizations | linear its / solve | " + " | ".join(f"error: {x}" for x in m)
               + " | Δ vs ccx | Δ vs hencky CHOLMOD | others |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|" + "---:|" * len(m) + "---:|---:|---:|")
    for r in size["rows"]:
        mem = r.get("peak_sum") or r.get("peak_rss")
        its = r.get("iterations_per_solve")
        errs = r.get("errors") or [None] * len(m)
        is_ccx = r["config"] == "ccx"
        out.append(
            f"| {'**ccx**' if is_ccx else 'hencky ' + r['label']} | {status_cell(r)} | {fmt_s(r['wall'])} | "
            + (ratio(cc["wall"], r["wall"]) if cc and not is_ccx and r["status"] == "converged" else "–")
            + f" | {mib(mem)} | {mib(r.get('peak_rank')) if not is_ccx else '–'} | "
            + (f"{mem / cc['peak_rss']:.2f}" if cc and not is_ccx else "–")
            + f" | {r.get('iterations') if r.get('iterations') is not None else '–'} | "
            f"{r.get('factorizations') if r.get('factorizations') is not None else '–'} | "
            + (f"{its:.1f}" if its is not None and r["config"].startswith("gamg") else "–") + " | "
            + " | ".join(pct(x, 3) if prob in ("plastic", "contact") else sci(x) for x in errs) + " | "
            + (delta(r.get("compare"), cc.get("compare"), same_code=False) if cc and not is_ccx else "–") + " | "
            + (delta(r.get("compare"), direct.get("compare")) if direct and r is not direct and not is_ccx else "–")
            + f" | {others_cell(r)} |")
    out.append("")
    notes = [f"- {r['label']}: {r['failure']}" for r in size["rows"] if r.get("failure") and r["status"] != "converged"]
    if notes:
        out.append("Failures, as reported:\n")
        out += notes
        out.append("")
    out.append(reproduce(res, "ccx", size["rows"]))
    return "\n".join(out)


def render_ccx(res: dict) -> str:
    c = res["parts"]["ccx"]
    out = ["### 4. Side by side with CalculiX on the same meshes\n"]
    if c.get("skipped"):
        return "\n".join(out + [c["skipped"], ""])
    out.append(f"hencky serial CHOLMOD ({res['threads']} threads, its default), CG + GAMG on 2 ranks, MUMPS on 2 "
               f"ranks, and ccx 2.20 (SPOOLES, {res['threads']} threads) on the very same .msh (ccx: converted "
               "by run_bench.py). Wall time and peak memory of the whole run (/usr/bin/time -v; for mpirun the sum "
               "of the ranks' peaks, summary.json, mpirun itself not counted; max rank next to it). ccx time / time "
               "> 1: hencky faster; memory / ccx < 1: hencky smaller. Errors: each benchmark's own measure; Δ = "
               "relative difference of the compared quantity (displacement at the probe, u(b), P) on the same mesh. "
               f"One run each (--ccx-repeat {res['parameters'].get('ccx_repeat', 1)}), in this order.\n")
    for size in c["sizes"]:
        out.append(render_ccx_size(size, res))
    return "\n".join(out)


def held_whole(one: dict, many: dict) -> float | None:
    """Bytes per unknown every rank holds beyond its share: (N × largest rank of N − 1 rank) /
    (N − 1) / unknowns (on 2 ranks: 2 × largest of 2 − 1 rank)."""
    if not (one.get("peak_rank") and many.get("peak_rank") and one.get("dofs") and many.get("ranks", 2) > 1):
        return None
    n = many.get("ranks", 2)
    return (n * many["peak_rank"] - one["peak_rank"]) / (n - 1) / one["dofs"]


def render_memory(res: dict) -> str:
    M = res["parts"]["memory"]
    bins = M["binaries"]
    ranks = M.get("ranks", [1, 2])
    multi = [n for n in ranks if n > 1]
    runs = {(r["problem"], r["target_dofs"], r["binary"], r["config"]): r for r in M["runs"]}
    keys = sorted({k[:3] for k in runs}, key=lambda k: (k[0] != "elastic", k[1], list(bins).index(k[2])))
    pl = M["plastic"]
    solver = M.get("solver", "gamg")
    solver_name = {"gamg": "CG + GAMG", "jacobi": "CG + point Jacobi (no multigrid set-up: hencky's own share)"}[solver]
    if M.get("petsc"):
        solver_name += f" with `--petsc \"{M['petsc']}\"`"
    slash = " / ".join(str(n) for n in ranks)
    where = lambda n: "1 rank" if n == 1 else f"{n} ranks"
    largest = lambda n: "MiB 1 rank" if n == 1 else f"MiB largest of {n} ranks | MiB all {n} ranks"
    out = ["### 5. Per-rank peak memory: what every rank still holds whole\n",
           f"`elastic`: the gamg part's cylinder and case (Lamé, one linear solve). `plastic`: the ccx part's plastic "
           f"cylinder (run_plastic_bench.py, perfect plasticity, {pl['scheme']}, {pl['steps']} increments to "
           f"p = {pl['p_end']:.4g} Pa, a slice {pl['layers']} elements thick) with `solver.linear: {pl['linear']}`. "
           f"Both with {solver_name}: 1 rank = `hencky run` without mpirun on one core, "
           + ", ".join(f"{n} ranks = `mpirun -np {n}`" for n in multi)
           + (" (`--oversubscribe` above the core count: the time is shared, the memory is not)"
              if any(n > (res["machine"].get("nproc") or 1) for n in multi) else "")
           + ", one thread each; one run each. MiB: summary.json peak_memory_bytes, the process's peak on 1 rank and "
           f"the largest rank's on {multi[0] if len(multi) == 1 else 'N'} (sum over the ranks next to it). CG its / solve: linear_solver.iterations / "
           "solves; set-up s: wall_seconds.factorization (the preconditioner's set-up). Wall: the process, "
           "/usr/bin/time -v.\n",
           f"| problem | unknowns | binary | status {slash} ranks | CG its / solve {slash} ranks | "
           f"set-up s {slash} ranks | " + " | ".join(f"wall s {where(n)}" for n in ranks) + " | "
           + " | ".join(largest(n) for n in ranks) + " | "
           + " | ".join(f"largest of {n} / 1 rank" for n in multi) + (" | " if multi else "")
           + " | ".join("held whole per rank, bytes / unknown" + (f" ({n} ranks)" if len(multi) > 1 else "")
                        for n in multi) + (" | " if multi else "") + f"others {slash} |",
           "|---|---:|---|---|---|---|" + "---:|" * (len(ranks) + len(ranks) + len(multi) + 2 * len(multi)) + "---:|"]
    shown = []
    for prob, target, binary in keys:
        rr = {n: runs.get((prob, target, binary, f"{solver}-{n}"), {}) for n in ranks}
        one = rr.get(1, {})
        dofs = next((r["dofs"] for r in rr.values() if r.get("dofs")), None)
        its = lambda r: f"{r['iterations_per_solve']:.1f}" if r.get("iterations_per_solve") else "–"
        setup = lambda r: fmt_s((r.get("phases") or {}).get("factorization"))
        peaks = lambda n: (mib(rr[n].get("peak_rank")) if n == 1
                           else f"{mib(rr[n].get('peak_rank'))} | {mib(rr[n].get('peak_sum'))}")
        row = (f"| {prob} | {f'{dofs:,}' if dofs else '~' + f'{target:,}'} | {binary} | "
               + " / ".join(status_cell(r) if r else "–" for r in rr.values()) + " | "
               + " / ".join(its(r) for r in rr.values()) + " | "
               + " / ".join(setup(r) for r in rr.values()) + " | "
               + " | ".join(fmt_s(r.get("wall")) for r in rr.values()) + " | "
               + " | ".join(peaks(n) for n in ranks) + " | ")
        for n in multi:
            row += (f"{rr[n]['peak_rank'] / one['peak_rank']:.2f}" if one.get("peak_rank") and rr[n].get("peak_rank")
                    else "–") + " | "
        for n in multi:
            hw = held_whole(one, rr[n])
            row += f"{hw:.0f}" if hw is not None else "–"
            row += " | "
        row += " / ".join(others_cell(r) if r else "–" for r in rr.values()) + " |"
        out.append(row)
        for r in rr.values():
            if r:
                shown.append(dict(r, config=f"{prob}-{target}-{binary}-{r['config']}",
                                  label=f"{prob} {dofs or target:,}, {binary}, {where(r['ranks'])}"))
    out.append("")
    out.append("Held whole per rank = (2 × MiB largest of 2 ranks − MiB 1 rank) / unknowns, in bytes per unknown: "
               "with R bytes held whole by every process and D distributed, 1 rank peaks at R + D and each of 2 "
               "ranks at about R + D/2, so the estimate is R (0 if nothing were replicated; the ratio would then be "
               "0.5). It also counts what a process of 2 holds beyond a serial one (MPI buffers, ghosts), the "
               "2-rank imbalance (the largest rank is taken) and each process's fixed start-up memory (libraries), "
               "which weighs on small models."
               + (" On N ranks (R + D/N each): (N × MiB largest of N ranks − MiB 1 rank) / (N − 1) / unknowns "
                  "(ratio 1/N if nothing were replicated)." if any(n != 2 for n in multi) else "") + "\n")
    lines = []
    for prob, binary in sorted({k[::2] for k in keys}, key=lambda k: (k[0] != "elastic", list(bins).index(k[1]))):
        for n in multi:
            pts = []
            for target in sorted({k[1] for k in keys if k[0] == prob and k[2] == binary}):
                one, many = runs.get((prob, target, binary, f"{solver}-1"), {}), runs.get((prob, target, binary, f"{solver}-{n}"), {})
                if held_whole(one, many) is not None:
                    pts.append((one["dofs"], (n * many["peak_rank"] - one["peak_rank"]) / (n - 1)))
            if len(pts) >= 2 and pts[-1][0] != pts[0][0]:
                (na, ra), (nb, rb_) = pts[0], pts[-1]
                lines.append(f"- {prob}, {binary}" + (f", {n} ranks" if multi != [2] else "")
                             + f": {(rb_ - ra) / (nb - na):.0f} bytes per unknown held whole per rank "
                             f"between {na:,} and {nb:,} unknowns")
    if lines:
        out.append("Between two sizes the fixed memory of a process cancels: (difference of 2 × largest of 2 − 1 "
                   "rank) / (difference of unknowns), the replicated bytes per added unknown"
                   + (" (on N ranks: of (N × largest of N − 1 rank) / (N − 1))" if any(n != 2 for n in multi) else "")
                   + ":\n")
        out += lines
        out.append("")
    out.append("Binaries: " + "; ".join(
        f"{b} = `{report.in_repository(i['path'])}` ({i['version']}, built {i['built']}"
        + (f"; its checkout's HEAD at the start {i['head']}" if i.get("head") else "")
        + (f", last commit changing src/, app/ or CMakeLists.txt before the build {i['source']}" if i.get("source") else "")
        + ")" for b, i in bins.items()) + ".\n")
    notes = [f"- {r['label']}: {r['failure']}" for r in shown if r.get("failure") and r["status"] != "converged"]
    if notes:
        out.append("Failures, as reported:\n")
        out += notes
        out.append("")
    out.append(reproduce(res, "memory", shown))
    return "\n".join(out)


def render(res: dict) -> str:
    m = res["machine"]
    out = [f"## Parallel benchmark run {res['timestamp']} ({res['date']})\n", "### Machine and run\n",
           report.machine_markdown(m, res["blas"]),
           f"- MPI and PETSc: {res['mpi']}; {res['petsc'].replace(chr(10), ', ')}",
           f"- {res['hencky_version']}, `{report.in_repository(res['hencky'])}` built "
           f"{res.get('hencky_built', '?')}" + (f" from git {res['hencky_build']['source']} (the last commit changing "
                                               "src/, app/ or CMakeLists.txt before the build)" if res.get("hencky_build") else "")
           + f"; repository HEAD {res['git']} at the start; serial runs on {res['threads']} threads; {res['seconds'] / 60:.1f} min",
           f"- command: `{report.in_repository(res['command'])}`",
           f"- load average (1 min) at the start: {res['load_start']:.2f}; other programs' CPU during each run "
           "is in the `others` columns (cores; above ~0.2 the time is disturbed)"]
    later = (res.get("hencky_build") or {}).get("later")
    if later:
        out.append("- not in the measured binary (committed after it was built, changing src/, app/ or CMakeLists.txt): "
                   + "; ".join(f"`{line[:120]}`" for line in later))
    out += [f"- **warning**: {w}" for w in res.get("warnings", [])] + [""]
    out.append("Configurations: `hencky run case.yaml` on one process (CHOLMOD; or PETSc through "
               "`solver.linear: petsc`, on one core), `mpirun -np 2 --bind-to none -x OMP_NUM_THREADS=1 hencky run` "
               "(`linear: petsc` → CG + GAMG, `linear: direct` → MUMPS). Since commit 360d72b the elastic and "
               "plastic cases run on a distributed mesh (rank 0 reads it and sends each rank its part; "
               "HENCKY_REPLICATED=1 keeps the whole mesh on every rank, as before); the element work, the matrix "
               "and the linear solve are distributed either way (docs/parallel.md).\n")
    for part, fn in (("gamg", render_gamg), ("scaling", render_scaling), ("largest", render_largest), ("ccx", render_ccx),
                     ("memory", render_memory)):
        if part in res["parts"]:
            out.append(fn(res))
    return "\n".join(out)


# ----------------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None,
                    help="hencky binary built with PETSc (default: the first of build-bench, build-f, build-release, build)")
    ap.add_argument("--parts", default=",".join(PARTS), help=f"comma separated, of {', '.join(PARTS)} (default: all)")
    ap.add_argument("--max-dofs", type=float, default=3.5e6, help="cap on every target size (default 3.5e6)")
    ap.add_argument("--gamg-sizes", default="25000,100000,400000,1600000",
                    help="gamg part: target unknowns (default 25000,100000,400000,1600000)")
    ap.add_argument("--gamg-repeat", type=int, default=1, help="gamg part: runs per size and rank count (default 1)")
    ap.add_argument("--scaling-dofs", type=float, default=400000, help="scaling part: target unknowns (default 400000)")
    ap.add_argument("--scaling-configs", default=None,
                    help="scaling part: configurations, of cholmod-<T>t, gamg-<N>, mumps-<N> (default "
                         "cholmod-<threads>t,cholmod-1t,gamg-1,gamg-2,mumps-1,mumps-2)")
    ap.add_argument("--repeat", type=int, default=3, help="scaling part: runs per configuration (default 3)")
    ap.add_argument("--largest-dofs", type=float, default=3e6, help="largest part: first target (default 3e6)")
    ap.add_argument("--largest-shrink", type=float, default=0.7, help="largest part: next target = this x the failed one")
    ap.add_argument("--largest-attempts", type=int, default=3, help="largest part: at most this many sizes (default 3)")
    ap.add_argument("--largest-timeout", type=float, default=1500, help="largest part: time limit of the run, s (default 1500)")
    ap.add_argument("--memory-sizes", default="100000,400000",
                    help="memory part: target unknowns of the elastic cylinder (default 100000,400000)")
    ap.add_argument("--memory-plastic-sizes", default="50000,100000",
                    help="memory part: target unknowns of the plastic cylinder (default 50000,100000; "
                         "its 20 Newton increments take minutes a run from ~100k up)")
    ap.add_argument("--memory-solver", choices=("gamg", "jacobi"), default="gamg",
                    help="memory part: the PETSc solver of every run (default gamg; jacobi has no multigrid set-up, "
                         "so the figures are hencky's own)")
    ap.add_argument("--memory-petsc", default="",
                    help="memory part: PETSc options added to every run (e.g. \"-matptap_via allatonce\")")
    ap.add_argument("--memory-ranks", default="1,2",
                    help="memory part: rank counts, comma separated (default 1,2; e.g. 1,2,4: --oversubscribe "
                         "above the core count)")
    ap.add_argument("--baseline-hencky", type=Path, default=None,
                    help="memory part: repeat every run with this hencky binary too (another build, compared in one run)")
    ap.add_argument("--ccx-cases", default="cylinder=100000,cantilever=100000,plastic=60000,contact=40000",
                    help="ccx part: problem=target unknowns, comma separated (cylinder, cantilever, plastic, contact)")
    ap.add_argument("--ccx-repeat", type=int, default=1, help="ccx part: runs of each program (default 1)")
    ap.add_argument("--ccx-timeout", type=float, default=900, help="time limit of one ccx run, s (default 900)")
    ap.add_argument("--timeout", type=float, default=1800, help="time limit of one hencky run, s (default 1800)")
    ap.add_argument("--rank-threads", type=int, default=1,
                    help="threads of the 1-rank PETSc runs (default 1: one core, the base of the rank speed-ups)")
    ap.add_argument("--disturbed", type=float, default=0.25,
                    help="leave runs during which other programs used more than this many cores out of the medians")
    ap.add_argument("--blas-n", type=int, default=4000, help="matrix size of the dgemm rate in the machine description")
    runner.add_common_arguments(ap)
    args = ap.parse_args()

    if args.report:
        print(render(json.loads(args.report.read_text())))
        return
    parts = [p for p in args.parts.split(",") if p]
    for p in parts:
        if p not in PARTS:
            raise SystemExit(f"--parts: unknown part {p!r} ({', '.join(PARTS)})")
    if args.no_ccx and "ccx" in parts:
        parts.remove("ccx")
        print("--no-ccx: the ccx part is left out", flush=True)
    if not shutil.which("mpirun"):
        raise SystemExit("mpirun not found (Open MPI, Debian package openmpi-bin)")
    if args.scaling_configs is None:
        args.scaling_configs = f"cholmod-{args.threads}t,cholmod-1t,gamg-1,gamg-2,mumps-1,mumps-2"
    args.timeout = args.timeout or None
    args.ccx_timeout = args.ccx_timeout or None
    if args.baseline_hencky and "memory" in parts:
        if not args.baseline_hencky.exists():
            raise SystemExit(f"--baseline-hencky: {args.baseline_hencky} not found")
        args.baseline_hencky = args.baseline_hencky.resolve()
    exe, work, stamp = runner.prepare_run(args)
    m = runner.machine_info()
    print(f"{runner.machine_line(m, exe)}; load {os.getloadavg()[0]:.2f}", flush=True)
    if args.wait_quiet > 0:
        runner.wait_quiet(args.wait_quiet)
    blas = dict(n=args.blas_n, gflops_all=runner.dgemm_rate(args.blas_n, None), gflops_1=runner.dgemm_rate(args.blas_n, 1))
    result = dict(
        timestamp=stamp, date=dt.datetime.now().astimezone().isoformat(timespec="seconds"), machine=m, blas=blas,
        mpi=runner.sh("mpirun --version 2>&1 | head -1"),
        petsc=runner.sh("dpkg-query -W -f='${Package} ${Version}\\n' 'libpetsc-real3.*-dev' 'libmumps-5*' 'libhypre-2*' 2>/dev/null"),
        **runner.program_facts(exe, list_files=True),
        hencky_built=runner.binary_stamp(exe), hencky_build=runner.build_provenance(exe),
        command=" ".join([sys.executable] + [shlex.quote(a) for a in sys.argv]), argv=sys.argv[1:],
        threads=args.threads, hencky_env=args.hencky_env, load_start=os.getloadavg()[0],
        parameters={k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()
                    if k not in ("hencky_environ",)},
        parts={}, seconds=0.0)
    jpath = args.results / f"parallel-{stamp}.json"
    mdpath = args.results / f"parallel-{stamp}.md"
    t_start = time.perf_counter()
    for part in PARTS:  # always in this order (the largest model last but for the memory part's moderate sizes)
        if part not in parts:
            continue
        t0 = time.perf_counter()
        if part == "gamg":
            result["parts"]["gamg"] = part_gamg(exe, work, args)
        elif part == "scaling":
            result["parts"]["scaling"] = part_scaling(exe, work, args)
        elif part == "ccx":
            result["parts"]["ccx"] = part_ccx(exe, work, args)
        elif part == "memory":
            result["parts"]["memory"] = part_memory(exe, work, args)
        else:
            result["parts"]["largest"] = part_largest(exe, work, args, result["parts"].get("gamg"))
        result["parts"][part]["seconds"] = time.perf_counter() - t0
        if runner.binary_stamp(exe) != result["hencky_built"]:
            result.setdefault("warnings", []).append(f"{exe} was rebuilt during the part {part} "
                                                     f"({runner.binary_stamp(exe)}): its figures may mix two builds")
        base = (result["parts"][part].get("binaries") or {}).get("baseline") if part == "memory" else None
        if base and runner.binary_stamp(Path(base["path"])) != base["built"]:
            result.setdefault("warnings", []).append(f"{base['path']} (--baseline-hencky) was rebuilt during the part "
                                                     f"{part} ({runner.binary_stamp(Path(base['path']))}): its figures may mix two builds")
        result["seconds"] = time.perf_counter() - t_start
        # written after every part: a long run that is stopped keeps what it measured
        report.write_results(jpath, mdpath, result, render(result))
        print(f"  ({part}: {result['parts'][part]['seconds'] / 60:.1f} min)", flush=True)
    md = render(result)
    mdpath.write_text(md)
    report.print_written(jpath, mdpath, md)


if __name__ == "__main__":
    main()
