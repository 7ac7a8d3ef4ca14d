#!/usr/bin/python3
"""Peak values of a hencky result step: largest von Mises stress and displacement, and where.

    python3 peak.py case.out/step_0002.vtu [--exclude-near X Y Z R ...]

Reads the .vtu that hencky writes (raw appended binary, UInt64 headers) with numpy only.
--exclude-near leaves out the nodes within R of the point (X, Y, Z), e.g. the clamped bolt
holes, whose rigid clamp gives a stress peak that grows with mesh refinement.
"""
import argparse
import re
import sys

import numpy as np


def read_vtu(path):
    raw = open(path, "rb").read()
    start = raw.index(b"<AppendedData")
    data = raw[raw.index(b"_", start) + 1:]
    head = raw[:start].decode()
    arrays = {}
    for m in re.finditer(r"<(PointData|CellData|Points)>(.*?)</\1>", head, re.S):
        for a in re.finditer(r"<DataArray ([^>]*)/>", m.group(2)):
            attr = dict(re.findall(r'(\w+)="([^"]*)"', a.group(1)))
            off = int(attr["offset"])
            n = int(np.frombuffer(data[off:off + 8], "<u8")[0])
            dtype = {"Float64": "<f8", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}[attr["type"]]
            v = np.frombuffer(data[off + 8:off + 8 + n], dtype)
            comps = int(attr.get("NumberOfComponents", "1"))
            arrays[(m.group(1), attr["Name"])] = v.reshape(-1, comps) if comps > 1 else v
    return arrays


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("vtu")
    p.add_argument("--exclude-near", type=float, nargs=4, action="append", default=[],
                   metavar=("X", "Y", "Z", "R"))
    args = p.parse_args()
    a = read_vtu(args.vtu)
    x = a[("Points", "Points")]
    vm = a[("PointData", "von_mises")]
    u = np.linalg.norm(a[("PointData", "displacement")], axis=1)
    keep = np.ones(len(x), bool)
    for cx, cy, cz, r in args.exclude_near:
        keep &= np.linalg.norm(x - [cx, cy, cz], axis=1) > r
    i = np.flatnonzero(keep)[np.argmax(vm[keep])]
    j = np.argmax(u)
    print("max von Mises %.4g Pa at (%.4g, %.4g, %.4g)" % (vm[i], *x[i]))
    print("max |displacement| %.4g m at (%.4g, %.4g, %.4g)" % (u[j], *x[j]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
