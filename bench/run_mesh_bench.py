#!/usr/bin/python3
"""What reading a .msh costs: hencky's own reader against the Gmsh library's.

hencky reads .msh files with its own parser since Gmsh 4.8's reader was found to crash on
malformed files (shared/crashes/msh4-*). This measures the two on the same files: a box meshed
by Gmsh in 10-node tetrahedra at a size near --dofs unknowns, saved as MSH 4.1 binary, 4.1
ASCII and 2.2 ASCII. Each reading runs in its own process (build-bench/hencky_mesh_read_bench)
so that its peak memory is its own; --repeat readings per file and reader, medians quoted.

    bash bench/setup.sh && /usr/bin/python3 bench/run_mesh_bench.py [--dofs 1000000] [--repeat 3]

Results: bench/results/mesh-read-<timestamp>.json and .md. Standard library only.
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "bench"

GEO = """SetFactory("OpenCASCADE");
Box(1) = {{0, 0, 0, 1, 0.5, 0.5}};
Mesh.MeshSizeMax = {h};
Mesh.ElementOrder = 2;
Physical Volume("body") = {{1}};
Physical Surface("x0") = {{1}};
Physical Surface("x1") = {{2}};
"""

FORMATS = {"4.1 binary": ("msh41", True), "4.1 ASCII": ("msh41", False), "2.2 ASCII": ("msh22", False)}


def mesh(work: Path, dofs: int) -> dict[str, Path]:
    """The box's mesh in each format. Tet10: about 1.4 nodes per element, h from a fit."""
    # A 1 x 0.5 x 0.5 box meshed at size h holds about 0.25 * 7.9 / h^3 nodes in tet10.
    h = (0.25 * 7.9 * 3 / dofs) ** (1 / 3)
    geo = work / "box.geo"
    geo.write_text(GEO.format(h=h))
    files = {}
    for name, (fmt, binary) in FORMATS.items():
        out = work / f"box-{fmt}{'b' if binary else 'a'}.msh"
        if not out.exists():
            cmd = ["gmsh", str(geo), "-3", "-format", fmt, "-o", str(out)] + (["-bin"] if binary else [])
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        files[name] = out
    return files


def read_once(tool: Path, file: Path, reader: str) -> dict:
    out = subprocess.run([str(tool), str(file), reader], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dofs", type=int, default=1_000_000, help="target size in unknowns (3 per node)")
    ap.add_argument("--repeat", type=int, default=3, help="readings per file and reader")
    ap.add_argument("--build", type=Path, default=ROOT / "build-bench", help="Release build directory")
    args = ap.parse_args()
    tool = args.build / "hencky_mesh_read_bench"
    if not tool.exists():
        sys.exit(f"{tool} not found: run bash bench/setup.sh first")
    work = BENCH / "work" / "mesh-read"
    work.mkdir(parents=True, exist_ok=True)
    files = mesh(work, args.dofs)
    rows = []
    for fmt, file in files.items():
        runs = {r: [read_once(tool, file, r) for _ in range(args.repeat)] for r in ("hencky", "gmsh")}
        row = {"format": fmt, "bytes": file.stat().st_size, "nodes": runs["hencky"][0]["nodes"],
               "cells": runs["hencky"][0]["cells"]}
        for r, rr in runs.items():
            row[r] = {"seconds": statistics.median(x["seconds"] for x in rr),
                      "peak_bytes": statistics.median(x["peak_bytes"] for x in rr),
                      "all_seconds": [x["seconds"] for x in rr]}
        rows.append(row)
        print(f"{fmt}: hencky {row['hencky']['seconds']:.2f} s, gmsh {row['gmsh']['seconds']:.2f} s", flush=True)
    stamp = dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    result = {"date": stamp, "dofs_target": args.dofs, "repeat": args.repeat, "rows": rows}
    out = BENCH / "results" / f"mesh-read-{stamp}"
    out.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
    lines = [f"# Reading a .msh: hencky's reader against the Gmsh library ({stamp})", "",
             f"Box in 10-node tetrahedra; median of {args.repeat} readings, each in its own process "
             "(peak memory of the whole process, including the mesh it builds).", "",
             "| format | file MB | nodes (unknowns) | elements | hencky s | Gmsh s | time ratio | "
             "hencky peak MiB | Gmsh peak MiB |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        h, g = r["hencky"], r["gmsh"]
        lines.append(f"| {r['format']} | {r['bytes'] / 1e6:.0f} | {r['nodes']} ({3 * r['nodes']}) | {r['cells']} | "
                     f"{h['seconds']:.2f} | {g['seconds']:.2f} | {h['seconds'] / g['seconds']:.2f} | "
                     f"{h['peak_bytes'] / 2**20:.0f} | {g['peak_bytes'] / 2**20:.0f} |")
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
