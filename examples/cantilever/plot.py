#!/usr/bin/env python3
"""The curve of the cantilever example, from case.out/history.csv: the deflection of the axis
and the bending stress of the top fibre along the beam (the probes at x = 0.2 .. 1 m), against
Timoshenko's beam: w(x) = F x^2 (3L - x)/(6 E I) + F x/(kappa G A), sigma_xx = F (L - x) c / I.

    python3 examples/cantilever/plot.py [case.out] [deflection-along.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "deflection-along.png")
last = rows[-1]

F, L, w, h, E, nu = 1e4, 1.0, 0.05, 0.1, 2.1e11, 0.3  # as in beam.geo and case.yaml
I, A, G = w * h ** 3 / 12, w * h, E / (2 * (1 + nu))
kappa = 10 * (1 + nu) / (12 + 11 * nu)  # Cowper's shear coefficient of a rectangle
deflection = lambda x: F * x * x * (3 * L - x) / (6 * E * I) + F * x / (kappa * G * A)
bending = lambda x: F * (L - x) * (h / 2) / I
x_line = [L * k / 100 for k in range(101)]
axis = [("axis2", 0.2), ("axis4", 0.4), ("axis6", 0.6), ("axis8", 0.8), ("tip", 1.0)]
top = [("top2", 0.2), ("top4", 0.4), ("mid_top", 0.5), ("top6", 0.6), ("top8", 0.8)]
mm, MPa = 1e3, 1e-6

fig, (ax_w, ax_s) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
ax_w.plot(x_line, [deflection(x) * mm for x in x_line], "-", lw=1, label="Timoshenko beam")
ax_w.plot([x for _, x in axis], [-last[f"{n}.displacement.z"] * mm for n, _ in axis], "o",
          mfc="none", ms=7, label="hencky, the axis")
ax_w.set_ylabel("deflection (mm, downwards)")
ax_w.set_title("Cantilever, 10 kN at the end: along the beam")
ax_w.grid(alpha=0.3)
ax_w.legend(fontsize=8)
ax_s.plot(x_line, [bending(x) * MPa for x in x_line], "-", lw=1, label="F (L − x) c / I")
ax_s.plot([x for _, x in top], [last[f"{n}.stress.xx"] * MPa for n, _ in top], "s", mfc="none",
          ms=7, label="hencky σ_xx, the top fibre")
ax_s.set_xlabel("x (m)")
ax_s.set_ylabel("bending stress (MPa)")
ax_s.grid(alpha=0.3)
ax_s.legend(fontsize=8)
fig.tight_layout()
fig.savefig(png, dpi=110)
tip = -last["tip.displacement.z"]
print(f"wrote {png}; tip deflection {tip * mm:.4f} mm, Timoshenko {deflection(L) * mm:.4f} mm "
      f"({100 * (tip / deflection(L) - 1):+.2f} %)")
