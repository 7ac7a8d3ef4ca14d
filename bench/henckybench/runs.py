"""One run of a benchmark problem, measured: hencky or ccx run, what it wrote read back, and the
result row that the scripts keep (status, failure, iterations, the compared values).

The hencky rows take `run`, the function that runs hencky (runner.run_hencky's signature and
result): run_parallel_bench.py passes one that runs the same case in a solver configuration
(PETSc, mpirun).
"""
from __future__ import annotations

import math
import re
import shutil
import time
from pathlib import Path
from typing import Callable

import numpy as np

from .calculix import ccx_counts, ccx_dat_blocks, ccx_dat_displacements, ccx_sta, ccx_status, frd_last_contact, run_ccx
from .problems import A, DELTA, PROBLEMS, Hertz, Hill, contact_case, plastic_case, radial_reference
from .runner import history_rows, reached_time, read_vtu, remove_partial, run_hencky

RunHencky = Callable[..., dict]


def rel_error(value: float | None, exact: float | None) -> float | None:
    """(value - exact) / exact; None without a value or a (nonzero) reference."""
    if value is None or not exact:
        return None
    return (value - exact) / exact


def probe_value(problem: str, summary: dict) -> float:
    """The compared value of an elastic problem of PROBLEMS: sign * u[component] at the probe of
    hencky's summary.json."""
    comp, sign = PROBLEMS[problem]["sign"]
    return sign * summary["probes"]["probe"]["displacement"]["xyz"[comp]]


def hencky_failure(r: dict, timeout: float | None) -> dict:
    """status and failure of a hencky run that wrote no summary.json: killed by the time limit,
    or crashed."""
    return dict(status="timeout" if r["timed_out"] else "error",
                failure=(f"killed after the time limit of {timeout:g} s" if r["timed_out"]
                         else f"exit status {r['rc']} without summary.json, see {r['log']}"))


# ----------------------------------------------------------------------------------------------
# Plastic cylinder (run_plastic_bench.py)
# ----------------------------------------------------------------------------------------------
def variants(args) -> list[dict]:
    """The material variants of a run: perfect (args.schemes) and, with args.hardening > 0 and
    args.hardening_schemes, the linear hardening one; ccx on each unless args.no_ccx."""
    vs = [dict(name="perfect", hardening=0.0, schemes=args.schemes, ccx=not args.no_ccx)]
    if args.hardening > 0 and args.hardening_schemes:
        vs.append(dict(name="hardening", hardening=args.hardening, schemes=args.hardening_schemes,
                       ccx=not args.no_ccx))
    return vs


def references(args) -> dict:
    """u(b) and u(a) at the end of the ramp: Hill (perfect plasticity only) and the 1D solution
    (same increments), for each material variant."""
    out = {}
    hill = Hill()
    for v in variants(args):
        t0 = time.perf_counter()
        hist = radial_reference(args.p_end, args.steps, v["hardening"], n_el=args.ref_elements)
        coarse = radial_reference(args.p_end, args.steps, v["hardening"], n_el=args.ref_elements // 2)
        out[v["name"]] = dict(
            hardening=v["hardening"],
            hill=hill.u_outer(args.p_end) if v["hardening"] == 0 else None,
            hill_front=hill.c_of_p(args.p_end) if v["hardening"] == 0 else None,
            u_outer=hist[-1][1], u_bore=hist[-1][0],
            u_outer_half_mesh=coarse[-1][1],
            elements=args.ref_elements, seconds=time.perf_counter() - t0)
    return out


def plastic_hencky_row(exe, run_dir: Path, msh: Path, scheme: str, variant: dict, args,
                       run: RunHencky = run_hencky) -> dict:
    """hencky with `scheme` on the material `variant` (case-<variant>-<scheme>.yaml next to the
    mesh): status (not-converged when it stopped before the end of the ramp), iterations,
    factorizations, u(b) and u(a); for a run killed or crashed, what its converged steps wrote."""
    case = run_dir / f"case-{variant['name']}-{scheme}.yaml"
    case.write_text(plastic_case(msh, scheme, variant, args))
    out = run_dir / f"hencky-{variant['name']}-{scheme}.out"
    remove_partial(out)
    r = run(exe, case, out, args.threads, args.hencky_environ, timeout=args.timeout, check=False)
    s = r["summary"]
    row = dict(program="hencky", scheme=scheme, material=variant["name"], wall=r["wall"],
               peak_rss=r["peak_rss"], cpu=r["cpu"], others=r["others"], rc=r["rc"], log=r["log"])
    if s is not None:
        row.update(status=s["status"], failure=s.get("failure"), iterations=s["iterations"],
                   factorizations=s["factorizations"], steps=s["steps"], dofs=s["dofs"],
                   nodes=s["nodes"], elements=s["elements"],
                   phases=s["wall_seconds"], linear_solver=s["linear_solver"],
                   reached=reached_time(out / "history.csv"))
        pr = s.get("probes") or {}
        if pr.get("outer"):
            row["u_outer"] = pr["outer"]["displacement"]["x"]
            row["u_bore"] = pr["bore"]["displacement"]["x"]
    else:
        # killed (time limit) or crashed: what the steps converged so far wrote to the
        # unfinished output folder (iterations of those steps only)
        partial = sorted(run_dir.glob(out.name + ".partial-*"))
        rows = history_rows(partial[-1] / "history.csv") if partial else []
        failed = hencky_failure(r, args.timeout)
        row.update(status=failed["status"],
                   reached=float(rows[-1][1]) if rows else None,
                   iterations=sum(int(x[2]) for x in rows) if rows else None,
                   failure=failed["failure"])
    if row["status"] == "converged" and row.get("reached") is not None and abs(row["reached"] - 1.0) > 1e-9:
        row["status"] = "not-converged"
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
        remove_partial(out)
    return row


def plastic_ccx_row(run_dir: Path, job: str, info: dict, variant: dict, args) -> dict:
    """ccx on the input `job`.inp written by calculix.write_plastic_inp (which returned `info`)."""
    c = run_ccx(run_dir, job, args.threads, timeout=args.ccx_timeout, check=False)
    counts = ccx_counts(c["text"], run_dir, job)
    blocks = ccx_dat_displacements(run_dir / f"{job}.dat")
    last_t = max(blocks) if blocks else None
    row = dict(program="ccx", scheme="ccx", material=variant["name"], wall=c["wall"],
               peak_rss=c["peak_rss"], cpu=c["cpu"], others=c["others"], rc=c["rc"], log=c["log"],
               iterations=counts["iterations"], factorizations=counts["factorizations"],
               increments=counts["increments"], reached=counts["total_time"], inp=info,
               reported_seconds=c.get("ccx_reported_seconds"), phases=None)
    row.update(ccx_status(c, last_t, args.ccx_timeout))
    if last_t is not None:
        u = blocks[last_t]
        if info["outer_node"] in u:
            row["u_outer"] = u[info["outer_node"]][0]
        if info["bore_node"] in u:
            row["u_bore"] = u[info["bore_node"]][0]
    if not args.keep_output:
        (run_dir / f"{job}.frd").unlink(missing_ok=True)
    return row


# ----------------------------------------------------------------------------------------------
# Hertz contact (run_contact_bench.py)
# ----------------------------------------------------------------------------------------------
def fit_pressure(xy: np.ndarray, p: np.ndarray, in_contact: np.ndarray, cut: float = 0.8) -> dict:
    """p0 and a of a contact centred on the z axis: least-squares line p^2 = A + B r^2 through the
    nodes in contact with r <= cut * r_max (r_max: the largest radius of a node in contact)."""
    r = np.hypot(xy[:, 0], xy[:, 1])[in_contact]
    pc = p[in_contact]
    if len(r) < 3:
        return dict(p0=None, a=None, r_max=float(r.max()) if len(r) else None, used=int(len(r)))
    r_max = float(r.max())
    sel = r <= cut * r_max
    if sel.sum() < 3:
        return dict(p0=None, a=None, r_max=r_max, used=int(sel.sum()))
    B, A_ = np.polyfit(r[sel] ** 2, pc[sel] ** 2, 1)
    ok = A_ > 0 and B < 0
    return dict(p0=float(math.sqrt(A_)) if A_ > 0 else None, a=float(math.sqrt(-A_ / B)) if ok else None,
                r_max=r_max, used=int(sel.sum()), nodes=int(in_contact.sum()))


def hencky_log_facts(log: Path) -> dict:
    """What hencky.log says about the contact iterations: the κ range, how often the contact set
    changed, κ was raised, a step was cut back or the set oscillated; the per-step contact lines."""
    if not log.exists():
        return {}
    text = log.read_text(errors="replace")
    lines = text.splitlines()
    m = re.search(r"κ auto ([\d.e+-]+) \.\. ([\d.e+-]+)", text)
    return dict(
        kappa_range=[float(m.group(1)), float(m.group(2))] if m else None,
        contact_line=next((l.strip() for l in lines if l.startswith("contact '")), None),
        set_changed=sum("set changed" in l for l in lines),
        kappa_raised=sum("κ raised" in l for l in lines),
        cutbacks=[l.strip() for l in lines if "cutting back" in l],
        oscillations=sum("oscillat" in l for l in lines),
        step_lines=[l.strip() for l in lines if re.match(r"\s+contact '", l)],
        last_lines=[l.rstrip() for l in lines[-6:]],
    )


def contact_hencky_row(exe: Path, run_dir: Path, msh: Path, args, hz: Hertz, run: RunHencky = run_hencky) -> dict:
    """hencky on the Hertz case (case.yaml next to the mesh): status, iterations, phases, the
    contact-search share, the force P (4 x the quarter's resultant) per step against Hertz, the
    peak pressure and the p² fit of the last .vtu, the facts of hencky.log."""
    case = run_dir / "case.yaml"
    case.write_text(contact_case(msh, args))
    out = run_dir / "hencky.out"
    remove_partial(out)
    r = run(exe, case, out, args.threads, args.hencky_environ, timeout=args.timeout, check=False)
    s = r["summary"]
    row = dict(program="hencky", wall=r["wall"], peak_rss=r["peak_rss"], cpu=r["cpu"], others=r["others"],
               load_before=r["load_before"], rc=r["rc"], log=r["log"])
    log_dir = out if out.exists() else next(iter(sorted(run_dir.glob(out.name + ".partial-*"))), out)
    row["log_facts"] = hencky_log_facts(log_dir / "hencky.log")
    if s is None:
        row.update(hencky_failure(r, args.timeout))
        hist = history_rows(log_dir / "history.csv")
        row["steps_done"] = len(hist)
    else:
        w = s["wall_seconds"]
        row.update(status=s["status"], failure=s.get("failure"), steps=s["steps"], iterations=s["iterations"],
                   factorizations=s["factorizations"], dofs=s["dofs"], nodes=s["nodes"],
                   elements=s["elements"], phases=w, linear_solver=s["linear_solver"],
                   peak_memory_bytes=s.get("peak_memory_bytes"), threads=s.get("threads"),
                   contact_fraction=w.get("contact", 0.0) / w["total"] if w.get("total") else None,
                   step_seconds=(w["total"] - w["mesh"] - w["setup"] - w["output"]) / max(1, s["steps"]))
        c = (s.get("contact") or {}).get("ball") or {}
        if c:
            row["P"] = -4 * c["resultant"]["z"]
            row["contact_nodes"] = c["nodes"]
            row["max_penetration"] = c["max_penetration"]
            row["max_pressure_summary"] = c.get("max_pressure")  # summary.json, newer hencky
        bottom = (s.get("reactions") or {}).get("bottom")
        if bottom and c:
            # the held bottom and the support balance (to the residual)
            row["balance"] = abs(bottom["z"] + c["resultant"]["z"]) / abs(c["resultant"]["z"])
        # per step, from history.csv
        hist_path = out / "history.csv"
        if hist_path.exists():
            lines = hist_path.read_text().splitlines()
            head = lines[0].split(",")
            col = {n: k for k, n in enumerate(head)}
            per = []
            for l in lines[1:]:
                v = l.split(",")
                t = float(v[col["time"]])
                P = -4 * float(v[col["contact.ball.resultant.z"]])
                per.append(dict(t=t, iterations=int(v[col["iterations"]]), factorizations=int(v[col["factorizations"]]),
                                P=P, P_error=P / hz.force(DELTA * t) - 1, nodes=int(float(v[col["contact.ball.nodes"]])),
                                max_penetration=float(v[col["contact.ball.max_penetration"]])))
            row["per_step"] = per
        vtus = sorted(out.glob("step_*.vtu"))
        if vtus and row.get("P") is not None:
            f = read_vtu(vtus[-1], ("contact_pressure", "contact_state"))
            pts, p, st = f["Points"], f["contact_pressure"], f["contact_state"]
            top = np.abs(pts[:, 2]) < 1e-9 * A
            row["peak_pressure"] = float(p.max())
            row["peak_pressure_node"] = [float(x) for x in pts[int(np.argmax(p))]]
            row["fit"] = fit_pressure(pts[:, :2], p, (st == 1) & top)
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
        remove_partial(out)
    return row


def contact_ccx_row(run_dir: Path, info: dict, args, hz: Hertz) -> dict:
    """ccx on job.inp written by calculix.write_contact_inp (which returned `info`): status,
    increments, iterations, the force per increment (the rigid body's RF and *CONTACT PRINT's
    CF), the peak pressure, the largest overlap and the p² fit of the last .frd CONTACT block."""
    c = run_ccx(run_dir, "job", args.threads, timeout=args.ccx_timeout, check=False)
    counts = ccx_counts(c["text"], run_dir, "job")
    dat = run_dir / "job.dat"
    rf = ccx_dat_blocks(dat, "forces (fx,fy,fz) for set REFN")
    cf = ccx_dat_blocks(dat, "statistics for slave set", skip_to="total surface force")
    row = dict(program="ccx", wall=c["wall"], peak_rss=c["peak_rss"], cpu=c["cpu"], others=c["others"],
               load_before=c["load_before"], rc=c["rc"], log=c["log"], iterations=counts["iterations"],
               factorizations=counts["factorizations"], increments=counts["increments"],
               reached=counts["total_time"], reported_seconds=c.get("ccx_reported_seconds"),
               K=info["K"], cpus=c.get("cpus"))
    last_t = max(rf) if rf else None
    row.update(ccx_status(c, last_t, args.ccx_timeout))
    # RF lines: node, fx, fy, fz; CF lines: fx, fy, fz, mx, my, mz (quarter model: P = 4 |fz|)
    row["per_step"] = [dict(t=t, P=4 * abs(v[3]), P_error=4 * abs(v[3]) / hz.force(DELTA * t) - 1,
                            P_cf=4 * abs(cf[t][2]) if t in cf else None)
                       for t, v in sorted(rf.items()) if len(v) >= 4]
    row["sta"] = ccx_sta(run_dir / "job.sta")
    if last_t is not None:
        row["P"] = row["per_step"][-1]["P"]
        row["P_cf"] = row["per_step"][-1]["P_cf"]
    t_frd, cont = frd_last_contact(run_dir / "job.frd")
    if cont:
        nodes = np.array(info["top_nodes"])
        xy = np.array(info["top_xy"])
        vals = np.array([cont.get(int(k), (0.0, 0.0)) for k in nodes])
        copen, press = vals[:, 0], vals[:, 1]
        row["frd_time"] = t_frd
        row["peak_pressure"] = float(press.max())
        row["peak_pressure_node"] = [float(x) for x in xy[int(np.argmax(press))]]
        row["max_overlap"] = float(max(0.0, -copen.min()))
        row["fit"] = fit_pressure(xy, press, press > 0)
        row["contact_nodes"] = int((press > 0).sum())
    if not args.keep_output:
        (run_dir / "job.frd").unlink(missing_ok=True)
    return row
