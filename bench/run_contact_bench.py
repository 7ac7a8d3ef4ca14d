#!/usr/bin/python3
"""hencky contact benchmark: a rigid sphere pressed into an elastic block (Hertz), hencky and CalculiX.

The case. A rigid sphere of radius R = 100 a is pressed by a prescribed approach
delta = a^2/R (a = 1 mm, the Hertz contact radius at the end) into an elastic block,
E = 2.1e11 Pa, nu = 0.3 (run_bench's steel), in --steps (4) equal steps. Quarter model: the block
[0, L] x [0, L] x [-L, 0] with L = --block (100) a, symmetry rollers on x = 0 and y = 0, the bottom
z = -L held, the sides x = L and y = L free. 10-node tetrahedra from Gmsh (the .geo is written by
problems.geo_block) with a size field: h = h_c within r_fine = 1.2 a of the first contact point
(the origin), growing by 0.25 per unit distance outside, at most L/4. h_c sets the size: the three
default sizes are ~20k, ~60k and ~150k unknowns (h_c ~ a/5, a/11, a/17). The fill of the Cholesky
factor is that of a compact 3D mesh (the fine zone is a solid ball: 143 M factor nonzeros and
420 Gflop per factorization at 144k unknowns), so the unknowns are kept below ~150k, where one
hencky run takes ~2.5 minutes on the 2-core benchmark machine. ccx factorizes (SPOOLES) at every
one of its ~30-35 iterations: 2.7 min at ~60k (8x hencky), an estimated ~30 min at ~150k. By
default (--ccx-max-dofs 100000) it is therefore not run at the largest size; the table records
that, with the estimate (ccx's time at the largest size it ran, scaled by the ratio of hencky's
factorization flops).

hencky: `contact` with `surface: {sphere: ...}`, `motion: [0, 0, "-delta*t"]`, `nodes: top`,
stiffness auto, the default penetration (1e-3 of the element size; --penetration to change it),
solver newton with the default tolerance; fields written at the last step only. Measured: the
end-to-end wall time and peak memory (/usr/bin/time -v), the phases of summary.json
`wall_seconds` (assembly, factorization, solve, material, contact, ...), the iterations and
factorizations in total and per step (history.csv), and the contact-search fraction
wall_seconds.contact / wall_seconds.total. "Time per step" = (wall_seconds.total - mesh - setup -
output) / steps, the time of the step loop per step.

CalculiX (ccx 2.20, where installed): the same .msh converted to an .inp (C3D10, run_bench's
conversion), and the sphere as a meshed rigid body: a cap of 8-node bricks (C3D8) whose lower
nodes lie on the sphere, on a grid of spacing e = h_c/2 over [-h_c, 1.6 a]^2 (a bilinear facet lies
inside the ball, at most e^2/(4R) = delta/(16 N^2) from the sphere for h_c = a/N: 0.27 % of delta
at the coarsest size, N = 4.8, which lowers ccx's force there by ~0.3 %), all of its nodes
in a *RIGID BODY, ELSET=CAP, REF NODE=<sphere centre>, ROT NODE=<extra node>. The approach is
prescribed on the reference node (*BOUNDARY, dof 3 = -delta, ramped over the *STATIC step; dofs
1, 2 and the rotations 0); *STATIC 0.25, 1, 1e-5, 0.25 (increments of at most a quarter: the
same four steps as hencky unless ccx cuts back). Contact: *CONTACT PAIR, INTERACTION=SI,
TYPE=SURFACE TO SURFACE (face-to-face penalty contact) with the block's top faces as the slave
surface and the cap's lower faces (C3D8 face S1) as the master; *SURFACE INTERACTION with
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR and slope K = --ccx-stiffness (10) x E / h_c.
What the CalculiX manual (CalculiX.tex, the User's Manual of the ccx sources) says, and what
this uses of it:
  - *CONTACT PAIR: TYPE=NODE TO SURFACE or SURFACE TO SURFACE (or MORTAR, MASSLESS); "if you are
    using quadratic elements, or if you select face-to-face contact, the slave surface has to be
    defined based on element faces"; small sliding is the default of face-to-face contact. The
    node-to-face section advises against node-to-face contact with quadratic elements (it
    re-weights the faces' equivalent nodal forces) and recommends face-to-face penalty or mortar
    contact instead: hence SURFACE TO SURFACE here.
  - *SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR: the slope K of the pressure-overclosure
    curve (pressure/length; "usually 5 to 50 times the typical Young's modulus", i.e. per unit
    length, the default being 50 E); for face-to-face contact only the slope is used (ccx 2.20
    prints an *INFO that it takes a default tension value, irrelevant for face-to-face contact).
    hencky's kappa_0 is 10 x the element stiffness at a node, ~10 E h, over a tributary area ~h^2:
    K = 10 E/h_c is of the same order. Unlike hencky's augmented update, a plain penalty keeps an
    overlap p/K (~0.07 delta/N at the centre for h_c = a/N): it is reported (max overlap/delta)
    and makes ccx's force a little low (~1.5 x the mean overlap / delta).
  - *RIGID BODY, NSET|ELSET, REF NODE, ROT NODE: the body's motion is a translation of the
    reference node and a rotation (the ROT NODE's translations); "it is in this node that the
    resultant force is applied", and RF of the reference node on *NODE PRINT is correct when the
    reference node does not belong to the body (here it is the sphere's centre, no element).
  - Forces: *NODE PRINT, NSET=REFN with RF gives the force on the rigid body per increment
    (P = 4 |RF_z|); *CONTACT PRINT, SLAVE=TOP, MASTER=CAPS with CF prints the "statistics for
    slave set" block, the total force of a face-to-face pair on the slave surface (checked
    against RF). *CONTACT FILE with CSTR writes the nodal CONTACT block to the .frd (COPEN, the
    clearance, negative = overlap; CPRESS, the contact pressure; CDIS and CSTR come together):
    the peak pressure and the pressure profile are read from it at the last increment.
  - ccx reads a real from the first 20 characters of a data field only (nodes.f reads f20.0):
    henckybench.calculix.ccx_num keeps every number within 20 characters.
Recorded per size: ccx's wall time, peak memory, increments, iterations and factorizations (its
"iteration" and "Factoring" lines), the force, the peak pressure, the contact radius, the
largest overlap; a failed run is recorded with its *ERROR lines, a run over --ccx-timeout as a
timeout, and a size above --ccx-max-dofs as not run.

Accuracy. Hertz for a rigid sphere on an elastic half-space: E* = E/(1 - nu^2),
P = (4/3) E* sqrt(R) delta^(3/2), a = sqrt(R delta), p0 = 3P/(2 pi a^2). Compared: the total force
P (4 x the quarter's contact.ball.resultant.z of summary.json; ccx: 4 |RF_z|, per step in the
.json), the peak pressure (largest nodal contact_pressure of the last .vtu; ccx: largest nodal
CPRESS), and the contact radius and p0 from the pressure profile by this estimator (that of
tests/unit/test_verify_contact.cpp): Hertz's p^2 = p0^2 (1 - r^2/a^2) is linear in r^2, so a
least-squares line p^2 = A + B r^2 through the nodes in contact (hencky: contact_state = 1; ccx:
CPRESS > 0) with r <= 0.8 r_max gives p0 = sqrt(A) and a = sqrt(-A/B); r_max, the largest radius
of a node in contact, is the measured extent (it overshoots a by up to an element). The nodes
beyond 0.8 r_max are left out: their tributary patches straddle the edge of the contact.
The model is stiffer than Hertz's half-space in two ways that do not depend on the mesh: the
block is finite (the held bottom at depth L removes far-field compliance) and a/R = 0.01 is finite
(the gap is measured to the true sphere from the displaced nodes, whose radial displacement Hertz
neglects). docs/verification.md (section 11, VerifyContactHertz) measured ~0.9 a/L for the block
and, with a/R = 0.01, about +0.6 % on P together at L = 200 a; at L = 100 a that is ~ +1.05 % on P
(a stiffer block at a given approach presses a little deeper locally: P ~ delta^(3/2), so a and p0
move by about a third of P's share). A converged mesh should give P ~ +1 % above Hertz; the
tables also give each size against the finest hencky run.

Usage:
    /usr/bin/python3 bench/run_contact_bench.py                   # ~20k, ~60k, ~150k unknowns
    /usr/bin/python3 bench/run_contact_bench.py --sizes 20000     # the small size only
    /usr/bin/python3 bench/run_contact_bench.py --no-ccx          # hencky only
    /usr/bin/python3 bench/run_contact_bench.py --report bench/results/contact-<stamp>.json

Before the first run it waits (--wait-load, default 900 s, polling every 30 s) until the 1-minute
load average is below --load-below (1.0), and before each program run up to --wait-quiet (30 s)
until other programs use < 0.15 cores; the load and the cores other programs used during each
run ("others", /proc/stat) are recorded. Results: bench/results/contact-<stamp>.json and .md
(one table per size, hencky and ccx side by side with Hertz; both rewritten after every size).
Meshes and runs go to bench/work/ (meshes reused). Needs a Release build (bash bench/setup.sh:
build-bench/hencky). Standard library + numpy (meshio for the .vtu if installed, else the XML
of src/io/vtu_writer.cpp is read directly). The problem, the ccx input, the runs and the readers
are in the henckybench package (bench/henckybench/: problems, calculix, runs, gmsh, runner).
"""
from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path

from henckybench import calculix, gmsh, report, runner
from henckybench.problems import A, DELTA, E, GROWTH, NU, R, R_FINE, Hertz, contact_problem
from henckybench.report import fmt_err, fmt_s, mib, pct, status_cell
from henckybench.runs import contact_ccx_row, contact_hencky_row, rel_error


# ----------------------------------------------------------------------------------------------
# Benchmark
# ----------------------------------------------------------------------------------------------
def bench_size(problem: str, target: int, args, work: Path, exe: Path, hz: Hertz) -> dict:
    msh, gmsh_seconds, hc = gmsh.size_for(problem, target, work, args.threads)
    run_dir, mesh = gmsh.size_run_dir(msh, work, "contact")
    n_nodes, n_elems = int(len(mesh["node_tags"])), int(len(mesh["tets"]))
    size = dict(target_dofs=target, h_c=hc, a_over_hc=A / hc, msh=str(msh), gmsh_seconds=gmsh_seconds,
                nodes=n_nodes, elements=n_elems, dofs=3 * n_nodes)
    run_ccx = (not args.no_ccx) and shutil.which("ccx") is not None
    if run_ccx and args.ccx_max_dofs and target > args.ccx_max_dofs:
        size["ccx"] = dict(program="ccx", status="not-run",
                           failure=f"not run: target size above --ccx-max-dofs {args.ccx_max_dofs:g}")
        run_ccx = False
    info = None
    if run_ccx:
        t0 = time.perf_counter()
        info = calculix.write_contact_inp(mesh, run_dir / "job.inp", hc, args)
        size["ccx_input"] = {k: v for k, v in info.items() if k not in ("top_nodes", "top_xy")}
        size["ccx_input"]["convert_seconds"] = time.perf_counter() - t0
    del mesh
    print(f"[~{target / 1000:.0f}k unknowns] h_c = {hc:g} m = a/{A / hc:.1f}: {msh.name}, {n_nodes} nodes, "
          f"{n_elems} tetrahedra", flush=True)
    runner.quiet(args)
    h = contact_hencky_row(exe, run_dir, run_dir / msh.name, args, hz)
    size["hencky"] = h
    if h.get("dofs"):
        size["dofs"] = h["dofs"]
    ph = h.get("phases") or {}
    print(f"    hencky {h['status']:13s} wall {h['wall']:8.2f} s  peak {h['peak_rss'] / 2**20:6.0f} MiB  "
          f"it {h.get('iterations')} fact {h.get('factorizations')}  contact {ph.get('contact', 0):.3f} s "
          f"({100 * (h.get('contact_fraction') or 0):.3f} %)  P {fmt_err(h, 'P', hz.force(DELTA))}  "
          f"peak p {fmt_err(h, 'peak_pressure', hz.peak(DELTA))}; others {h['others']:.2f} cores"
          + (f"\n        {h['failure']}" if h.get("failure") else ""), flush=True)
    if run_ccx:
        runner.quiet(args)
        c = contact_ccx_row(run_dir, info, args, hz)
        size["ccx"] = c
        print(f"    ccx    {c['status']:13s} wall {c['wall']:8.2f} s  peak {c['peak_rss'] / 2**20:6.0f} MiB  "
              f"inc {c['increments']} it {c['iterations']} fact {c['factorizations']}  "
              f"P {fmt_err(c, 'P', hz.force(DELTA))}  peak p {fmt_err(c, 'peak_pressure', hz.peak(DELTA))}; "
              f"others {c['others']:.2f} cores" + (f"\n        {c['failure']}" if c.get("failure") else ""), flush=True)
    return size



# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
def size_table(size: dict, res: dict) -> str:
    hz = Hertz(res["parameters"]["R"])
    P0, a0, p00 = hz.force(DELTA), hz.radius(DELTA), hz.peak(DELTA)
    h, c = size.get("hencky") or {}, size.get("ccx")
    finest = res.get("finest_P")
    out = [f"### ~{size['target_dofs'] / 1000:.0f}k: {size['dofs']:,} unknowns, {size['elements']:,} tetrahedra "
           f"(h_c = {size['h_c']:.4g} m = a/{size['a_over_hc']:.1f})\n"]
    ls = h.get("linear_solver") or {}
    if ls.get("factor_nonzeros"):
        out.append(f"hencky's factor: {ls['factor_nonzeros'] / 1e6:.1f} M nonzeros, {ls['factor_flops'] / 1e9:.1f} Gflop "
                   f"per factorization ({ls['method']}).\n")
    cc = c if c and c.get("status") not in (None, "not-run") else None

    def cell(r, fn):
        if r is None:
            return "–"
        try:
            v = fn(r)
        except (KeyError, TypeError, ZeroDivisionError):
            return "–"
        return "–" if v is None else v

    rows = [
        ("status", lambda r: status_cell(r), "–"),
        ("wall time, end to end (s)", lambda r: fmt_s(r["wall"]), "–"),
        ("time per step (s)", lambda r: fmt_s(r["step_seconds"]) if r["program"] == "hencky" else fmt_s(r["wall"] / max(1, r["increments"])), "–"),
        ("steps / increments", lambda r: f"{r['steps']}" if r["program"] == "hencky" else f"{r['increments']}", f"{res['parameters']['steps']}"),
        ("iterations (total)", lambda r: f"{r['iterations']}", "–"),
        ("iterations per step", lambda r: " ".join(str(s["iterations"]) for s in (r["per_step"] if r["program"] == "hencky" else r["sta"])), "–"),
        ("factorizations", lambda r: f"{r['factorizations']}" + (" (" + " ".join(str(s["factorizations"]) for s in r["per_step"]) + ")" if r["program"] == "hencky" else ""), "–"),
        ("contact search / total (wall_seconds)", lambda r: f"{fmt_s(r['phases']['contact'])} s / {fmt_s(r['phases']['total'])} s = {100 * r['contact_fraction']:.3f} %" if r["program"] == "hencky" else None, "–"),
        ("peak memory (MiB)", lambda r: mib(r["peak_rss"]), "–"),
        ("total force P (N)", lambda r: f"{r['P']:.5g} ({pct(rel_error(r['P'], P0))})", f"{P0:.5g}"),
        ("P vs the finest hencky mesh", lambda r: pct(rel_error(r["P"], finest)), "–"),
        ("peak pressure (Pa, largest nodal)", lambda r: f"{r['peak_pressure']:.4g} ({pct(rel_error(r['peak_pressure'], p00))})", f"{p00:.4g}"),
        ("p0 from the p² fit (Pa)", lambda r: f"{r['fit']['p0']:.4g} ({pct(rel_error(r['fit']['p0'], p00))})", f"{p00:.4g}"),
        ("contact radius a from the p² fit (m)", lambda r: f"{r['fit']['a']:.4g} ({pct(rel_error(r['fit']['a'], a0))})", f"{a0:.4g}"),
        ("largest radius in contact r_max (m)", lambda r: f"{r['fit']['r_max']:.4g} ({pct(rel_error(r['fit']['r_max'], a0))})", f"{a0:.4g}"),
        ("nodes in contact (quarter)", lambda r: f"{r['contact_nodes']}", "–"),
        ("largest penetration / δ", lambda r: (f"{r['max_penetration'] / DELTA:.1e}" if r["program"] == "hencky" else f"{r['max_overlap'] / DELTA:.2e} (penalty)"), "0"),
        ("others (cores) / load before", lambda r: f"{r['others']:.2f} / {r['load_before']:.2f}", "–"),
    ]
    out.append("| | hencky | ccx | Hertz |")
    out.append("|---|---:|---:|---:|")
    for name, fn, ref in rows:
        out.append(f"| {name} | {cell(h, fn)} | {cell(cc, fn) if cc else ('not run' if c and c.get('status') == 'not-run' else '–')} | {ref} |")
    out.append("")
    ph = h.get("phases")
    if ph:
        keys = ("mesh", "setup", "assembly", "factorization", "solve", "material", "contact", "output")
        known = sum(ph.get(k, 0) for k in keys)
        its = max(1, h.get("iterations") or 1)
        fac = max(1, h.get("factorizations") or 1)
        out.append("hencky phases (wall_seconds, s; share of `total`): "
                   + ", ".join(f"{k} {fmt_s(ph.get(k, 0))} ({100 * ph.get(k, 0) / ph['total']:.1f} %)" for k in keys)
                   + f", rest {fmt_s(ph['total'] - known)}; total {fmt_s(ph['total'])}. Per factorization (the matrix is "
                   f"assembled only for one): assembly {1000 * ph['assembly'] / fac:.0f} ms, factorization "
                   f"{1000 * ph['factorization'] / fac:.0f} ms; per iteration: material (stresses and internal "
                   f"forces) {1000 * ph['material'] / its:.0f} ms, solve {1000 * ph['solve'] / its:.0f} ms.\n")
    per = h.get("per_step") or []
    if per:
        cper = {round(s["t"], 9): s for s in (cc or {}).get("per_step") or []}
        out.append("Force per step (P vs Hertz at the step's approach): "
                   + "; ".join(f"t = {s['t']:g}: hencky {pct(s['P_error'])}"
                               + (f", ccx {pct(cper[round(s['t'], 9)]['P_error'])}" if round(s["t"], 9) in cper else "")
                               for s in per) + ".\n")
    facts = h.get("log_facts") or {}
    if facts:
        bal = h.get("balance")
        out.append(f"hencky log: {facts.get('contact_line') or ''}; the contact set changed in {facts.get('set_changed')} "
                   f"iterations, κ raised in {facts.get('kappa_raised')}, cut-backs {len(facts.get('cutbacks') or [])}, "
                   f"oscillation messages {facts.get('oscillations')}"
                   + (f"; |reaction(bottom) + contact resultant| = {bal:.1e} of the resultant (z)" if bal is not None else "")
                   + ".\n")
    notes = [f"- {name}: {r['failure']}" for name, r in (("hencky", h), ("ccx", c)) if r and r.get("failure")]
    if notes:
        out.append("Failures, as the programs report them:\n")
        out += notes
        out.append("")
    if cc and cc.get("P_cf") is not None:
        out.append(f"ccx: P from the rigid body's RF {cc['P']:.6g} N, from *CONTACT PRINT CF {cc['P_cf']:.6g} N; penalty "
                   f"K = {cc['K']:.3g} Pa/m = {res['parameters']['ccx_stiffness']:g} E/h_c.\n")
    return "\n".join(out)


def render(res: dict) -> str:
    p, m = res["parameters"], res["machine"]
    hz = Hertz(p["R"])
    out = [f"## Contact benchmark run {res['timestamp']} (Hertz: rigid sphere on an elastic block)\n"]
    out.append(f"- machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; "
               f"{m['os']}; CalculiX {m['ccx'] or 'not installed'}; Gmsh {m['gmsh']}")
    out.append(f"- {res['hencky_version']} (git {res['git']}), `{res['hencky']}`, {res['threads']} threads; "
               f"{res['seconds'] / 60:.1f} min; `{report.in_repository(res['command'])}`")
    lw = res.get("load_wait") or {}
    if lw:
        out.append(f"- 1-min load average at the start: {lw['load']:.2f} after waiting {lw['waited']:.0f} s "
                   f"({'below' if lw['met'] else '**not** below'} {p['load_below']:g})")
    out.append("")
    out.append(
        f"**Problem.** A rigid sphere R = {p['R']:g} m pressed by δ = {DELTA:g} m (`motion`, {p['steps']} equal steps) into "
        f"an elastic block (E = {E:.3g} Pa, ν = {NU}); quarter model [0, L]² × [−L, 0], L = {p['block']:g} a = "
        f"{p['block'] * A:g} m, rollers on x = 0 and y = 0, bottom held, sides free; 10-node tetrahedra "
        f"(Gmsh), h = h_c within {R_FINE / A:g} a of the contact point, growing by {GROWTH} per unit distance, at "
        f"most L/4. Hertz (rigid sphere, elastic half-space, E* = E/(1 − ν²)): P = (4/3)E*√R δ^3/2 = "
        f"{hz.force(DELTA):.5g} N, a = √(Rδ) = {hz.radius(DELTA):.4g} m (a/R = {hz.radius(DELTA) / p['R']:g}), "
        f"p0 = 3P/(2πa²) = {hz.peak(DELTA):.5g} Pa. hencky: stiffness auto, penetration "
        f"{p['penetration'] or 'default (1e-3)'}, newton, tolerance 1e-6 (default). ccx: the same .msh (C3D10), "
        f"the sphere as a rigid cap of C3D8 bricks (grid h_c/2, *RIGID BODY, approach on its reference node), "
        f"*CONTACT PAIR TYPE=SURFACE TO SURFACE, PRESSURE-OVERCLOSURE=LINEAR with K = {p['ccx_stiffness']:g} E/h_c, "
        f"*STATIC with increments ≤ 1/{p['steps']}.\n")
    out.append(
        "**Expected differences from Hertz.** The block is finite (bottom held at depth L) and a/R = "
        f"{hz.radius(DELTA) / p['R']:g} is finite: both make the model stiffer than the half-space, independently "
        f"of the mesh — about +0.9 a/L on P from the block (+{0.9 / p['block'] * 100:.2f} % here) and ~+0.15 % from "
        "a/R = 0.01 (docs/verification.md, section 11: +0.6 % together at L = 200 a), so ≈ +1 % on P and about a "
        "third of that on a and p0 on a converged mesh. A coarse mesh carries less force (the edge of the contact is resolved late). "
        "'P vs the finest hencky mesh' compares each size with the largest one. ccx's plain penalty leaves an "
        "overlap (reported) that lowers its force by ~1.5 × the mean overlap/δ.\n")
    out.append(
        "**Columns.** Wall time: whole process (`/usr/bin/time -v`), one run each. Time per step: hencky "
        "(wall_seconds.total − mesh − setup − output)/steps; ccx wall/increments. Iterations/factorizations: "
        "hencky summary.json and history.csv (per step); ccx its \"iteration\" and \"Factoring\" lines. Contact "
        "search fraction: wall_seconds.contact / wall_seconds.total (contact search and node-state updates; the "
        "contact matrix and forces' assembly into the system are in `assembly`). Peak pressure: the largest nodal "
        "value (hencky `contact_pressure` of the last .vtu; ccx nodal CPRESS of the last .frd CONTACT block). p0 "
        "and a: least-squares line p² = A + B r² through the nodes in contact with r ≤ 0.8 r_max (p0 = √A, "
        "a = √(−A/B)); r_max is the largest radius of a node in contact. Others: cores used by other programs "
        "during the run (/proc/stat; above ~0.2 the time is disturbed).\n")
    for size in res["sizes"]:
        out.append(size_table(size, res))
    return "\n".join(out)


def finalize(res: dict):
    """The finest converged hencky force (for the 'vs the finest mesh' row), and for a size at
    which ccx was not run, an estimate of its time: ccx's wall time at the largest size it
    completed, times the ratio of hencky's factorization flops (ccx factorizes at every
    iteration, and its iterations vary little with the size)."""
    ok = [s for s in res["sizes"] if (s.get("hencky") or {}).get("status") == "converged" and s["hencky"].get("P")]
    res["finest_P"] = max(ok, key=lambda s: s["dofs"])["hencky"]["P"] if ok else None
    flops = lambda s: ((s.get("hencky") or {}).get("linear_solver") or {}).get("factor_flops")
    done = [s for s in res["sizes"] if (s.get("ccx") or {}).get("status") == "converged" and flops(s)]
    for s in res["sizes"]:
        c = s.get("ccx") or {}
        if c.get("status") == "not-run" and done and flops(s):
            ref = max(done, key=lambda x: x["dofs"])
            est = ref["ccx"]["wall"] * flops(s) / flops(ref)
            c["estimated_wall"] = est
            c["failure"] = (c["failure"].split(";")[0] + f"; estimated ccx time ≈ {est / 60:.0f} min (its "
                            f"{ref['ccx']['wall']:.0f} s at {ref['dofs']:,} unknowns × the ratio of hencky's "
                            f"factorization flops, {flops(s) / flops(ref):.1f})")


# ----------------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None,
                    help="hencky binary (default: the first of build-bench, build-f, build-release, build)")
    ap.add_argument("--sizes", default="20000,60000,150000",
                    help="target unknowns, comma separated (default 20000,60000,150000)")
    ap.add_argument("--steps", type=int, default=4, help="load steps (default 4)")
    ap.add_argument("--linear", choices=("auto", "direct", "iterative", "petsc"), default="auto",
                    help="hencky solver.linear (default auto, hencky's default)")
    ap.add_argument("--block", type=float, default=100.0, help="block size L in contact radii a (default 100)")
    ap.add_argument("--penetration", type=float, default=None,
                    help="hencky contact penetration (default: hencky's default, 1e-3 of the element size)")
    ap.add_argument("--ccx-stiffness", type=float, default=10.0,
                    help="ccx pressure-overclosure slope K in units of E/h_c (default 10)")
    ap.add_argument("--timeout", type=float, default=900, help="time limit of one hencky run, s (default 900); 0: none")
    ap.add_argument("--ccx-timeout", type=float, default=1800, help="time limit of one ccx run, s (default 1800); 0: none")
    ap.add_argument("--ccx-max-dofs", type=float, default=100000,
                    help="run ccx only up to this target size (default 100000: not at ~150k, ~30 min; 0: all)")
    ap.add_argument("--wait-load", type=float, default=900.0,
                    help="before the runs wait up to this many seconds for the 1-min load to drop below --load-below (0: never)")
    ap.add_argument("--load-below", type=float, default=1.0, help="see --wait-load (default 1.0)")
    runner.add_common_arguments(ap)
    args = ap.parse_args()

    if args.report:
        print(render(json.loads(args.report.read_text())))
        return
    args.timeout = args.timeout or None
    args.ccx_timeout = args.ccx_timeout or None
    if args.timeout and not shutil.which("timeout"):
        raise SystemExit("coreutils' timeout not found")
    if not args.no_ccx and not shutil.which("ccx"):
        print("ccx not found (Debian package calculix-ccx, bash bench/setup.sh): CalculiX is skipped", flush=True)
        args.no_ccx = True

    exe, work, stamp = runner.prepare_run(args)
    problem = contact_problem(args.block)
    hz = Hertz(R)
    m = runner.machine_info()
    print(runner.machine_line(m, exe), flush=True)
    print(f"Hertz: P = {hz.force(DELTA):.6g} N, a = {hz.radius(DELTA):.6g} m, p0 = {hz.peak(DELTA):.6g} Pa "
          f"(R = {R:g} m, δ = {DELTA:g} m, block L = {args.block:g} a)", flush=True)
    sizes = runner.parse_sizes(args.sizes)
    # meshes first (Gmsh is not timed), then wait for a quiet machine
    for target in sizes:
        gmsh.size_for(problem, target, work, args.threads)
    load_wait = None
    if args.wait_load > 0:
        load_wait = runner.wait_load(args.wait_load, args.load_below)
        print(f"1-min load {load_wait['load']:.2f} after {load_wait['waited']:.0f} s"
              + ("" if load_wait["met"] else f" (not below {args.load_below:g}: running anyway, the load is recorded)"), flush=True)
    t_start = time.perf_counter()
    result = dict(
        timestamp=stamp, machine=m, **runner.program_facts(exe),
        command=" ".join([sys.executable] + sys.argv), threads=args.threads, hencky_env=args.hencky_env,
        load_wait=load_wait,
        parameters=dict(E=E, nu=NU, R=R, delta=DELTA, a=A, block=args.block, r_fine=R_FINE, growth=GROWTH,
                        steps=args.steps, penetration=args.penetration, ccx_stiffness=args.ccx_stiffness,
                        timeout=args.timeout, ccx_timeout=args.ccx_timeout, ccx_max_dofs=args.ccx_max_dofs,
                        load_below=args.load_below),
        hertz=dict(P=hz.force(DELTA), a=hz.radius(DELTA), p0=hz.peak(DELTA)),
        sizes=[], seconds=0.0)
    jpath = args.results / f"contact-{stamp}.json"
    mdpath = args.results / f"contact-{stamp}.md"
    for target in sizes:
        result["sizes"].append(bench_size(problem, target, args, work, exe, hz))
        result["seconds"] = time.perf_counter() - t_start
        finalize(result)
        # written after every size: a long run that is stopped keeps what it measured
        report.write_results(jpath, mdpath, result, render(result))
    report.print_written(jpath, mdpath, render(result))


if __name__ == "__main__":
    main()
