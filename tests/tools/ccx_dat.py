#!/usr/bin/python3
"""Compare a hencky run with a CalculiX .dat file (ccx's own output or a test deck's .dat.ref).

    ccx_dat.py RUN_DIR DAT DECK [RTOL]

Reads the last "displacements (vx,vy,vz) for set ... and time ..." block of DAT (plain or .gz):
node label, ux, uy, uz; and the displacement of the last step of RUN_DIR (its results.pvd's last
file, .vtu or .pvtu) by node label: a .pvtu's node_tag, or for a serial .vtu (which has no tags)
the label of the node of DECK (plain or .gz: its *NODE lines) at the same coordinates. Prints the number of
nodes compared, the largest difference |u_hencky - u_ccx| relative to the largest |u_ccx|, and
the node where it is. Exit status 0 when it is within RTOL (default 1e-6). Standard library +
numpy, and compare_results.py beside it.
"""
import gzip
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_results import read_pvtu, read_vtu, steps  # noqa: E402


def last_displacements(dat):
    opener = gzip.open if str(dat).endswith(".gz") else open
    with opener(dat, "rt") as f:
        lines = f.read().splitlines()
    start = max(i for i, line in enumerate(lines) if line.strip().startswith("displacements (vx,vy,vz)"))
    u = {}
    for line in lines[start + 1:]:
        parts = line.split()
        if not parts:
            if u:
                break
            continue
        if len(parts) != 4:
            break
        u[int(parts[0])] = np.array([float(p) for p in parts[1:]])
    return u


def deck_nodes(deck):
    """label -> (x, y, z) of the *NODE blocks of an .inp deck."""
    opener = gzip.open if str(deck).endswith(".gz") else open
    nodes, inside = {}, False
    with opener(deck, "rt") as f:
        for line in f:
            s = line.strip()
            if s.startswith("**") or not s:
                continue
            if s.startswith("*"):
                inside = s.upper().replace(" ", "").startswith("*NODE") and not s.upper().replace(
                    " ", "").startswith(("*NODEPRINT", "*NODEFILE", "*NODEOUTPUT"))
                continue
            if inside:
                parts = [p for p in s.split(",") if p.strip()]
                xyz = [float(v) for v in parts[1:4]]
                nodes[int(parts[0])] = tuple(xyz + [0.0] * (3 - len(xyz)))  # left out: 0
    return nodes


def labels_by_position(points, nodes):
    """The deck's label of each point, matched by coordinates (to 1e-9 of the model's size)."""
    coords = np.array(list(nodes.values()))
    size = np.ptp(coords, axis=0).max() or 1.0
    key = lambda x: tuple(np.round(np.asarray(x) / (1e-9 * size)).astype(np.int64))  # noqa: E731
    by_key = {key(x): n for n, x in nodes.items()}
    return [by_key.get(key(p), -1) for p in points]


def main():
    run, dat, deck = sys.argv[1], sys.argv[2], sys.argv[3]
    rtol = float(sys.argv[4]) if len(sys.argv) > 4 else 1e-6
    ref = last_displacements(dat)
    last = steps(run)[-1]
    fields = read_pvtu(last) if str(last).endswith(".pvtu") else read_vtu(last)
    if "node_tag" in fields:
        tags = fields["node_tag"][:, 0].tolist()
    else:
        tags = labels_by_position(fields["Points"], deck_nodes(deck))
    mine = dict(zip(tags, fields["displacement"]))
    missing = [n for n in ref if n not in mine]
    if missing:
        print(f"{len(missing)} nodes of the .dat are not in the run, e.g. {missing[:5]}")
        return 1
    scale = max(np.linalg.norm(v) for v in ref.values())
    worst, where = max((np.linalg.norm(mine[n] - v), n) for n, v in ref.items())
    print(f"{len(ref)} nodes; largest difference {worst / scale:.3e} of the largest displacement "
          f"{scale:.6e}, at node {where}: hencky {mine[where]}, ccx {ref[where]}")
    return 0 if worst <= rtol * scale else 1


if __name__ == "__main__":
    sys.exit(main())
