#!/usr/bin/python3
"""hencky heat conduction against CalculiX *HEAT TRANSFER: temperatures, wall time, peak memory.

**Problem.** A plate 0 < x < L = 0.1 m, 0 < y < W = 0.04 m, meshed in its plane with
unstructured triangles of size h and extruded in z by --layers (2) layers of thickness h (Gmsh
splits each prism into three tetrahedra; 10-node tetrahedra, ccx C3D10), so that it stays
--layers elements thick at every size and the unknowns grow as h^-2 (a truly 3D block makes
hencky's mechanical factorization, 3 dofs per node, cost minutes at 100k nodes: see the notes
below). Steel: k = 45 W/(m K), rho = 7850 kg/m^3, c = 460 J/(kg K), all constant. Initially at
T0 = 20 degC; from t = 0 the face x = 0 ("hot") is held at T1 = 100 degC and the face x = L
("cooled") loses heat by convection h_f = 500 W/(m^2 K) to T_amb = 20 degC (Biot hL/k = 1.11);
the other faces are insulated. Transient, backward Euler, --steps (20) equal steps to --end
(2000 s, Fourier number alpha t / L^2 = 2.5). The solution is one-dimensional, T(x, t), with a
closed form: steady part T_s(x) = T1 + (T_amb - T1) h_f x / (k + h_f L) plus
sum_n c_n sin(lambda_n x) g_n(t), lambda_n L cot(lambda_n L) = -Bi, and
  - exact in time: g_n = exp(-alpha lambda_n^2 t);
  - the same backward-Euler steps, exact in space: g_n = (1 + alpha lambda_n^2 dt)^-m after m
    steps (the "time-discrete reference": what both codes converge to as the mesh is refined,
    so the difference from it is their spatial error alone).

**Runs.** The very same .msh is solved by hencky (case.yaml: heat.analysis transient, heat.steps,
a temperature and a convection condition; hencky always runs a mechanical analysis after the heat
one, so the case also has it, as cheap as it gets: one linear elastic step, the hot face clamped)
and, converted to an .inp with the same nodes (numbers and coordinates) and the same elements
(C3D10 cards, the mid-edge nodes permuted to CalculiX's order), by ccx: *HEAT TRANSFER, DIRECT
with fixed increments dt = end/steps, *BOUNDARY on DOF 11 for the hot face, *FILM on the element
faces of the cooled face, *INITIAL CONDITIONS, TYPE=TEMPERATURE; *NODE PRINT NT of every node
(7 digits, compared) and *NODE FILE NT (.frd, 6 digits, checked against the .dat) at the last
increment, *NODE PRINT TOTALS=ONLY RFL of the hot face (the heat flow). Both runs in each
repetition, hencky first; the median of --repeats runs (a size whose slowest first run is above
--repeat-below seconds is run --repeat-large times only). Both codes get OMP_NUM_THREADS =
--threads (hencky also --threads; ccx also CCX_NPROC_EQUATION_SOLVER etc.).

hencky's Newton tolerance: the timed runs set `heat.tolerance` to --heat-tolerance (1e-12). With
hencky's default (1e-8) a step whose temperatures change little is taken as converged with no
iteration at all, and the temperatures then stay as they were for the rest of the analysis (the
relative residual is measured against the magnitudes of the terms, which grow as the mesh is
refined); each size runs hencky once more with the default (unless --no-default-check) and
reports how many steps it skipped and what that does to the temperatures.

Measured: end-to-end wall time and peak resident memory of each process (/usr/bin/time -v);
hencky's summary.json wall_seconds.heat (the heat analysis alone) and total; ccx's heat
analysis as the time from its "STEP 1" line to "Job finished" (matrix structure, increments,
output); factorizations and iterations of both. Temperatures at every node at t = end: hencky's
VTU (point data `temperature`) against ccx's .dat, matched by coordinates; both against the
closed forms; T at probe nodes along the plate; the heat flow through the hot face.

    /usr/bin/python3 bench/run_heat_bench.py                      # 10k, 30k, 100k nodes
    /usr/bin/python3 bench/run_heat_bench.py --sizes 5000 --repeats 1
    /usr/bin/python3 bench/run_heat_bench.py --report bench/results/heat-bench.json

Results: --results (bench/results/heat-bench.md) and the same stem .json (rewritten after every
size). Meshes and runs go to --work (bench/work; meshes reused). Standard library + numpy; the
henckybench package (bench/henckybench) for Gmsh, the .msh reader, the C3D10 cards, running
programs under /usr/bin/time -v and the machine facts. Needs gmsh, ccx (Debian calculix-ccx:
bash bench/setup.sh installs it) and GNU time.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from henckybench import BENCH, ROOT, gmsh, report, runner
from henckybench.calculix import ccx_environment, ccx_face_pressure, ccx_mesh_cards, ccx_nset, ccx_num, ccx_tets
from henckybench.problems import PROBLEMS
from henckybench.report import fmt_s, mib

# ----------------------------------------------------------------------------------------------
# The problem
# ----------------------------------------------------------------------------------------------
L, W = 0.1, 0.04          # plate length (heat flows along x) and width, m
K, RHO, C = 45.0, 7850.0, 460.0   # W/(m K), kg/m^3, J/(kg K)
E_MOD, NU, ALPHA = 2.1e11, 0.3, 1.2e-5  # for hencky's mechanical analysis only
T0, T_HOT, T_AMB = 20.0, 100.0, 20.0    # initial, hot face, ambient (degC)
PROBE_X = (0.0, 0.25, 0.5, 0.75, 1.0)   # probe nodes along the plate, as fractions of L


def geo_plate(h: float, layers: int) -> str:
    """The plate for Gmsh: triangles of size h in the plane, extruded by `layers` layers of
    thickness h. Physical groups: plate (volume), hot (x = 0), cooled (x = L)."""
    return f"""// hencky heat benchmark: plate {L} x {W} m, {layers} layers of thickness h, element size h
L = {L!r}; W = {W!r}; h = {h!r};
Point(1) = {{0, 0, 0, h}}; Point(2) = {{L, 0, 0, h}}; Point(3) = {{L, W, 0, h}}; Point(4) = {{0, W, 0, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
out[] = Extrude {{0, 0, {layers}*h}} {{ Surface{{1}}; Layers{{{layers}}}; }};
// out[0] top, out[1] volume, out[2..5] the lateral faces from lines 1..4
Physical Volume("plate") = {{out[1]}};
Physical Surface("hot") = {{out[5]}};
Physical Surface("cooled") = {{out[3]}};
Mesh.MeshSizeMax = h;
"""


def heat_problem(layers: int) -> str:
    """Registers the plate in PROBLEMS (gmsh.size_for's size fitting and mesh cache)."""
    name = f"heat-plate-l{layers}"
    PROBLEMS[name] = dict(geo=lambda h: geo_plate(h, layers), h_calib=0.003)
    return name


class Slab:
    """The closed form of the problem: T(x, t) in 0 < x < L, T(0) = T1, -k T'(L) = h (T(L) - Ta),
    T(x, 0) = T0; exact in time, or after m backward-Euler steps of dt (exact in space)."""

    def __init__(self, h_film: float, n_terms: int = 400):
        self.h = h_film
        self.alpha = K / (RHO * C)
        self.bi = h_film * L / K
        n = np.arange(1, n_terms + 1)
        lo, hi = (n - 0.5) * np.pi, n * np.pi  # f(z) = z cos z + Bi sin z changes sign in (lo, hi)
        f = lambda z: z * np.cos(z) + self.bi * np.sin(z)
        flo = f(lo)
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            fm = f(mid)
            left = np.sign(fm) == np.sign(flo)
            lo, flo = np.where(left, mid, lo), np.where(left, fm, flo)
            hi = np.where(left, hi, mid)
        lam = 0.5 * (lo + hi) / L
        self.lam = lam
        # theta(x, 0) = T0 - T_s(x) = A + B x
        self.slope = (T_AMB - T_HOT) * h_film / (K + h_film * L)  # T_s'(x)
        A, B = T0 - T_HOT, -self.slope
        I = A * (1 - np.cos(lam * L)) / lam + B * (np.sin(lam * L) / lam**2 - L * np.cos(lam * L) / lam)
        N = L / 2 - np.sin(2 * lam * L) / (4 * lam)
        self.c = I / N

    def decay(self, t: float, dt: float | None) -> np.ndarray:
        if dt is None:
            return np.exp(-self.alpha * self.lam**2 * t)
        m = round(t / dt)
        return (1 + self.alpha * self.lam**2 * dt) ** (-m)

    def T(self, x, t: float, dt: float | None = None) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        g = self.c * self.decay(t, dt)
        return T_HOT + self.slope * x + np.sin(np.multiply.outer(x, self.lam)) @ g

    def hot_flow(self, t: float, area: float, dt: float | None = None) -> float:
        """Heat into the body through x = 0, W: -k A T'(0, t)."""
        g = self.c * self.decay(t, dt)
        return float(-K * area * (self.slope + np.dot(self.lam, g)))

    def hot_flow_mean(self, t: float, area: float, dt: float | None = None) -> float:
        """The mean of hot_flow over [0, t], W: the heat brought in over [0, t] divided by t
        (backward Euler: a step brings q(t_k) dt in, the mean is that of the step ends)."""
        if dt is not None:
            m = round(t / dt)
            return float(np.mean([self.hot_flow(k * dt, area, dt) for k in range(1, m + 1)]))
        a = self.alpha * self.lam**2
        integral = self.slope * t + np.dot(self.c * self.lam, (1 - np.exp(-a * t)) / a)
        return float(-K * area * integral / t)


# ----------------------------------------------------------------------------------------------
# Input decks
# ----------------------------------------------------------------------------------------------
def hencky_case(msh: Path, args, tolerance: float | None) -> str:
    tol = f"\n  tolerance: {tolerance!r}" if tolerance else ""
    probes = "".join(f"\n    - {{name: x{int(round(100 * f)):03d}, point: [{f * L!r}, {W / 2!r}, 0.0]}}" for f in PROBE_X)
    return f"""title: heat bench {msh.stem}
mesh: {{file: {msh.name}}}
materials:
  - name: steel
    E: {E_MOD!r}
    nu: {NU!r}
    alpha: {ALPHA!r}
    conductivity: {K!r}
    density: {RHO!r}
    specific_heat: {C!r}
temperature: {{reference: {T0!r}, from: heat}}
heat:
  analysis: transient
  initial: {T0!r}
  theta: 1.0
  steps: {args.steps}{tol}
  boundary:
    - {{region: hot, temperature: {T_HOT!r}}}
    - {{region: cooled, convection: {{h: {args.film!r}, ambient: {T_AMB!r}}}}}
boundary:
  - {{region: hot, displacement: {{x: 0, y: 0, z: 0}}}}
solver: {{steps: 1, end: {args.end!r}}}
output:
  every: 1
  heat_flows: [hot, cooled]
  probes:{probes}
"""


def write_ccx_inp(mesh: dict, inp: Path, args) -> dict:
    """The plate for ccx: the .msh's nodes and C3D10 elements, the heat transfer step."""
    tets_ccx, order_error = ccx_tets(mesh)
    surf = mesh["surfaces"]
    out = [f"*HEADING\nhencky heat benchmark: {len(tets_ccx)} C3D10, {len(mesh['node_tags'])} nodes\n"]
    out += ccx_mesh_cards(mesh, tets_ccx)
    out.append(ccx_nset("HOT", surf["hot"]))
    out.append(f"*MATERIAL, NAME=STEEL\n*CONDUCTIVITY\n{ccx_num(K)}\n*SPECIFIC HEAT\n{ccx_num(C)}\n"
               f"*DENSITY\n{ccx_num(RHO)}\n")
    out.append("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
    out.append(f"*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, {ccx_num(T0)}\n")
    dt = args.end / args.steps
    out.append(f"*STEP, INC={10 * args.steps}\n*HEAT TRANSFER, DIRECT\n{ccx_num(dt)}, {ccx_num(args.end)}\n")
    out.append(f"*BOUNDARY\nHOT, 11, 11, {ccx_num(T_HOT)}\n")
    # the cooled face's element faces (the face matcher writes "element,P<face>,value" lines)
    faces = [l.split(",")[:2] for l in
             ccx_face_pressure(mesh["coords"], tets_ccx, surf["cooled"], 0.0, "cooled").splitlines()[1:]]
    out.append("*FILM\n" + "".join(f"{e},F{p[1:]},{ccx_num(T_AMB)},{ccx_num(args.film)}\n" for e, p in faces))
    n = args.steps
    out.append(f"*NODE PRINT, NSET=NALL, FREQUENCY={n}\nNT\n"
               f"*NODE PRINT, NSET=HOT, TOTALS=ONLY, FREQUENCY={n}\nRFL\n"
               f"*NODE FILE, FREQUENCY={n}\nNT\n*END STEP\n")
    inp.write_text("".join(out))
    return dict(film_faces=len(faces), tet10_midnode_check=order_error)


# ----------------------------------------------------------------------------------------------
# Reading the results
# ----------------------------------------------------------------------------------------------
def ccx_dat_temperatures(dat: Path) -> tuple[float | None, dict[int, float], dict[float, float]]:
    """The last "temperatures" block of a ccx .dat ({node: T}, its time) and the "total heat
    generation" (RFL totals) values, {time: value}."""
    t_last, temps, cur, flows = None, {}, None, {}
    lines = dat.read_text(errors="replace").splitlines() if dat.exists() else []
    k = 0
    while k < len(lines):
        line = lines[k]
        m = re.match(r"\s*temperatures for set \S+ and time\s+([-+0-9.Ee]+)", line)
        if m:
            t_last, cur = float(m.group(1)), {}
            temps = cur
            k += 1
            continue
        m = re.match(r"\s*total heat generation for set \S+ and time\s+([-+0-9.Ee]+)", line)
        if m:
            cur = None
            for l2 in lines[k + 1:k + 5]:
                if l2.strip():
                    flows[float(m.group(1))] = float(l2.split()[0])
                    break
            k += 1
            continue
        v = line.split()
        if cur is not None and len(v) == 2:
            try:
                cur[int(v[0])] = float(v[1])
            except ValueError:
                cur = None
        elif cur is not None and v:
            cur = None
        k += 1
    return t_last, temps, flows


def ccx_frd_temperatures(frd: Path) -> dict[int, float]:
    """The last NDTEMP block of an ASCII .frd: {node: T} (E12.5: 6 digits)."""
    last, cur = {}, None
    if not frd.exists():
        return last
    with open(frd, errors="replace") as f:
        for line in f:
            if line.startswith(" -4  NDTEMP"):
                cur = {}
            elif cur is not None and line.startswith(" -1"):
                cur[int(line[3:13])] = float(line[13:25])
            elif cur is not None and line.startswith(" -3"):
                last, cur = cur, None
    return last


def match_by_coordinates(xa: np.ndarray, xb: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Orderings ia, ib with xa[ia] ~ xb[ib] (both the same point set), and the largest distance
    between matched points (0 when they hold the same doubles)."""
    if len(xa) != len(xb):
        raise SystemExit(f"the two point sets differ in size: {len(xa)} and {len(xb)}")
    scale = max(float(np.abs(xa).max()), 1e-300)
    key = lambda x: np.lexsort(tuple(np.round(x[:, d] / scale, 10) for d in (2, 1, 0)))
    ia, ib = key(xa), key(xb)
    return ia, ib, float(np.linalg.norm(xa[ia] - xb[ib], axis=1).max())


def zero_iteration_steps(log: Path) -> list[float]:
    """The heat steps that hencky's log says took 0 Newton iterations (their end times)."""
    if not log.exists():
        return []
    return [float(m.group(1)) for m in re.finditer(r"heat t = ([-+0-9.eE]+): 0 iterations", log.read_text())]


# ----------------------------------------------------------------------------------------------
# Runs
# ----------------------------------------------------------------------------------------------
def run_hencky(exe: Path, case: Path, out: Path, args) -> dict:
    r = runner.run_hencky(exe, case, out, args.threads, env=args.hencky_environ, check=False)
    s = r["summary"]
    if r["rc"] != 0 or s is None or s.get("status") != "converged":
        raise SystemExit(f"hencky failed on {case} (exit {r['rc']}), see {r['log']} and {out}/hencky.log")
    return r


def run_ccx(run_dir: Path, job: str, args) -> dict:
    """ccx under /usr/bin/time -v (line-buffered, so that its progress lines carry times)."""
    env = dict(os.environ, **ccx_environment(args.threads))
    for ext in (".dat", ".frd", ".sta", ".cvg", ".12d"):
        (run_dir / (job + ext)).unlink(missing_ok=True)
    log = run_dir / f"{job}.ccx.log"
    cmd = ["ccx", "-i", job]
    if shutil.which("stdbuf"):
        cmd = ["stdbuf", "-oL", "-eL"] + cmd
    r = runner.timed(cmd, run_dir, env=env, log=log)
    text = "\n".join(l for _, l in r["lines"])
    if r["rc"] != 0 or "*ERROR" in text or "Job finished" not in text:
        raise SystemExit(f"ccx failed (exit {r['rc']}), see {log}")

    def first(pattern):
        return next((t for t, l in r["lines"] if re.search(pattern, l)), None)

    t_step, t_end = first(r"^\s*STEP\s+1\b"), first(r"Job finished")
    r["heat_seconds"] = t_end - t_step if t_step is not None and t_end is not None else None
    r["input_seconds"] = t_step
    r["factorizations"] = len(re.findall(r"Factoring the system of equations", text))
    r["iterations"] = len(re.findall(r"^\s*iteration\s+\d+", text, flags=re.M))
    r["increments"] = len(re.findall(r"^\s*increment\s+\d+\s+attempt", text, flags=re.M))
    m = re.search(r"number of equations\s*\n\s*(\d+)", text)
    r["equations"] = int(m.group(1)) if m else None
    m = re.search(r"number of nonzero lower triangular matrix elements\s*\n\s*(\d+)", text)
    r["matrix_nonzeros_lower"] = int(m.group(1)) if m else None
    r["cpus"] = {what.strip(): int(n) for n, what in re.findall(r"Using up to (\d+) cpu\(s\) for ([^.\n]+)", text)}
    m = re.search(r"Total CalculiX Time:\s*([\d.Ee+-]+)", text)
    r["reported_seconds"] = float(m.group(1)) if m else None
    del r["lines"]
    return r


def accuracy(T: np.ndarray, ref: np.ndarray) -> dict:
    d = T - ref
    return dict(max=float(np.abs(d).max()), rms=float(np.sqrt(np.mean(d * d))), mean=float(d.mean()))


def bench_size(problem: str, target: int, args, work: Path, exe: Path, slab: Slab) -> dict:
    msh, gmsh_seconds, h = gmsh.size_for(problem, 3 * target, work, args.threads)
    run_dir = gmsh.mesh_run_dir(msh, work)
    local_msh = run_dir / msh.name
    mesh = gmsh.read_msh4(msh)
    used = mesh["node_tags"]
    n_nodes, n_tets = int(len(used)), int(len(mesh["tets"]))
    thickness = float(mesh["coords"][used, 2].max())
    inp_info = write_ccx_inp(mesh, run_dir / "heat.inp", args)
    case = run_dir / "case.yaml"
    case.write_text(hencky_case(local_msh, args, args.heat_tolerance or None))
    size = dict(target_nodes=target, h=h, msh=str(msh), gmsh_seconds=gmsh_seconds, nodes=n_nodes,
                tetrahedra=n_tets, thickness=thickness, ccx_input=inp_info)
    print(f"[~{target / 1000:.0f}k nodes] h = {h:g}: {msh.name}, {n_nodes} nodes, {n_tets} tetrahedra, "
          f"{thickness * 1000:.3g} mm thick", flush=True)

    hencky_runs, ccx_runs = [], []
    repeats, k = max(1, args.repeats), 0
    out = run_dir / "hencky.out"
    while k < repeats:
        runner.quiet(args)
        r = run_hencky(exe, case, out, args)
        s = r["summary"]
        hencky_runs.append(r)
        w = s["wall_seconds"]
        print(f"    hencky  wall {r['wall']:7.2f} s (heat {w['heat']:.2f}, mechanical factor {w['factorization']:.2f})"
              f"  peak {r['peak_rss'] / 2**20:6.0f} MiB  heat iterations {s['heat']['iterations']}"
              f"  others {r['others']:.2f} cores", flush=True)
        if not args.no_ccx:
            runner.quiet(args)
            c = run_ccx(run_dir, "heat", args)
            ccx_runs.append(c)
            print(f"    ccx     wall {c['wall']:7.2f} s (heat {c['heat_seconds']:.2f})  peak {c['peak_rss'] / 2**20:6.0f} MiB"
                  f"  factorizations {c['factorizations']}  others {c['others']:.2f} cores", flush=True)
        k += 1
        slowest = max([r["wall"]] + [c["wall"] for c in ccx_runs[-1:]])
        if k == 1 and slowest > args.repeat_below:
            repeats = max(1, args.repeat_large)

    # Temperatures at t = end: hencky's last run's VTU, ccx's last run's .dat, the closed forms.
    s = hencky_runs[-1]["summary"]
    vtus = sorted(out.glob("step_*.vtu"))
    v = runner.read_vtu(vtus[-1], ("temperature",))
    xh, th = np.asarray(v["Points"], dtype=float), np.asarray(v["temperature"], dtype=float)
    dt = args.end / args.steps
    exact_h = slab.T(xh[:, 0], args.end)
    disc_h = slab.T(xh[:, 0], args.end, dt)
    area = W * thickness
    acc = dict(
        hencky=dict(vs_exact=accuracy(th, exact_h), vs_discrete=accuracy(th, disc_h),
                    hot_flow=s["heat_flows"]["hot"], cooled_flow=s["heat_flows"]["cooled"],
                    T_min=float(th.min()), T_max=float(th.max())),
        reference=dict(hot_flow_exact=slab.hot_flow(args.end, area),
                       hot_flow_discrete=slab.hot_flow(args.end, area, dt),
                       hot_flow_mean_exact=slab.hot_flow_mean(args.end, area),
                       hot_flow_mean_discrete=slab.hot_flow_mean(args.end, area, dt), area=area),
    )
    probes = []
    for f in PROBE_X:
        node, dist = gmsh.nearest_node(mesh, (f * L, W / 2, 0.0))
        x = mesh["coords"][node]
        probes.append(dict(fraction=f, node=node, x=x.tolist(), distance=dist,
                           exact=float(slab.T([x[0]], args.end)[0]),
                           discrete=float(slab.T([x[0]], args.end, dt)[0])))
    hp = s.get("probes") or {}
    for p in probes:
        e = hp.get(f"x{int(round(100 * p['fraction'])):03d}") or {}
        p["hencky_probe"] = e.get("temperature")  # hencky's own probe (interpolated at the point)
    if ccx_runs:
        t_last, tc_map, flows = ccx_dat_temperatures(run_dir / "heat.dat")
        flow = flows[max(flows)] if flows else None
        frd = ccx_frd_temperatures(run_dir / "heat.frd")
        nodes = np.array(sorted(tc_map), dtype=np.int64)
        tc = np.array([tc_map[n] for n in nodes])
        xc = mesh["coords"][nodes]
        ia, ib, dist = match_by_coordinates(xh, xc)
        if dist > 1e-12 * L:
            raise SystemExit(f"hencky's VTU points and the mesh's nodes differ (by up to {dist:g} m)")
        frd_diff = max((abs(frd[n] - tc_map[n]) for n in tc_map if n in frd), default=None)
        acc["ccx"] = dict(vs_exact=accuracy(tc, slab.T(xc[:, 0], args.end)),
                          vs_discrete=accuracy(tc, slab.T(xc[:, 0], args.end, dt)),
                          hot_flow=flow, time=t_last,
                          T_min=float(tc.min()), T_max=float(tc.max()),
                          frd_vs_dat_max=frd_diff, frd_nodes=len(frd))
        acc["hencky_vs_ccx"] = dict(accuracy(th[ia], tc[ib]), match_distance=dist, nodes=int(len(ia)))
        for p in probes:
            p["ccx"] = tc_map.get(p["node"])
    # hencky's temperature at the probe nodes (its VTU, matched by coordinates)
    for p in probes:
        d = np.linalg.norm(xh - np.array(p["x"]), axis=1)
        j = int(np.argmin(d))
        p["hencky"] = float(th[j]) if d[j] < 1e-12 else None
    size["accuracy"] = acc
    size["probes"] = probes

    def med(runs, fn):
        return runner.median([fn(x) for x in runs])

    size["hencky"] = dict(
        runs=len(hencky_runs), wall_all=[r["wall"] for r in hencky_runs], others_all=[r["others"] for r in hencky_runs],
        wall=med(hencky_runs, lambda r: r["wall"]),
        heat=med(hencky_runs, lambda r: r["summary"]["wall_seconds"]["heat"]),
        heat_all=[r["summary"]["wall_seconds"]["heat"] for r in hencky_runs],
        phases={p: med(hencky_runs, lambda r: r["summary"]["wall_seconds"].get(p))
                for p in ("mesh", "setup", "heat", "assembly", "factorization", "solve", "material", "output", "total")},
        peak_rss=med(hencky_runs, lambda r: r["peak_rss"]),
        peak_memory_bytes=med(hencky_runs, lambda r: r["summary"]["peak_memory_bytes"]),
        cpu=med(hencky_runs, lambda r: r["cpu"]), others=med(hencky_runs, lambda r: r["others"]),
        heat_summary=s["heat"], mechanical_linear_solver=s["linear_solver"], dofs=s["dofs"],
        threads=s.get("threads"), zero_iteration_steps=zero_iteration_steps(out / "hencky.log"))
    if ccx_runs:
        c = ccx_runs[-1]
        size["ccx"] = dict(
            runs=len(ccx_runs), wall_all=[x["wall"] for x in ccx_runs], others_all=[x["others"] for x in ccx_runs],
            wall=med(ccx_runs, lambda x: x["wall"]), heat=med(ccx_runs, lambda x: x["heat_seconds"]),
            heat_all=[x["heat_seconds"] for x in ccx_runs],
            input=med(ccx_runs, lambda x: x["input_seconds"]),
            peak_rss=med(ccx_runs, lambda x: x["peak_rss"]), cpu=med(ccx_runs, lambda x: x["cpu"]),
            others=med(ccx_runs, lambda x: x["others"]), reported_seconds=med(ccx_runs, lambda x: x["reported_seconds"]),
            factorizations=c["factorizations"], iterations=c["iterations"], increments=c["increments"],
            equations=c["equations"], matrix_nonzeros_lower=c["matrix_nonzeros_lower"], cpus=c["cpus"])

    # hencky once more with its default heat.tolerance: does it skip steps?
    if args.default_check and args.heat_tolerance:
        dcase = run_dir / "case-default-tolerance.yaml"
        dcase.write_text(hencky_case(local_msh, args, None))
        dout = run_dir / "hencky-default.out"
        runner.quiet(args)
        r = run_hencky(exe, dcase, dout, args)
        ds = r["summary"]
        dv = runner.read_vtu(sorted(dout.glob("step_*.vtu"))[-1], ("temperature",))
        dx, dtemp = np.asarray(dv["Points"], dtype=float), np.asarray(dv["temperature"], dtype=float)
        ia, ib, _ = match_by_coordinates(dx, xh)
        size["default_tolerance"] = dict(
            wall=r["wall"], heat=ds["wall_seconds"]["heat"], heat_summary=ds["heat"],
            zero_iteration_steps=zero_iteration_steps(dout / "hencky.log"),
            vs_tight=accuracy(dtemp[ia], th[ib]),
            vs_discrete=accuracy(dtemp, slab.T(dx[:, 0], args.end, dt)),
            hot_flow=ds["heat_flows"]["hot"])
        z = size["default_tolerance"]["zero_iteration_steps"]
        print(f"    hencky, default heat.tolerance: {ds['heat']['iterations']} heat iterations, "
              f"{len(z)} steps with none{(' (t = ' + ', '.join(f'{t:g}' for t in z) + ')') if z else ''}; "
              f"max |T - T(tolerance {args.heat_tolerance:g})| = {size['default_tolerance']['vs_tight']['max']:.3g} K", flush=True)
        if not args.keep_output:
            shutil.rmtree(dout, ignore_errors=True)

    a = size["accuracy"]
    print(f"    T at t = {args.end:g} s: hencky vs time-discrete reference max {a['hencky']['vs_discrete']['max']:.2e} K"
          + (f", ccx {a['ccx']['vs_discrete']['max']:.2e} K; hencky - ccx max {a['hencky_vs_ccx']['max']:.2e} K"
             if "ccx" in a else ""), flush=True)
    if not args.keep_output:
        shutil.rmtree(out, ignore_errors=True)
        (run_dir / "heat.frd").unlink(missing_ok=True)
    return size


# ----------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------
def spread(xs) -> str:
    xs = [x for x in xs if x is not None]
    if len(xs) < 2:
        return ""
    return f" ({min(xs):.3g}–{max(xs):.3g})"


def ratio(a, b) -> str:
    return "–" if not a or not b else f"{a / b:.2f}×"


def kelvin(x, digits=2) -> str:
    return "–" if x is None else f"{x:.{digits}e}"


def render(res: dict) -> str:
    p, m = res["parameters"], res["machine"]
    ref = res["reference"]
    out = ["# Heat conduction: hencky against CalculiX *HEAT TRANSFER\n"]
    out.append(f"Run {res['timestamp']}, {res['seconds'] / 60:.1f} min in all.\n")
    out.append(f"- Command: `{report.in_repository(res['command'])}`")
    out.append(f"- Machine: {m['cpu']}, {m['nproc']} cores ({m['hypervisor'] or 'bare metal'}), "
               f"{m['memory_bytes'] / 2**30:.1f} GiB; {m['os']}, kernel {m['kernel']}")
    out.append(f"- {res['hencky_version']}: `{report.in_repository(res['hencky'])}` (built {res.get('built', '?')}; "
               f"repository at git {res['git']}), `--threads {res['threads']}`; CHOLMOD: {m['cholmod'].replace(chr(10), ', ')}; "
               f"BLAS `{m['blas']}`")
    out.append(f"- CalculiX: {m['ccx']} (SPOOLES: {m['spooles']}); Gmsh {m['gmsh']}; numpy {m['numpy']}")
    out.append(f"- Threads: OMP_NUM_THREADS={res['threads']} for both codes (ccx also "
               f"CCX_NPROC_EQUATION_SOLVER/STIFFNESS/RESULTS={res['threads']}); "
               f"extra hencky environment: {', '.join(res['hencky_env']) or 'none'}")
    out.append(f"- Repeats: median of {p['repeats']} runs per size (of {p['repeat_large']} where the first run "
               f"of either code took over {p['repeat_below']:g} s); the machine is shared and noisy: "
               "\"others\" is the CPU (cores, median) that other programs took during the runs.\n")
    out.append(
        f"**Problem.** Plate 0 < x < {L} m, 0 < y < {W} m, {p['layers']} layers of 10-node tetrahedra through "
        f"its thickness (= {p['layers']} h; Gmsh: triangles of size h extruded, each prism split in three), "
        f"the same .msh for both codes (ccx: the same nodes and C3D10 elements in an .inp). k = {K:g} W/(m K), "
        f"ρ = {RHO:g} kg/m³, c = {C:g} J/(kg K) (α = {ref['alpha']:.4e} m²/s). Initially {T0:g} °C; "
        f"from t = 0 the face x = 0 held at {T_HOT:g} °C, the face x = L cooled by convection "
        f"h = {p['film']:g} W/(m² K) to {T_AMB:g} °C (Biot {ref['biot']:.3f}), the other faces insulated. "
        f"Transient, backward Euler, {p['steps']} equal steps to {p['end']:g} s (Fourier number "
        f"{ref['alpha'] * p['end'] / L**2:.2f}). hencky: `heat.tolerance: {p['heat_tolerance']:g}` "
        f"(see the last table for its default) and, as hencky always runs one, a linear elastic "
        f"mechanical step at t = {p['end']:g} s (hot face clamped). ccx: `*HEAT TRANSFER, DIRECT` with "
        f"increments of {p['end'] / p['steps']:g} s, `*BOUNDARY` DOF 11, `*FILM` on the element faces, "
        f"`*INITIAL CONDITIONS, TYPE=TEMPERATURE`, its default convergence controls.\n")
    out.append(
        "**References.** The solution is T(x, t): steady part plus Σ cₙ sin(λₙx) gₙ(t) with "
        "λₙL cot λₙL = −Bi. *Exact*: gₙ = exp(−αλₙ²t). *Time-discrete*: the same backward-Euler steps "
        "solved exactly in space, gₙ = (1 + αλₙ²Δt)⁻ᵐ after m steps; both codes converge to it as "
        "the mesh is refined, so their difference from it is their spatial error, and the difference "
        "between the two references is the time-stepping error common to both "
        f"(at x = L/2: exact {ref['mid_exact']:.4f} °C, time-discrete {ref['mid_discrete']:.4f} °C).\n")

    sizes = res["sizes"]
    out.append("## Time and memory\n")
    out.append(
        "Wall: the whole process (`/usr/bin/time -v`), median (min–max). hencky heat: `wall_seconds.heat` "
        "of summary.json (the heat analysis alone: assembly, factorization, the steps). ccx heat: from "
        "its `STEP 1` line to `Job finished` (matrix structure, the increments, the output); the rest of "
        "ccx's wall is reading the .inp. hencky's total includes reading the mesh, the mechanical step "
        "(a factorization with 3 unknowns per node) and writing the VTU, and its peak memory is that of "
        "the mechanical system; ccx's holds the heat system only. Ratios > 1: hencky faster; memory "
        "ratio < 1: hencky smaller.\n")
    out.append("| nodes | tets | thickness mm | runs h/c | hencky wall s | hencky heat s | ccx wall s | ccx heat s | "
               "wall ccx/hencky | heat ccx/hencky | hencky peak MiB | ccx peak MiB | memory hencky/ccx | "
               "factorizations h/c | others h/c |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for sz in sizes:
        h, c = sz["hencky"], sz.get("ccx")
        hf = h["heat_summary"]["linear_solver"]["factorizations"]
        mf = h["mechanical_linear_solver"]["factorizations"]
        out.append(
            f"| {sz['nodes']:,} | {sz['tetrahedra']:,} | {1000 * sz['thickness']:.3g} | {h['runs']}/{c['runs'] if c else 0} | "
            f"{fmt_s(h['wall'])}{spread(h['wall_all'])} | {fmt_s(h['heat'])}{spread(h['heat_all'])} | "
            + (f"{fmt_s(c['wall'])}{spread(c['wall_all'])} | {fmt_s(c['heat'])}{spread(c['heat_all'])} | "
               f"{ratio(c['wall'], h['wall'])} | {ratio(c['heat'], h['heat'])} | " if c else "– | – | – | – | ")
            + f"{mib(h['peak_rss'])} | {mib(c['peak_rss']) if c else '–'} | "
            + (f"{h['peak_rss'] / c['peak_rss']:.2f} | " if c else "– | ")
            + f"{hf} heat + {mf} mech. / {c['factorizations'] if c else '–'} | "
            + f"{h['others']:.2f}/{c['others'] if c else 0:.2f} |")
    out.append("")
    out.append("hencky's phases (median seconds) and ccx's counts:\n")
    out.append("| nodes | mesh | heat | mechanical assembly | mechanical factorization | output | total | "
               "heat solves | mechanical factor (nonzeros, Gflop) | ccx input | ccx increments / iterations / factorizations | ccx equations |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for sz in sizes:
        h, c = sz["hencky"], sz.get("ccx")
        ph, ml = h["phases"], h["mechanical_linear_solver"]
        out.append(
            f"| {sz['nodes']:,} | {fmt_s(ph['mesh'])} | {fmt_s(ph['heat'])} | {fmt_s(ph['assembly'])} | "
            f"{fmt_s(ph['factorization'])} | {fmt_s(ph['output'])} | {fmt_s(ph['total'])} | "
            f"{h['heat_summary']['linear_solver']['solves']} | "
            f"{(ml.get('factor_nonzeros') or 0) / 1e6:.1f} M, {(ml.get('factor_flops') or 0) / 1e9:.1f} | "
            + (f"{fmt_s(c['input'])} | {c['increments']} / {c['iterations']} / {c['factorizations']} | {c['equations']:,} |"
               if c else "– | – | – |"))
    out.append("")

    out.append(f"## Temperatures at t = {p['end']:g} s\n")
    out.append("Every node: hencky's VTU (`temperature`) and ccx's `*NODE PRINT` NT (.dat, 7 digits), "
               "matched by coordinates (the same doubles). Max and RMS of the difference, in K; the "
               "temperatures span 20–100 °C, which ccx prints to 7 significant digits: ±5e-6 K, the floor "
               "of every difference with ccx.\n")
    out.append("| nodes | hencky − ccx max | RMS | hencky − time-discrete max | RMS | ccx − time-discrete max | RMS | "
               "hencky − exact max | ccx − exact max |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for sz in sizes:
        a = sz["accuracy"]
        hh, cc, hc, rf = a["hencky"], a.get("ccx"), a.get("hencky_vs_ccx"), a["reference"]
        dash = "–"
        cells = [f"{sz['nodes']:,}",
                 kelvin(hc["max"]) if hc else dash, kelvin(hc["rms"]) if hc else dash,
                 kelvin(hh["vs_discrete"]["max"]), kelvin(hh["vs_discrete"]["rms"]),
                 kelvin(cc["vs_discrete"]["max"]) if cc else dash, kelvin(cc["vs_discrete"]["rms"]) if cc else dash,
                 kelvin(hh["vs_exact"]["max"]), kelvin(cc["vs_exact"]["max"]) if cc else dash]
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
    out.append("Heat flow through the hot face into the plate, W, at t = end and its mean over [0, end] (the "
               "heat brought in divided by the time). hencky: `heat_flows.hot` of summary.json, which is "
               "the flow at the end of the mechanical step in the binaries up to e4ed35b and its mean over "
               "the mechanical step (here [0, end]) from 1671b5c on; ccx: `*NODE PRINT, TOTALS=ONLY` RFL "
               "of the hot face's nodes at the last increment (ccx has one print frequency for all its "
               "`*NODE PRINT` requests, and the nodal temperatures are printed at the end only). The plate "
               "is as thick as its layers (thickness column above), so the flow falls with the mesh size.\n")
    out.append("| nodes | hencky `heat_flows.hot` | ccx at end | time-discrete at end | exact at end | "
               "time-discrete mean | exact mean |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|")
    slab = Slab(p["film"])
    for sz in sizes:
        a = sz["accuracy"]
        hh, cc, rf = a["hencky"], a.get("ccx") or {}, dict(a["reference"])
        if "hot_flow_mean_discrete" not in rf:  # results written before the means were added
            rf["hot_flow_mean_exact"] = slab.hot_flow_mean(p["end"], rf["area"])
            rf["hot_flow_mean_discrete"] = slab.hot_flow_mean(p["end"], rf["area"], p["end"] / p["steps"])
        g = lambda d, k: "–" if d.get(k) is None else f"{d[k]:.5g}"
        out.append(f"| {sz['nodes']:,} | {g(hh, 'hot_flow')} | {g(cc, 'hot_flow')} | {g(rf, 'hot_flow_discrete')} | "
                   f"{g(rf, 'hot_flow_exact')} | {g(rf, 'hot_flow_mean_discrete')} | "
                   f"{g(rf, 'hot_flow_mean_exact')} |")
    out.append("")
    big = sizes[-1] if sizes else None
    if big:
        out.append(f"Probe nodes on y = W/2, z = 0 ({big['nodes']:,} nodes), °C:\n")
        out.append("| x / L | node x (m) | hencky | ccx | time-discrete | exact |")
        out.append("|---:|---:|---:|---:|---:|---:|")
        for pr in big["probes"]:
            out.append(f"| {pr['fraction']:g} | {pr['x'][0]:.5f} | "
                       + ("–" if pr.get("hencky") is None else f"{pr['hencky']:.4f}") + " | "
                       + ("–" if pr.get("ccx") is None else f"{pr['ccx']:.4f}") + " | "
                       + f"{pr['discrete']:.4f} | {pr['exact']:.4f} |")
        out.append("")
        cc = big["accuracy"].get("ccx")
        if cc and cc.get("frd_vs_dat_max") is not None:
            out.append(f"ccx's .frd NT (6 digits) and .dat NT agree to {cc['frd_vs_dat_max']:.1e} K at every node "
                       f"({cc['frd_nodes']:,} nodes at {big['nodes']:,}).\n")
    dts = [sz for sz in sizes if sz.get("default_tolerance")]
    if dts:
        out.append("## hencky with its default heat.tolerance (1e-8)\n")
        out.append("One run per size of the same case without `heat.tolerance`. A step whose relative "
                   "residual at its start is already below the tolerance is taken with no Newton iteration, "
                   "i.e. with the temperatures of the step before; the residual is relative to the "
                   "magnitudes of the terms it is made of, which grow as the mesh is refined, and once a "
                   "step is skipped the next one starts from the same temperatures, so every later step "
                   "is skipped as well.\n")
        out.append("| nodes | heat iterations (of 20 steps) | steps with 0 iterations (t, s) | "
                   f"max \\|T − T(tol {p['heat_tolerance']:g})\\| K | max \\|T − time-discrete\\| K | `heat_flows.hot` W | heat s |")
        out.append("|---:|---:|---|---:|---:|---:|---:|")
        for sz in dts:
            d = sz["default_tolerance"]
            z = d["zero_iteration_steps"]
            out.append(f"| {sz['nodes']:,} | {d['heat_summary']['iterations']} | "
                       + (", ".join(f"{t:g}" for t in z) if z else "none") + " | "
                       f"{d['vs_tight']['max']:.3g} | {d['vs_discrete']['max']:.3g} | {d['hot_flow']:.5g} | {fmt_s(d['heat'])} |")
        out.append("")
    return "\n".join(out)


# ----------------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hencky", type=Path, default=None,
                    help="hencky binary (default: the first of build-bench, build-f, build-release, build under the repository)")
    ap.add_argument("--sizes", default="10000,30000,100000", help="target nodes, comma separated (default 10000,30000,100000)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per size and code (median reported; default 3)")
    ap.add_argument("--repeat-below", type=float, default=120.0,
                    help="a size whose first run (either code) took longer than this many seconds is run --repeat-large times (default 120)")
    ap.add_argument("--repeat-large", type=int, default=1, help="runs per size above --repeat-below (default 1)")
    ap.add_argument("--layers", type=int, default=2, help="elements through the thickness (default 2)")
    ap.add_argument("--steps", type=int, default=20, help="backward-Euler steps (default 20)")
    ap.add_argument("--end", type=float, default=2000.0, help="end time, s (default 2000)")
    ap.add_argument("--film", type=float, default=500.0, help="film coefficient of the cooled face, W/(m^2 K) (default 500)")
    ap.add_argument("--heat-tolerance", type=float, default=1e-12,
                    help="hencky heat.tolerance of the timed runs (default 1e-12; 0: hencky's default, 1e-8)")
    ap.add_argument("--no-default-check", dest="default_check", action="store_false",
                    help="do not run hencky once more per size with its default heat.tolerance")
    ap.add_argument("--no-ccx", action="store_true", help="do not run CalculiX")
    ap.add_argument("--threads", type=int, default=os.cpu_count(),
                    help="threads for both codes: OMP_NUM_THREADS, hencky --threads, ccx CCX_NPROC_* (default: all cores)")
    ap.add_argument("--hencky-env", action="append", default=[], metavar="NAME=VALUE", help="extra environment for hencky")
    ap.add_argument("--wait-quiet", type=float, default=5.0,
                    help="before each run wait up to this many seconds for other programs to leave the CPU (default 5; 0: never)")
    ap.add_argument("--work", type=Path, default=BENCH / "work", help="meshes and runs (default bench/work)")
    ap.add_argument("--results", type=Path, default=BENCH / "results" / "heat-bench.md",
                    help="the markdown results (default bench/results/heat-bench.md; the .json beside it)")
    ap.add_argument("--keep-output", action="store_true", help="keep hencky's output folders and ccx's .frd")
    ap.add_argument("--report", type=Path, help="run nothing: print the markdown of this results .json")
    args = ap.parse_args()

    if args.report:
        print(render(json.loads(args.report.read_text())))
        return
    for tool in ("gmsh", "/usr/bin/time") + (() if args.no_ccx else ("ccx",)):
        if not shutil.which(tool):
            raise SystemExit(f"{tool} not found (Debian packages gmsh, time, calculix-ccx: bash bench/setup.sh)")

    exe = args.hencky
    if exe is None:
        exe = next((ROOT / d / "hencky" for d in ("build-bench", "build-f", "build-release", "build")
                    if (ROOT / d / "hencky").exists()), None)
    if exe is None or not exe.exists():
        raise SystemExit("no hencky binary: build it (bash bench/setup.sh) or pass --hencky")
    exe = exe.resolve()
    t = str(args.threads)
    args.hencky_environ = dict(os.environ, OMP_NUM_THREADS=t, **dict(kv.split("=", 1) for kv in args.hencky_env))
    work = args.work.resolve()
    work.mkdir(parents=True, exist_ok=True)
    args.results.parent.mkdir(parents=True, exist_ok=True)
    mdpath = args.results
    jpath = mdpath.with_suffix(".json")

    problem = heat_problem(args.layers)
    slab = Slab(args.film)
    m = runner.machine_info()
    print(runner.machine_line(m, exe), flush=True)
    dt = args.end / args.steps
    ref = dict(alpha=slab.alpha, biot=slab.bi, lambda_L=(slab.lam[:3] * L).tolist(),
               mid_exact=float(slab.T([L / 2], args.end)[0]), mid_discrete=float(slab.T([L / 2], args.end, dt)[0]))
    print(f"closed form: Bi = {slab.bi:.4f}, T(L/2, {args.end:g} s) = {ref['mid_exact']:.4f} (exact), "
          f"{ref['mid_discrete']:.4f} (backward Euler, {args.steps} steps)", flush=True)
    t_start = time.perf_counter()
    result = dict(
        timestamp=time.strftime("%Y%m%d-%H%M%S"), machine=m, **runner.program_facts(exe), built=runner.binary_stamp(exe),
        command=" ".join(["/usr/bin/python3"] + sys.argv), threads=args.threads, hencky_env=args.hencky_env,
        parameters=dict(L=L, W=W, layers=args.layers, k=K, rho=RHO, c=C, T0=T0, T_hot=T_HOT, T_amb=T_AMB,
                        film=args.film, steps=args.steps, end=args.end, heat_tolerance=args.heat_tolerance,
                        repeats=args.repeats, repeat_below=args.repeat_below, repeat_large=args.repeat_large),
        reference=ref, sizes=[], seconds=0.0)
    for target in runner.parse_sizes(args.sizes):
        result["sizes"].append(bench_size(problem, target, args, work, exe, slab))
        result["seconds"] = time.perf_counter() - t_start
        report.write_results(jpath, mdpath, result, render(result))  # kept if a later size is stopped
    result["seconds"] = time.perf_counter() - t_start
    md = render(result)
    report.write_results(jpath, mdpath, result, md)
    report.print_written(jpath, mdpath, md)


if __name__ == "__main__":
    main()
