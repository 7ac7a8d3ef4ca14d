#!/usr/bin/python3
"""Compare two CalculiX result files (.frd, ASCII): hencky's MODEL.frd against ccx's.

    frd_compare.py A.frd B.frd RTOL FIELD [FIELD ...]

The node (2C) and element (3C) blocks must be the same text. For each FIELD (DISP, FORC, ...),
the blocks of that name are paired in order (the same count in both files) and every node's
values compared, relative to the largest value of B's block: the largest difference must be
within RTOL (the format's 12.5E fields hold 6 digits: 1e-5 is their resolution). Prints one line
per block. Standard library only.
"""
import sys


def read(path):
    with open(path) as f:
        lines = f.read().splitlines()
    mesh = {}
    fields = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("    2C") or line.startswith("    3C"):
            key = line[4:6]
            block = []
            i += 1
            while not lines[i].startswith(" -3"):
                block.append(lines[i])
                i += 1
            mesh[key] = (line.split()[1], block)
        elif line.startswith(" -4"):
            name = line[5:13].strip()
            values = {}
            i += 1
            while lines[i].startswith(" -5"):
                i += 1
            while not lines[i].startswith(" -3"):
                if lines[i].startswith(" -1"):
                    node = int(lines[i][3:13])
                    text = lines[i][13:]
                    values[node] = [float(text[k:k + 12]) for k in range(0, len(text), 12) if text[k:k + 12].strip()]
                i += 1
            fields.append((name, values))
        i += 1
    return mesh, fields


def main():
    a, b, rtol, names = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4:]
    (mesh_a, fields_a), (mesh_b, fields_b) = read(a), read(b)
    ok = True
    for key, what in (("2C", "nodes"), ("3C", "elements")):
        same = mesh_a.get(key) == mesh_b.get(key)
        print(f"{what}: {'the same' if same else 'DIFFERENT'} ({mesh_b.get(key, ('0',))[0]} in {b})")
        ok = ok and same
    for name in names:
        xs = [v for n, v in fields_a if n == name]
        ys = [v for n, v in fields_b if n == name]
        if len(xs) != len(ys) or not ys:
            print(f"{name}: {len(xs)} blocks against {len(ys)}")
            ok = False
            continue
        for k, (x, y) in enumerate(zip(xs, ys)):
            scale = max([abs(v) for row in y.values() for v in row] + [1e-30])
            worst = max((abs(p - q) / scale for node in y for p, q in zip(x.get(node, []), y[node])), default=0.0)
            if set(x) != set(y):
                print(f"{name} block {k + 1}: other nodes")
                ok = False
                continue
            print(f"{name} block {k + 1}: {len(y)} nodes, largest difference {worst:.2e} of {scale:.5e}")
            ok = ok and worst <= rtol
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
