#!/usr/bin/env pvpython
"""Render a hencky result to a PNG with ParaView, headless.

    pvpython scripts/render.py RESULT.pvd|RESULT.vtu OUT.png --field von_mises
        [--component N] [--warp displacement --scale S] [--camera iso|x|y|z]
        [--title TEXT] [--units TEXT] [--size 1200x800] [--edges] [--range MIN MAX]
        [--time T] [--colormap NAME] [--no-colorbar]

Shows the last time step (or --time T) as a surface coloured by the point or cell array
--field (its magnitude if it has several components, unless --component N), on a white
background with a colour bar titled with the field name (and --units). With --warp the shape
is deformed by that point vector array (Warp By Vector, times --scale).

Debian's ParaView renders through X only (--force-offscreen-rendering crashes without a
display), so without $DISPLAY the script runs itself again under `xvfb-run` (package xvfb);
equivalently: xvfb-run -a -s "-screen 0 1920x1080x24" pvpython scripts/render.py ...
"""
import argparse
import os
import shutil
import sys


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("result", help=".pvd or .vtu")
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
    args = p.parse_args()
    try:
        w, h = args.size.lower().split("x")
        args.size = [int(w), int(h)]
        if args.size[0] <= 0 or args.size[1] <= 0:
            raise ValueError
    except ValueError:
        p.error("--size must be WxH, e.g. 1200x800")
    return args


def rerun_under_xvfb(args):
    """No X display: run this script again under xvfb-run (ParaView on Debian needs X)."""
    if os.environ.get("DISPLAY") or os.environ.get("HENCKY_RENDER_IN_XVFB"):
        return
    xvfb = shutil.which("xvfb-run")
    pv = shutil.which("pvpython") or shutil.which("pvbatch")
    if not xvfb or not pv:
        print("error: no X display and no xvfb-run (apt-get install xvfb) to make one",
              file=sys.stderr)
        sys.exit(1)
    screen = "-screen 0 %dx%dx24" % (max(args.size[0], 640), max(args.size[1], 480))
    env = dict(os.environ, HENCKY_RENDER_IN_XVFB="1")
    sys.stdout.flush()
    os.execvpe(xvfb, [xvfb, "-a", "-s", screen, pv, os.path.abspath(sys.argv[0])] + sys.argv[1:], env)


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
        bar.WindowLocation = "Any Location"
        bar.Orientation = "Vertical"
        bar.Position = [0.89, 0.12]
        bar.ScalarBarLength = 0.7

    if args.title:
        text = simple.Text(Text=args.title)
        td = simple.Show(text, view)
        td.WindowLocation = "Upper Center"
        td.FontSize = 22
        td.Color = [0.0, 0.0, 0.0]

    # Camera: look at the (deformed) body along the chosen direction, then fit.
    directions = {"iso": ((1.0, 1.0, 1.0), (0.0, 0.0, 1.0)),
                  "x": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
                  "y": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
                  "z": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))}
    d, up = directions[args.camera]
    b = source.GetDataInformation().GetBounds()
    c = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
    view.CameraFocalPoint = c
    view.CameraPosition = [c[k] + d[k] for k in range(3)]
    view.CameraViewUp = list(up)
    view.CameraParallelProjection = 0
    view.ResetCamera()
    if args.camera == "iso":
        simple.GetActiveCamera().Dolly(1.15)  # the bounding sphere is loose along a diagonal

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
