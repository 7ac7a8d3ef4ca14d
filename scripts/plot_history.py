#!/usr/bin/python3
"""Curves of a run's history.csv: what `hencky plot DIR` runs (docs/outputs.md, "Plots").

    plot_history.py DIR [--x COLUMN] [--y COLUMN ...] [--log-y] [-o PREFIX]

Writes PREFIX.png and PREFIX.svg (default DIR/plot): one panel per quantity (the components of a
vector or tensor share one: `reaction.bottom.x`, `.y` and `.z`; `contact.ball.force` has its
own), each column against --x (default: time). A COLUMN may
be a shell pattern (`reaction.*.z`, `centre.stress.*`). Without --y: the reactions, the contact
forces, and the probes' von Mises stress and displacement, those of them the run has. --log-y
draws the y axes logarithmic (the residual, say).

Needs Debian's python3-matplotlib (scripts/setup.sh installs it). Exit status 1 with a message
naming the file or the column for what cannot be plotted; nothing is written then.
"""
import argparse
import csv
import fnmatch
import math
import sys
from pathlib import Path


def fail(message):
    print("error: " + message, file=sys.stderr)
    sys.exit(1)


def read_history(path):
    try:
        with open(path, newline="") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if not header:
                fail(f"{path}: empty, no column names")
            rows = []
            for line, row in enumerate(reader, start=2):
                if len(row) != len(header):
                    fail(f"{path}:{line}: {len(row)} values for {len(header)} columns")
                try:
                    rows.append([float(v) for v in row])
                except ValueError as e:
                    fail(f"{path}:{line}: {e}")
    except OSError as e:
        fail(f"{path}: cannot be read ({e.strerror}); is it a hencky output directory?")
    return header, rows


def default_columns(header):
    """The reactions, contact forces and probes' von Mises stress and displacement."""
    picked = []
    for c in header:
        parts = c.split(".")
        if parts[0] == "reaction" or (parts[0] == "contact" and parts[-1] == "force"):
            picked.append(c)
        elif len(parts) == 2 and parts[1] == "von_mises":
            picked.append(c)
        elif len(parts) == 3 and parts[1] == "displacement":
            picked.append(c)
    return picked


def select(header, patterns):
    chosen = []
    for p in patterns:
        hits = [c for c in header if fnmatch.fnmatchcase(c, p)]
        if not hits:
            near = [c for c in header if p.split(".")[0] in c][:8] or header[:8]
            fail(f"--y '{p}': no column of history.csv matches it; columns include "
                 + ", ".join(near))
        chosen += [c for c in hits if c not in chosen]
    return chosen


COMPONENTS = {"x", "y", "z", "xx", "yy", "zz", "xy", "yz", "xz"}


def panel_of(column):
    """The components of one vector or tensor share a panel; any other column has its own."""
    parts = column.split(".")
    return ".".join(parts[:-1]) if len(parts) > 1 and parts[-1] in COMPONENTS else column


def main():
    ap = argparse.ArgumentParser(prog="hencky plot", description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", help="a run's output directory (holds history.csv)")
    ap.add_argument("--x", default="time", help="the column along x (default: time)")
    ap.add_argument("--y", nargs="+", default=None, help="columns or patterns along y")
    ap.add_argument("--log-y", action="store_true", help="logarithmic y axes")
    ap.add_argument("-o", "--output", default=None, help="PREFIX of PREFIX.png and PREFIX.svg")
    a = ap.parse_args()

    history = Path(a.dir) / "history.csv"
    header, rows = read_history(history)
    if a.x not in header:
        fail(f"--x '{a.x}': not a column of {history}; columns include "
             + ", ".join(header[:8]))
    ys = select(header, a.y) if a.y else default_columns(header)
    ys = [c for c in ys if c != a.x]
    if not ys:
        fail(f"{history}: no reactions, contact or probes to plot by default; name the columns "
             "with --y (e.g. --y iterations residual)")
    if not rows:
        fail(f"{history}: no step converged, nothing to plot")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        fail("hencky plot needs matplotlib: run scripts/setup.sh (Debian's python3-matplotlib)")

    prefix = Path(a.output) if a.output else Path(a.dir) / "plot"
    panels = []
    for c in ys:
        if panel_of(c) not in panels:
            panels.append(panel_of(c))
    ix = header.index(a.x)
    x = [r[ix] for r in rows]
    fig, axes = plt.subplots(len(panels), 1, figsize=(7.5, 2.6 + 2.2 * len(panels)),
                             sharex=True, squeeze=False)
    for ax, panel in zip(axes[:, 0], panels):
        for c in ys:
            if panel_of(c) != panel:
                continue
            y = [r[header.index(c)] for r in rows]
            if a.log_y:
                y = [v if v > 0 else math.nan for v in y]
            ax.plot(x, y, "-o", ms=3, label=c.split(".")[-1] if c != panel else c)
        ax.set_ylabel(panel)
        if a.log_y:
            ax.set_yscale("log")
        ax.grid(alpha=0.3)
        if len([c for c in ys if panel_of(c) == panel]) > 1:
            ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel(a.x)
    axes[0, 0].set_title(f"{history}", fontsize=9)
    fig.tight_layout()
    try:
        prefix.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(str(prefix) + ".png", dpi=120)
        fig.savefig(str(prefix) + ".svg")
    except OSError as e:
        fail(f"{prefix}: cannot write the plot ({e.strerror})")
    print(f"wrote {prefix}.png and {prefix}.svg ({len(ys)} curves against {a.x})")


if __name__ == "__main__":
    main()
