#!/usr/bin/env python3
"""The curve of the thermal-plate example, from case.out/history.csv: the in-plane stress
through the thickness at the plate's centre at each step, against the closed form of a plate
whose edges are held in plane: sigma_xx(z) = -E(T) (alpha(T) T - alpha(20) 20) / (1 - nu),
T = 20 + 230 t z/h, with E(T) and alpha(T) the case's tables (linear between their points).

    python3 examples/thermal-plate/plot.py [case.out] [stress-through-thickness.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "stress-through-thickness.png")

T_TABLE = [20, 100, 200, 300]  # as in case.yaml
E_TABLE = [2.10e11, 2.05e11, 1.97e11, 1.88e11]
A_TABLE = [1.20e-5, 1.24e-5, 1.29e-5, 1.33e-5]
NU, H = 0.3, 0.02


def table(T, values):
    if T <= T_TABLE[0]:
        return values[0]
    for k in range(1, len(T_TABLE)):
        if T <= T_TABLE[k]:
            s = (T - T_TABLE[k - 1]) / (T_TABLE[k] - T_TABLE[k - 1])
            return values[k - 1] + s * (values[k] - values[k - 1])
    return values[-1]


def sigma(z, t):
    T = 20 + 230 * t * z / H
    return -table(T, E_TABLE) * (table(T, A_TABLE) * T - A_TABLE[0] * 20) / (1 - NU)


probes = [("z0", 0.0), ("z5", 0.005), ("middle", 0.01), ("z15", 0.015), ("top", 0.02)]
z_line = [H * k / 100 for k in range(101)]
MPa, mm = 1e-6, 1e3
fig, ax = plt.subplots(figsize=(6.5, 5.5))
worst = 0.0
for r in rows:
    t = r["time"]
    line, = ax.plot([sigma(z, t) * MPa for z in z_line], [z * mm for z in z_line], "-", lw=1,
                    label=f"closed form, top at {20 + 230 * t:g} °C")
    ax.plot([r[f"{n}.stress.xx"] * MPa for n, _ in probes], [z * mm for _, z in probes], "o",
            mfc="none", ms=7, color=line.get_color())
    worst = max([worst] + [abs(r[f"{n}.stress.xx"] - sigma(z, t)) / abs(sigma(H, 1))
                           for n, z in probes])
ax.plot([], [], "o", mfc="none", color="0.3", label="hencky σ_xx (probes)")
ax.set_xlabel("σ_xx (MPa)")
ax.set_ylabel("z (mm)")
ax.set_title("Plate heated from the top, edges held")
ax.grid(alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(png, dpi=110)
print(f"wrote {png}; within {100 * worst:.2f} % of the top face's stress at t = 1")
