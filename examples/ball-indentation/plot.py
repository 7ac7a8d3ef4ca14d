#!/usr/bin/env python3
"""The curve of the ball-indentation example, from case.out/history.csv: the ball's force and
the peak contact pressure against the approach, pressed in and lifted off, with Hertz's
P = (4/3) E* sqrt(R) delta^(3/2) and p0 = (2 E* / pi) sqrt(delta / R).

    python3 examples/ball-indentation/plot.py [case.out] [force-approach.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "force-approach.png")

E, NU, R = 210e9, 0.3, 0.01  # as in case.yaml
E_STAR = E / (1 - NU ** 2)


def approach(t):  # the ball's motion in case.yaml, m
    return 2e-6 * (t if t <= 1 else 2 - t)


def hertz_force(d):
    return 4 / 3 * E_STAR * math.sqrt(R) * d ** 1.5


def hertz_p0(d):
    return 2 * E_STAR / math.pi * math.sqrt(d / R)


d_line = [2e-6 * k / 200 for k in range(201)]
loading = [r for r in rows if r["time"] <= 1]
unloading = [r for r in rows if r["time"] >= 1]
um, N, GPa = 1e6, 1.0, 1e-9

fig, (ax_f, ax_p) = plt.subplots(2, 1, figsize=(7, 8), sharex=True)
ax_f.plot([d * um for d in d_line], [hertz_force(d) for d in d_line], "-", color="0.3",
          lw=1, label="Hertz, (4/3) E* √R δ^1.5")
for part, style, label in ((loading, "o", "hencky, pressed in"),
                           (unloading, "s", "hencky, lifted off")):
    ax_f.plot([approach(r["time"]) * um for r in part],
              [-4 * r["contact.ball.resultant.z"] * N for r in part], style, mfc="none",
              ms=7, label=label)
ax_f.set_ylabel("ball force P (N): 4 × the quarter model's")
ax_f.set_title("Rigid ball (R = 10 mm) on steel: force and peak pressure")
ax_f.grid(alpha=0.3)
ax_f.legend(fontsize=8)

ax_p.plot([d * um for d in d_line], [hertz_p0(d) * GPa for d in d_line], "-", color="0.3",
          lw=1, label="Hertz, p0 = (2E*/π) √(δ/R)")
for part, style, label in ((loading, "o", "hencky, largest nodal pressure, pressed in"),
                           (unloading, "s", "lifted off")):
    ax_p.plot([approach(r["time"]) * um for r in part],
              [r["contact.ball.max_pressure"] * GPa for r in part], style, mfc="none", ms=7,
              label=label)
ax_p.set_xlabel("approach δ (µm)")
ax_p.set_ylabel("peak contact pressure (GPa)")
ax_p.grid(alpha=0.3)
ax_p.legend(fontsize=8)
fig.tight_layout()
fig.savefig(png, dpi=110)
at1 = [r for r in rows if r["time"] == 1][0]
print(f"wrote {png}; at δ = 2 µm: P = {-4 * at1['contact.ball.resultant.z']:.2f} N "
      f"(Hertz {hertz_force(2e-6):.2f}), p0 = {at1['contact.ball.max_pressure'] * GPa:.3f} GPa "
      f"(Hertz {hertz_p0(2e-6) * GPa:.3f})")
