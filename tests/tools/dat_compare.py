#!/usr/bin/python3
"""Compare two CalculiX .dat files block by block (hencky's MODEL.dat against ccx's, or a test
deck's .dat.ref).

    dat_compare.py A.dat B.dat [RTOL] [--blocks N]

Reads every block of both files (plain or .gz): its title (" displacements (vx,vy,vz) for set
NALL and time  0.1000000E+01": the words before "for set", the set and the time) and its lines,
keyed by their leading whole numbers (a node, or an element and an integration point). Blocks of
A and B are paired in the order they come for each (what, set) and must have the same time and
the same keys. For each pair, the largest difference of a value relative to the largest value
of the block in B (to a floor of 1e-30). Prints one line per block; exit status 0 when every
block is within RTOL (default 1e-6) and A has as many blocks as B (or at least N with --blocks).
Standard library only: the same reader parses ccx's files and hencky's.
"""
import gzip
import re
import sys

TITLE = re.compile(r"^ (?P<what>[a-z].*?)\s*for ?set (?P<set>\S+) and time\s+(?P<time>\S+)\s*$")


def blocks(path):
    opener = gzip.open if str(path).endswith(".gz") else open
    with opener(path, "rt") as f:
        lines = f.read().splitlines()
    out, cur = [], None
    for line in lines:
        m = TITLE.match(line)
        if m:
            cur = {"what": m["what"], "set": m["set"], "time": float(m["time"]), "rows": {}}
            out.append(cur)
            continue
        if cur is None or not line.strip():
            continue
        words = line.split()
        keys = []
        while words and re.fullmatch(r"-?\d+", words[0]) and len(keys) < 2:
            keys.append(int(words.pop(0)))
        try:
            cur["rows"][tuple(keys)] = [float(w) for w in words]
        except ValueError:
            cur = None  # a block hencky does not read (a line of words)
    return out


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    need = None
    if "--blocks" in sys.argv:
        need = int(sys.argv[sys.argv.index("--blocks") + 1])
        args.remove(str(need))
    a, b = blocks(args[0]), blocks(args[1])
    rtol = float(args[2]) if len(args) > 2 else 1e-6
    ok = True
    pending = {}
    for blk in b:
        pending.setdefault((blk["what"], blk["set"].upper()), []).append(blk)
    compared = 0
    for blk in a:
        queue = pending.get((blk["what"], blk["set"].upper()))
        if not queue:
            print(f"{blk['what']} for set {blk['set']}: not in {args[1]}")
            ok = False
            continue
        ref = queue.pop(0)
        if abs(ref["time"] - blk["time"]) > 1e-6 * max(1.0, abs(ref["time"])):
            print(f"{blk['what']} for set {blk['set']}: time {blk['time']} against {ref['time']}")
            ok = False
            continue
        if set(ref["rows"]) != set(blk["rows"]):
            print(f"{blk['what']} for set {blk['set']} at {blk['time']}: {len(blk['rows'])} lines "
                  f"against {len(ref['rows'])}, other nodes or points")
            ok = False
            continue
        scale = max([abs(v) for row in ref["rows"].values() for v in row] + [1e-30])
        worst, where = 0.0, None
        for key, row in ref["rows"].items():
            for x, y in zip(blk["rows"][key], row):
                if abs(x - y) / scale > worst:
                    worst, where = abs(x - y) / scale, key
        compared += 1
        print(f"{blk['what']} for set {blk['set']} at {blk['time']:g}: {len(ref['rows'])} lines, "
              f"largest difference {worst:.3e} of {scale:.6e}" + (f" at {where}" if where else ""))
        ok = ok and worst <= rtol
    if need is not None and compared < need:
        print(f"{compared} blocks compared, {need} expected")
        ok = False
    if need is None and compared != len(b):
        print(f"{compared} blocks compared of the {len(b)} in {args[1]}")
        ok = False
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
