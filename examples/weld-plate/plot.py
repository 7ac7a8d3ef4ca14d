#!/usr/bin/env python3
"""The plot of the weld-plate example, from case.out/history.csv: the temperature and the
stresses on the weld line at mid-length (probe `weld`) against time, with the yield stress at
the probe's temperature, and the residual longitudinal stress across the half width at the end
(probes `weld`, `y5` ... `edge`).

    python3 examples/weld-plate/plot.py [case.out] [temperature-stress.png]

Needs matplotlib: scripts/setup.sh installs it (Debian's python3-matplotlib); the
prologue is scripts/example_plot.py's."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from example_plot import start  # noqa: E402

plt, rows, png = start(__file__, "temperature-stress.png")

# The yield stress over temperature, as in case.yaml (Pa).
YIELD_T = [0, 20, 200, 400, 600, 800, 1000, 2500]
YIELD = [250e6, 250e6, 230e6, 190e6, 110e6, 45e6, 20e6, 20e6]


def interp(x, xs, ys):
    if x <= xs[0]:
        return ys[0]
    for k in range(1, len(xs)):
        if x <= xs[k]:
            return ys[k - 1] + (ys[k] - ys[k - 1]) * (x - xs[k - 1]) / (xs[k] - xs[k - 1])
    return ys[-1]


t = [r["time"] for r in rows]
MPa = 1e-6
fig, (ax_T, ax_s, ax_y) = plt.subplots(3, 1, figsize=(7.5, 10.5),
                                       gridspec_kw={"height_ratios": [1, 1.2, 1]})

for name, label, style in (("weld", "on the weld line", "-"), ("y10", "10 mm from it", "--"),
                           ("y30", "30 mm", "-."), ("edge", "100 mm (the edge)", ":")):
    ax_T.plot(t, [r[name + ".temperature"] for r in rows], style, label=label)
ax_T.set_xscale("log")
ax_T.set_xlim(8, 4000)
ax_T.set_ylabel("temperature (°C)")
ax_T.axvline(40, color="0.7", lw=0.8)
ax_T.text(41, 1200, "torch off (t = 40 s)", color="0.4", fontsize=8)
ax_T.legend(loc="upper right", fontsize=8)
ax_T.grid(alpha=0.3, which="both")
ax_T.set_title("Weld along a steel plate: the upper face at mid-length (x = 100 mm)")

ax_s.plot(t, [r["weld.stress.xx"] * MPa for r in rows], "-o", ms=3, label="σ_xx (along the weld)")
ax_s.plot(t, [r["weld.stress.yy"] * MPa for r in rows], "-s", ms=3, label="σ_yy (across it)")
ax_s.plot(t, [r["weld.von_mises"] * MPa for r in rows], "-", color="0.3", lw=1,
          label="von Mises")
ax_s.plot(t, [interp(r["weld.temperature"], YIELD_T, YIELD) * MPa for r in rows], "--",
          color="tab:red", label="yield stress at its temperature")
ax_s.set_xscale("log")
ax_s.set_xlim(8, 4000)
ax_s.set_ylim(-350, 350)
ax_s.axhline(0, color="0.8", lw=0.8)
ax_s.axvline(40, color="0.7", lw=0.8)
ax_s.set_xlabel("time (s)")
ax_s.set_ylabel("stress on the weld line (MPa)")
ax_s.legend(loc="lower right", fontsize=8)
ax_s.grid(alpha=0.3, which="both")

names = ["weld", "y5", "y10", "y15", "y20", "y25", "y30", "y40", "y60", "y80", "edge"]
ys = [0, 5, 10, 15, 20, 25, 30, 40, 60, 80, 100]
end = rows[-1]
ax_y.plot(ys, [end[n + ".stress.xx"] * MPa for n in names], "-o", label="σ_xx (along the weld)")
ax_y.plot(ys, [end[n + ".stress.yy"] * MPa for n in names], "-s", label="σ_yy (across it)")
ax_y.axhline(YIELD[0] * MPa, color="tab:red", ls="--", lw=1, label="yield stress at 20 °C")
ax_y.axhline(0, color="0.8", lw=0.8)
ax_y.set_xlabel("distance from the weld line y (mm), at x = 100 mm")
ax_y.set_ylabel("residual stress (MPa)")
ax_y.set_title("after cooling (t = %g s)" % end["time"], fontsize=10)
ax_y.legend(loc="upper right", fontsize=8)
ax_y.grid(alpha=0.3)

fig.tight_layout()
fig.savefig(png, dpi=100)
print(f"wrote {png}")
