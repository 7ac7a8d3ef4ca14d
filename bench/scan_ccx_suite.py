#!/usr/bin/python3
"""Which decks of CalculiX's test suite hencky's .inp reader reads (issue 48).

    scan_ccx_suite.py HENCKY_BINARY OUTPUT.md [SUITE_DIR]

SUITE_DIR: the decks of Debian's calculix-ccx-test (/usr/share/doc/calculix-ccx-test/examples/
test by default; .inp or .inp.gz). Each deck is copied (unzipped) into a scratch folder with a
case file that names it as the mesh and nothing else (a material, no boundary), and checked with
`hencky check`. The mesh was read when the check fails only for the missing displacement
condition (or passes); otherwise the deck was refused, and the first line of the error says why.
Writes the counts, the refusals grouped by their reason, and every deck's outcome to OUTPUT.md.
"""
import collections
import gzip
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def main():
    binary, output = sys.argv[1], Path(sys.argv[2])
    suite = Path(sys.argv[3] if len(sys.argv) > 3 else "/usr/share/doc/calculix-ccx-test/examples/test")
    decks = sorted(p for p in suite.iterdir() if p.name.endswith((".inp", ".inp.gz")))
    outcome = {}
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        for deck in decks:
            name = deck.name.removesuffix(".gz").removesuffix(".inp")
            d = work / name
            d.mkdir()
            target = d / (name + ".inp")
            if deck.name.endswith(".gz"):
                with gzip.open(deck, "rb") as src, open(target, "wb") as dst:
                    shutil.copyfileobj(src, dst)
            else:
                shutil.copy(deck, target)
            (d / "case.yaml").write_text(
                f"mesh: {{file: {name}.inp}}\nmaterials: [{{E: 2.1e11, nu: 0.3}}]\nboundary: []\n")
            try:
                r = subprocess.run([binary, "check", str(d / "case.yaml")], capture_output=True,
                                   text=True, timeout=120)
                text, code = r.stdout + r.stderr, r.returncode
            except subprocess.TimeoutExpired:
                text, code = "timed out after 120 s", -1
            errors = [l for l in text.splitlines() if l.startswith("error:")]
            if code == 0 or (code == 1 and errors and "no displacement condition" in errors[0]):
                outcome[name] = ("read", "")
            elif code == 1 and errors:
                reason = re.sub(r"^error: \S+?: ", "", errors[0])
                outcome[name] = ("refused", reason)
            else:
                outcome[name] = ("CRASH or hang", f"exit {code}: {text.strip().splitlines()[-1] if text.strip() else ''}")
    counts = collections.Counter(kind for kind, _ in outcome.values())
    kinds = collections.Counter()
    for kind, reason in outcome.values():
        if kind == "refused":
            key = re.sub(r"\d+", "N", reason)
            key = re.sub(r"'[^']*'", "'…'", key)
            kinds[key[:140]] += 1
    with open(output, "w") as f:
        f.write(f"# CalculiX's test decks through `hencky check` (mesh only)\n\n")
        f.write(f"{len(outcome)} decks of {suite}; binary `{binary}`. A deck is *read* when the check "
                "stops only at the missing displacement condition of the scan's case file.\n\n")
        for kind in ("read", "refused", "CRASH or hang"):
            f.write(f"- {kind}: {counts.get(kind, 0)}\n")
        f.write("\n## Refusals by reason (numbers and names masked)\n\n| decks | reason |\n|---|---|\n")
        for key, n in kinds.most_common():
            f.write(f"| {n} | {key.replace('|', '/')} |\n")
        f.write("\n## Every deck\n\n| deck | outcome | reason |\n|---|---|---|\n")
        for name, (kind, reason) in sorted(outcome.items()):
            f.write(f"| {name} | {kind} | {reason.replace('|', '/')[:200]} |\n")
    print(f"{len(outcome)} decks: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    return 0 if counts.get("CRASH or hang", 0) == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
