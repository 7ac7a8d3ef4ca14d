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
Uses bench/run_bench.py's mesh, conversion and run functions. Standard library + numpy only.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run_bench as rb  # noqa: E402

ROOT, BENCH = rb.ROOT, rb.BENCH

# ----------------------------------------------------------------------------------------------
# Problem
# ----------------------------------------------------------------------------------------------
E, NU = rb.E, rb.NU
SY = 240e6  # yield stress, Pa
A_IN, B_OUT = rb.CYL["a"], rb.CYL["b"]
SCHEMES = ["newton", "variable-stiffness", "initial-strain", "initial-strain-stiffness",
           "initial-stress", "initial-stress-stiffness"]
# A scheme name with "+anderson" runs that scheme with `solver.acceleration: anderson`.
ACCELERATED = ["initial-stress+anderson", "initial-stress-stiffness+anderson"]


def limit_pressure(sy: float = SY, a: float = A_IN, b: float = B_OUT) -> float:
    return 2 * sy / math.sqrt(3) * math.log(b / a)


class Hill:
    """Elastic-perfectly-plastic thick cylinder, plane strain, with the plastic front at r = c
    (tests/unit/test_verify_plastic.cpp, class Hill): with k = sigma_y/sqrt(3)
    p(c) = k (1 - c^2/b^2 + 2 ln(c/a)), p_L = 2k ln(b/a), u(b) = 2(1 - nu^2) k c^2 / (E b)."""

    def __init__(self, a=A_IN, b=B_OUT, E=E, nu=NU, sy=SY):
        self.a, self.b, self.E, self.nu, self.sy = a, b, E, nu, sy
        self.k = sy / math.sqrt(3)

    def p_of_c(self, c):
        return self.k * (1 - c * c / self.b**2 + 2 * math.log(c / self.a))

    def c_of_p(self, p):
        lo, hi = self.a, self.b
        for _ in range(200):
            m = 0.5 * (lo + hi)
            if self.p_of_c(m) < p:
                lo = m
            else:
                hi = m
        return 0.5 * (lo + hi)

    def u_outer(self, p):
        a, b, nu, E = self.a, self.b, self.nu, self.E
        if p <= self.p_of_c(a):  # elastic (Lamé)
            return p * a * a * 2 * (1 - nu * nu) / (E * (b * b - a * a)) * b
        c = self.c_of_p(p)
        return 2 * (1 - nu * nu) * self.k * c * c / (E * b)


def radial_reference(p_end: float, steps: int, hardening: float = 0.0, n_el: int = 200,
                     a=A_IN, b=B_OUT, E=E, nu=NU, sy=SY, tol=1e-10) -> list[tuple[float, float]]:
    """The cylinder along the radius: u = u(r), strains (du/dr, u/r, 0) (plane strain), von Mises
    with linear isotropic hardening `hardening` (0: perfect), the pressure ramped to p_end in
    `steps` equal increments; n_el quadratic elements (3 Gauss points, weight r dr), radial
    return and Newton with the consistent tangent. Returns (u(a), u(b)) after each increment."""
    H = hardening
    G = E / (2 * (1 + nu))
    K = E / (3 * (1 - 2 * nu))
    D = (K - 2 * G / 3) * np.ones((3, 3)) + 2 * G * np.eye(3)
    one = np.ones(3)
    Idev = np.eye(3) - np.outer(one, one) / 3
    r_nodes = np.linspace(a, b, 2 * n_el + 1)
    n = len(r_nodes)
    gx, gw = np.polynomial.legendre.leggauss(3)
    conn = np.array([[2 * e, 2 * e + 1, 2 * e + 2] for e in range(n_el)])
    N = np.stack([gx * (gx - 1) / 2, 1 - gx**2, gx * (gx + 1) / 2], axis=1)  # (point, node)
    dN = np.stack([gx - 0.5, -2 * gx, gx + 0.5], axis=1)
    xe = r_nodes[conn]
    r_gp = xe @ N.T
    J = xe @ dN.T
    w = gw[None, :] * J * r_gp
    B = np.zeros((n_el, 3, 3, 3))  # (element, point, strain component r/theta/z, node)
    B[:, :, 0, :] = dN[None, :, :] / J[:, :, None]
    B[:, :, 1, :] = N[None, :, :] / r_gp[:, :, None]
    ep = np.zeros((n_el, 3, 3))
    alpha = np.zeros((n_el, 3))
    u = np.zeros(n)
    history = []

    def material(eps):
        s_tr = (eps - ep) @ D.T
        dev = s_tr - s_tr.mean(axis=2, keepdims=True)
        nrm = np.sqrt((dev**2).sum(axis=2))
        q = math.sqrt(1.5) * nrm
        f = q - (sy + H * alpha)
        C = np.broadcast_to(D, eps.shape[:2] + (3, 3)).copy()
        sig, ep_new, al_new = s_tr.copy(), ep.copy(), alpha.copy()
        pl = f > 0
        if pl.any():
            dg = f[pl] / (3 * G + H)
            nh = dev[pl] / nrm[pl][:, None]
            sig[pl] = s_tr[pl] - 2 * G * math.sqrt(1.5) * dg[:, None] * nh
            ep_new[pl] = ep[pl] + math.sqrt(1.5) * dg[:, None] * nh
            al_new[pl] = alpha[pl] + dg
            C[pl] = (K * np.outer(one, one)[None]
                     + (2 * G * (1 - 3 * G * dg / q[pl]))[:, None, None] * Idev[None]
                     + (6 * G * G * (dg / q[pl] - 1 / (3 * G + H)))[:, None, None]
                     * np.einsum("pi,pj->pij", nh, nh))
        return sig, ep_new, al_new, C

    for k in range(1, steps + 1):
        f_ext = np.zeros(n)
        f_ext[0] = p_end * k / steps * a
        for it in range(100):
            eps = np.einsum("egcn,en->egc", B, u[conn])
            sig, ep_new, al_new, C = material(eps)
            fint = np.zeros(n)
            np.add.at(fint, conn, np.einsum("egcn,egc,eg->en", B, sig, w))
            res = f_ext - fint
            if it > 0 and np.linalg.norm(res) <= tol * np.linalg.norm(f_ext):
                break
            Ke = np.einsum("egci,egcd,egdj,eg->eij", B, C, B, w)
            Kg = np.zeros((n, n))
            np.add.at(Kg, (conn[:, :, None], conn[:, None, :]), Ke)
            u = u + np.linalg.solve(Kg, res)
        else:
            raise RuntimeError("1D reference: Newton did not converge")
        ep, alpha = ep_new, al_new
        history.append((float(u[0]), float(u[-1])))
    return history


def geo_slice(h: float, layers: int) -> str:
    """The quarter ring a < r < b meshed in its plane (triangles of size h) and extruded in z by
    `layers` layers of thickness h: a slice layers*h thick whose tetrahedra have about the same
    size in every direction. Refining keeps the slice `layers` elements thick, so the unknowns
    grow as h^-2 and the factorization's fill as that of a 2D mesh. run_bench's cylinder
    geometry and physical groups."""
    return rb.geo_cylinder(h, dict(rb.CYL, Lz=layers * h), layers)


def register_geometry(layers: int, thickness: float) -> str:
    """The plane-strain slice as a problem of run_bench (its mesh-size fitting and mesh cache):
    `layers` > 0: a structured slice `layers` elements thick (geo_slice); otherwise an
    unstructured slice of fixed axial length `thickness` (run_bench's cylinder geometry), whose
    fill grows as that of a 3D mesh."""
    if layers > 0:
        name = f"ring-l{layers}"
        rb.PROBLEMS[name] = dict(geo=lambda h: geo_slice(h, layers), h_calib=0.009)
    else:
        name = f"ring-t{thickness:g}"
        c = dict(rb.CYL, Lz=thickness)
        rb.PROBLEMS[name] = dict(geo=lambda h: rb.geo_cylinder(h, c), h_calib=0.4 * thickness)
    return name


# ----------------------------------------------------------------------------------------------
# Inputs
# ----------------------------------------------------------------------------------------------
def material_yaml(variant: dict) -> str:
    if variant["hardening"] == 0:
        return f"{{perfect: {{yield: {SY!r}}}}}"
    return f"{{linear: {{yield: {SY!r}, hardening: {variant['hardening']!r}}}}}"


def hencky_case(msh: Path, scheme: str, variant: dict, args) -> str:
    scheme, _, accel = scheme.partition("+")
    solver = [f"scheme: {scheme}", f"steps: {args.steps}", "end: 1.0",
              f"tolerance: {args.tolerance!r}", f"max_iterations: {args.max_iterations}",
              f"cutback: {args.cutback}", f"linear: {args.linear}"]
    if scheme == "initial-strain":
        solver.append(f"relaxation: {args.relaxation!r}")
    elif scheme == "initial-strain-stiffness":
        solver.append(f"relaxation: {args.relaxation_stiffness!r}")
    if accel:
        solver.append(f"acceleration: {accel}")
    return f"""title: plastic bench {scheme}{'+' + accel if accel else ''} {variant['name']} {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
    plasticity: {material_yaml(variant)}
{rb.cylinder_boundary_yaml(f'"{args.p_end!r}*t"')}solver: {{{', '.join(solver)}}}
output:
  every: {args.steps}
  probes:
    - name: outer
      point: [{B_OUT!r}, 0.0, 0.0]
    - name: bore
      point: [{A_IN!r}, 0.0, 0.0]
"""


def write_ccx_plastic_inp(mesh: dict, inp: Path, variant: dict, args) -> dict:
    """The cylinder for ccx: C3D10, *ELASTIC + *PLASTIC (isotropic hardening table: stress,
    plastic strain), one *STATIC step with args.steps fixed increments (DIRECT), the bore
    pressure ramped (the default amplitude of a static step) on the element faces; the outer
    and bore probe nodes printed to the .dat every increment, U and S to the .frd at the end."""
    coords, tets = mesh["coords"], mesh["tets"]
    tets_ccx, order_error = rb.ccx_tets(mesh)
    outer, d_outer = rb.nearest_node(mesh, (B_OUT, 0.0, 0.0))
    bore, d_bore = rb.nearest_node(mesh, (A_IN, 0.0, 0.0))
    out = [f"*HEADING\nhencky plastic benchmark: {len(tets)} C3D10, {len(mesh['node_tags'])} nodes, "
           f"{variant['name']}\n"]
    out += rb.ccx_mesh_cards(mesh, tets_ccx)
    out.append(rb.ccx_nset("PROBES", [outer, bore]))
    surf = mesh["surfaces"]
    for name in ("sym_x", "sym_y", "bottom", "top"):
        out.append(rb.ccx_nset(name.upper(), surf[name]))
    H = variant["hardening"]
    table = f"{SY:.17g},0.\n" if H == 0 else f"{SY:.17g},0.\n{SY + H:.17g},1.\n"
    out.append(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:.17g},{NU:.17g}\n*PLASTIC\n{table}")
    out.append("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
    inc = 1.0 / args.steps
    out.append(f"*STEP, INC={10 * args.steps}\n*STATIC, DIRECT\n{inc:.17g},1.\n")
    out.append("*BOUNDARY\nSYM_X,1,1\nSYM_Y,2,2\nBOTTOM,3,3\nTOP,3,3\n")
    out.append(rb.ccx_face_pressure(coords, tets_ccx, surf["bore"], args.p_end))
    out.append(f"*NODE PRINT, NSET=PROBES\nU\n*NODE FILE, FREQUENCY={args.steps}\nU\n"
               f"*EL FILE, FREQUENCY={args.steps}\nS, PEEQ\n*END STEP\n")
    inp.write_text("".join(out))
    return dict(outer_node=outer, outer_offset=d_outer, bore_node=bore, bore_offset=d_bore,
                tet10_midnode_check=order_error)


# ----------------------------------------------------------------------------------------------
# Results of the runs
# ----------------------------------------------------------------------------------------------
def ccx_dat_displacements(dat: Path) -> dict[float, dict[int, list[float]]]:
    """{time: {node: [ux, uy, uz]}} of every displacement block in a ccx .dat file."""
    blocks = {}
    cur = None
    if not dat.exists():
        return blocks
    for line in dat.read_text().splitlines():
        m = re.match(r"\s*displacements .* time\s+([-+0-9.Ee]+)", line)
        if m:
            cur = blocks.setdefault(float(m.group(1)), {})
            continue
        v = line.split()
        if cur is not None and len(v) == 4:
            try:
                cur[int(v[0])] = [float(x) for x in v[1:]]
            except ValueError:
                cur = None
        elif v and cur is not None and cur:
            cur = None
    return blocks


def ccx_counts(text: str, job_dir: Path, job: str) -> dict:
    """Newton iterations and factorizations of a ccx run, from its output: one "iteration N"
    line per iteration (attempts that were cut back included), one "Factoring the system of
    equations" line per factorization; the increments from the .sta file."""
    iterations = len(re.findall(r"^\s*iteration\s+\d+", text, flags=re.M))
    factorizations = len(re.findall(r"Factoring the system of equations", text))
    increments, total_time = 0, None
    sta = job_dir / f"{job}.sta"
    if sta.exists():
        for line in sta.read_text().splitlines():
            v = line.split()
            if len(v) >= 7 and v[0].isdigit() and v[1].isdigit():
                increments += 1
                total_time = float(v[4])
    return dict(iterations=iterations, factorizations=factorizations, increments=increments,
                total_time=total_time)


def history_rows(history_csv: Path) -> list[list[str]]:
    """The rows (one per converged step: step, time, iterations, ...) of a hencky history.csv."""
    if not history_csv.exists():
        return []
    return [l.split(",") for l in history_csv.read_text().splitlines()[1:] if l.strip()]


def reached_time(history_csv: Path) -> float | None:
    """Time of the last converged step in a hencky history.csv (None without one)."""
    rows = history_rows(history_csv)
    return float(rows[-1][1]) if rows else None


def errors(value: float | None, exact: float | None):
    if value is None or not exact:
        return None
    return (value - exact) / exact


def run_hencky_case(exe, run_dir: Path, msh: Path, scheme: str, variant: dict, args) -> dict:
    case = run_dir / f"case-{variant['name']}-{scheme}.yaml"
    case.write_text(hencky_case(msh, scheme, variant, args))
    out = run_dir / f"hencky-{variant['name']}-{scheme}.out"
    for old in run_dir.glob(out.name + ".partial-*"):
        shutil.rmtree(old, ignore_errors=True)
    r = rb.run_hencky(exe, case, out, args.threads, args.hencky_environ, timeout=args.timeout, check=False)
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
        row.update(status="timeout" if r["timed_out"] else "error",
                   reached=float(rows[-1][1]) if rows else None,
                   iterations=sum(int(x[2]) for x in rows) if rows else None,
                   failure=(f"killed after the time limit of {args.timeout:g} s" if r["timed_out"]
                            else f"exit status {r['rc']} without summary.json, see {r['log']}"))
    if row["status"] == "converged" and row.get("reached") is not None and abs(row["reached"] - 1.0) > 1e-9:
        row["status"] = "not-converged"
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
        for old in run_dir.glob(out.name + ".partial-*"):
            shutil.rmtree(old, ignore_errors=True)
    return row


def run_ccx_case(run_dir: Path, job: str, info: dict, variant: dict, args) -> dict:
    """ccx on the input `job`.inp written by write_ccx_plastic_inp (which returned `info`)."""
    c = rb.run_ccx(run_dir, job, args.threads, timeout=args.ccx_timeout, check=False)
    counts = ccx_counts(c["text"], run_dir, job)
    blocks = ccx_dat_displacements(run_dir / f"{job}.dat")
    last_t = max(blocks) if blocks else None
    row = dict(program="ccx", scheme="ccx", material=variant["name"], wall=c["wall"],
               peak_rss=c["peak_rss"], cpu=c["cpu"], others=c["others"], rc=c["rc"], log=c["log"],
               iterations=counts["iterations"], factorizations=counts["factorizations"],
               increments=counts["increments"], reached=counts["total_time"], inp=info,
               reported_seconds=c.get("ccx_reported_seconds"), phases=None)
    if c["ok"] and last_t is not None and abs(last_t - 1.0) < 1e-6:
        row["status"] = "converged"
    elif c["timed_out"]:
        row.update(status="timeout", failure=f"killed after the time limit of {args.ccx_timeout:g} s")
    else:
        row.update(status="not-converged" if c.get("errors") else "error",
                   failure="; ".join(c.get("errors") or []) or f"exit status {c['rc']}, see {c['log']}")
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
# Benchmark
# ----------------------------------------------------------------------------------------------
def variants(args) -> list[dict]:
    vs = [dict(name="perfect", hardening=0.0, schemes=args.schemes, ccx=not args.no_ccx)]
    if args.hardening > 0 and args.hardening_schemes:
        vs.append(dict(name="hardening", hardening=args.hardening, schemes=args.hardening_schemes,
                       ccx=not args.no_ccx))
    return vs


def bench_size(problem: str, target: int, args, work: Path, exe: Path, refs: dict) -> dict:
    msh, gmsh_seconds, h = rb.size_for(problem, target, work, args.threads)
    run_dir, mesh = rb.size_run_dir(msh, work, "plastic")
    n_nodes, n_elems = int(len(mesh["node_tags"])), int(len(mesh["tets"]))
    size = dict(target_dofs=target, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds, nodes=n_nodes,
                elements=n_elems, runs=[])
    ccx_inputs = {}  # written first, so that the mesh is not held in memory during the runs
    for v in variants(args):
        if v["ccx"]:
            job = f"ccx-{v['name']}"
            ccx_inputs[v["name"]] = (job, write_ccx_plastic_inp(mesh, run_dir / f"{job}.inp", v, args))
    del mesh
    print(f"[~{target / 1000:.0f}k unknowns] h = {h:g}: {msh.name}, {n_nodes} nodes, {n_elems} tetrahedra", flush=True)
    for v in variants(args):
        ref = refs[v["name"]]
        programs = (["ccx"] if v["ccx"] else []) + list(v["schemes"])
        for prog in programs:
            if args.wait_quiet > 0:
                q = rb.wait_quiet(args.wait_quiet)
                if q["waited"] > 1.5:
                    print(f"    (waited {q['waited']:.0f} s for other programs; background now {q['background']:.2f} cores)", flush=True)
            if prog == "ccx":
                row = run_ccx_case(run_dir, *ccx_inputs[v["name"]], v, args)
            else:
                row = run_hencky_case(exe, run_dir, run_dir / msh.name, prog, v, args)
            row["error_hill"] = errors(row.get("u_outer"), ref["hill"])
            row["error_ref"] = errors(row.get("u_outer"), ref["u_outer"])
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


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
fmt_s, mib = rb.fmt_s, rb.mib


def pct(x, digits=2):
    return "–" if x is None else f"{100 * x:+.{digits}f} %"


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
               f"{res['seconds'] / 60:.1f} min; `{res['command'].replace(str(ROOT) + '/', '')}`")
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
        f"max_iterations {p['max_iterations']}, cutback {p['cutback']}, relaxation ω = {p['relaxation']:g} "
        f"(initial-strain) and {p.get('relaxation_stiffness', p['relaxation']):g} (initial-strain-stiffness), "
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
    ap.add_argument("--relaxation", type=float, default=0.01,
                    help="solver.relaxation ω of initial-strain (default 0.01 ≈ 1/(1 + E/H) for H = E/100: elastic matrix everywhere)")
    ap.add_argument("--relaxation-stiffness", type=float, default=0.015,
                    help="solver.relaxation ω of initial-strain-stiffness (default 0.015; see the module notes)")
    ap.add_argument("--layers", type=int, default=2,
                    help="the slice is this many elements thick at every size (default 2); 0: unstructured slice of --thickness")
    ap.add_argument("--thickness", type=float, default=0.02,
                    help="with --layers 0: axial length of the unstructured slice, m (default 0.02)")
    ap.add_argument("--load-factor", type=float, default=0.9, help="end of the ramp as a fraction of p_L (default 0.9)")
    ap.add_argument("--steps", type=int, default=20, help="load increments (default 20)")
    ap.add_argument("--tolerance", type=float, default=1e-6, help="hencky solver.tolerance (default 1e-6, the case default)")
    ap.add_argument("--max-iterations", type=int, default=1000,
                    help="hencky solver.max_iterations per step (default 1000: the fixed-matrix schemes need many near the limit load)")
    ap.add_argument("--cutback", type=int, default=4, help="hencky solver.cutback (default 4, the case default)")
    ap.add_argument("--linear", choices=("direct", "iterative"), default="direct", help="hencky solver.linear")
    ap.add_argument("--timeout", type=float, default=1800, help="time limit of one hencky run, s (default 1800); 0: none")
    ap.add_argument("--ccx-timeout", type=float, default=None, help="time limit of one ccx run, s (default: --timeout)")
    ap.add_argument("--ref-elements", type=int, default=200, help="quadratic elements of the 1D reference (default 200)")
    rb.add_common_arguments(ap)
    args = ap.parse_args()

    if args.report:
        print(render(json.loads(args.report.read_text())))
        return

    args.schemes = [s for s in args.schemes.split(",") if s]
    args.hardening_schemes = [s for s in args.hardening_schemes.split(",") if s]
    for s in args.schemes + args.hardening_schemes:
        if s not in SCHEMES + ACCELERATED:
            raise SystemExit(f"unknown scheme {s!r}; the schemes are {', '.join(SCHEMES + ACCELERATED)}")
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

    exe, work, stamp = rb.prepare_run(args)
    problem = register_geometry(args.layers, args.thickness)

    m = rb.machine_info()
    print(f"machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; hencky {exe}", flush=True)
    refs = references(args)
    rp = refs["perfect"]
    print(f"p_L = {args.p_limit:.6g} Pa, ramp to {args.p_end:.6g} Pa in {args.steps} increments; u(b): Hill "
          f"{rp['hill']:.6e} m, 1D reference {rp['u_outer']:.6e} m"
          + (f", with hardening {refs['hardening']['u_outer']:.6e} m" if "hardening" in refs else ""), flush=True)

    sizes = [int(float(x)) for x in args.sizes.split(",") if x]
    sizes = [x for x in sizes if x <= args.max_dofs]
    t_start = time.perf_counter()
    dirty = rb.sh(f"git -C {ROOT} status --porcelain --untracked-files=no -- src app CMakeLists.txt")
    result = dict(
        timestamp=stamp, machine=m, hencky=str(exe), hencky_version=rb.sh(f"{exe} --version"),
        git=rb.sh(f"git -C {ROOT} rev-parse --short HEAD") + (" + uncommitted changes in src/" if dirty else ""),
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
        jpath.write_text(json.dumps(result, indent=1))
        mdpath.write_text(render(result))
    result["seconds"] = time.perf_counter() - t_start
    jpath.write_text(json.dumps(result, indent=1))
    md = render(result)
    mdpath.write_text(md)
    print(f"\nwrote {jpath} and {mdpath}\n")
    print(md)


if __name__ == "__main__":
    main()
