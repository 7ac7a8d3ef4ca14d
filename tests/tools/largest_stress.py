#!/usr/bin/python3
"""The largest stress component anywhere in a hencky result directory, step by step.

    largest_stress.py DIR

Reads every step_*.vtu of DIR (hencky's raw appended format, compare_results.read_vtu) and
prints, for each, the largest magnitude of any component of the nodal `stress` and of the
cells' `stress` (the cells' means), then the largest of all steps on the last line. Standard
library + numpy.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_results import read_vtu  # noqa: E402


def main():
    steps = sorted(Path(sys.argv[1]).glob("step_*.vtu"))
    if not steps:
        sys.exit(f"no step_*.vtu in {sys.argv[1]}")
    worst = 0.0
    for f in steps:
        fields = read_vtu(f)
        w = max(float(np.abs(fields[k]).max()) for k in ("stress", "cell.stress") if k in fields)
        print(f"{f.name} {w:.3e}")
        worst = max(worst, w)
    print(f"{worst:.17g}")


if __name__ == "__main__":
    main()
