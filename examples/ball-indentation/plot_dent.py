#!/usr/bin/env python3
"""The curve of dent.yaml, from dent.out/history.csv: the ball's force against the approach,
pressed past yield and lifted off, on Hertz's elastic P = (4/3) E* sqrt(R) delta^(3/2), with
Hertz's first yield and the dent the ball leaves.

    python3 examples/ball-indentation/plot_dent.py [dent.out] [dent-curve.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "dent-curve.png", "dent.out")

E, NU, R, SY = 210e9, 0.3, 0.01, 600e6  # as in dent.yaml
E_STAR = E / (1 - NU ** 2)
# Hertz's first yield: the largest von Mises stress, 0.62 p0 at 0.48 a deep (nu = 0.3), reaches
# sigma_y at p0 = 1.61 sigma_y; p0 = (2 E*/pi) sqrt(delta/R) gives the approach.
DELTA_Y = R * (math.pi * 1.61 * SY / (2 * E_STAR)) ** 2


def approach(t):  # the ball's motion in dent.yaml, m
    return 2e-6 * (t if t <= 1 else 2 - t)


def hertz_force(d):
    return 4 / 3 * E_STAR * math.sqrt(R) * d ** 1.5


um = 1e6
d_line = [2e-6 * k / 200 for k in range(201)]
loading = [{"time": 0.0, "contact.ball.resultant.z": 0.0}] + [r for r in rows if r["time"] <= 1]
unloading = [r for r in rows if r["time"] >= 1]
dent = -[r for r in rows if r["time"] == 2][0]["centre.displacement.z"]

fig, ax = plt.subplots(figsize=(7, 5))
ax.plot([d * um for d in d_line], [hertz_force(d) for d in d_line], "-", color="0.3", lw=1,
        label="Hertz (elastic), (4/3) E* √R δ^1.5")
ax.axvline(DELTA_Y * um, color="0.5", ls=":", lw=1)
ax.text(DELTA_Y * um, 0.45 * hertz_force(2e-6), " Hertz's first yield\n δ = %.2f µm" % (DELTA_Y * um),
        fontsize=8, va="top")
for part, style, label in ((loading, "o-", "hencky, pressed in"),
                           (unloading, "s-", "hencky, lifted off")):
    ax.plot([approach(r["time"]) * um for r in part],
            [-4 * r["contact.ball.resultant.z"] for r in part], style, mfc="none", ms=6, lw=0.8,
            label=label)
ax.annotate("dent %.2f µm" % (dent * um), xy=(dent * um, 0), xytext=(dent * um + 0.15, 12),
            arrowprops=dict(arrowstyle="->", lw=0.8), fontsize=8)
ax.set_xlabel("approach δ of the ball (µm)")
ax.set_ylabel("ball force P (N): 4 × the quarter model's")
ax.set_title("Ball (R = 10 mm) into steel past yield (σ_y = 600 MPa) and out: the dent")
ax.set_xlim(0, 2.1)
ax.set_ylim(0, None)
ax.grid(alpha=0.3)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(png, dpi=110)
at1 = [r for r in rows if r["time"] == 1][0]
print(f"wrote {png}; at δ = 2 µm: P = {-4 * at1['contact.ball.resultant.z']:.2f} N "
      f"(Hertz elastic {hertz_force(2e-6):.2f}); dent {dent * um:.3f} µm; "
      f"Hertz's first yield at δ = {DELTA_Y * um:.3f} µm")
