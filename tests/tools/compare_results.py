#!/usr/bin/python3
"""Compare two hencky result directories field by field.

    compare_results.py DIR_A DIR_B RTOL [--fields displacement,stress,...]

Reads every step's .vtu of both (hencky's own raw appended format), and for each point and
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
    cell fields as "cell.<name>"."""
    raw = Path(path).read_bytes()
    marker = raw.index(b"<AppendedData")
    start = raw.index(b"_", raw.index(b">", marker)) + 1
    header = raw[:marker].decode() + "</VTKFile>"
    root = ET.fromstring(header)
    fields = {}
    for kind, prefix in (("PointData", ""), ("CellData", "cell.")):
        for section in root.iter(kind):
            for a in section.iter("DataArray"):
                offset = start + int(a.get("offset"))
                n_bytes = int(np.frombuffer(raw, np.uint64, 1, offset)[0])
                data = np.frombuffer(raw, TYPES[a.get("type")], n_bytes // np.dtype(TYPES[a.get("type")]).itemsize,
                                     offset + 8)
                fields[prefix + a.get("Name")] = data.reshape(-1, int(a.get("NumberOfComponents", "1")))
    return fields


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
    if [p.name for p in a_steps] != [p.name for p in b_steps]:
        print(f"different steps: {[p.name for p in a_steps]} vs {[p.name for p in b_steps]}")
        return 1
    # Per field: the largest ||a - b|| of any step and the largest ||a|| of any step (a field
    # that returns to zero, as on unloading, is compared at the scale it had).
    worst, scale = {}, {}
    for pa, pb in zip(a_steps, b_steps):
        fa, fb = read_vtu(pa), read_vtu(pb)
        if set(fa) != set(fb):
            print(f"{pa.name}: different fields {sorted(fa)} vs {sorted(fb)}")
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
