#!/usr/bin/env python3
"""The curve of the Lamé example, from case.out/history.csv: the radial and hoop stresses and
the radial displacement across the wall at p = 100 MPa (the probes on y = 0, where r = x),
against Lamé's solution for plane strain: sigma_r = A - B/r^2, sigma_theta = A + B/r^2,
u_r = ((1 + nu)/E) ((1 - 2 nu) A r + B/r), A = p a^2/(b^2 - a^2), B = p a^2 b^2/(b^2 - a^2).

    python3 examples/lame-cylinder/plot.py [case.out] [stress-across-wall.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "stress-across-wall.png")
last = rows[-1]

a, b, p, E, nu = 0.1, 0.2, 100e6, 2.1e11, 0.3  # as in cylinder.geo and case.yaml (t = 1)
A, B = p * a * a / (b * b - a * a), p * a * a * b * b / (b * b - a * a)
probes = [("bore", 0.1), ("r120", 0.12), ("r140", 0.14), ("r160", 0.16), ("r180", 0.18),
          ("outer", 0.2)]
r_line = [a + (b - a) * k / 100 for k in range(101)]
MPa, um = 1e-6, 1e6

fig, (ax_s, ax_u) = plt.subplots(2, 1, figsize=(7, 7.5), sharex=True,
                                 gridspec_kw={"height_ratios": [1.4, 1]})
for name, law, col, style in (("σ_θ (hoop)", lambda r: A + B / r ** 2, "stress.yy", "o"),
                              ("σ_r (radial)", lambda r: A - B / r ** 2, "stress.xx", "s"),
                              ("σ_z (axial)", lambda r: 2 * nu * A, "stress.zz", "^")):
    line, = ax_s.plot([r * 1e3 for r in r_line], [law(r) * MPa for r in r_line], "-", lw=1,
                      label=f"Lamé {name}")
    ax_s.plot([r * 1e3 for _, r in probes], [last[f"{n}.{col}"] * MPa for n, _ in probes], style,
              mfc="none", ms=7, color=line.get_color(), label=f"hencky {name}")
ax_s.set_ylabel("stress (MPa)")
ax_s.set_title("Thick cylinder, p = 100 MPa: across the wall on y = 0")
ax_s.grid(alpha=0.3)
ax_s.legend(fontsize=8, ncol=2)

u_law = lambda r: (1 + nu) / E * ((1 - 2 * nu) * A * r + B / r)
ax_u.plot([r * 1e3 for r in r_line], [u_law(r) * um for r in r_line], "-", lw=1, label="Lamé u_r")
ax_u.plot([r * 1e3 for _, r in probes], [last[f"{n}.displacement.x"] * um for n, _ in probes],
          "o", mfc="none", ms=7, label="hencky u_r")
ax_u.set_xlabel("r (mm)")
ax_u.set_ylabel("u_r (µm)")
ax_u.grid(alpha=0.3)
ax_u.legend(fontsize=8)
fig.tight_layout()
fig.savefig(png, dpi=110)
worst = max(abs(last[f"{n}.stress.yy"] - (A + B / r ** 2)) / (A + B / a ** 2) for n, r in probes)
print(f"wrote {png}; hoop stress within {100 * worst:.2f} % of Lamé's largest")
