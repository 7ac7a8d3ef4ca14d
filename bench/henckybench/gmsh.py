"""Gmsh: meshing a problem of problems.PROBLEMS near a target number of unknowns (10-node
tetrahedra; meshes cached in the work folder by size), reading a .msh (format 4.1, ASCII) in
Python, and the run folders that hold a mesh."""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

from .problems import PROBLEMS


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


def nearest_node(mesh: dict, point) -> tuple[int, float]:
    """The used mesh node nearest to `point` and its distance."""
    coords, used = mesh["coords"], mesh["node_tags"]
    px = np.array(point, dtype=float)
    node = int(used[np.argmin(np.linalg.norm(coords[used] - px, axis=1))])
    return node, float(np.linalg.norm(coords[node] - px))


# ----------------------------------------------------------------------------------------------
# Meshing
# ----------------------------------------------------------------------------------------------
def gmsh_mesh(problem: str, h: float, work: Path, threads: int) -> tuple[Path, float]:
    """work/<problem>_h<h>.msh (meshed by Gmsh unless it exists) and Gmsh's seconds for it."""
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


# ----------------------------------------------------------------------------------------------
# Run folders
# ----------------------------------------------------------------------------------------------
def mesh_run_dir(msh: Path, work: Path, prefix: str = "") -> Path:
    """work/<prefix>-<mesh stem>/ (work/<mesh stem>/ without a prefix), created, holding a hard
    link to the .msh (a copy where a link cannot be made); the mesh is not read."""
    run_dir = work / (f"{prefix}-{msh.stem}" if prefix else msh.stem)
    run_dir.mkdir(exist_ok=True)
    local_msh = run_dir / msh.name
    if not local_msh.exists():
        try:
            os.link(msh, local_msh)
        except OSError:
            shutil.copy(msh, local_msh)
    return run_dir


def size_run_dir(msh: Path, work: Path, prefix: str) -> tuple[Path, dict]:
    """work/<prefix>-<mesh stem>/ holding (a hard link to) the .msh, and the mesh read."""
    return mesh_run_dir(msh, work, prefix), read_msh4(msh)
