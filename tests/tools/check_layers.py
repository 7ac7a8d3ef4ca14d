#!/usr/bin/python3
"""The layers of hencky's sources, bottom to top, and the check that every #include points
down (or within its own folder). docs/development.md names the same layers.

    check_layers.py SOURCE_DIR        exit 0 when every include points down; else lists them
"""
import re
import sys
from pathlib import Path

# Each entry is one layer; folders in one layer are siblings and may not include each other.
LAYERS = [
    ("core",),               # errors, Voigt types, log, expressions, suggestions
    ("spec",),               # the case's plain data types
    ("fem",),                # reference elements, quadrature, geometry
    ("mesh",),               # nodes, cells, regions
    ("material", "contact"),  # point laws; rigid surfaces and contact nodes
    ("parallel",),           # MPI, partition
    ("linalg",),             # pattern, assembler, linear solver back ends
    ("solve",),              # model, step loop, schemes, recovery
    ("input", "output"),     # case, mesh and STL reading; VTU/CSV/JSON writing
    ("app",),                # the command line
]
RANK = {folder: i for i, layer in enumerate(LAYERS) for folder in layer}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/[^"]+"', re.M)


def folder_of(path: Path, root: Path) -> str:
    rel = path.relative_to(root).parts
    return rel[1] if rel[0] == "src" else rel[0]


def main() -> int:
    root = Path(sys.argv[1]).resolve()
    files = sorted([*root.glob("src/**/*.[ch]pp"), *root.glob("app/*.cpp")])
    wrong, unknown = [], set()
    for f in files:
        here = folder_of(f, root)
        if here not in RANK:
            unknown.add(here)
            continue
        for target in INCLUDE.findall(f.read_text()):
            if target == here or target == "hencky":  # hencky/version.hpp is generated
                continue
            if target not in RANK:
                unknown.add(target)
            elif RANK[target] >= RANK[here]:
                wrong.append(f"{f.relative_to(root)} ({here}, layer {RANK[here]}) includes "
                             f"{target}/ (layer {RANK[target]})")
    for w in wrong:
        print("upward include:", w)
    for u in sorted(unknown):
        print(f"folder '{u}' is in no layer: add it to LAYERS in {Path(__file__).name} and to "
              "docs/development.md")
    print(f"{len(files)} files, {len(wrong)} upward includes, {len(unknown)} unknown folders")
    return 1 if wrong or unknown else 0


if __name__ == "__main__":
    sys.exit(main())
