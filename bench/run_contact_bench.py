#!/usr/bin/python3
"""hencky contact benchmark: a rigid sphere pressed into an elastic block (Hertz), hencky and CalculiX.

The case. A rigid sphere of radius R = 100 a is pressed by a prescribed approach
delta = a^2/R (a = 1 mm, the Hertz contact radius at the end) into an elastic block,
E = 2.1e11 Pa, nu = 0.3 (run_bench's steel), in --steps (4) equal steps. Quarter model: the block
[0, L] x [0, L] x [-L, 0] with L = --block (100) a, symmetry rollers on x = 0 and y = 0, the bottom
z = -L held, the sides x = L and y = L free. 10-node tetrahedra from Gmsh (the .geo is written by
geo_block below) with a size field: h = h_c within r_fine = 1.2 a of the first contact point
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
    run_bench.ccx_num keeps every number within 20 characters.
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
of src/io/vtu_writer.cpp is read directly). Uses run_bench.py's meshing, conversion and run
functions and run_plastic_bench.py's ccx counters.
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
import run_plastic_bench as pb  # noqa: E402

ROOT, BENCH = rb.ROOT, rb.BENCH

# ----------------------------------------------------------------------------------------------
# Problem
# ----------------------------------------------------------------------------------------------
E, NU = rb.E, rb.NU
E_STAR = E / (1 - NU * NU)
A = 1e-3            # Hertz contact radius at the full approach, m
R = 100 * A         # sphere radius
DELTA = A * A / R   # full approach (1e-5 m)
R_FINE = 1.2 * A    # the size field is h_c within this distance of the origin
GROWTH = 0.25       # ... and grows by this much per unit distance outside
CAP_EXTENT = 1.6 * A  # the ccx rigid cap covers [-h_c, CAP_EXTENT]^2


class Hertz:
    """Rigid sphere of radius R pressed by an approach d into an elastic half-space (E*)."""

    def __init__(self, R: float = R):
        self.R = R

    def force(self, d):
        return 4.0 / 3.0 * E_STAR * math.sqrt(self.R) * d**1.5

    def radius(self, d):
        return math.sqrt(self.R * d)

    def peak(self, d):
        return 3 * self.force(d) / (2 * math.pi * self.R * d)

    def approach(self, P):
        return (3 * P / (4 * E_STAR * math.sqrt(self.R))) ** (2.0 / 3.0)


def geo_block(hc: float, L: float) -> str:
    """The quarter block [0, L] x [0, L] x [-L, 0] for Gmsh (built-in kernel) with a size field
    h = min(L/4, h_c + GROWTH max(0, |x| - R_FINE)). Physical groups: body; xsym (x = 0), ysym
    (y = 0), top (z = 0), bottom (z = -L); the faces x = L and y = L have none (free)."""
    return f"""// hencky contact benchmark: quarter block L = {L!r}, h_c = {hc!r} within {R_FINE!r} of the origin
L = {L!r};
Point(1) = {{0, 0, 0}}; Point(2) = {{L, 0, 0}}; Point(3) = {{L, L, 0}}; Point(4) = {{0, L, 0}};
Point(5) = {{0, 0, -L}}; Point(6) = {{L, 0, -L}}; Point(7) = {{L, L, -L}}; Point(8) = {{0, L, -L}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Line(5) = {{5, 6}}; Line(6) = {{6, 7}}; Line(7) = {{7, 8}}; Line(8) = {{8, 5}};
Line(9) = {{1, 5}}; Line(10) = {{2, 6}}; Line(11) = {{3, 7}}; Line(12) = {{4, 8}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Curve Loop(2) = {{5, 6, 7, 8}}; Plane Surface(2) = {{2}};
Curve Loop(3) = {{1, 10, -5, -9}}; Plane Surface(3) = {{3}};
Curve Loop(4) = {{2, 11, -6, -10}}; Plane Surface(4) = {{4}};
Curve Loop(5) = {{3, 12, -7, -11}}; Plane Surface(5) = {{5}};
Curve Loop(6) = {{4, 9, -8, -12}}; Plane Surface(6) = {{6}};
Surface Loop(1) = {{1, 2, 3, 4, 5, 6}}; Volume(1) = {{1}};
Physical Volume("body") = {{1}};
Physical Surface("xsym") = {{6}}; Physical Surface("ysym") = {{3}};
Physical Surface("top") = {{1}}; Physical Surface("bottom") = {{2}};
Field[1] = MathEval;
Field[1].F = "min({L / 4!r}, {hc!r} + {GROWTH!r}*max(0, sqrt(x*x + y*y + z*z) - {R_FINE!r}))";
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
"""


def register_geometry(block: float) -> str:
    """The block as a problem of run_bench (its mesh-size fitting and mesh cache); the mesh
    parameter h is h_c."""
    name = f"hertz-L{block:g}a"
    rb.PROBLEMS[name] = dict(geo=lambda h: geo_block(h, block * A), h_calib=A / 6)
    return name


# ----------------------------------------------------------------------------------------------
# hencky
# ----------------------------------------------------------------------------------------------
def hencky_case(msh: Path, args) -> str:
    extra = f"\n    penetration: {args.penetration!r}" if args.penetration else ""
    return f"""title: contact bench hertz {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
boundary:
  - region: xsym
    displacement: {{x: 0}}
  - region: ysym
    displacement: {{y: 0}}
  - region: bottom
    displacement: {{x: 0, y: 0, z: 0}}
contact:
  - name: ball
    nodes: top
    surface: {{sphere: {{center: [0, 0, {R!r}], radius: {R!r}}}}}
    motion: [0, 0, "-{DELTA!r}*t"]{extra}
solver: {{steps: {args.steps}, end: 1.0, linear: direct}}
output:
  every: {args.steps}
  reactions: [bottom]
"""


def read_vtu(path: Path, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Point data `names` and the points of a .vtu: meshio when installed, otherwise the XML
    header and raw appended data that src/io/vtu_writer.cpp writes (header_type UInt64: each
    block is its byte count, then the values)."""
    try:
        import meshio  # noqa: F401
        m = meshio.read(path)
        return {"Points": np.asarray(m.points), **{n: np.asarray(m.point_data[n]) for n in names}}
    except ImportError:
        pass
    buf = path.read_bytes()
    marker = buf.index(b'<AppendedData encoding="raw">')
    base = buf.index(b"_", marker) + 1
    head = buf[:marker].decode()
    if 'header_type="UInt64"' not in head or 'byte_order="LittleEndian"' not in head:
        raise SystemExit(f"{path}: expected a little-endian .vtu with UInt64 headers")
    out = {}
    types = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1"}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)"(?: NumberOfComponents="(\d+)")?'
                         r' format="appended" offset="(\d+)"', head):
        typ, name, ncomp, off = m.group(1), m.group(2), int(m.group(3) or 1), int(m.group(4))
        if name != "Points" and name not in names:
            continue
        # cell data have names of their own except "stress" etc.: take the point data (first)
        if name in out:
            continue
        start = base + off
        nbytes = int(np.frombuffer(buf, "<u8", count=1, offset=start)[0])
        dt = np.dtype(types[typ])
        a = np.frombuffer(buf, dt, count=nbytes // dt.itemsize, offset=start + 8)
        out[name] = a.reshape(-1, ncomp) if ncomp > 1 else a.copy()
    missing = [n for n in ("Points",) + tuple(names) if n not in out]
    if missing:
        raise SystemExit(f"{path}: no {', '.join(missing)}")
    return out


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


def run_hencky_size(exe: Path, run_dir: Path, msh: Path, args, hz: Hertz) -> dict:
    case = run_dir / "case.yaml"
    case.write_text(hencky_case(msh, args))
    out = run_dir / "hencky.out"
    for old in run_dir.glob(out.name + ".partial-*"):
        shutil.rmtree(old, ignore_errors=True)
    r = rb.run_hencky(exe, case, out, args.threads, args.hencky_environ, timeout=args.timeout, check=False)
    s = r["summary"]
    row = dict(program="hencky", wall=r["wall"], peak_rss=r["peak_rss"], cpu=r["cpu"], others=r["others"],
               load_before=r["load_before"], rc=r["rc"], log=r["log"])
    log_dir = out if out.exists() else next(iter(sorted(run_dir.glob(out.name + ".partial-*"))), out)
    row["log_facts"] = hencky_log_facts(log_dir / "hencky.log")
    if s is None:
        row.update(status="timeout" if r["timed_out"] else "error",
                   failure=(f"killed after the time limit of {args.timeout:g} s" if r["timed_out"]
                            else f"exit status {r['rc']} without summary.json, see {r['log']}"))
        hist = pb.history_rows(log_dir / "history.csv")
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
        for old in run_dir.glob(out.name + ".partial-*"):
            shutil.rmtree(old, ignore_errors=True)
    return row


# ----------------------------------------------------------------------------------------------
# CalculiX
# ----------------------------------------------------------------------------------------------
def write_ccx_contact_inp(mesh: dict, inp: Path, hc: float, args) -> dict:
    """The block (C3D10, run_bench's conversion) and a rigid cap of C3D8 bricks on the sphere:
    see the module notes. Returns the node numbers and the top surface's nodes (for the
    pressure profile) and the contact stiffness."""
    coords = mesh["coords"]
    tets_ccx, order_error = rb.ccx_tets(mesh)
    surf = mesh["surfaces"]
    out = [f"*HEADING\nhencky contact benchmark: {len(tets_ccx)} C3D10, {len(mesh['node_tags'])} nodes, rigid sphere cap\n"]
    out += rb.ccx_mesh_cards(mesh, tets_ccx)
    # The top's element faces: run_bench's face matcher writes them as *DLOAD lines
    # "element,P<face>,value"; the same pairs make the *SURFACE (element, S<face>).
    faces = [l.split(",")[:2] for l in rb.ccx_face_pressure(coords, tets_ccx, surf["top"], 0.0, "top").splitlines()[1:]]
    out.append("*SURFACE, NAME=TOP\n" + "".join(f"{e},S{p[1:]}\n" for e, p in faces))
    for name in ("xsym", "ysym", "bottom"):
        out.append(rb.ccx_nset(name.upper(), surf[name]))
    # Rigid cap: lower nodes on the sphere (centre (0, 0, R)), upper nodes 0.5 a above them.
    e = hc / 2
    xs = np.arange(-2 * e, CAP_EXTENT + 0.5 * e, e)
    n = len(xs)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    Z = R - np.sqrt(R * R - X**2 - Y**2)
    first = int(coords.shape[0]) + 1
    ids = first + np.arange(2 * n * n).reshape(2, n, n)
    node_lines = [f"{ids[k, i, j]},{rb.ccx_num(X[i, j])},{rb.ccx_num(Y[i, j])},{rb.ccx_num(Z[i, j] + k * 0.5 * A)}\n"
                  for k in range(2) for i in range(n) for j in range(n)]
    ref, rot = int(ids.max()) + 1, int(ids.max()) + 2
    out.append("*NODE, NSET=CAPN\n" + "".join(node_lines))
    out.append(f"*NODE\n{ref},0,0,{rb.ccx_num(R)}\n{rot},0,0,{rb.ccx_num(R)}\n")
    el0 = len(tets_ccx) + 1
    els = []
    for i in range(n - 1):
        for j in range(n - 1):
            lower = [ids[0, i, j], ids[0, i + 1, j], ids[0, i + 1, j + 1], ids[0, i, j + 1]]
            upper = [ids[1, i, j], ids[1, i + 1, j], ids[1, i + 1, j + 1], ids[1, i, j + 1]]
            els.append(f"{el0 + len(els)}," + ",".join(map(str, lower + upper)) + "\n")
    # C3D8 face S1 = nodes 1-2-3-4, the lower face (outward normal -z, towards the block)
    out.append("*ELEMENT, TYPE=C3D8, ELSET=CAP\n" + "".join(els))
    out.append("*SURFACE, NAME=CAPS\nCAP,S1\n")
    out.append(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{rb.ccx_num(E)},{rb.ccx_num(NU)}\n"
               "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*SOLID SECTION, ELSET=CAP, MATERIAL=STEEL\n")
    out.append(f"*RIGID BODY, ELSET=CAP, REF NODE={ref}, ROT NODE={rot}\n")
    out.append(rb.ccx_nset("REFN", [ref]))
    K = args.ccx_stiffness * E / hc
    out.append(f"*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{rb.ccx_num(K)}\n")
    out.append("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nTOP,CAPS\n")
    inc = 1.0 / args.steps
    out.append(f"*STEP, INC=1000\n*STATIC\n{rb.ccx_num(inc)},1.,1e-5,{rb.ccx_num(inc)}\n")
    out.append(f"*BOUNDARY\nXSYM,1,1\nYSYM,2,2\nBOTTOM,1,3\n{ref},1,2,0\n{ref},3,3,{rb.ccx_num(-DELTA)}\n{rot},1,3,0\n")
    out.append("*NODE PRINT, NSET=REFN\nRF\n*CONTACT PRINT, SLAVE=TOP, MASTER=CAPS\nCF\n*CONTACT FILE\nCSTR\n*END STEP\n")
    inp.write_text("".join(out))
    top_nodes = np.unique(surf["top"])
    return dict(ref_node=ref, rot_node=rot, K=K, cap_spacing=e, cap_nodes=int(2 * n * n), cap_elements=len(els),
                top_faces=len(faces), tet10_midnode_check=order_error,
                top_nodes=top_nodes.tolist(), top_xy=coords[top_nodes, :2].tolist())


def ccx_dat_blocks(dat: Path, title: str, skip_to: str | None = None) -> dict[float, list[float]]:
    """{time: first numeric line} of the .dat blocks whose header starts with `title` (after the
    line containing `skip_to`, when given)."""
    out = {}
    if not dat.exists():
        return out
    lines = dat.read_text(errors="replace").splitlines()
    for k, line in enumerate(lines):
        m = re.match(r"\s*" + re.escape(title) + r".* time\s+([-+0-9.Ee]+)", line)
        if not m:
            continue
        t = float(m.group(1))
        seen = skip_to is None
        for l2 in lines[k + 1:k + 12]:
            if not seen:
                seen = skip_to in l2
                continue
            v = l2.split()
            if v:
                try:
                    out[t] = [float(x) for x in v]
                except ValueError:
                    continue
                break
    return out


def frd_last_contact(frd: Path) -> tuple[float | None, dict[int, tuple[float, float]]]:
    """The last CONTACT block of a .frd (ASCII, *CONTACT FILE): its time and {node: (COPEN, CPRESS)}."""
    if not frd.exists():
        return None, {}
    last_t, block, cur, t = None, {}, None, None
    with open(frd, errors="replace") as f:
        for line in f:
            if line.startswith("  100C"):
                try:
                    t = float(line[12:24])
                except ValueError:
                    t = None
                cur = None
            elif line.startswith(" -4  CONTACT"):
                cur = {}
            elif cur is not None and line.startswith(" -1"):
                node = int(line[3:13])
                vals = [float(line[13 + 12 * k:25 + 12 * k]) for k in range(6)]
                cur[node] = (vals[0], vals[3])
            elif cur is not None and line.startswith(" -3"):
                last_t, block, cur = t, cur, None
    return last_t, block


def ccx_sta(sta: Path) -> list[dict]:
    """The converged increments of a ccx .sta file: attempt and iterations of each."""
    out = []
    if sta.exists():
        for line in sta.read_text().splitlines():
            v = line.split()
            if len(v) >= 7 and v[0].isdigit() and v[1].isdigit():
                out.append(dict(increment=int(v[1]), attempt=int(v[2]), iterations=int(v[3]), t=float(v[4])))
    return out


def run_ccx_size(run_dir: Path, info: dict, args, hz: Hertz) -> dict:
    c = rb.run_ccx(run_dir, "job", args.threads, timeout=args.ccx_timeout, check=False)
    counts = pb.ccx_counts(c["text"], run_dir, "job")
    dat = run_dir / "job.dat"
    rf = ccx_dat_blocks(dat, "forces (fx,fy,fz) for set REFN")
    cf = ccx_dat_blocks(dat, "statistics for slave set", skip_to="total surface force")
    row = dict(program="ccx", wall=c["wall"], peak_rss=c["peak_rss"], cpu=c["cpu"], others=c["others"],
               load_before=c["load_before"], rc=c["rc"], log=c["log"], iterations=counts["iterations"],
               factorizations=counts["factorizations"], increments=counts["increments"],
               reached=counts["total_time"], reported_seconds=c.get("ccx_reported_seconds"),
               K=info["K"], cpus=c.get("cpus"))
    last_t = max(rf) if rf else None
    if c["ok"] and last_t is not None and abs(last_t - 1.0) < 1e-6:
        row["status"] = "converged"
    elif c["timed_out"]:
        row.update(status="timeout", failure=f"killed after the time limit of {args.ccx_timeout:g} s")
    else:
        row.update(status="not-converged" if c.get("errors") else "error",
                   failure="; ".join(c.get("errors") or []) or f"exit status {c['rc']}, see {c['log']}")
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


# ----------------------------------------------------------------------------------------------
# Benchmark
# ----------------------------------------------------------------------------------------------
def wait_load(max_wait: float, below: float, poll: float = 30.0) -> dict:
    """Wait (at most max_wait s, polling every `poll` s) until the 1-minute load average is below
    `below`. Returns the wait and the load then."""
    t0 = time.perf_counter()
    while True:
        load = os.getloadavg()[0]
        waited = time.perf_counter() - t0
        if load < below or waited >= max_wait:
            return dict(waited=waited, load=load, met=load < below)
        print(f"    (1-min load {load:.2f} >= {below:g}; waiting, {waited:.0f} s so far)", flush=True)
        time.sleep(poll)


def quiet(args):
    if args.wait_quiet > 0:
        q = rb.wait_quiet(args.wait_quiet)
        if q["waited"] > 1.5:
            print(f"    (waited {q['waited']:.0f} s for other programs; background now {q['background']:.2f} cores)", flush=True)


def bench_size(problem: str, target: int, args, work: Path, exe: Path, hz: Hertz) -> dict:
    msh, gmsh_seconds, hc = rb.size_for(problem, target, work, args.threads)
    run_dir, mesh = rb.size_run_dir(msh, work, "contact")
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
        info = write_ccx_contact_inp(mesh, run_dir / "job.inp", hc, args)
        size["ccx_input"] = {k: v for k, v in info.items() if k not in ("top_nodes", "top_xy")}
        size["ccx_input"]["convert_seconds"] = time.perf_counter() - t0
    del mesh
    print(f"[~{target / 1000:.0f}k unknowns] h_c = {hc:g} m = a/{A / hc:.1f}: {msh.name}, {n_nodes} nodes, "
          f"{n_elems} tetrahedra", flush=True)
    quiet(args)
    h = run_hencky_size(exe, run_dir, run_dir / msh.name, args, hz)
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
        quiet(args)
        c = run_ccx_size(run_dir, info, args, hz)
        size["ccx"] = c
        print(f"    ccx    {c['status']:13s} wall {c['wall']:8.2f} s  peak {c['peak_rss'] / 2**20:6.0f} MiB  "
              f"inc {c['increments']} it {c['iterations']} fact {c['factorizations']}  "
              f"P {fmt_err(c, 'P', hz.force(DELTA))}  peak p {fmt_err(c, 'peak_pressure', hz.peak(DELTA))}; "
              f"others {c['others']:.2f} cores" + (f"\n        {c['failure']}" if c.get("failure") else ""), flush=True)
    return size


def fmt_err(row: dict, key: str, exact: float) -> str:
    v = row.get(key)
    return "–" if v is None else f"{v:.5g} ({100 * (v / exact - 1):+.2f} %)"


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
fmt_s, mib = rb.fmt_s, rb.mib


def pct(x, digits=2):
    return "–" if x is None else f"{100 * x:+.{digits}f} %"


def rel(v, ref):
    return None if v is None or not ref else v / ref - 1


def status_text(r: dict) -> str:
    s = r.get("status", "–")
    return s if s == "converged" else f"**{s}**"


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
        ("status", lambda r: status_text(r), "–"),
        ("wall time, end to end (s)", lambda r: fmt_s(r["wall"]), "–"),
        ("time per step (s)", lambda r: fmt_s(r["step_seconds"]) if r["program"] == "hencky" else fmt_s(r["wall"] / max(1, r["increments"])), "–"),
        ("steps / increments", lambda r: f"{r['steps']}" if r["program"] == "hencky" else f"{r['increments']}", f"{res['parameters']['steps']}"),
        ("iterations (total)", lambda r: f"{r['iterations']}", "–"),
        ("iterations per step", lambda r: " ".join(str(s["iterations"]) for s in (r["per_step"] if r["program"] == "hencky" else r["sta"])), "–"),
        ("factorizations", lambda r: f"{r['factorizations']}" + (" (" + " ".join(str(s["factorizations"]) for s in r["per_step"]) + ")" if r["program"] == "hencky" else ""), "–"),
        ("contact search / total (wall_seconds)", lambda r: f"{fmt_s(r['phases']['contact'])} s / {fmt_s(r['phases']['total'])} s = {100 * r['contact_fraction']:.3f} %" if r["program"] == "hencky" else None, "–"),
        ("peak memory (MiB)", lambda r: mib(r["peak_rss"]), "–"),
        ("total force P (N)", lambda r: f"{r['P']:.5g} ({pct(rel(r['P'], P0))})", f"{P0:.5g}"),
        ("P vs the finest hencky mesh", lambda r: pct(rel(r["P"], finest)), "–"),
        ("peak pressure (Pa, largest nodal)", lambda r: f"{r['peak_pressure']:.4g} ({pct(rel(r['peak_pressure'], p00))})", f"{p00:.4g}"),
        ("p0 from the p² fit (Pa)", lambda r: f"{r['fit']['p0']:.4g} ({pct(rel(r['fit']['p0'], p00))})", f"{p00:.4g}"),
        ("contact radius a from the p² fit (m)", lambda r: f"{r['fit']['a']:.4g} ({pct(rel(r['fit']['a'], a0))})", f"{a0:.4g}"),
        ("largest radius in contact r_max (m)", lambda r: f"{r['fit']['r_max']:.4g} ({pct(rel(r['fit']['r_max'], a0))})", f"{a0:.4g}"),
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
        kr = facts.get("kappa_range")
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
               f"{res['seconds'] / 60:.1f} min; `{res['command'].replace(str(ROOT) + '/', '')}`")
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
    rb.add_common_arguments(ap)
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

    exe, work, stamp = rb.prepare_run(args)
    problem = register_geometry(args.block)
    hz = Hertz(R)
    m = rb.machine_info()
    print(f"machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; hencky {exe}", flush=True)
    print(f"Hertz: P = {hz.force(DELTA):.6g} N, a = {hz.radius(DELTA):.6g} m, p0 = {hz.peak(DELTA):.6g} Pa "
          f"(R = {R:g} m, δ = {DELTA:g} m, block L = {args.block:g} a)", flush=True)
    sizes = [int(float(x)) for x in args.sizes.split(",") if x]
    # meshes first (Gmsh is not timed), then wait for a quiet machine
    for target in sizes:
        rb.size_for(problem, target, work, args.threads)
    load_wait = None
    if args.wait_load > 0:
        load_wait = wait_load(args.wait_load, args.load_below)
        print(f"1-min load {load_wait['load']:.2f} after {load_wait['waited']:.0f} s"
              + ("" if load_wait["met"] else f" (not below {args.load_below:g}: running anyway, the load is recorded)"), flush=True)
    t_start = time.perf_counter()
    dirty = rb.sh(f"git -C {ROOT} status --porcelain --untracked-files=no -- src app CMakeLists.txt")
    result = dict(
        timestamp=stamp, machine=m, hencky=str(exe), hencky_version=rb.sh(f"{exe} --version"),
        git=rb.sh(f"git -C {ROOT} rev-parse --short HEAD") + (" + uncommitted changes in src/" if dirty else ""),
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
        jpath.write_text(json.dumps(result, indent=1))
        mdpath.write_text(render(result))
    md = render(result)
    print(f"\nwrote {jpath} and {mdpath}\n")
    print(md)


if __name__ == "__main__":
    main()
