#!/usr/bin/env python3
"""The load-displacement plot of the cantilever-hook example: the tip's displacement over L
against the load q L^3 / EI, hencky's (case.out/history.csv) and the rod solution of
tests/tools/follower_rod.py.

    python3 examples/cantilever-hook/plot.py [case.out] [load-displacement.png]

Needs matplotlib: scripts/setup-plots.sh installs it (Debian's python3-matplotlib)."""
import csv
import math
import sys
from pathlib import Path

here = Path(__file__).resolve().parent
sys.path.insert(0, str(here.parents[1] / "tests" / "tools"))
from follower_rod import follower_rod  # noqa: E402

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("plot.py needs matplotlib: run scripts/setup-plots.sh (Debian's python3-matplotlib)")

L, ALPHA_END = 0.25, 18.0
out_dir = Path(sys.argv[1]) if len(sys.argv) > 1 else here / "case.out"
png = Path(sys.argv[2]) if len(sys.argv) > 2 else here / "load-displacement.png"
rows = list(csv.DictReader(open(out_dir / "history.csv")))
alpha = [0.0] + [ALPHA_END * float(r["time"]) for r in rows]
ux = [0.0] + [float(r["tip.displacement.x"]) / L for r in rows]
uy = [0.0] + [float(r["tip.displacement.y"]) / L for r in rows]
a_ref = [ALPHA_END * k / 150 for k in range(151)]
ref = [follower_rod(a) if a > 0 else (0.0, 0.0, 0.0) for a in a_ref]

fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(a_ref, [r[0] for r in ref], "-", color="tab:blue", label="rod theory, $u_x/L$")
ax.plot(a_ref, [r[1] for r in ref], "-", color="tab:red", label="rod theory, $u_y/L$")
ax.plot(alpha[::3], ux[::3], "o", color="tab:blue", mfc="none", label="hencky, $u_x/L$")
ax.plot(alpha[::3], uy[::3], "s", color="tab:red", mfc="none", label="hencky, $u_y/L$")
ax.set_xlabel("load $qL^3/EI$ (follower pressure on the upper face)")
ax.set_ylabel("tip displacement / $L$")
ax.axhline(0, color="0.8", lw=0.8)
ax.grid(alpha=0.3)
ax.legend(loc="lower left")
ax.set_title("Cantilever strip curled by a follower load: tip path")
fig.tight_layout()
fig.savefig(png, dpi=110)
print(f"wrote {png}")
