#!/usr/bin/env pvpython
"""Check a hencky result (.vtu or .pvd) with ParaView.

Run with ParaView's Python (Debian package python3-paraview):

    pvpython scripts/check_vtu.py RESULT.vtu|RESULT.pvd [--volume V] [--area A] [--rtol R]
                                   [--validate] [--straight-edges] [--print-cells N]

Prints the number of points and cells, the point/cell arrays with their component counts and
ranges, and the size of every cell (ParaView's Cell Size filter: volume of 3D cells, area of
2D cells). Exit status 1 if any 3D cell has a volume <= 0, if the summed 3D volume differs from
--volume (or the summed 2D area from --area) by more than --rtol relative, and with --validate
if VTK's cell validator flags a cell (wrong face orientation, non-convex, ...), with
--straight-edges if a mid-edge node of a quadratic cell is not the midpoint of its edge (only
meaningful for straight-sided cells, e.g. a reference test). For a .pvd every time step is
checked. Works headless: no render window is created.

Speed: ParaView 5.11's Cell Size filter is fast for linear tetrahedra (about 1 s per million)
but slow for the other 3D cells, which it tetrahedralizes one by one (about 0.1-0.2 ms per
hexahedron: minutes for millions of cells). --no-sizes skips it for a quick look at big files.
For curved quadratic cells the size is that of VTK's linear subdivision, so compare with
--volume using a looser --rtol.
"""
import argparse
import math
import sys

from paraview import servermanager
from paraview import simple

from vtkmodules.vtkCommonDataModel import vtkDataSet, vtkCompositeDataSet
from vtkmodules.vtkFiltersGeneral import vtkCellValidator

VTK_NAMES = {
    1: "vertex", 3: "line", 5: "triangle", 9: "quad", 10: "tetra", 12: "hexahedron", 13: "wedge",
    14: "pyramid", 21: "quadratic edge", 22: "quadratic triangle", 23: "quadratic quad",
    24: "quadratic tetra", 25: "quadratic hexahedron", 26: "quadratic wedge",
}
QUADRATIC = {21, 22, 23, 24, 25, 26, 27}
DIMENSION = {1: 0, 3: 1, 21: 1, 5: 2, 9: 2, 22: 2, 23: 2,
             10: 3, 12: 3, 13: 3, 14: 3, 24: 3, 25: 3, 26: 3}


def datasets(obj):
    """The vtkDataSet leaves of what Fetch returned."""
    if obj is None:
        return []
    if isinstance(obj, vtkCompositeDataSet):
        out = []
        it = obj.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            out.append(it.GetCurrentDataObject())
            it.GoToNextItem()
        return out
    if isinstance(obj, vtkDataSet):
        return [obj]
    return []


def describe_arrays(label, data):
    for i in range(data.GetNumberOfArrays()):
        a = data.GetAbstractArray(i)
        if a is None:
            continue
        line = "  %s array %-24s %d component(s), %s" % (
            label, '"%s"' % a.GetName(), a.GetNumberOfComponents(), a.GetDataTypeAsString())
        if hasattr(a, "GetRange") and a.GetNumberOfTuples() > 0:
            if a.GetNumberOfComponents() == 1:
                lo, hi = a.GetRange(0)
            else:
                lo, hi = a.GetRange(-1)  # magnitude
                line += ", magnitude"
            line += " range [%.6g, %.6g]" % (lo, hi)
        print(line)


def check_straight_edges(ds, tol):
    """Mid-edge nodes of quadratic cells at the midpoints of their edges, in VTK's own edge
    definition (vtkCell::GetEdge: end, end, mid). Returns the number of bad edges."""
    bad = 0
    for c in range(ds.GetNumberOfCells()):
        if ds.GetCellType(c) not in QUADRATIC:
            continue
        cell = ds.GetCell(c)
        b = cell.GetBounds()
        size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
        for e in range(cell.GetNumberOfEdges()):
            edge = cell.GetEdge(e)
            p = [edge.GetPoints().GetPoint(k) for k in range(3)]
            d = math.sqrt(sum((p[2][k] - 0.5 * (p[0][k] + p[1][k])) ** 2 for k in range(3)))
            if d > tol * size:
                bad += 1
                print("  cell %d (%s): edge %d: mid node %d is %.3g off the midpoint of %d-%d"
                      % (c, VTK_NAMES.get(ds.GetCellType(c), "?"), e, edge.GetPointId(2), d,
                         edge.GetPointId(0), edge.GetPointId(1)))
    return bad


def check_dataset(ds, args, label):
    """Returns (list of failure messages, 3D volume, 2D area)."""
    failures = []
    n_cells = ds.GetNumberOfCells()
    print("%s: %d points, %d cells" % (label, ds.GetNumberOfPoints(), n_cells))
    counts = {}
    for c in range(n_cells):
        t = ds.GetCellType(c)
        counts[t] = counts.get(t, 0) + 1
    for t in sorted(counts):
        print("  %d x %s (VTK type %d)" % (counts[t], VTK_NAMES.get(t, "?"), t))
    describe_arrays("point", ds.GetPointData())
    describe_arrays("cell ", ds.GetCellData())
    describe_arrays("field", ds.GetFieldData())

    vol_arr = ds.GetCellData().GetArray("Volume")
    area_arr = ds.GetCellData().GetArray("Area")
    volume = 0.0
    area = 0.0
    n_bad = 0
    n_3d = 0
    min_vol = math.inf
    show = args.print_cells < 0 or n_cells <= args.print_cells
    for c in range(n_cells if vol_arr is not None and area_arr is not None else 0):
        t = ds.GetCellType(c)
        dim = DIMENSION.get(t)
        if dim is None:
            dim = ds.GetCell(c).GetCellDimension()
        if dim == 3:
            v = vol_arr.GetValue(c)
            volume += v
            n_3d += 1
            min_vol = min(min_vol, v)
            if not v > 0:
                n_bad += 1
                if n_bad <= 20:
                    print("  cell %d (%s): volume %.10g <= 0" % (c, VTK_NAMES.get(t, "?"), v))
            if show:
                print("  cell %d %-22s volume %.15g" % (c, VTK_NAMES.get(t, "?"), v))
        elif dim == 2:
            a = area_arr.GetValue(c)
            area += a
            if show:
                print("  cell %d %-22s area   %.15g" % (c, VTK_NAMES.get(t, "?"), a))
    if n_3d:
        print("  3D cells: %d, summed volume %.15g, smallest %.6g" % (n_3d, volume, min_vol))
    if area:
        print("  2D cells: summed area %.15g" % area)
    if n_bad:
        failures.append("%s: %d 3D cell(s) with volume <= 0" % (label, n_bad))

    if args.validate:
        v = vtkCellValidator()
        v.SetInputData(ds)
        v.Update()
        state = v.GetOutput().GetCellData().GetArray("ValidityState")
        n_invalid = 0
        for c in range(n_cells):
            s = int(state.GetValue(c))
            if s != 0:
                n_invalid += 1
                if n_invalid <= 20:
                    print("  cell %d (%s): vtkCellValidator state %d%s"
                          % (c, VTK_NAMES.get(ds.GetCellType(c), "?"), s,
                             " (faces oriented incorrectly)" if s & 32 else ""))
        print("  vtkCellValidator: %d invalid cell(s)" % n_invalid)
        if n_invalid:
            failures.append("%s: vtkCellValidator flags %d cell(s)" % (label, n_invalid))

    if args.straight_edges:
        bad = check_straight_edges(ds, 1e-9)
        print("  straight edges: %d mid-edge node(s) off their edge's midpoint" % bad)
        if bad:
            failures.append("%s: %d mid-edge node(s) not at edge midpoints" % (label, bad))
    return failures, volume, area


def close(value, expected, rtol):
    return abs(value - expected) <= rtol * max(abs(expected), 1e-300)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("file", help=".vtu or .pvd")
    p.add_argument("--volume", type=float, help="expected sum of the 3D cell volumes")
    p.add_argument("--area", type=float, help="expected sum of the 2D cell areas")
    p.add_argument("--rtol", type=float, default=1e-9, help="relative tolerance (default 1e-9)")
    p.add_argument("--validate", action="store_true", help="run vtkCellValidator on every cell")
    p.add_argument("--straight-edges", action="store_true",
                   help="mid-edge nodes of quadratic cells must be at the edge midpoints")
    p.add_argument("--no-sizes", action="store_true",
                   help="skip the cell sizes (and --volume/--area): counts and arrays only")
    p.add_argument("--print-cells", type=int, default=100, metavar="N",
                   help="print every cell's size if there are at most N cells (-1: always)")
    args = p.parse_args()

    reader = simple.OpenDataFile(args.file)
    if reader is None:
        print("error: ParaView cannot open %s" % args.file, file=sys.stderr)
        return 1
    tv = reader.TimestepValues if hasattr(reader, "TimestepValues") else None
    if isinstance(tv, (int, float)):  # a single time step comes as a number
        times = [float(tv)]
    else:
        times = list(tv or [])
    if args.no_sizes:
        if args.volume is not None or args.area is not None:
            print("error: --volume and --area need the cell sizes (no --no-sizes)", file=sys.stderr)
            return 2
        sizes = reader
    else:
        sizes = simple.CellSize(Input=reader)
        sizes.ComputeVertexCount = 0
        sizes.ComputeLength = 0
        sizes.ComputeArea = 1
        sizes.ComputeVolume = 1
        sizes.ComputeSum = 0

    failures = []
    steps = times if times else [None]
    if times:
        print("%s: %d time step(s): %s" % (args.file, len(times), ", ".join("%g" % t for t in times)))
    for t in steps:
        if t is None:
            sizes.UpdatePipeline()
        else:
            sizes.UpdatePipeline(t)
        data = servermanager.Fetch(sizes)
        parts = datasets(data)
        if not parts:
            failures.append("%s: no data set read" % (args.file if t is None else "t=%g" % t))
            continue
        volume = area = 0.0
        step_label = args.file if t is None else "%s @ t=%g" % (args.file, t)
        for i, ds in enumerate(parts):
            label = step_label
            if len(parts) > 1:
                label += " [block %d]" % i
            f, v, a = check_dataset(ds, args, label)
            failures += f
            volume += v
            area += a
        if args.volume is not None and not close(volume, args.volume, args.rtol):
            failures.append("%s: summed volume %.15g, expected %.15g (rel. diff %.3g)"
                            % (step_label, volume, args.volume, abs(volume - args.volume) / abs(args.volume)))
        if args.area is not None and not close(area, args.area, args.rtol):
            failures.append("%s: summed area %.15g, expected %.15g" % (step_label, area, args.area))

    if failures:
        for f in failures:
            print("FAIL: " + f)
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
