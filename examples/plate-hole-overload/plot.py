#!/usr/bin/env python3
"""The curves of the plate-hole-overload example, from case.out/history.csv: the strip's load
against its elongation (P = -4 x the net section's reaction, elongation = 2 x the end's
displacement), with the elastic line of the first step and the net-section limit load
P_L = sigma_y (w - d) t of a perfectly plastic strip; and the stress at the hole's edge against
the gross stress S, with the elastic K_t S (K_t from the first, elastic, step).

    python3 examples/plate-hole-overload/plot.py [case.out] [load-elongation.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "load-elongation.png")
rows = [{"time": 0.0, "reaction.symmetry_y.y": 0.0, "end.displacement.y": 0.0,
         "hole_edge.stress.yy": 0.0}] + rows

S_MAX, SIGMA_Y, W, D, T = 225e6, 355e6, 0.1, 0.025, 0.005  # case.yaml and plate.geo


def gross(t):
    return S_MAX * (t if t <= 1 else 2 - t)


P = [-4 * r["reaction.symmetry_y.y"] for r in rows]  # the support pulls back: P = −4 R
dl = [2 * r["end.displacement.y"] for r in rows]
first = rows[1]  # elastic
stiffness = -4 * first["reaction.symmetry_y.y"] / (2 * first["end.displacement.y"])
k_t = first["hole_edge.stress.yy"] / gross(first["time"])
P_L = SIGMA_Y * (W - D) * T
kN, mm, MPa = 1e-3, 1e3, 1e-6

fig, (ax_p, ax_s) = plt.subplots(2, 1, figsize=(7, 8))
ax_p.plot([x * mm for x in dl], [p * kN for p in P], "-o", mfc="none", ms=6,
          label="hencky, loaded and unloaded")
top = max(P) * 1.2
ax_p.plot([0, top / stiffness * mm], [0, top * kN], "--", lw=1, color="0.4",
          label="elastic line (the first step's stiffness)")
ax_p.axhline(P_L * kN, color="0.6", lw=1, ls=":")
ax_p.text(0.01, P_L * kN + 2, f"net-section limit load σ_y (w − d) t = {P_L * kN:.1f} kN",
          fontsize=8, color="0.3")
ax_p.set_xlabel("elongation of the 300 mm strip (mm)")
ax_p.set_ylabel("load P (kN)")
ax_p.set_ylim(0, P_L * kN * 1.12)
ax_p.set_title("Strip with a hole, overloaded and unloaded (S355)")
ax_p.grid(alpha=0.3)
ax_p.legend(fontsize=8, loc="lower right")

S = [gross(r["time"]) for r in rows]
ax_s.plot([s * MPa for s in S], [r["hole_edge.stress.yy"] * MPa for r in rows], "-s",
          mfc="none", ms=6, label="hencky σ_yy at the hole's edge")
ax_s.plot([0, S_MAX * MPa], [0, k_t * S_MAX * MPa], "--", lw=1, color="0.4",
          label=f"elastic K_t S, K_t = {k_t:.3f}")
ax_s.axhline(SIGMA_Y * MPa, color="0.6", lw=1, ls=":")
ax_s.text(2, SIGMA_Y * MPa + 15, "σ_y = 355 MPa", fontsize=8, color="0.3")
ax_s.set_xlabel("gross stress S (MPa)")
ax_s.set_ylabel("stress (MPa)")
ax_s.grid(alpha=0.3)
ax_s.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(png, dpi=110)
peak = max(range(len(P)), key=lambda i: P[i])
print(f"wrote {png}; K_t = {k_t:.3f}, peak {P[peak] * kN:.2f} kN = {P[peak] / P_L:.3f} P_L, "
      f"permanent elongation {dl[-1] * 1e6:.2f} um")
