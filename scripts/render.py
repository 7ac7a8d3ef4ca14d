#!/usr/bin/env pvpython
"""Render a hencky result to a PNG with ParaView, headless.

    pvpython scripts/render.py RESULT.pvd|RESULT.vtu|RESULT.pvtu OUT.png --field von_mises
        [--component N] [--warp displacement --scale S] [--camera iso|x|y|z]
        [--title TEXT] [--units TEXT] [--size 1200x800] [--edges] [--range MIN MAX]
        [--time T] [--colormap NAME] [--no-colorbar] [--crop XMIN XMAX YMIN YMAX ZMIN ZMAX]
        [--outline] [--no-surfaces]

Shows the last time step (or --time T) as a surface coloured by the point or cell array
--field (its magnitude if it has several components, unless --component N), on a white
background with a colour bar titled with the field name (and --units). With --warp the shape
is deformed by that point vector array (Warp By Vector, times --scale). With --crop only the
part of the (deformed) body inside the box is shown, and the camera frames it: the body is cut
along the box, or with --edges, the cells that lie entirely inside it are shown whole (so that
the edges are the mesh's). With --outline (and --warp) the undeformed body's edges are drawn
in grey over the deformed shape.

The rigid surfaces of the case's `contact` (plane, sphere, cylinder, STL body) are drawn in
grey where they are at the shown time: their shape from the result's summary.json, their
translation from its history.csv (columns contact.<name>.motion.x|y|z), times --scale with
--warp, so that a surface touches the body where it does in the run. Each is cut to the
shown body's box, widened only towards the side where the surface lies (a ball above a quarter
block is drawn as the quarter over it). --no-surfaces leaves them out.

Debian's ParaView renders through X only (--force-offscreen-rendering crashes without a
display), so without $DISPLAY the script runs itself again under `xvfb-run` (package xvfb);
equivalently: xvfb-run -a -s "-screen 0 1920x1080x24" pvpython scripts/render.py ...
scripts/setup-plots.sh installs ParaView (paraview, python3-paraview) and xvfb from Debian.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import time

BAR_PIXELS = 110  # height kept free at the bottom for the colour bar and its labels
TITLE_PIXELS = 50  # and at the top for the title


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    # "-5e-4" is a number, not an option: argparse's own test takes only plain decimals as
    # negative numbers, so that --crop 0 1 -5e-4 ... stopped with "expected 6 arguments".
    p._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
    p.add_argument("result", help=".pvd, .vtu or .pvtu (a run on several MPI ranks)")
    p.add_argument("out", help="PNG file to write")
    p.add_argument("--field", default="von_mises", help="array to colour by (default von_mises)")
    p.add_argument("--component", type=int, default=None, metavar="N",
                   help="component of a multi-component array (default: magnitude)")
    p.add_argument("--warp", metavar="VECTOR", help="point vector array to deform by, e.g. displacement")
    p.add_argument("--scale", type=float, default=1.0, help="warp scale factor (default 1)")
    p.add_argument("--camera", choices=["iso", "x", "y", "z"], default="iso")
    p.add_argument("--title", help="text at the top of the image")
    p.add_argument("--units", help="units shown in the colour bar title, e.g. MPa")
    p.add_argument("--size", default="1200x800", help="image size WxH (default 1200x800)")
    p.add_argument("--edges", action="store_true", help="draw the cell edges")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"),
                   help="colour range (default: data range at the time shown)")
    p.add_argument("--time", type=float, help="time step to show (default: the last one)")
    p.add_argument("--colormap", default="Turbo", help="ParaView colour map preset (default Turbo)")
    p.add_argument("--no-colorbar", action="store_true", help="no colour bar")
    p.add_argument("--outline", action="store_true",
                   help="with --warp: draw the undeformed body's edges in grey")
    p.add_argument("--no-surfaces", action="store_true",
                   help="do not draw the rigid contact surfaces")
    p.add_argument("--crop", type=float, nargs=6,
                   metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"),
                   help="show only the cells entirely inside this box (coordinates of the shown shape)")
    args = p.parse_args()
    try:
        w, h = args.size.lower().split("x")
        args.size = [int(w), int(h)]
        if args.size[0] <= 0 or args.size[1] <= 0:
            raise ValueError
    except ValueError:
        p.error("--size must be WxH, e.g. 1200x800")
    if args.crop and any(args.crop[2 * k] >= args.crop[2 * k + 1] for k in range(3)):
        p.error("--crop needs XMIN < XMAX, YMIN < YMAX and ZMIN < ZMAX")
    return args


def rerun_under_xvfb(args):
    """No X display: run this script again under xvfb-run (ParaView on Debian needs X), and
    exit with its status.

    One run in five or so, back to back, ParaView aborts at once with "bad X server connection"
    on the display xvfb-run has just made (Xvfb 21 and xvfb-run of Debian 12: the display a
    finished run left is taken again before it is gone). This was the "--crop with --edges
    crash": it has nothing to do with the options. Such a run is started again, up to 4 times.
    """
    if os.environ.get("DISPLAY") or os.environ.get("HENCKY_RENDER_IN_XVFB"):
        return
    xvfb = shutil.which("xvfb-run")
    pv = shutil.which("pvpython") or shutil.which("pvbatch")
    if not xvfb or not pv:
        print("error: no X display and no xvfb-run to make one (scripts/setup-plots.sh installs it)",
              file=sys.stderr)
        sys.exit(1)
    screen = "-screen 0 %dx%dx24" % (max(args.size[0], 640), max(args.size[1], 480))
    env = dict(os.environ, HENCKY_RENDER_IN_XVFB="1")
    command = [xvfb, "-a", "-s", screen, pv, os.path.abspath(sys.argv[0])] + sys.argv[1:]
    sys.stdout.flush()
    for attempt in range(4):
        run = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, errors="replace")
        if run.returncode == 0 or "bad X server connection" not in run.stderr:
            break
        time.sleep(0.5 * (attempt + 1))
    sys.stdout.write(run.stdout)
    sys.stderr.write(run.stderr)
    sys.exit(run.returncode)


def screen_frame(direction, up):
    """Unit vectors: towards the camera, screen up, screen right."""
    def unit(v):
        n = math.sqrt(sum(x * x for x in v)) or 1.0
        return [x / n for x in v]

    d = unit(direction)
    along = sum(a * b for a, b in zip(up, d))
    u = unit([up[k] - along * d[k] for k in range(3)])
    r = [u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2], u[0] * d[1] - u[1] * d[0]]
    return d, u, r


def screen_extents(source, r, u, bounds, t):
    """Ranges of x.r and x.u over the points of source (exact, computed by ParaView in one
    pass); the bounding box corners if that fails."""
    try:
        from paraview import simple
        if source is None:
            raise ValueError("no source: the box's corners")
        calc = simple.Calculator(Input=source)
        calc.AttributeType = "Point Data"
        calc.ResultArrayName = "hencky_screen_xy"
        calc.Function = ("(coordsX*%.17g+coordsY*%.17g+coordsZ*%.17g)*iHat+"
                         "(coordsX*%.17g+coordsY*%.17g+coordsZ*%.17g)*jHat"
                         % (r[0], r[1], r[2], u[0], u[1], u[2]))
        calc.UpdatePipeline(t) if t is not None else calc.UpdatePipeline()
        a = calc.GetDataInformation().GetPointDataInformation().GetArrayInformation(
            "hencky_screen_xy")
        xr, yr = a.GetComponentRange(0), a.GetComponentRange(1)
        simple.Delete(calc)
        if xr[0] <= xr[1] and yr[0] <= yr[1]:
            return xr, yr
    except Exception:  # noqa: BLE001 -- fall back to the bounding box
        pass
    xs, ys = [], []
    for i in range(8):
        p = [bounds[0 + (i & 1)], bounds[2 + ((i >> 1) & 1)], bounds[4 + ((i >> 2) & 1)]]
        xs.append(sum(a * b for a, b in zip(p, r)))
        ys.append(sum(a * b for a, b in zip(p, u)))
    return (min(xs), max(xs)), (min(ys), max(ys))


def fit_camera(bounds, xr, yr, d, u, r, size, bottom, top, margin=0.06):
    """Focal point, position and parallel scale of a camera looking along -d with u up that
    shows the points (screen coordinates x.r in xr, x.u in yr) inside the image of `size`
    pixels less `bottom` and `top` pixel bands, with a relative margin."""
    w, h = float(size[0]), float(size[1])
    avail_w = w * (1 - 2 * margin)
    avail_h = max(h - bottom - top, 0.2 * h) * (1 - 2 * margin)
    per_pixel = max((xr[1] - xr[0]) / avail_w, (yr[1] - yr[0]) / avail_h)
    if per_pixel <= 0:
        per_pixel = 1.0 / h
    # The middle of the points goes to the middle of the free band, `lift` pixels above the
    # image centre.
    lift = (bottom + 0.5 * (h - bottom - top)) - 0.5 * h
    xc, yc = 0.5 * (xr[0] + xr[1]), 0.5 * (yr[0] + yr[1])
    c = [0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
         0.5 * (bounds[4] + bounds[5])]
    depth = sum(a * b for a, b in zip(c, d))
    focal = [xc * r[k] + (yc - lift * per_pixel) * u[k] + depth * d[k] for k in range(3)]
    diag = math.sqrt((bounds[1] - bounds[0]) ** 2 + (bounds[3] - bounds[2]) ** 2 +
                     (bounds[5] - bounds[4]) ** 2) or 1.0
    position = [focal[k] + 2.0 * diag * d[k] for k in range(3)]
    return focal, position, 0.5 * h * per_pixel


def read_surfaces(result, t, scale=1.0):
    """[(name, description, motion)] of the run's rigid contact surfaces at time t: the
    description from summary.json beside the result, the translation from the history.csv row
    nearest t (zero when the run is older than those columns), times `scale`."""
    import csv
    import json
    folder = os.path.dirname(os.path.abspath(result))
    try:
        with open(os.path.join(folder, "summary.json")) as f:
            contact = json.load(f).get("contact", {})
    except (OSError, ValueError):
        return []
    rows = []
    try:
        with open(os.path.join(folder, "history.csv")) as f:
            rows = list(csv.DictReader(f))
    except OSError:
        pass
    row = min(rows, key=lambda r: abs(float(r["time"]) - (t or 0.0))) if rows else {}
    out = []
    for name, c in sorted(contact.items()):
        if "surface" not in c:
            continue
        motion = [scale * float(row.get("contact.%s.motion.%s" % (name, ax), 0.0) or 0.0)
                  for ax in "xyz"]
        out.append((name, c["surface"], motion))
    return out


def unit(v):
    n = math.sqrt(sum(x * x for x in v)) or 1.0
    return [x / n for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def placed(simple, source, e1, e2, e3, origin):
    """`source` moved rigidly: its x, y and z axes onto e1, e2 and e3, its origin to `origin`."""
    moved = simple.Calculator(Input=source)
    moved.CoordinateResults = 1
    moved.Function = "+".join(
        "(%.17g*coordsX+%.17g*coordsY+%.17g*coordsZ+%.17g)*%s" % (e1[k], e2[k], e3[k], origin[k],
                                                                 hat)
        for k, hat in enumerate(("iHat", "jHat", "kHat")))
    return moved


def sphere_section(simple, desc, motion, plane_point, plane_normal):
    """The sphere's section by a plane (a filled disk), or None when the plane misses it."""
    c = [desc["center"][k] + motion[k] for k in range(3)]
    n = unit(plane_normal)
    dist = sum((plane_point[k] - c[k]) * n[k] for k in range(3))
    if abs(dist) >= desc["radius"]:
        return None
    disk = simple.Disk(InnerRadius=0.0, OuterRadius=math.sqrt(desc["radius"] ** 2 - dist ** 2),
                       CircumferentialResolution=720, RadialResolution=1)
    e1 = unit(cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]))
    return placed(simple, disk, e1, cross(n, e1), n, [c[k] + dist * n[k] for k in range(3)])


def surface_source(simple, desc, motion, bounds):
    """A ParaView source of the rigid surface `desc` moved by `motion`, and its centre: the
    sphere's centre, the cylinder's axis point nearest the body, the plane's point under the
    body's centre, the STL body's box centre. Planes and cylinders are drawn as large as the
    body's box."""
    centre_body = [0.5 * (bounds[2 * k] + bounds[2 * k + 1]) for k in range(3)]
    diag = math.sqrt(sum((bounds[2 * k + 1] - bounds[2 * k]) ** 2 for k in range(3))) or 1.0
    shape = desc["shape"]
    if shape == "sphere":
        # The cap that faces the body, finely divided: a whole sphere's facets (2 degrees)
        # would be larger than a close-up of its contact.
        c = [desc["center"][k] + motion[k] for k in range(3)]
        radius = desc["radius"]
        towards = [centre_body[k] - c[k] for k in range(3)]
        if math.sqrt(sum(x * x for x in towards)) < 1e-12 * radius:
            towards = [0.0, 0.0, -1.0]
        axis = unit(towards)
        # The angle, seen from the centre, within which the body's box lies (generously).
        half = math.degrees(math.atan2(1.5 * diag, math.sqrt(sum(x * x for x in towards))))
        half = min(180.0, max(2.0 * half, 1.0))
        cap = simple.Sphere(Center=[0, 0, 0], Radius=radius, ThetaResolution=360,
                            PhiResolution=400, StartPhi=180.0 - half, EndPhi=180.0)
        # The cap's pole (-z) onto `axis`, its centre to c.
        e1 = unit(cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0]))
        return placed(simple, cap, e1, cross(e1, axis), [-x for x in axis], c), c
    if shape == "plane":
        n = unit(desc["normal"])
        p0 = [desc["point"][k] + motion[k] for k in range(3)]
        along = sum((centre_body[k] - p0[k]) * n[k] for k in range(3))
        c = [centre_body[k] - along * n[k] for k in range(3)]
        helper = [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]
        e1 = unit(cross(n, helper))
        e2 = cross(n, e1)
        origin = [c[k] - diag * (e1[k] + e2[k]) for k in range(3)]
        return simple.Plane(Origin=origin, Point1=[origin[k] + 2 * diag * e1[k] for k in range(3)],
                            Point2=[origin[k] + 2 * diag * e2[k] for k in range(3)],
                            XResolution=1, YResolution=1), c
    if shape == "cylinder":
        a = unit(desc["axis"])
        p0 = [desc["point"][k] + motion[k] for k in range(3)]
        along = sum((centre_body[k] - p0[k]) * a[k] for k in range(3))
        c = [p0[k] + along * a[k] for k in range(3)]
        line = simple.Line(Point1=[c[k] - diag * a[k] for k in range(3)],
                           Point2=[c[k] + diag * a[k] for k in range(3)], Resolution=1)
        return simple.Tube(Input=line, Radius=desc["radius"], NumberofSides=1440, Capping=0), c
    reader = simple.STLReader(FileNames=[desc["file"]])
    moved = simple.Transform(Input=reader)
    moved.Transform.Scale = [desc.get("scale", 1.0)] * 3
    moved.Transform.Translate = motion
    moved.UpdatePipeline()
    b = moved.GetDataInformation().GetBounds()
    return moved, [0.5 * (b[2 * k] + b[2 * k + 1]) for k in range(3)]


def box_cut(simple, source, lo, hi):
    """What of `source` lies inside the box lo..hi, cut along the box's faces (six exact plane
    cuts: ParaView's implicit box left jagged pieces of quadratic cells)."""
    clip = simple.Clip(Input=source)
    clip.ClipType = "Box"
    clip.ClipType.UseReferenceBounds = 0
    clip.ClipType.Position = list(lo)
    clip.ClipType.Length = [h - l for l, h in zip(lo, hi)]
    clip.Invert = 1  # keep what is inside
    clip.Exact = 1
    return clip


def grown(bounds, source):
    """`bounds` (None: empty) grown by the box of what `source` holds."""
    source.UpdatePipeline()
    if source.GetDataInformation().GetNumberOfPoints() == 0:
        return bounds
    b = source.GetDataInformation().GetBounds()
    if bounds is None:
        return list(b)
    return [min(bounds[i], b[i]) if i % 2 == 0 else max(bounds[i], b[i]) for i in range(6)]


def show_surfaces(simple, view, surfaces, bounds, section=None, crop=None):
    """Draws each rigid surface in grey, cut to the body's box `bounds` widened (per axis)
    towards the surface where its centre lies beyond the box. `section`: (point, normal) of the
    plane of a cut the camera looks at: a sphere's section there is drawn filled. Nothing is
    drawn outside `crop` (XMIN XMAX YMIN YMAX ZMIN ZMAX) when it is given. Returns the
    bounds of what was drawn (None when nothing was)."""
    drawn = None
    diag = math.sqrt(sum((bounds[2 * k + 1] - bounds[2 * k]) ** 2 for k in range(3))) or 1.0
    margin = 1e-3 * diag
    for name, desc, motion in surfaces:
        try:
            src, c = surface_source(simple, desc, motion, bounds)
        except Exception as e:  # noqa: BLE001 -- a surface that cannot be drawn is left out
            print("warning: rigid surface '%s' not drawn: %s" % (name, e), file=sys.stderr)
            continue
        src.UpdatePipeline()
        sb = src.GetDataInformation().GetBounds()
        lo = [bounds[2 * k] - margin for k in range(3)]
        hi = [bounds[2 * k + 1] + margin for k in range(3)]
        for k in range(3):
            # Towards the surface: to its end but at most the body's size further (a large
            # roller under a small part), or with --crop to the crop box's side.
            if c[k] > bounds[2 * k + 1]:
                hi[k] = crop[2 * k + 1] if crop else max(
                    hi[k], min(sb[2 * k + 1] + margin, bounds[2 * k + 1] + diag))
            if c[k] < bounds[2 * k]:
                lo[k] = crop[2 * k] if crop else min(
                    lo[k], max(sb[2 * k] - margin, bounds[2 * k] - diag))
            if crop:
                lo[k], hi[k] = max(lo[k], crop[2 * k]), min(hi[k], crop[2 * k + 1])
        if any(lo[k] >= hi[k] for k in range(3)):
            continue
        clip = box_cut(simple, src, lo, hi)
        drawn = grown(drawn, clip)
        d = simple.Show(clip, view)
        d.SetRepresentationType("Surface")
        d.ColorArrayName = ['POINTS', '']
        d.AmbientColor = d.DiffuseColor = [0.62, 0.63, 0.66]
        d.Opacity = 0.55
        # Where the box cuts the surface: in a view along an axis of a cut body this is the
        # surface's profile in the cut (a ball's arc over its dent).
        cut = simple.FeatureEdges(Input=simple.ExtractSurface(Input=clip))
        cut.BoundaryEdges = 1
        cut.FeatureEdges = 0
        cut.NonManifoldEdges = 0
        cut.ManifoldEdges = 0
        e = simple.Show(cut, view)
        e.ColorArrayName = ['POINTS', '']
        e.AmbientColor = e.DiffuseColor = [0.25, 0.25, 0.3]
        e.LineWidth = 2.5
        if section and desc["shape"] == "sphere":
            disk = sphere_section(simple, desc, motion, *section)
            if disk is not None:
                # The disk lies on a face of the box: the box is widened across it.
                across = [margin if abs(section[1][k]) > 0.5 else 0.0 for k in range(3)]
                inside = box_cut(simple, disk, [lo[k] - across[k] for k in range(3)],
                                 [hi[k] + across[k] for k in range(3)])
                drawn = grown(drawn, inside)
                f = simple.Show(inside, view)
                f.ColorArrayName = ['POINTS', '']
                f.AmbientColor = f.DiffuseColor = [0.62, 0.63, 0.66]
    return drawn


def show_outline(simple, view, undeformed, crop=None):
    """The undeformed body's edges (the feature edges of its surface) in grey, cut to `crop`.
    The edges are taken before the cut: a cut's facets would add edges of their own."""
    edges = simple.FeatureEdges(Input=simple.ExtractSurface(Input=undeformed))
    edges.FeatureAngle = 30.0
    edges.BoundaryEdges = 0
    edges.NonManifoldEdges = 0
    edges.ManifoldEdges = 0
    if crop:
        # Widened a little: the edges on the box's faces (a cut on a symmetry plane) stay.
        m = 1e-3 * math.sqrt(sum((crop[2 * k + 1] - crop[2 * k]) ** 2 for k in range(3)))
        lo, hi = [v - m for v in crop[0::2]], [v + m for v in crop[1::2]]
        edges = box_cut(simple, edges, lo, hi)
    d = simple.Show(edges, view)
    d.ColorArrayName = ['POINTS', '']
    d.AmbientColor = d.DiffuseColor = [0.35, 0.35, 0.35]
    d.LineWidth = 1.5


def component_name(n_comp, component):
    """The name of a component of hencky's arrays: x, y, z of a vector, xx, yy, zz, xy, yz, xz
    of a symmetric tensor (the order the fields files write), or the magnitude."""
    if component is None:
        return "magnitude"
    names = {3: ["x", "y", "z"], 6: ["xx", "yy", "zz", "xy", "yz", "xz"]}.get(n_comp)
    return names[component] if names else "component %d" % component


def find_array(source, name):
    """('POINTS'|'CELLS', number of components) of the array, or None."""
    info = source.GetDataInformation()
    for assoc, data in (("POINTS", info.GetPointDataInformation()),
                        ("CELLS", info.GetCellDataInformation())):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArrayInformation(i)
            if a.GetName() == name:
                return assoc, a.GetNumberOfComponents()
    return None


def array_names(source):
    info = source.GetDataInformation()
    names = []
    for data in (info.GetPointDataInformation(), info.GetCellDataInformation()):
        for i in range(data.GetNumberOfArrays()):
            names.append(data.GetArrayInformation(i).GetName())
    return names


def main():
    args = parse_args()
    rerun_under_xvfb(args)

    from paraview import simple

    if not os.path.exists(args.result):
        print("error: no such file: %s" % args.result, file=sys.stderr)
        return 1
    reader = simple.OpenDataFile(args.result)
    if reader is None:
        print("error: ParaView cannot read %s" % args.result, file=sys.stderr)
        return 1

    tv = reader.TimestepValues if hasattr(reader, "TimestepValues") else None
    times = [float(tv)] if isinstance(tv, (int, float)) else list(tv or [])
    t = args.time if args.time is not None else (times[-1] if times else None)

    source = reader
    source.UpdatePipeline(t) if t is not None else source.UpdatePipeline()
    if args.warp:
        found = find_array(reader, args.warp)
        if found is None or found[0] != "POINTS" or found[1] != 3:
            print("error: --warp needs a 3-component point array; '%s' is %s (arrays: %s)"
                  % (args.warp, "missing" if found is None else "%s with %d component(s)" % found,
                     ", ".join(array_names(reader))), file=sys.stderr)
            return 1
        source = simple.WarpByVector(Input=reader)
        source.Vectors = ["POINTS", args.warp]
        source.ScaleFactor = args.scale
        source.UpdatePipeline(t) if t is not None else source.UpdatePipeline()

    def cropped(what):
        """`what` cut to the --crop box; with --edges the cells entirely inside it instead
        (whole cells, so that the edges are the mesh's)."""
        lo, hi = args.crop[0::2], args.crop[1::2]
        if not args.edges:
            return box_cut(simple, what, lo, hi)
        crop = simple.ExtractCellsByRegion(Input=what)
        crop.IntersectWith = "Box"
        crop.IntersectWith.UseReferenceBounds = 0
        crop.IntersectWith.Position = lo
        crop.IntersectWith.Length = [h - l for l, h in zip(lo, hi)]
        crop.ExtractionSide = "inside"
        crop.Extractintersected = 0
        return crop

    if args.crop:
        source = cropped(source)
        source.UpdatePipeline(t) if t is not None else source.UpdatePipeline()
        if source.GetDataInformation().GetNumberOfCells() == 0:
            print("error: nothing of the body lies inside --crop %s" % " ".join("%g" % v for v in args.crop),
                  file=sys.stderr)
            return 1

    found = find_array(source, args.field)
    if found is None:
        print("error: no array '%s' in %s (arrays: %s)"
              % (args.field, args.result, ", ".join(array_names(source))), file=sys.stderr)
        return 1
    assoc, n_comp = found
    if args.component is not None and not 0 <= args.component < n_comp:
        print("error: '%s' has %d component(s), no component %d"
              % (args.field, n_comp, args.component), file=sys.stderr)
        return 1

    # The view only now: after an error above, the X window's teardown would add noise.
    view = simple.CreateView("RenderView")
    view.ViewSize = args.size
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 1
    if hasattr(view, "OrientationAxesLabelColor"):
        view.OrientationAxesLabelColor = [0.0, 0.0, 0.0]
    if t is not None:
        view.ViewTime = t
        scene = simple.GetAnimationScene()
        scene.UpdateAnimationUsingDataTimeSteps()
        scene.AnimationTime = t

    display = simple.Show(source, view)
    display.SetRepresentationType("Surface With Edges" if args.edges else "Surface")
    surfaces_bounds = None
    if args.outline and args.warp:
        show_outline(simple, view, reader, args.crop)
    if not args.no_surfaces:
        # With --warp the displacements are drawn --scale times: so are the motions.
        body = source.GetDataInformation().GetBounds()
        section = None
        if args.crop and args.camera != "iso":
            # The cut the camera looks at: the crop box's face towards it.
            axis = "xyz".index(args.camera)
            towards = 1.0 if args.camera != "y" else -1.0  # the cameras of `directions` below
            normal = [towards if k == axis else 0.0 for k in range(3)]
            point = [0.5 * (body[2 * k] + body[2 * k + 1]) for k in range(3)]
            point[axis] = args.crop[2 * axis + (1 if towards > 0 else 0)]
            section = (point, normal)
        drawn = show_surfaces(simple, view,
                              read_surfaces(args.result, t, args.scale if args.warp else 1.0),
                              body, section, args.crop)
        if drawn is not None and all(drawn[2 * k] <= drawn[2 * k + 1] for k in range(3)):
            surfaces_bounds = drawn
    if args.edges:
        display.EdgeColor = [0.15, 0.15, 0.15]
    simple.ColorBy(display, (assoc, args.field))
    lut = simple.GetColorTransferFunction(args.field)
    if n_comp > 1:
        if args.component is None:
            lut.VectorMode = "Magnitude"
        else:
            lut.VectorMode = "Component"
            lut.VectorComponent = args.component
    if not lut.ApplyPreset(args.colormap, True):
        print("warning: no colour map preset '%s', keeping the default" % args.colormap,
              file=sys.stderr)
    if args.range:
        lut.RescaleTransferFunction(args.range[0], args.range[1])
        simple.GetOpacityTransferFunction(args.field).RescaleTransferFunction(*args.range)
    else:
        display.RescaleTransferFunctionToDataRange(False, True)

    if args.no_colorbar:
        display.SetScalarBarVisibility(view, False)
    else:
        display.SetScalarBarVisibility(view, True)
        bar = simple.GetScalarBar(lut, view)
        # Plain text only: ParaView 5.11's colour bar title shows "[" as "(" and drops "|".
        title = args.field
        if n_comp > 1:
            title += " " + component_name(n_comp, args.component)
        if args.units:
            title += " (%s)" % args.units
        bar.Title = title
        bar.ComponentTitle = ""
        bar.TitleColor = [0.0, 0.0, 0.0]
        bar.LabelColor = [0.0, 0.0, 0.0]
        bar.TitleFontSize = 18
        bar.LabelFontSize = 16
        bar.RangeLabelFormat = "%-#.4g"
        # Horizontal, at the bottom: long titles and wide labels do not collide there.
        bar.Orientation = "Horizontal"
        bar.WindowLocation = "Lower Center"
        bar.ScalarBarLength = 0.5
        bar.ScalarBarThickness = 16

    if args.title:
        text = simple.Text(Text=args.title)
        td = simple.Show(text, view)
        td.WindowLocation = "Upper Center"
        td.FontSize = 22
        td.Color = [0.0, 0.0, 0.0]

    # Camera: parallel projection along the chosen direction, fitted so that the (deformed)
    # body's bounding box fills the image between the title and the colour bar.
    directions = {"iso": ((1.0, 1.0, 1.0), (0.0, 0.0, 1.0)),
                  "x": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
                  "y": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
                  "z": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))}
    d, u, r = screen_frame(*directions[args.camera])
    b = source.GetDataInformation().GetBounds()
    xr, yr = screen_extents(source, r, u, b, t)
    if surfaces_bounds is not None:
        # The rigid surfaces drawn (within --crop) are framed too: the corners of their box.
        sx, sy = screen_extents(None, r, u, surfaces_bounds, t)
        xr, yr = (min(xr[0], sx[0]), max(xr[1], sx[1])), (min(yr[0], sy[0]), max(yr[1], sy[1]))
        b = [min(b[i], surfaces_bounds[i]) if i % 2 == 0 else max(b[i], surfaces_bounds[i])
             for i in range(6)]
    focal, position, scale = fit_camera(b, xr, yr, d, u, r, args.size,
                                        bottom=0 if args.no_colorbar else BAR_PIXELS,
                                        top=TITLE_PIXELS if args.title else 0)
    simple.Render(view)  # the first render resets the camera: get that over with
    view.CameraParallelProjection = 1
    view.CameraFocalPoint = focal
    view.CameraPosition = position
    view.CameraViewUp = u
    view.CameraParallelScale = scale
    view.CenterOfRotation = focal

    simple.Render(view)
    simple.SaveScreenshot(args.out, view, ImageResolution=args.size, TransparentBackground=0)
    print("wrote %s (%s, t=%s, %s '%s'%s)" % (
        args.out, args.result, "-" if t is None else "%g" % t, assoc.lower()[:-1] + " array",
        args.field, "" if n_comp == 1 else " " + component_name(n_comp, args.component)))
    return 0


if __name__ == "__main__":
    # No sys.exit() on success: raising SystemExit while the render window is alive makes
    # ParaView 5.11 fail with "X Error ... GLXBadContext" at exit (status 1).
    status = main()
    if status:
        sys.exit(status)
