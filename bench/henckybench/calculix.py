"""CalculiX (ccx): the .inp writer (the Gmsh mesh as C3D10 cards, node sets, pressure on element
faces; the input of each problem), running ccx under /usr/bin/time -v, and reading what it writes
(.dat displacements, forces and contact statistics, .sta increments, .frd contact blocks)."""
from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np

from . import ROOT
from .gmsh import nearest_node
from .problems import A, A_IN, B_OUT, CANT, CAP_EXTENT, CYL, DELTA, E, NU, PROBLEMS, R, SY
from .runner import timed

# ----------------------------------------------------------------------------------------------
# The mesh as ccx cards
# ----------------------------------------------------------------------------------------------
# Gmsh 10-node tetrahedron: corners 0-3, then edges (0,1) (1,2) (2,0) (3,0) (3,2) (3,1).
# CalculiX/Abaqus C3D10: corners 1-4, then edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.
# Edge (1,3) of Gmsh is its node 9, edge (2,3) its node 8: the two last ones swap.
GMSH_TO_CCX_TET10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
# Faces of C3D10 (CalculiX manual, element faces): S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1
CCX_TET_FACES = [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)]


def check_tet10_order(coords: np.ndarray, tets_ccx: np.ndarray) -> float:
    """Largest distance (relative to the edge length) between a CalculiX-ordered mid-edge node
    and the midpoint of its edge: ~0 for straight edges when the permutation is right."""
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    worst = 0.0
    sample = tets_ccx[: min(len(tets_ccx), 20000)]
    for k, (p, q) in enumerate(edges):
        xp, xq, xm = coords[sample[:, p]], coords[sample[:, q]], coords[sample[:, 4 + k]]
        d = np.linalg.norm(xm - 0.5 * (xp + xq), axis=1) / np.linalg.norm(xq - xp, axis=1)
        worst = max(worst, float(np.median(d)))
    return worst


def ccx_nset(name: str, nodes) -> str:
    nodes = np.unique(nodes).tolist()
    body = "".join(",".join(map(str, nodes[k:k + 16])) + "\n" for k in range(0, len(nodes), 16))
    return f"*NSET, NSET={name}\n{body}"


def ccx_tets(mesh: dict) -> tuple[np.ndarray, float]:
    """The mesh's tetrahedra in CalculiX's node order, with the mid-edge node check."""
    tets_ccx = mesh["tets"][:, GMSH_TO_CCX_TET10]
    order_error = check_tet10_order(mesh["coords"], tets_ccx)
    if order_error > 1e-3:
        raise SystemExit(f"tet10 node permutation looks wrong (mid-node offset {order_error:.2e})")
    return tets_ccx, order_error


def ccx_num(x: float) -> str:
    """x for a ccx data line: ccx reads a real from the first 20 characters of its field only
    (nodes.f: read(textpart(2)(1:20),'(f20.0)')), so a longer %.17g (1.2345678901234567e-05, or
    a negative number with a leading 0.00) would be cut, or stop ccx with *ERROR reading *NODE.
    The most significant digits that fit in 20 characters."""
    for digits in range(17, 5, -1):
        s = f"{x:.{digits}g}"
        if len(s) <= 20:
            return s
    return s


def ccx_mesh_cards(mesh: dict, tets_ccx: np.ndarray) -> list[str]:
    """*NODE (NALL) and *ELEMENT (C3D10, EALL) cards."""
    coords, used = mesh["coords"], mesh["node_tags"]
    out = ["*NODE, NSET=NALL\n"]
    xyz = coords[used]
    out.append("".join(f"{t},{ccx_num(x)},{ccx_num(y)},{ccx_num(z)}\n" for t, (x, y, z) in zip(used.tolist(), xyz.tolist())))
    out.append("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
    out.append("".join(f"{e + 1}," + ",".join(map(str, row)) + "\n" for e, row in enumerate(tets_ccx.tolist())))
    return out


def ccx_face_pressure(coords: np.ndarray, tets_ccx: np.ndarray, tris: np.ndarray, value: float,
                      what: str = "bore") -> str:
    """*DLOAD lines (element, face label Pn, pressure) for the element faces that lie on the
    6-node triangles `tris` (one face per triangle)."""
    tri = np.sort(tris[:, :3], axis=1)
    big = np.int64(coords.shape[0] + 1)
    key = lambda a: (a[:, 0] * big + a[:, 1]) * big + a[:, 2]
    bore_keys = np.sort(key(tri))
    lines = []
    found = 0
    for f, (p, q, r) in enumerate(CCX_TET_FACES):
        fk = key(np.sort(tets_ccx[:, [p, q, r]], axis=1))
        pos = np.clip(np.searchsorted(bore_keys, fk), 0, len(bore_keys) - 1)
        hit = np.nonzero(bore_keys[pos] == fk)[0]
        found += len(hit)
        lines += [f"{e + 1},P{f + 1},{value:.17g}\n" for e in hit.tolist()]
    if found != len(tri):
        raise SystemExit(f"{what}: {found} element faces found for {len(tri)} triangles")
    return "*DLOAD\n" + "".join(lines)


def ccx_surface(name: str, coords: np.ndarray, tets_ccx: np.ndarray, tris: np.ndarray) -> str:
    """*SURFACE (element, S<face>) of the element faces that lie on the 6-node triangles `tris`:
    ccx does not need it for *DLOAD, but it names the face set as hencky's .inp reader reads it
    (tests/cli/cases/80_inp.sh runs hencky on these decks)."""
    pairs = [l.split(",")[:2] for l in ccx_face_pressure(coords, tets_ccx, tris, 0.0, name).splitlines()[1:]]
    return f"*SURFACE, NAME={name.upper()}\n" + "".join(f"{e},S{p[1:]}\n" for e, p in pairs)


# ----------------------------------------------------------------------------------------------
# The problems' inputs
# ----------------------------------------------------------------------------------------------
def write_elastic_inp(problem: str, mesh: dict, inp: Path, solver: str = "spooles") -> dict:
    """An elastic problem of PROBLEMS for ccx: C3D10, *ELASTIC, one *STATIC step (solved by
    SPOOLES, or with solver = "iterative-cholesky" by ccx's CG preconditioned with an incomplete
    Cholesky factorization, *STATIC, SOLVER=ITERATIVE CHOLESKY); the probe node printed to the
    .dat."""
    coords, tets = mesh["coords"], mesh["tets"]
    tets_ccx, order_error = ccx_tets(mesh)
    used = mesh["node_tags"]
    probe, probe_dist = nearest_node(mesh, PROBLEMS[problem]["probe"])
    out = [f"*HEADING\nhencky benchmark: {problem}, {len(tets)} C3D10, {len(used)} nodes\n"]
    out += ccx_mesh_cards(mesh, tets_ccx)
    nset = ccx_nset
    out.append(nset("PROBE", [probe]))
    out.append(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:.17g},{NU:.17g}\n")
    out.append("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
    surf = mesh["surfaces"]
    loads = []
    if problem == "cantilever":
        out.append(nset("FIXED", surf["fixed"]))
        out.append(ccx_surface("tip", coords, tets_ccx, surf["tip"]))
        bcs = "*BOUNDARY\nFIXED,1,3\n"
        # Uniform traction t = P/A on flat 6-node triangles: consistent nodal forces are zero at
        # the corners and area/3 * t at each mid-edge node (what hencky's `force` integrates).
        tri = surf["tip"]
        x0, x1, x2 = coords[tri[:, 0]], coords[tri[:, 1]], coords[tri[:, 2]]
        area = 0.5 * np.linalg.norm(np.cross(x1 - x0, x2 - x0), axis=1)
        total = area.sum()
        fz = np.zeros(coords.shape[0])
        for k in (3, 4, 5):
            np.add.at(fz, tri[:, k], -CANT["P"] * area / (3 * total))
        nz = np.nonzero(fz)[0]
        loads.append("*CLOAD\n" + "".join(f"{n},3,{fz[n]:.17g}\n" for n in nz.tolist()))
    else:
        for name, comp in (("sym_x", 1), ("sym_y", 2), ("bottom", 3), ("top", 3)):
            out.append(nset(name.upper(), surf[name]))
        out.append(ccx_surface("bore", coords, tets_ccx, surf["bore"]))
        bcs = "*BOUNDARY\nSYM_X,1,1\nSYM_Y,2,2\nBOTTOM,3,3\nTOP,3,3\n"
        # Pressure on the bore: *DLOAD on the element faces that lie on it.
        loads.append(ccx_face_pressure(coords, tets_ccx, surf["bore"], CYL["p"]))
    out.append("*STEP\n*STATIC\n" if solver == "spooles" else "*STEP\n*STATIC, SOLVER=ITERATIVE CHOLESKY\n")
    out.append(bcs)
    out += loads
    out.append("*NODE PRINT, NSET=PROBE\nU\n*NODE FILE\nU\n*EL FILE\nS\n*END STEP\n")
    inp.write_text("".join(out))
    return dict(probe_node=probe, probe_offset=probe_dist, tet10_midnode_check=order_error)


def write_plastic_inp(mesh: dict, inp: Path, variant: dict, args) -> dict:
    """The cylinder for ccx: C3D10, *ELASTIC + *PLASTIC (isotropic hardening table: stress,
    plastic strain), one *STATIC step with args.steps fixed increments (DIRECT), the bore
    pressure ramped (the default amplitude of a static step) on the element faces; the outer
    and bore probe nodes printed to the .dat every increment, U and S to the .frd at the end."""
    coords, tets = mesh["coords"], mesh["tets"]
    tets_ccx, order_error = ccx_tets(mesh)
    outer, d_outer = nearest_node(mesh, (B_OUT, 0.0, 0.0))
    bore, d_bore = nearest_node(mesh, (A_IN, 0.0, 0.0))
    out = [f"*HEADING\nhencky plastic benchmark: {len(tets)} C3D10, {len(mesh['node_tags'])} nodes, "
           f"{variant['name']}\n"]
    out += ccx_mesh_cards(mesh, tets_ccx)
    out.append(ccx_nset("PROBES", [outer, bore]))
    surf = mesh["surfaces"]
    for name in ("sym_x", "sym_y", "bottom", "top"):
        out.append(ccx_nset(name.upper(), surf[name]))
    H = variant["hardening"]
    table = f"{SY:.17g},0.\n" if H == 0 else f"{SY:.17g},0.\n{SY + H:.17g},1.\n"
    out.append(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:.17g},{NU:.17g}\n*PLASTIC\n{table}")
    out.append("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
    inc = 1.0 / args.steps
    out.append(f"*STEP, INC={10 * args.steps}\n*STATIC, DIRECT\n{inc:.17g},1.\n")
    out.append("*BOUNDARY\nSYM_X,1,1\nSYM_Y,2,2\nBOTTOM,3,3\nTOP,3,3\n")
    out.append(ccx_face_pressure(coords, tets_ccx, surf["bore"], args.p_end))
    out.append(f"*NODE PRINT, NSET=PROBES\nU\n*NODE FILE, FREQUENCY={args.steps}\nU\n"
               f"*EL FILE, FREQUENCY={args.steps}\nS, PEEQ\n*END STEP\n")
    inp.write_text("".join(out))
    return dict(outer_node=outer, outer_offset=d_outer, bore_node=bore, bore_offset=d_bore,
                tet10_midnode_check=order_error)


def write_contact_inp(mesh: dict, inp: Path, hc: float, args) -> dict:
    """The block (C3D10) and a rigid cap of C3D8 bricks on the sphere: see run_contact_bench.py's
    notes. Returns the node numbers and the top surface's nodes (for the pressure profile) and
    the contact stiffness."""
    coords = mesh["coords"]
    tets_ccx, order_error = ccx_tets(mesh)
    surf = mesh["surfaces"]
    out = [f"*HEADING\nhencky contact benchmark: {len(tets_ccx)} C3D10, {len(mesh['node_tags'])} nodes, rigid sphere cap\n"]
    out += ccx_mesh_cards(mesh, tets_ccx)
    # The top's element faces: the face matcher writes them as *DLOAD lines
    # "element,P<face>,value"; the same pairs make the *SURFACE (element, S<face>).
    faces = [l.split(",")[:2] for l in ccx_face_pressure(coords, tets_ccx, surf["top"], 0.0, "top").splitlines()[1:]]
    out.append("*SURFACE, NAME=TOP\n" + "".join(f"{e},S{p[1:]}\n" for e, p in faces))
    for name in ("xsym", "ysym", "bottom"):
        out.append(ccx_nset(name.upper(), surf[name]))
    # Rigid cap: lower nodes on the sphere (centre (0, 0, R)), upper nodes 0.5 a above them.
    e = hc / 2
    xs = np.arange(-2 * e, CAP_EXTENT + 0.5 * e, e)
    n = len(xs)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    Z = R - np.sqrt(R * R - X**2 - Y**2)
    first = int(coords.shape[0]) + 1
    ids = first + np.arange(2 * n * n).reshape(2, n, n)
    node_lines = [f"{ids[k, i, j]},{ccx_num(X[i, j])},{ccx_num(Y[i, j])},{ccx_num(Z[i, j] + k * 0.5 * A)}\n"
                  for k in range(2) for i in range(n) for j in range(n)]
    ref, rot = int(ids.max()) + 1, int(ids.max()) + 2
    out.append("*NODE, NSET=CAPN\n" + "".join(node_lines))
    out.append(f"*NODE\n{ref},0,0,{ccx_num(R)}\n{rot},0,0,{ccx_num(R)}\n")
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
    out.append(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{ccx_num(E)},{ccx_num(NU)}\n"
               "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*SOLID SECTION, ELSET=CAP, MATERIAL=STEEL\n")
    out.append(f"*RIGID BODY, ELSET=CAP, REF NODE={ref}, ROT NODE={rot}\n")
    out.append(ccx_nset("REFN", [ref]))
    K = args.ccx_stiffness * E / hc
    out.append(f"*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{ccx_num(K)}\n")
    out.append("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nTOP,CAPS\n")
    inc = 1.0 / args.steps
    out.append(f"*STEP, INC=1000\n*STATIC\n{ccx_num(inc)},1.,1e-5,{ccx_num(inc)}\n")
    out.append(f"*BOUNDARY\nXSYM,1,1\nYSYM,2,2\nBOTTOM,1,3\n{ref},1,2,0\n{ref},3,3,{ccx_num(-DELTA)}\n{rot},1,3,0\n")
    out.append("*NODE PRINT, NSET=REFN\nRF\n*CONTACT PRINT, SLAVE=TOP, MASTER=CAPS\nCF\n*CONTACT FILE\nCSTR\n*END STEP\n")
    inp.write_text("".join(out))
    top_nodes = np.unique(surf["top"])
    return dict(ref_node=ref, rot_node=rot, K=K, cap_spacing=e, cap_nodes=int(2 * n * n), cap_elements=len(els),
                top_faces=len(faces), tet10_midnode_check=order_error,
                top_nodes=top_nodes.tolist(), top_xy=coords[top_nodes, :2].tolist())


# ----------------------------------------------------------------------------------------------
# Running ccx
# ----------------------------------------------------------------------------------------------
def ccx_environment(threads: int) -> dict[str, str]:
    """ccx's threads (OpenMP, SPOOLES, stiffness, results) and unbuffered Fortran output."""
    t = str(threads)
    return dict(OMP_NUM_THREADS=t, CCX_NPROC_EQUATION_SOLVER=t, CCX_NPROC_STIFFNESS=t, CCX_NPROC_RESULTS=t,
                GFORTRAN_UNBUFFERED_PRECONNECTED="y")


def ccx_phases(lines, wall) -> dict:
    """Coarse phases of a ccx run from the time its progress lines appeared (stdout made line
    buffered): input and matrix structure | element stiffness | SPOOLES factor and solve |
    stresses and result files."""
    def first(pattern, after=0.0):
        for t, l in lines:
            if t >= after and re.search(pattern, l):
                return t
        return None
    t_asm = first(r"symmetric stiffness/mass contributions")
    t_fac = first(r"Factoring the system of equations")
    t_str = first(r"for the stress calculation", after=t_fac or 0.0) if t_fac else None
    if None in (t_asm, t_fac, t_str):
        return {}
    return dict(input_structure=t_asm, assembly=t_fac - t_asm, factor_solve=t_str - t_fac,
                stress_output=wall - t_str)


def run_ccx(job_dir: Path, job: str, threads: int, timeout: float | None = None, check: bool = True) -> dict:
    """ccx under /usr/bin/time -v; r["text"] is its output. check: raise when it fails (exit
    status, *ERROR); otherwise r["ok"] says whether it ran to the end and r["errors"] holds its
    *ERROR lines."""
    env = dict(os.environ, **ccx_environment(threads))
    for ext in (".dat", ".frd", ".sta", ".cvg", ".12d"):
        (job_dir / (job + ext)).unlink(missing_ok=True)
    log = job_dir / f"{job}.ccx.log"
    cmd = ["ccx", "-i", job]
    if shutil.which("stdbuf"):
        cmd = ["stdbuf", "-oL", "-eL"] + cmd
    r = timed(cmd, job_dir, env=env, log=log, timeout=timeout)
    text = "\n".join(l for _, l in r["lines"])
    r["ok"] = r["rc"] == 0 and "*ERROR" not in text
    r["text"] = text
    if not r["ok"]:
        if check:
            raise SystemExit(f"ccx failed (exit {r['rc']}), see {log}")
        r["errors"] = [l.strip() for l in text.splitlines() if "*ERROR" in l][:5]
    m = re.findall(r"Using up to (\d+) cpu\(s\) for ([^.\n]+)", text)
    r["cpus"] = {what.strip(): int(n) for n, what in m}
    m = re.search(r"Total CalculiX Time:\s*([\d.Ee+-]+)", text)
    r["ccx_reported_seconds"] = float(m.group(1)) if m else None
    r["solver"] = "SPOOLES" if "spooles" in text.lower() else "?"
    r["phases"] = ccx_phases(r["lines"], r["wall"])
    del r["lines"]
    return r


def ccx_shell_line(run_dir: Path, job: str, threads: int) -> str:
    """How run_ccx runs ccx (its environment and line buffering), as one shell line to be pasted
    in the repository's root."""
    return (f"cd {os.path.relpath(run_dir, ROOT)} && "
            + " ".join(f"{k}={v}" for k, v in ccx_environment(threads).items()) + f" stdbuf -oL -eL ccx -i {job}")


def ccx_status(c: dict, last_t: float | None, timeout: float | None) -> dict:
    """status (and failure) of a run_ccx(check=False) run whose last result is at time last_t:
    converged when ccx ran to the end and its last result is at t = 1."""
    if c["ok"] and last_t is not None and abs(last_t - 1.0) < 1e-6:
        return dict(status="converged")
    if c["timed_out"]:
        return dict(status="timeout", failure=f"killed after the time limit of {timeout:g} s")
    return dict(status="not-converged" if c.get("errors") else "error",
                failure="; ".join(c.get("errors") or []) or f"exit status {c['rc']}, see {c['log']}")


# ----------------------------------------------------------------------------------------------
# Reading ccx's results
# ----------------------------------------------------------------------------------------------
def parse_ccx_dat(dat: Path, node: int) -> list[float]:
    """The displacement of `node` in the (last) displacement block of a .dat file."""
    u = None
    lines = dat.read_text().splitlines()
    for k, line in enumerate(lines):
        if line.strip().startswith("displacements"):
            for l2 in lines[k + 1:]:
                v = l2.split()
                if len(v) == 4 and v[0] == str(node):
                    u = [float(x) for x in v[1:]]
                    break
    if u is None:
        raise SystemExit(f"{dat}: no displacement of node {node}")
    return u


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


def ccx_sta(sta: Path) -> list[dict]:
    """The converged increments of a ccx .sta file: attempt and iterations of each."""
    out = []
    if sta.exists():
        for line in sta.read_text().splitlines():
            v = line.split()
            if len(v) >= 7 and v[0].isdigit() and v[1].isdigit():
                out.append(dict(increment=int(v[1]), attempt=int(v[2]), iterations=int(v[3]), t=float(v[4])))
    return out


def ccx_counts(text: str, job_dir: Path, job: str) -> dict:
    """Newton iterations and factorizations of a ccx run, from its output: one "iteration N"
    line per iteration (attempts that were cut back included), one "Factoring the system of
    equations" line per factorization; the increments from the .sta file."""
    iterations = len(re.findall(r"^\s*iteration\s+\d+", text, flags=re.M))
    factorizations = len(re.findall(r"Factoring the system of equations", text))
    sta = ccx_sta(job_dir / f"{job}.sta")
    return dict(iterations=iterations, factorizations=factorizations, increments=len(sta),
                total_time=sta[-1]["t"] if sta else None)


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
