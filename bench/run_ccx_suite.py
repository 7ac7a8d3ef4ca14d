#!/usr/bin/python3
"""CalculiX's own test suite through hencky and ccx (issue 48, item 4).

    bench/run_ccx_suite.py HENCKY [OUT.md] [--only DECK ...] [--jobs N]

For every deck of Debian's calculix-ccx-test (/usr/share/doc/calculix-ccx-test/examples/test,
installed by scripts/setup.sh): `hencky check DECK.inp` (the whole deck, as `hencky run` reads
it). A deck hencky refuses is counted under the first keyword or message of its refusal. A deck
it accepts is run by `hencky run` and by `ccx`, and both .dat files are compared block by block
with the deck's .dat.ref (tests/tools/dat_compare.py's reader): per deck the largest difference
of the displacements and of every other block hencky writes, relative to the block's largest
value. Writes the summary as Markdown to OUT.md (default bench/results/ccx-suite-run-DATE.md).
Standard library only; a deck's runs are limited to 300 s each.
"""
import collections
import concurrent.futures
import datetime
import gzip
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests" / "tools"))
from dat_compare import blocks  # noqa: E402

SUITE = Path("/usr/share/doc/calculix-ccx-test/examples/test")


def unpack(src, dst):
    opener = gzip.open if src.suffix == ".gz" else open
    with opener(src, "rb") as f:
        dst.write_bytes(f.read())


def compare(mine, ref):
    """{what: largest difference} of the blocks of `mine` against `ref`, paired in order."""
    out = {}
    queue = collections.defaultdict(list)
    for b in ref:
        queue[(b["what"], b["set"].upper())].append(b)
    for b in mine:
        q = queue.get((b["what"], b["set"].upper()))
        if not q:
            continue
        r = q.pop(0)
        if set(r["rows"]) != set(b["rows"]):
            out[b["what"].split(" (")[0] + ": other points"] = None
            continue
        scale = max([abs(v) for row in r["rows"].values() for v in row] + [1e-30])
        worst = max((abs(x - y) / scale for k, row in r["rows"].items()
                     for x, y in zip(b["rows"][k], row)), default=0.0)
        out[b["what"]] = max(out.get(b["what"], 0.0), worst)
    return out


def first_refusal(text):
    for line in text.splitlines():
        m = re.match(r"^  \S+:\d+: (\*[A-Z][A-Z -]*[A-Z])", line)
        if m:
            return m.group(1)
    m = re.search(r"error: (?:\S+: )?(.*)", text)
    if not m:
        return "(no message)"
    msg = m.group(1)
    msg = re.sub(r"'[^']*'", "'…'", msg)
    msg = re.sub(r"\b\d+\b", "N", msg)  # numbers, not the digits of C3D20
    return msg[:90]


def one(hencky, deck, work):
    name = deck.name.split(".")[0]
    d = work / name
    d.mkdir()
    inp = d / f"{name}.inp"
    unpack(deck, inp)
    res = {"deck": name}
    try:
        chk = subprocess.run([hencky, "check", str(inp)], capture_output=True, text=True, timeout=300)
    except subprocess.TimeoutExpired:
        res.update(status="check timed out")
        return res
    if chk.returncode != 0:
        res.update(status="refused" if chk.returncode == 1 else f"check exit {chk.returncode}",
                   reason=first_refusal(chk.stderr + chk.stdout))
        return res
    try:
        run = subprocess.run([hencky, "run", str(inp), "--quiet"], capture_output=True, text=True,
                             timeout=300, cwd=d)
        res["hencky"] = run.returncode
        ccx = subprocess.run(["ccx", "-i", name], capture_output=True, text=True, timeout=300, cwd=d)
        res["ccx"] = ccx.returncode
    except subprocess.TimeoutExpired:
        res.update(status="run timed out")
        return res
    ref_file = SUITE / f"{name}.dat.ref.gz"
    if not ref_file.exists():
        ref_file = SUITE / f"{name}.dat.ref"
    ref = blocks(ref_file) if ref_file.exists() else []
    mine_file = d / f"{name}.out" / f"{name}.dat"
    res["status"] = "ran" if res["hencky"] == 0 else f"hencky exit {res['hencky']}"
    if run.returncode != 0:
        res["reason"] = (run.stderr.strip().splitlines() or ["?"])[-1][:120]
    res["hencky_vs_ref"] = compare(blocks(mine_file), ref) if mine_file.exists() else {}
    res["ccx_vs_ref"] = compare(blocks(d / f"{name}.dat"), ref) if (d / f"{name}.dat").exists() else {}
    text = inp.read_text(errors="replace")
    res["types"] = sorted(set(re.findall(r"TYPE\s*=\s*(C3D\w+)", text.upper())))
    if "C3D20R" in res["types"]:
        # The same deck with C3D20 for C3D20R, through both: the same element in the two codes.
        full = d / f"{name}_full.inp"
        full.write_text(re.sub(r"C3D20R", "C3D20 ", text, flags=re.IGNORECASE))
        try:
            subprocess.run([hencky, "run", str(full), "--quiet"], capture_output=True, timeout=300, cwd=d)
            subprocess.run(["ccx", "-i", full.stem], capture_output=True, timeout=300, cwd=d)
            mine_full = d / f"{full.stem}.out" / f"{full.stem}.dat"
            if mine_full.exists() and (d / f"{full.stem}.dat").exists():
                res["full_vs_ccx"] = compare(blocks(mine_full), blocks(d / f"{full.stem}.dat"))
        except subprocess.TimeoutExpired:
            res["full_vs_ccx"] = {"timed out": None}
    return res


def main():
    args = [a for a in sys.argv[1:]]
    only = []
    if "--only" in args:
        i = args.index("--only")
        only = args[i + 1:]
        args = args[:i]
    jobs = 2
    if "--jobs" in args:
        i = args.index("--jobs")
        jobs = int(args[i + 1])
        del args[i:i + 2]
    hencky = os.path.abspath(args[0])
    out = Path(args[1]) if len(args) > 1 else Path(__file__).resolve().parent / "results" / \
        f"ccx-suite-run-{datetime.date.today():%Y%m%d}.md"
    decks = sorted(p for p in SUITE.glob("*.inp*") if not only or p.name.split(".")[0] in only)
    work = Path(tempfile.mkdtemp(prefix="ccx-suite-"))
    try:
        with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
            results = list(pool.map(lambda p: one(hencky, p, work), decks))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    lines = [f"# CalculiX's test suite through hencky ({datetime.date.today()})", "",
             f"`bench/run_ccx_suite.py` on the {len(results)} decks of calculix-ccx-test: "
             "`hencky check` on each whole deck; the accepted ones run by hencky and ccx 2.20, "
             "both .dat files compared block by block with the deck's .dat.ref (the largest "
             "difference relative to the block's largest value).", ""]
    count = collections.Counter(r["status"] for r in results)
    lines += ["| outcome | decks |", "|---|---|"] + [f"| {k} | {v} |" for k, v in count.most_common()] + [""]
    ran = [r for r in results if "hencky_vs_ref" in r]
    lines += ["## Decks hencky runs", "",
              "| deck | elements | hencky | U (NT without U): hencky / ccx vs .dat.ref | other blocks (hencky) "
              "| C3D20R as C3D20 in both: hencky vs ccx |",
              "|---|---|---|---|---|---|"]
    for r in ran:
        hv, cv = r["hencky_vs_ref"], r["ccx_vs_ref"]
        u = "displacements (vx,vy,vz)"
        if u not in hv and u not in cv:  # a heat analysis alone: its temperatures
            u = "temperatures"
        other = ", ".join(f"{k.split(' (')[0]} {v:.1e}" if v is not None else k
                          for k, v in hv.items() if k != u)
        fv = r.get("full_vs_ccx", {})
        full = ", ".join(f"{k.split(' (')[0]} {v:.1e}" if v is not None else k for k, v in fv.items())
        lines.append(f"| {r['deck']} | {' '.join(r.get('types', []))} | {r['status']} | "
                     f"{hv.get(u, float('nan')):.1e} / {cv.get(u, float('nan')):.1e} | {other} "
                     f"| {full} |")
    refused = collections.Counter(r.get("reason", "?") for r in results if r["status"] == "refused")
    lines += ["", "## Why the others are refused (the first keyword or message of each)", "",
              "| reason | decks |", "|---|---|"] + [f"| {k} | {v} |" for k, v in refused.most_common()]
    crashed = [r["deck"] for r in results if r["status"] not in ("ran", "refused")]
    lines += ["", f"Neither refused nor run to the end: {', '.join(crashed) if crashed else 'none'}."]
    out.write_text("\n".join(lines) + "\n")
    print(out)
    print("\n".join(lines[:12]))


if __name__ == "__main__":
    main()
