#!/usr/bin/python3
"""hencky performance benchmark: hencky vs CalculiX on the same quadratic tetrahedral meshes.

Two linear-elastic problems with closed-form answers, meshed once by Gmsh (10-node tetrahedra)
at increasing sizes; the very same .msh is solved by hencky and, converted to an .inp, by
CalculiX (ccx). For every size it records hencky's phase times (summary.json), the end-to-end
wall time and peak memory of both programs (/usr/bin/time -v), the accuracy of both against
the closed form, and the flop rate of CHOLMOD's factorization next to the machine's dense
matrix-multiply rate (numpy, same OpenBLAS).

    /usr/bin/python3 bench/run_bench.py                    # default sizes, up to ~400k unknowns
    /usr/bin/python3 bench/run_bench.py --max-dofs 1100000 # add the ~1M size
    /usr/bin/python3 bench/run_bench.py --help

Results: bench/results/<timestamp>.json and .md; --write-docs regenerates the generated part of
docs/performance.md (the text outside the GENERATED markers is kept).
Standard library + numpy only.
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "bench"

# ----------------------------------------------------------------------------------------------
# Problems
# ----------------------------------------------------------------------------------------------
E = 2.1e11
NU = 0.3

# Cantilever: 1 x 0.1 x 0.1 m, clamped at x = 0 (all components), total end force P in -z
# spread uniformly over the end face x = L. Probe: centre of the end face (a mesh node: the
# point is embedded in the end surface).
CANT = dict(L=1.0, W=0.1, H=0.1, P=1000.0)

# Thick cylinder: quarter of a ring a < r < b, axial length Lz; symmetry planes x = 0, y = 0;
# both end faces held axially (u_z = 0: plane strain); internal pressure p. Probe: the bore
# vertex (a, 0, 0) (a geometry point, hence a mesh node). Radial displacement = u_x there.
CYL = dict(a=0.1, b=0.2, Lz=0.1, p=100e6)


def timoshenko_tip_deflection() -> float:
    """Tip deflection of a cantilever with an end load: bending + shear (Timoshenko beam)."""
    L, W, H, P = CANT["L"], CANT["W"], CANT["H"], CANT["P"]
    I = W * H**3 / 12.0
    A = W * H
    G = E / (2 * (1 + NU))
    kappa = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper's shear coefficient, rectangle
    return P * L**3 / (3 * E * I) + P * L / (kappa * G * A)


def lame_bore_displacement() -> float:
    """Radial displacement of the bore of a thick cylinder, plane strain (Lamé)."""
    a, b, p = CYL["a"], CYL["b"], CYL["p"]
    A = p * a**2 / (b**2 - a**2)
    B = p * a**2 * b**2 / (b**2 - a**2)
    return (1 + NU) / E * ((1 - 2 * NU) * A * a + B / a)


def geo_cantilever(h: float) -> str:
    c = CANT
    return f"""// hencky benchmark: cantilever {c['L']} x {c['W']} x {c['H']} m, element size h
L = {c['L']}; W = {c['W']}; H = {c['H']}; h = {h!r};
Point(1) = {{0, 0, 0, h}}; Point(2) = {{0, W, 0, h}}; Point(3) = {{0, W, H, h}}; Point(4) = {{0, 0, H, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
out[] = Extrude {{L, 0, 0}} {{ Surface{{1}}; }};
Point(100) = {{L, W/2, H/2, h}};
Point{{100}} In Surface{{out[0]}};   // a node at the centre of the end face (the probe)
Physical Volume("beam") = {{out[1]}};
Physical Surface("fixed") = {{1}};
Physical Surface("tip") = {{out[0]}};
Mesh.MeshSizeMax = h;
"""


def geo_cylinder(h: float, c: dict = CYL, layers: int = 0) -> str:
    """Quarter ring a < r < b, axial length Lz (the keys of CYL; the plastic benchmark passes
    its own), meshed with unstructured tetrahedra of size h; with `layers` > 0 meshed in its
    plane and extruded in that many layers (Gmsh splits each prism into three tetrahedra)."""
    extrude = f" Layers{{{layers}}};" if layers > 0 else ""
    return f"""// hencky benchmark: quarter thick cylinder a={c['a']} b={c['b']} length {c['Lz']}, element size h
a = {c['a']}; b = {c['b']}; Lz = {c['Lz']}; h = {h!r};
Point(1) = {{0, 0, 0, h}};
Point(2) = {{a, 0, 0, h}}; Point(3) = {{b, 0, 0, h}};
Point(4) = {{0, b, 0, h}}; Point(5) = {{0, a, 0, h}};
Line(1) = {{2, 3}};            // on y = 0
Circle(2) = {{3, 1, 4}};       // outer
Line(3) = {{4, 5}};            // on x = 0
Circle(4) = {{5, 1, 2}};       // bore
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
out[] = Extrude {{0, 0, Lz}} {{ Surface{{1}};{extrude} }};
// out[0] top, out[1] volume, out[2..5] lateral faces from lines 1..4
Physical Volume("wall") = {{out[1]}};
Physical Surface("bottom") = {{1}};
Physical Surface("top") = {{out[0]}};
Physical Surface("sym_y") = {{out[2]}};
Physical Surface("outer") = {{out[3]}};
Physical Surface("sym_x") = {{out[4]}};
Physical Surface("bore") = {{out[5]}};
Mesh.MeshSizeMax = h;
"""


def prepare_run(args) -> tuple[Path, Path, str]:
    """For a benchmark run: the hencky binary (--hencky, or the first build directory that has
    one; bench/setup.sh builds build-bench), its environment (args.hencky_environ, with
    --hencky-env), the work and results directories (created), and the run's time stamp."""
    exe = args.hencky
    if exe is None:
        for d in ("build-bench", "build-f", "build-release", "build"):
            if (ROOT / d / "hencky").exists():
                exe = ROOT / d / "hencky"
                break
    if exe is None or not exe.exists():
        raise SystemExit("no hencky binary: build it (bash bench/setup.sh) or pass --hencky")
    args.hencky_environ = dict(os.environ, **dict(kv.split("=", 1) for kv in args.hencky_env))
    work = args.work.resolve()
    work.mkdir(parents=True, exist_ok=True)
    args.results.mkdir(parents=True, exist_ok=True)
    return exe.resolve(), work, dt.datetime.now().strftime("%Y%m%d-%H%M%S")


def cylinder_boundary_yaml(pressure: str) -> str:
    """The hencky boundary block of the quarter cylinder (geo_cylinder's regions): `pressure`
    (a number or a quoted expression) on the bore, symmetry rollers, both end faces held
    axially."""
    return f"""boundary:
  - region: bore
    pressure: {pressure}
  - region: sym_x
    displacement: {{x: 0}}
  - region: sym_y
    displacement: {{y: 0}}
  - region: bottom
    displacement: {{z: 0}}
  - region: top
    displacement: {{z: 0}}
"""


PROBLEMS = {
    "cantilever": dict(
        geo=geo_cantilever,
        probe=(CANT["L"], CANT["W"] / 2, CANT["H"] / 2),
        exact=timoshenko_tip_deflection,
        reference="Timoshenko beam (bending + shear, Cowper k)",
        quantity="tip deflection -u_z",
        sign=(2, -1.0),  # (component, sign): the compared value is sign * u[component]
        h_calib=0.02,
    ),
    "cylinder": dict(
        geo=geo_cylinder,
        probe=(CYL["a"], 0.0, 0.0),
        exact=lame_bore_displacement,
        reference="Lamé, plane strain",
        quantity="bore radial displacement u_r",
        sign=(0, 1.0),
        h_calib=0.012,
    ),
}


def hencky_case(problem: str, msh: Path, linear: str = "direct") -> str:
    px, py, pz = PROBLEMS[problem]["probe"]
    head = f"""title: bench {problem} {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E!r}
    nu: {NU!r}
"""
    if problem == "cantilever":
        body = f"""boundary:
  - region: fixed
    displacement: {{x: 0, y: 0, z: 0}}
  - region: tip
    force: [0, 0, {-CANT['P']!r}]
"""
        reactions = "[fixed]"
    else:
        body = cylinder_boundary_yaml(repr(CYL['p']))
        reactions = "[sym_x]"
    return head + body + f"""solver: {{steps: 1, end: 1.0, linear: {linear}}}
output:
  probes:
    - name: probe
      point: [{px!r}, {py!r}, {pz!r}]
  reactions: {reactions}
"""


# ----------------------------------------------------------------------------------------------
# Gmsh .msh (format 4.1, ASCII) reader: nodes, 10-node tetrahedra, 6-node triangles by
# physical surface name.
# ----------------------------------------------------------------------------------------------
def read_msh4(path: Path) -> dict:
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    n_lines = len(lines)
    names = {}  # (dim, phys tag) -> name
    ent_phys = {}  # (dim, entity tag) -> [phys tags]
    node_tags = []
    node_xyz = []
    elems = {}  # element type -> list of (entity dim, entity tag, conn array)

    def ints(block):
        return np.array(" ".join(block).split(), dtype=np.int64)

    while i < n_lines:
        s = lines[i].strip()
        if s == "$MeshFormat":
            ver, ftype = lines[i + 1].split()[:2]
            if not ver.startswith("4") or ftype != "0":
                raise SystemExit(f"{path}: expected an ASCII .msh 4.x file, found {lines[i + 1]}")
            i += 2
        elif s == "$PhysicalNames":
            n = int(lines[i + 1])
            for k in range(n):
                m = re.match(r'\s*(\d+)\s+(\d+)\s+"(.*)"', lines[i + 2 + k])
                names[(int(m.group(1)), int(m.group(2)))] = m.group(3)
            i += 2 + n
        elif s == "$Entities":
            counts = [int(v) for v in lines[i + 1].split()]
            i += 2
            for dim in range(4):
                for _ in range(counts[dim]):
                    v = lines[i].split()
                    tag = int(v[0])
                    k = 4 if dim == 0 else 7
                    nphys = int(v[k])
                    ent_phys[(dim, tag)] = [abs(int(t)) for t in v[k + 1:k + 1 + nphys]]
                    i += 1
        elif s == "$Nodes":
            n_blocks = int(lines[i + 1].split()[0])
            i += 2
            for _ in range(n_blocks):
                edim, etag, param, n = (int(v) for v in lines[i].split())
                i += 1
                if n == 0:
                    continue
                node_tags.append(ints(lines[i:i + n]))
                xyz = np.array(" ".join(lines[i + n:i + 2 * n]).split(), dtype=float).reshape(n, -1)
                node_xyz.append(xyz[:, :3])
                i += 2 * n
        elif s == "$Elements":
            n_blocks = int(lines[i + 1].split()[0])
            i += 2
            for _ in range(n_blocks):
                edim, etag, etype, n = (int(v) for v in lines[i].split())
                i += 1
                if n == 0:
                    continue
                a = ints(lines[i:i + n]).reshape(n, -1)
                elems.setdefault(etype, []).append((edim, etag, a))
                i += n
        else:
            i += 1
    tags = np.concatenate(node_tags)
    xyz = np.concatenate(node_xyz)
    coords = np.zeros((tags.max() + 1, 3))
    coords[tags] = xyz
    if 11 not in elems:
        raise SystemExit(f"{path}: no 10-node tetrahedra (Gmsh type 11); mesh with -order 2")
    tets = np.concatenate([a[:, 1:] for (_, _, a) in elems[11]])
    surfaces = {}
    for (_, etag, a) in elems.get(9, []):  # 6-node triangles
        for ph in ent_phys.get((2, etag), []):
            surfaces.setdefault(names.get((2, ph), str(ph)), []).append(a[:, 1:])
    surfaces = {k: np.concatenate(v) for k, v in surfaces.items()}
    return dict(coords=coords, node_tags=np.unique(tets), tets=tets, surfaces=surfaces)


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


def nearest_node(mesh: dict, point) -> tuple[int, float]:
    """The used mesh node nearest to `point` and its distance."""
    coords, used = mesh["coords"], mesh["node_tags"]
    px = np.array(point, dtype=float)
    node = int(used[np.argmin(np.linalg.norm(coords[used] - px, axis=1))])
    return node, float(np.linalg.norm(coords[node] - px))


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


def write_ccx_inp(problem: str, mesh: dict, inp: Path) -> dict:
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
        bcs = "*BOUNDARY\nSYM_X,1,1\nSYM_Y,2,2\nBOTTOM,3,3\nTOP,3,3\n"
        # Pressure on the bore: *DLOAD on the element faces that lie on it.
        loads.append(ccx_face_pressure(coords, tets_ccx, surf["bore"], CYL["p"]))
    out.append("*STEP\n*STATIC\n")
    out.append(bcs)
    out += loads
    out.append("*NODE PRINT, NSET=PROBE\nU\n*NODE FILE\nU\n*EL FILE\nS\n*END STEP\n")
    inp.write_text("".join(out))
    return dict(probe_node=probe, probe_offset=probe_dist, tet10_midnode_check=order_error)


# ----------------------------------------------------------------------------------------------
# Running programs
# ----------------------------------------------------------------------------------------------
def cpu_snapshot() -> tuple[float, float]:
    """(busy, steal) CPU seconds of the whole machine since boot, from /proc/stat."""
    v = [int(x) for x in open("/proc/stat").readline().split()[1:]]
    hz = os.sysconf("SC_CLK_TCK")
    user, nice, system, idle, iowait, irq, softirq, steal = (v + [0] * 8)[:8]
    return (user + nice + system + irq + softirq) / hz, steal / hz


def wait_quiet(max_wait: float, threshold: float = 0.15) -> dict:
    """Wait (at most max_wait seconds) until other programs use less than `threshold` cores,
    measured over one second. Returns the wait and the last measured background."""
    t0 = time.perf_counter()
    while True:
        b0, s0 = cpu_snapshot()
        time.sleep(1.0)
        b1, s1 = cpu_snapshot()
        bg = (b1 - b0) + (s1 - s0)
        waited = time.perf_counter() - t0
        if bg < threshold or waited >= max_wait:
            return dict(waited=waited, background=bg)
        time.sleep(2.0)


def timed(cmd, cwd, env=None, log=None) -> dict:
    """Run under /usr/bin/time -v: wall seconds (measured here), peak RSS, CPU seconds. The
    output lines go to `log`, each prefixed with the seconds since the start (for phases)."""
    tv = cwd / "time-v.txt"
    full = ["/usr/bin/time", "-v", "-o", str(tv)] + [str(c) for c in cmd]
    load = os.getloadavg()[0]
    busy0, steal0 = cpu_snapshot()
    t0 = time.perf_counter()
    stamped = []
    with subprocess.Popen(full, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, errors="replace", bufsize=1) as proc:
        for line in proc.stdout:
            stamped.append((time.perf_counter() - t0, line.rstrip("\n")))
        rc = proc.wait()
    wall = time.perf_counter() - t0
    busy1, steal1 = cpu_snapshot()
    if log:
        Path(log).write_text("".join(f"[{t:9.3f}] {l}\n" for t, l in stamped))
    text = tv.read_text()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) * 1024
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1))
    sys_ = float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1))
    # CPU taken by other programs during the run (cores on average): the machine's busy time
    # minus this process tree's, plus the hypervisor's steal time.
    others = max(0.0, (busy1 - busy0) - (user + sys_) + (steal1 - steal0)) / wall
    return dict(rc=rc, wall=wall, peak_rss=rss, cpu=user + sys_, load_before=load, others=others,
                lines=stamped)


def with_timeout(cmd: list, timeout: float | None) -> list:
    """`cmd` run under coreutils' timeout (SIGTERM after `timeout` s, SIGKILL 30 s later; exit
    status 124 or 137 then). Under /usr/bin/time -v the peak memory is still the program's."""
    if not timeout:
        return cmd
    return ["timeout", "--kill-after=30", f"{timeout:g}"] + cmd


TIMEOUT_EXIT = (124, 137)


def run_hencky(exe: Path, case: Path, out: Path, threads: int, env=None, timeout: float | None = None,
               check: bool = True) -> dict:
    """hencky run under /usr/bin/time -v; r["summary"] is summary.json (None when the run wrote
    none: killed by the timeout, crashed). check: raise unless hencky converged (exit 0)."""
    if out.exists():
        shutil.rmtree(out)
    log = case.parent / f"{case.stem}.hencky.log"
    r = timed(with_timeout([exe, "run", case, "-o", out, "--threads", threads, "--quiet"], timeout),
              case.parent, env=env, log=log)
    del r["lines"]
    if r["rc"] != 0 and check:
        raise SystemExit(f"hencky failed (exit {r['rc']}), see {log}")
    r["timed_out"] = bool(timeout) and r["rc"] in TIMEOUT_EXIT
    r["log"] = str(log)
    summary = out / "summary.json"
    r["summary"] = json.loads(summary.read_text()) if summary.exists() else None
    return r


def parse_ccx_dat(dat: Path, node: int) -> list[float]:
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
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads),
               CCX_NPROC_STIFFNESS=str(threads), CCX_NPROC_RESULTS=str(threads),
               GFORTRAN_UNBUFFERED_PRECONNECTED="y")
    for ext in (".dat", ".frd", ".sta", ".cvg", ".12d"):
        (job_dir / (job + ext)).unlink(missing_ok=True)
    log = job_dir / f"{job}.ccx.log"
    cmd = ["ccx", "-i", job]
    if shutil.which("stdbuf"):
        cmd = ["stdbuf", "-oL", "-eL"] + cmd
    r = timed(with_timeout(cmd, timeout), job_dir, env=env, log=log)
    text = "\n".join(l for _, l in r["lines"])
    r["ok"] = r["rc"] == 0 and "*ERROR" not in text
    r["timed_out"] = bool(timeout) and r["rc"] in TIMEOUT_EXIT
    r["log"] = str(log)
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


# ----------------------------------------------------------------------------------------------
# Machine
# ----------------------------------------------------------------------------------------------
def sh(cmd) -> str:
    try:
        return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()
    except Exception:
        return ""


def machine_info() -> dict:
    cpu = ""
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    flags = ""
    for line in open("/proc/cpuinfo"):
        if line.startswith("flags"):
            fl = line.split(":", 1)[1].split()
            flags = " ".join(f for f in ("avx2", "fma", "avx512f") if f in fl)
            break
    mem = 0
    for line in open("/proc/meminfo"):
        if line.startswith("MemTotal"):
            mem = int(line.split()[1]) * 1024
    blas = sh("update-alternatives --query libblas.so.3-x86_64-linux-gnu | sed -n 's/^Value: //p'")
    return dict(
        nproc=os.cpu_count(),
        cpu=cpu,
        cpu_flags=flags,
        hypervisor=sh("lscpu | sed -n 's/^Hypervisor vendor: *//p'"),
        memory_bytes=mem,
        kernel=platform.release(),
        os=sh(". /etc/os-release && echo $PRETTY_NAME"),
        blas=blas,
        openblas=sh("dpkg-query -W -f='${Package} ${Version}\\n' 'libopenblas0*' 2>/dev/null"),
        cholmod=sh("dpkg-query -W -f='${Package} ${Version}\\n' 'libcholmod*' 2>/dev/null"),
        ccx=sh("dpkg-query -W -f='${Package} ${Version}' calculix-ccx 2>/dev/null"),
        spooles=sh("dpkg-query -W -f='${Package} ${Version}' 'libspooles*' 2>/dev/null"),
        gmsh=sh("gmsh --version 2>&1"),
        numpy=np.__version__,
        python=platform.python_version(),
    )


def dgemm_rate(n: int, threads: int | None, reps: int = 3) -> float:
    """Median GFLOP/s of numpy a @ b (OpenBLAS dgemm) in a child process, so that the thread
    count can be set before OpenBLAS starts."""
    code = (
        "import numpy as np, time, statistics\n"
        f"n={n}\n"
        "a=np.random.rand(n,n); b=np.random.rand(n,n); a@b\n"
        "r=[]\n"
        f"for _ in range({reps}):\n"
        "    t=time.perf_counter(); a@b; r.append(2*n**3/(time.perf_counter()-t)/1e9)\n"
        "print(statistics.median(r))\n"
    )
    env = dict(os.environ)
    if threads:
        env["OPENBLAS_NUM_THREADS"] = str(threads)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    return float(out.stdout.strip())


# ----------------------------------------------------------------------------------------------
# Benchmark
# ----------------------------------------------------------------------------------------------
def gmsh_mesh(problem: str, h: float, work: Path, threads: int) -> tuple[Path, float]:
    name = f"{problem}_h{h:.6g}"
    geo, msh = work / f"{name}.geo", work / f"{name}.msh"
    if not msh.exists():
        geo.write_text(PROBLEMS[problem]["geo"](h))
        t0 = time.perf_counter()
        r = subprocess.run(["gmsh", "-3", "-order", "2", "-format", "msh4", "-nt", str(threads),
                            str(geo), "-o", str(msh)], capture_output=True, text=True)
        if r.returncode != 0 or not msh.exists():
            raise SystemExit(f"gmsh failed on {geo}:\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
        (work / f"{name}.gmsh-seconds").write_text(f"{time.perf_counter() - t0}\n")
    secs = float((work / f"{name}.gmsh-seconds").read_text())
    return msh, secs


def count_nodes(msh: Path) -> int:
    cache = msh.with_suffix(".nodes")
    if cache.exists() and cache.stat().st_mtime >= msh.stat().st_mtime:
        return int(cache.read_text())
    with open(msh) as f:
        for line in f:
            if line.startswith("$Nodes"):
                n = int(next(f).split()[1])
                cache.write_text(f"{n}\n")
                return n
    raise SystemExit(f"{msh}: no $Nodes")


def size_for(problem: str, target_dofs: float, work: Path, threads: int) -> tuple[Path, float, float]:
    """Mesh with about target_dofs unknowns (3 per node). Unknowns scale about as h^-p
    (p a little under 3: surface effects); p and the constant are fitted on the meshes made so
    far for this problem (a small calibration mesh first), the size is corrected until the
    mesh is within 6 % of the target (at most 4 meshes)."""
    samples = {}
    for msh in work.glob(f"{problem}_h*.msh"):
        samples[float(msh.stem.split("_h")[1])] = 3 * count_nodes(msh)
    h0 = PROBLEMS[problem]["h_calib"]
    if not samples:
        msh, _ = gmsh_mesh(problem, h0, work, threads)
        samples[h0] = 3 * count_nodes(msh)
    for _ in range(4):
        best = min(samples, key=lambda h: abs(math.log(samples[h] / target_dofs)))
        if abs(samples[best] / target_dofs - 1) <= 0.06:
            break
        near = sorted(samples, key=lambda h: abs(math.log(samples[h] / target_dofs)))[:2]
        p = 2.85
        if len(near) == 2 and abs(math.log(near[0] / near[1])) > 0.05:
            p = -math.log(samples[near[0]] / samples[near[1]]) / math.log(near[0] / near[1])
            p = min(max(p, 2.0), 3.5)
        h = float(f"{best * (samples[best] / target_dofs) ** (1 / p):.4g}")
        if h in samples:
            break
        msh, _ = gmsh_mesh(problem, h, work, threads)
        samples[h] = 3 * count_nodes(msh)
    best = min(samples, key=lambda h: abs(math.log(samples[h] / target_dofs)))
    msh, secs = gmsh_mesh(problem, best, work, threads)
    return msh, secs, best


def add_common_arguments(ap: argparse.ArgumentParser) -> None:
    """The options the plastic and contact benchmarks share."""
    ap.add_argument("--no-ccx", action="store_true", help="do not run CalculiX")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="threads for hencky and ccx (default: all cores)")
    ap.add_argument("--hencky-env", action="append", default=[], metavar="NAME=VALUE", help="extra environment for hencky")
    ap.add_argument("--wait-quiet", type=float, default=30.0,
                    help="before each run wait up to this many seconds for other programs to leave the CPU (0: never)")
    ap.add_argument("--work", type=Path, default=BENCH / "work", help="meshes and runs (default bench/work)")
    ap.add_argument("--results", type=Path, default=BENCH / "results")
    ap.add_argument("--keep-output", action="store_true", help="keep hencky's output folders and ccx's .frd")
    ap.add_argument("--report", type=Path, help="run nothing: print the markdown of this results .json")


def size_run_dir(msh: Path, work: Path, prefix: str) -> tuple[Path, dict]:
    """work/<prefix>-<mesh stem>/ holding (a hard link to) the .msh, and the mesh read."""
    run_dir = work / f"{prefix}-{msh.stem}"
    run_dir.mkdir(exist_ok=True)
    local_msh = run_dir / msh.name
    if not local_msh.exists():
        os.link(msh, local_msh) if msh.stat().st_dev == run_dir.stat().st_dev else shutil.copy(msh, local_msh)
    return run_dir, read_msh4(msh)


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def bench_one(problem, target, args, work, exe) -> dict:
    spec = PROBLEMS[problem]
    msh, gmsh_seconds, h = size_for(problem, target, work, args.threads)
    run_dir = work / msh.stem
    run_dir.mkdir(exist_ok=True)
    local_msh = run_dir / msh.name
    if not local_msh.exists():
        os.link(msh, local_msh) if msh.stat().st_dev == run_dir.stat().st_dev else shutil.copy(msh, local_msh)
    case = run_dir / ("case.yaml" if args.linear == "direct" else f"case-{args.linear}.yaml")
    case.write_text(hencky_case(problem, local_msh, args.linear))
    exact = spec["exact"]()
    comp, sign = spec["sign"]
    row = dict(problem=problem, target_dofs=target, linear=args.linear, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds,
               exact=exact, reference=spec["reference"], quantity=spec["quantity"])
    print(f"[{problem} ~{target / 1000:.0f}k] h = {h:g}: {msh.name}", flush=True)

    ccx_ok = (not args.no_ccx) and shutil.which("ccx") and (args.ccx_max_dofs <= 0 or target <= args.ccx_max_dofs)
    inp_info = None
    if ccx_ok:
        t0 = time.perf_counter()
        mesh = read_msh4(msh)
        inp_info = write_ccx_inp(problem, mesh, run_dir / "job.inp")
        row["ccx_input"] = dict(inp_info, convert_seconds=time.perf_counter() - t0,
                                elements=int(len(mesh["tets"])), nodes=int(len(mesh["node_tags"])))
        del mesh

    hencky_runs, ccx_runs = [], []
    repeats = max(1, args.repeat)
    k = 0
    while k < repeats:
        if args.wait_quiet > 0:
            q = wait_quiet(args.wait_quiet)
            if q["waited"] > 1.5:
                print(f"    (waited {q['waited']:.0f} s for other programs to stop; background now {q['background']:.2f} cores)", flush=True)
        r = run_hencky(exe, case, run_dir / "hencky.out", args.threads, getattr(args, "hencky_environ", None))
        hencky_runs.append(r)
        s = r["summary"]
        print(f"    hencky  {s['dofs']:>8d} dofs  wall {r['wall']:7.2f} s  peak {r['peak_rss'] / 2**20:7.0f} MiB"
              f"  (mesh {s['wall_seconds']['mesh']:.2f}, setup {s['wall_seconds']['setup']:.2f},"
              f" assembly {s['wall_seconds']['assembly']:.2f}, factor {s['wall_seconds']['factorization']:.2f},"
              f" solve {s['wall_seconds']['solve']:.2f}, output {s['wall_seconds']['output']:.2f});"
              f" others {r['others']:.2f} cores", flush=True)
        if ccx_ok:
            if args.wait_quiet > 0:
                wait_quiet(args.wait_quiet)
            c = run_ccx(run_dir, "job", args.threads)
            c["u"] = parse_ccx_dat(run_dir / "job.dat", inp_info["probe_node"])
            ccx_runs.append(c)
            print(f"    ccx              wall {c['wall']:7.2f} s  peak {c['peak_rss'] / 2**20:7.0f} MiB"
                  f"  SPOOLES on {c['cpus'].get('spooles', '?')} threads; others {c['others']:.2f} cores", flush=True)
        k += 1
        slowest = max([r["wall"]] + ([c["wall"]] if ccx_ok else []))
        if k == 1 and slowest > args.repeat_below:
            repeats = max(1, args.repeat_large)  # large sizes: fewer runs
    # Runs during which other programs took more than --disturbed cores are left out of the
    # statistics when at least one undisturbed run exists (all runs are kept in *_all).
    def undisturbed(runs):
        clean = [x for x in runs if x["others"] <= args.disturbed]
        return clean or runs
    hencky_all, ccx_all = hencky_runs, ccx_runs
    hencky_runs, ccx_runs = undisturbed(hencky_all), undisturbed(ccx_all)
    s = hencky_runs[-1]["summary"]
    u_h = s["probes"]["probe"]["displacement"]
    value_h = sign * u_h["xyz"[comp]]
    phases = ("mesh", "setup", "assembly", "factorization", "solve", "material", "output", "total")
    row["hencky"] = dict(
        runs=len(hencky_runs),
        dofs=s["dofs"], nodes=s["nodes"], elements=s["elements"],
        wall=median([r["wall"] for r in hencky_runs]),
        wall_all=[r["wall"] for r in hencky_all],
        others_all=[r["others"] for r in hencky_all],
        cpu=median([r["cpu"] for r in hencky_runs]),
        peak_rss=median([r["peak_rss"] for r in hencky_runs]),
        peak_memory_bytes=median([r["summary"]["peak_memory_bytes"] for r in hencky_runs]),
        phases={p: median([r["summary"]["wall_seconds"][p] for r in hencky_runs]) for p in phases},
        factor_flops=s["linear_solver"]["factor_flops"],
        factor_nonzeros=s["linear_solver"].get("factor_nonzeros"),
        factor_gflops=median([r["summary"]["linear_solver"].get("factor_gflops_per_second") for r in hencky_runs]),
        method=s["linear_solver"]["method"],
        iterations=s["linear_solver"].get("iterations"),
        threads=s.get("threads"),
        load=median([r["load_before"] for r in hencky_runs]),
        others=median([r["others"] for r in hencky_runs]),
        value=value_h,
        error=(value_h - exact) / exact,
    )
    if ccx_runs:
        value_c = sign * ccx_runs[-1]["u"][comp]
        row["ccx"] = dict(
            runs=len(ccx_runs),
            wall=median([c["wall"] for c in ccx_runs]),
            wall_all=[c["wall"] for c in ccx_all],
            others_all=[c["others"] for c in ccx_all],
            cpu=median([c["cpu"] for c in ccx_runs]),
            peak_rss=median([c["peak_rss"] for c in ccx_runs]),
            reported_seconds=median([c["ccx_reported_seconds"] for c in ccx_runs]),
            cpus=ccx_runs[-1]["cpus"],
            solver=ccx_runs[-1]["solver"],
            phases={k: median([c["phases"].get(k) for c in ccx_runs])
                    for k in ("input_structure", "assembly", "factor_solve", "stress_output")},
            load=median([c["load_before"] for c in ccx_runs]),
            others=median([c["others"] for c in ccx_runs]),
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
def fmt_s(x):
    if x is None:
        return "–"
    return f"{x:.3f}" if x < 1 else f"{x:.2f}" if x < 100 else f"{x:.0f}"


def mib(b):
    return "–" if b is None else f"{b / 2**20:.0f}"


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
    out.append("| problem | unknowns | n | hencky s | ccx s | speed-up | hencky MiB | ccx MiB | mem. ratio | hencky error | ccx error | Δ | others h/c |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        h, c, q = r["hencky"], r.get("ccx"), r.get("ratio")
        oth = f"{h['others']:.2f}" if h.get("others") is not None else "–"
        if c and c.get("others") is not None:
            oth += f"/{c['others']:.2f}"
        out.append(
            f"| {r['problem']} | {h['dofs']:,} | {h['runs']}"
            + (f"/{c['runs']}" if c else "")
            + f" | {fmt_s(h['wall'])} | {fmt_s(c['wall']) if c else '–'} | "
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
               "AMD, then METIS when AMD's fill is high; the smaller fill wins). `material` is the "
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
        rate = h["factor_gflops"] or 0
        out.append(f"| {r['problem']} | {h['dofs']:,} | {(h['factor_nonzeros'] or 0) / 1e6:.1f} | "
                   f"{h['factor_flops'] / 1e9:.1f} | {fmt_s(h['phases']['factorization'])} | {rate:.1f} | "
                   f"{100 * rate / blas['gflops_all']:.0f} % | {h['method'].replace('CHOLMOD ', '')} |")
    out.append("")
    return "\n".join(out)


def machine_markdown(m: dict, blas: dict) -> str:
    return "\n".join([
        f"- CPU: {m['cpu']} ({m['nproc']} cores as seen by Linux, {m['hypervisor'] or 'bare metal'} "
        f"guest; {m['cpu_flags']})",
        f"- Memory: {m['memory_bytes'] / 2**30:.1f} GiB; OS: {m['os']}, kernel {m['kernel']}",
        f"- BLAS: `libblas.so.3` → `{m['blas']}` ({m['openblas'].replace(chr(10), ', ')}); "
        f"CHOLMOD: {m['cholmod'].replace(chr(10), ', ')} (links the same `libblas.so.3`)",
        f"- CalculiX: {m['ccx']} with {m['spooles']}; Gmsh {m['gmsh']}; numpy {m['numpy']}",
        f"- Dense matrix multiply (numpy `a @ b`, n = {blas['n']}, OpenBLAS dgemm): "
        f"**{blas['gflops_all']:.1f} GFLOP/s** with all cores, {blas['gflops_1']:.1f} GFLOP/s on one core",
    ])


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
    iterative = [r for (p, t, lin), r in rows.items() if lin == "iterative"]
    main = results[-1]
    head = machine_markdown(main["machine"], main["blas"]) + "\n\n" + "\n".join(
        f"- run `{res['timestamp']}`: hencky {res['hencky_version']} (git {res['git']}), "
        f"{res['threads']} threads, {res['seconds'] / 60:.1f} min; dgemm then "
        f"{res['blas']['gflops_all']:.1f} GFLOP/s; `{res['command'].replace(str(ROOT) + '/', '')}`"
        + (f"; hencky environment {res['hencky_env']}" if res.get("hencky_env") else "")
        for res in results)
    tables = markdown_tables(list(direct.values()), main["blas"]) if direct else ""
    if iterative:
        tables += "\n" + iterative_table(iterative, direct)
    return head, tables


GEN_BEGIN = "<!-- BEGIN GENERATED by bench/run_bench.py: do not edit between these markers -->"
GEN_END = "<!-- END GENERATED -->"


def write_docs(path: Path, generated: str):
    block = f"{GEN_BEGIN}\n{generated.rstrip()}\n{GEN_END}"
    if path.exists() and GEN_BEGIN in path.read_text():
        text = path.read_text()
        pre, rest = text.split(GEN_BEGIN, 1)
        post = rest.split(GEN_END, 1)[1] if GEN_END in rest else ""
        path.write_text(pre + block + post)
    else:
        path.write_text("# Performance\n\n" + block + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None, help="hencky binary (default: the first of build-f, build-release, build under the repository)")
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
    ap.add_argument("--linear", choices=("direct", "iterative"), default="direct",
                    help="hencky's linear solver (solver.linear of the case)")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="threads for hencky and ccx (default: all cores)")
    ap.add_argument("--hencky-env", action="append", default=[], metavar="NAME=VALUE",
                    help="extra environment for hencky (experiments, e.g. OMP_WAIT_POLICY=passive)")
    ap.add_argument("--no-ccx", action="store_true", help="do not run CalculiX")
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
        exe, work, stamp = prepare_run(args)

        m = machine_info()
        print(f"machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; hencky {exe}", flush=True)
        def measure_blas():
            if args.wait_quiet > 0:
                wait_quiet(args.wait_quiet)
            b = dict(gflops_all=dgemm_rate(args.blas_n, None), gflops_1=dgemm_rate(args.blas_n, 1))
            print(f"dgemm n={args.blas_n}: {b['gflops_all']:.1f} GFLOP/s all cores, {b['gflops_1']:.1f} one core", flush=True)
            return b
        blas_runs = [measure_blas()]

        sizes = [float(x) for x in args.sizes.split(",")]
        sizes = [x for x in sizes if args.min_dofs <= x <= args.max_dofs]
        rows = []
        t_start = time.perf_counter()
        for problem in args.problems.split(","):
            for target in sizes:
                rows.append(bench_one(problem, int(target), args, work, exe))
        blas_runs.append(measure_blas())
        # The machine's capability: the best of the measurements (other programs only slow it).
        blas = dict(n=args.blas_n, runs=blas_runs,
                    gflops_all=max(b["gflops_all"] for b in blas_runs),
                    gflops_1=max(b["gflops_1"] for b in blas_runs))
        dirty = sh(f"git -C {ROOT} status --porcelain --untracked-files=no -- src app CMakeLists.txt")
        result = dict(
            timestamp=stamp, machine=m, blas=blas, hencky=str(exe),
            hencky_version=sh(f"{exe} --version"),
            git=sh(f"git -C {ROOT} rev-parse --short HEAD") + (" + uncommitted changes in src/" if dirty else ""),
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
        write_docs(ROOT / "docs" / "performance.md", gen)
        print("updated docs/performance.md")


if __name__ == "__main__":
    main()
