#!/usr/bin/env pvpython
"""Render a hencky result to a PNG with ParaView, headless.

    pvpython scripts/render.py RESULT.pvd|RESULT.vtu|RESULT.pvtu OUT.png --field von_mises
        [--component N] [--warp displacement --scale S] [--camera iso|x|y|z]
        [--title TEXT] [--units TEXT] [--size 1200x800] [--edges] [--range MIN MAX]
        [--time T] [--colormap NAME] [--no-colorbar] [--crop XMIN XMAX YMIN YMAX ZMIN ZMAX]

Shows the last time step (or --time T) as a surface coloured by the point or cell array
--field (its magnitude if it has several components, unless --component N), on a white
background with a colour bar titled with the field name (and --units). With --warp the shape
is deformed by that point vector array (Warp By Vector, times --scale). With --crop only the
cells of the (deformed) body that lie entirely inside the box are shown, and the camera frames
them.

Debian's ParaView renders through X only (--force-offscreen-rendering crashes without a
display), so without $DISPLAY the script runs itself again under `xvfb-run` (package xvfb);
equivalently: xvfb-run -a -s "-screen 0 1920x1080x24" pvpython scripts/render.py ...
scripts/setup-plots.sh installs ParaView (paraview, python3-paraview) and xvfb from Debian.
"""
import argparse
import math
import os
import shutil
import sys

BAR_PIXELS = 110  # height kept free at the bottom for the colour bar and its labels
TITLE_PIXELS = 50  # and at the top for the title


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
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
    """No X display: run this script again under xvfb-run (ParaView on Debian needs X)."""
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
    sys.stdout.flush()
    os.execvpe(xvfb, [xvfb, "-a", "-s", screen, pv, os.path.abspath(sys.argv[0])] + sys.argv[1:], env)


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

    if args.crop:
        lo, hi = args.crop[0::2], args.crop[1::2]
        # Whole cells (those entirely inside the box), so that --edges shows the mesh.
        crop = simple.ExtractCellsByRegion(Input=source)
        crop.IntersectWith = "Box"
        crop.IntersectWith.UseReferenceBounds = 0
        crop.IntersectWith.Position = lo
        crop.IntersectWith.Length = [h - l for l, h in zip(lo, hi)]
        crop.ExtractionSide = "inside"
        crop.Extractintersected = 0
        source = crop
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
            title += " component %d" % args.component if args.component is not None else " magnitude"
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
        args.field, "" if n_comp == 1 else
        (" component %d" % args.component if args.component is not None else " magnitude")))
    return 0


if __name__ == "__main__":
    # No sys.exit() on success: raising SystemExit while the render window is alive makes
    # ParaView 5.11 fail with "X Error ... GLXBadContext" at exit (status 1).
    status = main()
    if status:
        sys.exit(status)
