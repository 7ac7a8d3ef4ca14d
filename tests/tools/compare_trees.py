#!/usr/bin/python3
"""Byte-for-byte comparison of the results of two runs of the same cases (two binaries, one
before and one after a change that must not change outputs).

    compare_trees.py DIR_A DIR_B

Compares every .vtu, .pvtu and history.csv under DIR_A with the file of the same relative path
under DIR_B (the log, summary.json and the checkpoints carry times and paths, and are left out).
Prints each file that differs or is missing, and a count; exit 0 when all are identical.
"""
import sys
from pathlib import Path


def results(root: Path):
    return sorted(p.relative_to(root) for p in root.rglob("*")
                  if p.is_file() and (p.suffix in (".vtu", ".pvtu") or p.name == "history.csv"))


def main() -> int:
    a, b = Path(sys.argv[1]), Path(sys.argv[2])
    fa, fb = results(a), results(b)
    differ = [f for f in fa if f in set(fb) and (a / f).read_bytes() != (b / f).read_bytes()]
    only_a = sorted(set(fa) - set(fb))
    only_b = sorted(set(fb) - set(fa))
    for f in differ:
        print("differs:", f)
    for f in only_a:
        print("only in", a, ":", f)
    for f in only_b:
        print("only in", b, ":", f)
    print(f"{len(fa)} files compared, {len(differ)} differ, {len(only_a) + len(only_b)} unmatched")
    return 1 if differ or only_a or only_b else 0


if __name__ == "__main__":
    sys.exit(main())
