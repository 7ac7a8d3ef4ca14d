"""What the examples' plot.py scripts share: matplotlib (headless), the run's history.csv and
the picture's path, from the command line

    python3 examples/<example>/plot.py [case.out] [picture.png]

(defaults: the example's case.out, or the result the script names, and its named picture). Needs Debian's python3-matplotlib,
which scripts/setup.sh installs."""
import csv
import sys
from pathlib import Path


def start(script, picture, result="case.out"):
    """(pyplot, the history's rows as dicts of floats, the picture's path) for the example
    whose plot.py is `script` (its __file__), drawing `picture` from `result` by default."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot.py needs matplotlib: run scripts/setup.sh (Debian's python3-matplotlib)")
    here = Path(script).resolve().parent
    out_dir = Path(sys.argv[1]) if len(sys.argv) > 1 else here / result
    png = Path(sys.argv[2]) if len(sys.argv) > 2 else here / picture
    with open(out_dir / "history.csv", newline="") as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    return plt, rows, png
