#!/usr/bin/python3
"""The CalculiX deck that the bench writes for an elastic problem (bench/henckybench/calculix.py,
write_elastic_inp), on a coarse mesh, beside hencky's case of the same problem on the same mesh
read from the .msh and from the deck:

    bench_deck.py PROBLEM H OUTDIR

PROBLEM is cylinder or cantilever (bench/henckybench/problems.py), H the element size. Writes
OUTDIR/<problem>_h<H>.msh (Gmsh, 10-node tetrahedra), OUTDIR/deck.inp, OUTDIR/msh.yaml and
OUTDIR/inp.yaml; the two cases differ in mesh.file only, and name the regions in lower case
where the deck has them in upper case. Standard library + numpy, and the gmsh command.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))

from henckybench.calculix import write_elastic_inp  # noqa: E402
from henckybench.gmsh import gmsh_mesh, read_msh4  # noqa: E402
from henckybench.problems import elastic_case  # noqa: E402


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    problem, h, out = sys.argv[1], float(sys.argv[2]), Path(sys.argv[3])
    out.mkdir(parents=True, exist_ok=True)
    msh, _ = gmsh_mesh(problem, h, out, 1)
    deck = out / "deck.inp"
    write_elastic_inp(problem, read_msh4(msh), deck)
    (out / "msh.yaml").write_text(elastic_case(problem, msh))
    (out / "inp.yaml").write_text(elastic_case(problem, deck))


if __name__ == "__main__":
    main()
