"""Running the programs and describing where they ran.

  - timed: a command under /usr/bin/time -v (and coreutils' timeout): wall time, peak memory,
    CPU time, and the CPU that other programs took meanwhile (/proc/stat);
  - hencky: run_hencky (serial, as the scripts run it) and hencky_timed (any hencky command line,
    for run_parallel_bench.py's configurations), and the files a run writes (history.csv, .vtu);
  - waiting for a quiet machine (wait_quiet, quiet, wait_load);
  - the machine's facts, its dgemm rate, the binary's and the repository's provenance;
  - the options and the set-up that the scripts share (add_common_arguments, prepare_run), and
    the statistics of repeated runs (median, undisturbed).
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from . import BENCH, ROOT

# exit status of a command killed by with_timeout's limit (SIGTERM, then SIGKILL)
TIMEOUT_EXIT = (124, 137)


# ----------------------------------------------------------------------------------------------
# Timing a command
# ----------------------------------------------------------------------------------------------
def cpu_snapshot() -> tuple[float, float]:
    """(busy, steal) CPU seconds of the whole machine since boot, from /proc/stat."""
    v = [int(x) for x in open("/proc/stat").readline().split()[1:]]
    hz = os.sysconf("SC_CLK_TCK")
    user, nice, system, idle, iowait, irq, softirq, steal = (v + [0] * 8)[:8]
    return (user + nice + system + irq + softirq) / hz, steal / hz


def with_timeout(cmd: list, timeout: float | None) -> list:
    """`cmd` run under coreutils' timeout (SIGTERM after `timeout` s, SIGKILL 30 s later; exit
    status 124 or 137 then). Under /usr/bin/time -v the peak memory is still the program's."""
    if not timeout:
        return cmd
    return ["timeout", "--kill-after=30", f"{timeout:g}"] + cmd


def timed(cmd, cwd, env=None, log=None, timeout: float | None = None) -> dict:
    """Run under /usr/bin/time -v (and with_timeout's `timeout`): wall seconds (measured here),
    peak RSS, CPU seconds, the 1-minute load before, the cores other programs used meanwhile;
    r["timed_out"]: killed by the time limit; r["lines"]: (seconds since the start, line) of its
    output, which also goes to `log` (r["log"]), each line prefixed with those seconds (for
    phases)."""
    tv = cwd / "time-v.txt"
    full = ["/usr/bin/time", "-v", "-o", str(tv)] + [str(c) for c in with_timeout(list(cmd), timeout)]
    load = os.getloadavg()[0]
    busy0, steal0 = cpu_snapshot()
    t0 = time.perf_counter()
    stamped = []
    with subprocess.Popen(full, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, errors="replace", bufsize=1) as proc:
        for line in proc.stdout:
            stamped.append((time.perf_counter() - t0, line.rstrip("\n")))
        rc = proc.wait()
    wall = time.perf_counter() - t0
    busy1, steal1 = cpu_snapshot()
    if log:
        Path(log).write_text("".join(f"[{t:9.3f}] {l}\n" for t, l in stamped))
    text = tv.read_text()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) * 1024
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1))
    sys_ = float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1))
    # CPU taken by other programs during the run (cores on average): the machine's busy time
    # minus this process tree's, plus the hypervisor's steal time.
    others = max(0.0, (busy1 - busy0) - (user + sys_) + (steal1 - steal0)) / wall
    return dict(rc=rc, wall=wall, peak_rss=rss, cpu=user + sys_, load_before=load, others=others,
                lines=stamped, timed_out=bool(timeout) and rc in TIMEOUT_EXIT,
                log=str(log) if log else None)


# ----------------------------------------------------------------------------------------------
# hencky
# ----------------------------------------------------------------------------------------------
def hencky_timed(cmd: list, case: Path, out: Path, env=None, log=None, timeout: float | None = None) -> dict:
    """`cmd`, a hencky run of `case` that writes to `out` (removed first), in the case's folder
    under timed(); r["summary"] is its summary.json (None when the run wrote none: killed by the
    time limit, crashed)."""
    if out.exists():
        shutil.rmtree(out)
    r = timed(cmd, case.parent, env=env, log=log, timeout=timeout)
    summary = out / "summary.json"
    r["summary"] = json.loads(summary.read_text()) if summary.exists() else None
    return r


def run_hencky(exe: Path, case: Path, out: Path, threads: int, env=None, timeout: float | None = None,
               check: bool = True) -> dict:
    """hencky run under /usr/bin/time -v; r["summary"] is summary.json (None when the run wrote
    none: killed by the timeout, crashed). check: raise unless hencky converged (exit 0)."""
    log = case.parent / f"{case.stem}.hencky.log"
    r = hencky_timed([exe, "run", case, "-o", out, "--threads", threads, "--quiet"], case, out,
                     env=env, log=log, timeout=timeout)
    del r["lines"]
    if r["rc"] != 0 and check:
        raise SystemExit(f"hencky failed (exit {r['rc']}), see {log}")
    return r


def remove_partial(out: Path) -> None:
    """Remove the unfinished output folders (<out>.partial-*) of an earlier or killed run."""
    for old in out.parent.glob(out.name + ".partial-*"):
        shutil.rmtree(old, ignore_errors=True)


def history_rows(history_csv: Path) -> list[list[str]]:
    """The rows (one per converged step: step, time, iterations, ...) of a hencky history.csv."""
    if not history_csv.exists():
        return []
    return [l.split(",") for l in history_csv.read_text().splitlines()[1:] if l.strip()]


def reached_time(history_csv: Path) -> float | None:
    """Time of the last converged step in a hencky history.csv (None without one)."""
    rows = history_rows(history_csv)
    return float(rows[-1][1]) if rows else None


def read_vtu(path: Path, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Point data `names` and the points of a .vtu: meshio when installed, otherwise the XML
    header and raw appended data that src/io/vtu_writer.cpp writes (header_type UInt64: each
    block is its byte count, then the values)."""
    try:
        import meshio  # noqa: F401
        m = meshio.read(path)
        return {"Points": np.asarray(m.points), **{n: np.asarray(m.point_data[n]) for n in names}}
    except ImportError:
        pass
    buf = path.read_bytes()
    marker = buf.index(b'<AppendedData encoding="raw">')
    base = buf.index(b"_", marker) + 1
    head = buf[:marker].decode()
    if 'header_type="UInt64"' not in head or 'byte_order="LittleEndian"' not in head:
        raise SystemExit(f"{path}: expected a little-endian .vtu with UInt64 headers")
    out = {}
    types = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1"}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)"(?: NumberOfComponents="(\d+)")?'
                         r' format="appended" offset="(\d+)"', head):
        typ, name, ncomp, off = m.group(1), m.group(2), int(m.group(3) or 1), int(m.group(4))
        if name != "Points" and name not in names:
            continue
        # cell data have names of their own except "stress" etc.: take the point data (first)
        if name in out:
            continue
        start = base + off
        nbytes = int(np.frombuffer(buf, "<u8", count=1, offset=start)[0])
        dtype = np.dtype(types[typ])
        a = np.frombuffer(buf, dtype, count=nbytes // dtype.itemsize, offset=start + 8)
        out[name] = a.reshape(-1, ncomp) if ncomp > 1 else a.copy()
    missing = [n for n in ("Points",) + tuple(names) if n not in out]
    if missing:
        raise SystemExit(f"{path}: no {', '.join(missing)}")
    return out


# ----------------------------------------------------------------------------------------------
# A quiet machine
# ----------------------------------------------------------------------------------------------
def wait_quiet(max_wait: float, threshold: float = 0.15) -> dict:
    """Wait (at most max_wait seconds) until other programs use less than `threshold` cores,
    measured over one second. Returns the wait and the last measured background."""
    t0 = time.perf_counter()
    while True:
        b0, s0 = cpu_snapshot()
        time.sleep(1.0)
        b1, s1 = cpu_snapshot()
        bg = (b1 - b0) + (s1 - s0)
        waited = time.perf_counter() - t0
        if bg < threshold or waited >= max_wait:
            return dict(waited=waited, background=bg)
        time.sleep(2.0)


def quiet(args) -> None:
    """Before a run: wait_quiet(args.wait_quiet) unless that is 0, saying so when it waited."""
    if args.wait_quiet > 0:
        q = wait_quiet(args.wait_quiet)
        if q["waited"] > 1.5:
            print(f"    (waited {q['waited']:.0f} s for other programs; background now {q['background']:.2f} cores)", flush=True)


def wait_load(max_wait: float, below: float, poll: float = 30.0) -> dict:
    """Wait (at most max_wait s, polling every `poll` s) until the 1-minute load average is below
    `below`. Returns the wait and the load then."""
    t0 = time.perf_counter()
    while True:
        load = os.getloadavg()[0]
        waited = time.perf_counter() - t0
        if load < below or waited >= max_wait:
            return dict(waited=waited, load=load, met=load < below)
        print(f"    (1-min load {load:.2f} >= {below:g}; waiting, {waited:.0f} s so far)", flush=True)
        time.sleep(poll)


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def undisturbed(runs: list[dict], limit: float) -> list[dict]:
    """The runs during which other programs used at most `limit` cores; all of them when none
    was undisturbed."""
    clean = [r for r in runs if r["others"] <= limit]
    return clean or runs


# ----------------------------------------------------------------------------------------------
# Machine, binary and repository
# ----------------------------------------------------------------------------------------------
def sh(cmd) -> str:
    try:
        return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()
    except Exception:
        return ""


def machine_info() -> dict:
    cpu = ""
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    flags = ""
    for line in open("/proc/cpuinfo"):
        if line.startswith("flags"):
            fl = line.split(":", 1)[1].split()
            flags = " ".join(f for f in ("avx2", "fma", "avx512f") if f in fl)
            break
    mem = 0
    for line in open("/proc/meminfo"):
        if line.startswith("MemTotal"):
            mem = int(line.split()[1]) * 1024
    blas = sh("update-alternatives --query libblas.so.3-x86_64-linux-gnu | sed -n 's/^Value: //p'")
    return dict(
        nproc=os.cpu_count(),
        cpu=cpu,
        cpu_flags=flags,
        hypervisor=sh("lscpu | sed -n 's/^Hypervisor vendor: *//p'"),
        memory_bytes=mem,
        kernel=platform.release(),
        os=sh(". /etc/os-release && echo $PRETTY_NAME"),
        blas=blas,
        openblas=sh("dpkg-query -W -f='${Package} ${Version}\\n' 'libopenblas0*' 2>/dev/null"),
        cholmod=sh("dpkg-query -W -f='${Package} ${Version}\\n' 'libcholmod*' 2>/dev/null"),
        ccx=sh("dpkg-query -W -f='${Package} ${Version}' calculix-ccx 2>/dev/null"),
        spooles=sh("dpkg-query -W -f='${Package} ${Version}' 'libspooles*' 2>/dev/null"),
        gmsh=sh("gmsh --version 2>&1"),
        numpy=np.__version__,
        python=platform.python_version(),
    )


def machine_line(m: dict, exe: Path) -> str:
    """The progress line that starts a run: the machine (machine_info) and the binary."""
    return f"machine: {m['cpu']}, {m['nproc']} cores, {m['memory_bytes'] / 2**30:.1f} GiB; hencky {exe}"


def mem_available() -> int:
    for line in open("/proc/meminfo"):
        if line.startswith("MemAvailable"):
            return int(line.split()[1]) * 1024
    return 0


def dgemm_rate(n: int, threads: int | None, reps: int = 3) -> float:
    """Median GFLOP/s of numpy a @ b (OpenBLAS dgemm) in a child process, so that the thread
    count can be set before OpenBLAS starts."""
    code = (
        "import numpy as np, time, statistics\n"
        f"n={n}\n"
        "a=np.random.rand(n,n); b=np.random.rand(n,n); a@b\n"
        "r=[]\n"
        f"for _ in range({reps}):\n"
        "    t=time.perf_counter(); a@b; r.append(2*n**3/(time.perf_counter()-t)/1e9)\n"
        "print(statistics.median(r))\n"
    )
    env = dict(os.environ)
    if threads:
        env["OPENBLAS_NUM_THREADS"] = str(threads)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    return float(out.stdout.strip())


def stream_rate(n: int = 20_000_000, reps: int = 5) -> float:
    """Memory bandwidth of one core in GB/s, STREAM-like: the best of `reps` triads
    a = b + s c on arrays of n doubles (numpy, in place: 5 × 8n bytes read or written), in a
    child process on one thread. What a sparse matrix-vector product on one core (PETSc in one
    process) is bounded by."""
    code = (
        "import numpy as np, time\n"
        f"n={n}\n"
        "a=np.zeros(n); b=np.random.rand(n); c=np.random.rand(n)\n"
        "best=0\n"
        f"for _ in range({reps}):\n"
        "    t=time.perf_counter(); np.multiply(c, 3.0, out=a); np.add(a, b, out=a)\n"
        "    best=max(best, 5*8*n/(time.perf_counter()-t)/1e9)\n"
        "print(best)\n"
    )
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    return float(out.stdout.strip())


SOURCE_PATHS = "-- src app CMakeLists.txt"  # what a hencky binary is built from, for git


def git_description(list_files: bool = False) -> str:
    """The repository's HEAD (short hash), with " + uncommitted changes in src/" when src/, app/
    or CMakeLists.txt have uncommitted changes (list_files: the changed files instead of src/)."""
    dirty = sh(f"git -C {ROOT} status --porcelain --untracked-files=no {SOURCE_PATHS}")
    where = ", ".join(line.split()[-1] for line in dirty.splitlines()) if list_files else "src/"
    return sh(f"git -C {ROOT} rev-parse --short HEAD") + (f" + uncommitted changes in {where}" if dirty else "")


def program_facts(exe: Path, list_files: bool = False) -> dict:
    """The binary, its version and the repository's state (git_description), for the results."""
    return dict(hencky=str(exe), hencky_version=sh(f"{exe} --version"), git=git_description(list_files))


def binary_stamp(exe: Path) -> str:
    """The binary's modification time: the benchmark notes a rebuild while it runs."""
    return dt.datetime.fromtimestamp(exe.stat().st_mtime).astimezone().isoformat(timespec="seconds")


def build_provenance(exe: Path) -> dict:
    """Which sources the binary holds, as far as git and its modification time tell: the last
    commit that changed src/, app/ or CMakeLists.txt before it was built, and the later ones
    (committed after the build, so not in the measured binary)."""
    built = binary_stamp(exe)
    return dict(built=built,
                source=sh(f"git -C {ROOT} log -1 --format=%h --until={built} {SOURCE_PATHS}"),
                later=sh(f"git -C {ROOT} log --format='%h %cI %s' --since={built} {SOURCE_PATHS}").splitlines())


def binary_info(exe: Path) -> dict:
    """What identifies a binary of run_parallel_bench.py's memory part: path, version, build time
    and, when it sits in a git checkout, that checkout's HEAD at the start and (as
    build_provenance) the last commit changing src/, app/ or CMakeLists.txt before the build
    (uncommitted changes not seen)."""
    built = binary_stamp(exe)
    top = sh(f"git -C {shlex.quote(str(exe.parent))} rev-parse --show-toplevel 2>/dev/null")

    def git(cmd):
        return (sh(f"git -C {shlex.quote(top)} {cmd} 2>/dev/null") or None) if top else None

    return dict(path=str(exe), version=sh(f"{shlex.quote(str(exe))} --version"), built=built,
                checkout=top or None, head=git("rev-parse --short HEAD"),
                source=git(f"log -1 --format=%h --until={built} {SOURCE_PATHS}"))


# ----------------------------------------------------------------------------------------------
# What the scripts share on their command line
# ----------------------------------------------------------------------------------------------
def add_common_arguments(ap: argparse.ArgumentParser) -> None:
    """The options the plastic, contact and parallel benchmarks share."""
    ap.add_argument("--no-ccx", action="store_true", help="do not run CalculiX")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="threads for hencky and ccx (default: all cores)")
    ap.add_argument("--hencky-env", action="append", default=[], metavar="NAME=VALUE", help="extra environment for hencky")
    ap.add_argument("--wait-quiet", type=float, default=30.0,
                    help="before each run wait up to this many seconds for other programs to leave the CPU (0: never)")
    ap.add_argument("--work", type=Path, default=BENCH / "work", help="meshes and runs (default bench/work)")
    ap.add_argument("--results", type=Path, default=BENCH / "results")
    ap.add_argument("--keep-output", action="store_true", help="keep hencky's output folders and ccx's .frd")
    ap.add_argument("--report", type=Path, help="run nothing: print the markdown of this results .json")


def parse_sizes(text: str) -> list[int]:
    """Target unknowns from a comma-separated option (1e5 and 100000 alike)."""
    return [int(float(x)) for x in text.split(",") if x]


def prepare_run(args) -> tuple[Path, Path, str]:
    """For a benchmark run: the hencky binary (--hencky, or the first build directory that has
    one; bench/setup.sh builds build-bench), its environment (args.hencky_environ, with
    --hencky-env), the work and results directories (created), and the run's time stamp."""
    exe = args.hencky
    if exe is None:
        for d in ("build-bench", "build-f", "build-release", "build"):
            if (ROOT / d / "hencky").exists():
                exe = ROOT / d / "hencky"
                break
    if exe is None or not exe.exists():
        raise SystemExit("no hencky binary: build it (bash bench/setup.sh) or pass --hencky")
    args.hencky_environ = dict(os.environ, **dict(kv.split("=", 1) for kv in args.hencky_env))
    work = args.work.resolve()
    work.mkdir(parents=True, exist_ok=True)
    args.results.mkdir(parents=True, exist_ok=True)
    return exe.resolve(), work, dt.datetime.now().strftime("%Y%m%d-%H%M%S")
