#!/usr/bin/python3
"""Compare two hencky result directories field by field.

    compare_results.py DIR_A DIR_B RTOL [--fields displacement,stress,...]

Reads every step's .vtu of both (hencky's own raw appended format), or the .vtu pieces of a
.pvtu (a run on several MPI ranks: a node shared by pieces counted once, by its node_tag), puts
the nodes and cells of both in one order (by coordinates and by centroid, so that a serial and a
parallel run compare), and for each point and
cell field (cell fields as "cell.<name>"; --fields NAME selects both)
computes the largest difference of any step, max ||a - b||, relative to the field's largest
norm of any step, max ||a|| (Euclidean over all nodes and components; absolute when a is 0
throughout). Exit status 0 when both ran the same steps and every difference is
within RTOL; prints the largest difference per field either way. Standard library + numpy.
"""
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

TYPES = {"Float64": np.float64, "Int32": np.int32, "Int64": np.int64, "UInt8": np.uint8}


def read_vtu(path):
    """Fields of a hencky .vtu: {name: array (n, n_components)}, point fields by their name,
    cell fields as "cell.<name>", and the mesh as "Points", "connectivity" and "offsets"."""
    raw = Path(path).read_bytes()
    marker = raw.index(b"<AppendedData")
    start = raw.index(b"_", raw.index(b">", marker)) + 1
    header = raw[:marker].decode() + "</VTKFile>"
    root = ET.fromstring(header)
    fields = {}
    for kind, prefix in (("PointData", ""), ("CellData", "cell."), ("Points", ""), ("Cells", "")):
        for section in root.iter(kind):
            for a in section.iter("DataArray"):
                offset = start + int(a.get("offset"))
                n_bytes = int(np.frombuffer(raw, np.uint64, 1, offset)[0])
                data = np.frombuffer(raw, TYPES[a.get("type")], n_bytes // np.dtype(TYPES[a.get("type")]).itemsize,
                                     offset + 8)
                fields[prefix + a.get("Name")] = data.reshape(-1, int(a.get("NumberOfComponents", "1")))
    return fields


MESH = ("Points", "connectivity", "offsets", "types")
IDS = ("node_tag", "cell.element_tag")


def read_pvtu(path):
    """The pieces of a .pvtu as one set of fields: nodes shared by pieces once (by node_tag)."""
    root = ET.parse(path).getroot()
    pieces = [read_vtu(Path(path).parent / p.get("Source")) for p in root.iter("Piece")]
    tags = np.concatenate([p["node_tag"][:, 0] for p in pieces])
    _, first = np.unique(tags, return_index=True)
    out, shift = {}, 0
    conn = []
    for p in pieces:
        conn.append(p["connectivity"][:, 0] + shift)
        shift += len(p["Points"])
    # Every piece's node index -> the index of that tag's first copy in the merged list.
    merged = np.searchsorted(tags[first], tags)
    out["connectivity"] = merged[np.concatenate(conn)].reshape(-1, 1)
    ends = np.cumsum([len(p["connectivity"]) for p in pieces])
    out["offsets"] = np.concatenate(
        [p["offsets"][:, 0] + (ends[i - 1] if i else 0) for i, p in enumerate(pieces)]).reshape(-1, 1)
    for name in pieces[0]:
        if name in ("connectivity", "offsets"):
            continue
        data = np.concatenate([p[name] for p in pieces])
        if name.startswith("cell.") or name == "types":
            out[name] = data
            continue
        out[name] = data[first]
        # The copies of a node in several pieces carry the same values, to the bit.
        if not np.array_equal(data, out[name][merged]):
            raise ValueError(f"{path}: the pieces disagree on {name} at shared nodes")
    return out


def sort_key(x, low, size):
    """Coordinates rounded to 1e-10 of the mesh's size: two files of one mesh that wrote its
    coordinates to different digits (an .inp's 14 against a .msh's 17) sort alike."""
    return np.round((x - low) / size, 10)


def canonical(f):
    """The fields with the nodes sorted by their coordinates and the cells by their centroids,
    without the mesh and the global numbers."""
    x = f["Points"]
    low = x.min(axis=0)
    size = max(float(np.max(x.max(axis=0) - low)), 1e-300)
    k = sort_key(x, low, size)
    node_order = np.lexsort((k[:, 2], k[:, 1], k[:, 0]))
    conn, ends = f["connectivity"][:, 0], f["offsets"][:, 0]
    starts = np.concatenate(([0], ends[:-1]))
    centroid = sort_key(np.add.reduceat(x[conn], starts, axis=0) / (ends - starts)[:, None],
                        low, size)
    cell_order = np.lexsort((centroid[:, 2], centroid[:, 1], centroid[:, 0]))
    out = {}
    for name, data in f.items():
        if name in MESH or name in IDS:
            continue
        out[name] = data[cell_order] if name.startswith("cell.") else data[node_order]
    return out


def read_result(path):
    return canonical(read_pvtu(path) if str(path).endswith(".pvtu") else read_vtu(path))


def steps(d):
    """The .vtu files of the series, in the order of results.pvd."""
    pvd = (Path(d) / "results.pvd").read_text()
    return [Path(d) / f for f in re.findall(r'file="([^"]+)"', pvd)]


def main():
    a_dir, b_dir, rtol = sys.argv[1], sys.argv[2], float(sys.argv[3])
    only = None
    if len(sys.argv) > 5 and sys.argv[4] == "--fields":
        only = set(sys.argv[5].split(","))
    a_steps, b_steps = steps(a_dir), steps(b_dir)
    if [p.stem for p in a_steps] != [p.stem for p in b_steps]:
        print(f"different steps: {[p.name for p in a_steps]} vs {[p.name for p in b_steps]}")
        return 1
    # Per field: the largest ||a - b|| of any step and the largest ||a|| of any step (a field
    # that returns to zero, as on unloading, is compared at the scale it had).
    worst, scale = {}, {}
    for pa, pb in zip(a_steps, b_steps):
        fa, fb = read_result(pa), read_result(pb)
        if set(fa) != set(fb):
            print(f"{pa.name}: different fields {sorted(fa)} vs {sorted(fb)}")
            return 1
        shapes = {n: (fa[n].shape, fb[n].shape) for n in fa if fa[n].shape != fb[n].shape}
        if shapes:
            print(f"{pa.name}: different sizes {shapes}")
            return 1
        for name in fa:
            if only and name not in only and name.removeprefix("cell.") not in only:
                continue
            x, y = fa[name].astype(float), fb[name].astype(float)
            scale[name] = max(scale.get(name, 0.0), np.linalg.norm(x))
            d = np.linalg.norm(x - y)
            if d >= worst.get(name, (-1, ""))[0]:
                worst[name] = (d, pa.name)
    for name, (d, where) in worst.items():
        worst[name] = (d / scale[name] if scale[name] > 0 else d, where)
    ok = True
    for name, (d, where) in sorted(worst.items()):
        flag = "" if d <= rtol else "  > " + str(rtol)
        ok = ok and d <= rtol
        print(f"{name}: {d:.3e} (largest at {where}){flag}")
    return 0 if ok and worst else 1


if __name__ == "__main__":
    sys.exit(main())
