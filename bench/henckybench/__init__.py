"""henckybench: the code that the benchmark scripts in bench/ share.

The scripts (run_bench.py, run_plastic_bench.py, run_contact_bench.py, run_parallel_bench.py) are
thin: their command line, the orchestration of their runs and their own tables. What they share
is here, one module per concern:

  problems   the benchmark problems: material, geometry (Gmsh .geo text), closed forms and
             reference solutions (Timoshenko, Lamé, Hill and the 1D radial solution, Hertz), the
             registry of meshable problems, hencky's case files
  gmsh       meshing with Gmsh near a target number of unknowns (meshes cached in the work
             folder), the .msh 4.1 ASCII reader, the run folders that hold a mesh
  calculix   CalculiX: the .inp writer (mesh cards, node sets, face pressure; each problem's
             input), running ccx, reading its .dat, .sta and .frd
  runner     running programs under /usr/bin/time -v (wall time, peak memory, CPU, the other
             programs' load), hencky runs and the files they write, waiting for a quiet machine,
             the machine's facts and dgemm rate, the binary's and the repository's provenance,
             the options and set-up the scripts share
  runs       one run of a problem (hencky or ccx) measured into a result row: the elastic probe
             value, the plastic cylinder's and the Hertz contact's rows
  report     markdown formatting, the machine description, the result files, the generated part
             of docs/performance.md

How the scripts import it: Python puts the folder of the script it runs first on sys.path, so
`/usr/bin/python3 bench/run_bench.py`, from any directory, finds this package in bench/ with no
path set-up in the scripts (except under `python3 -I` or `-P` / PYTHONSAFEPATH, which leave that
folder out). Inside the package the imports are relative. Standard library + numpy only.
"""
from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent  # the repository
BENCH = ROOT / "bench"
