"""Render one frame of an lsalepm XDMF time series to a PNG, headless.

Run under pvbatch with a virtual X server (tools/render_frame.sh does this):

    xvfb-run -a pvbatch tools/render_frame.py out/sedov3d/sedov3d.xdmf \
        --field density --time last --out frame.png

The outer surface of the (curvilinear, possibly distorted) grid is coloured by
a cell field, with the cell edges drawn thinly so the Lagrangian mesh motion
shows, the bounding box outlined, a colour bar and the frame time. The camera
looks from an oblique direction, z up; the default looks from the low x and
y side and from above, so the two vertical faces through the lowest corner
(the symmetry planes of an octant run) face the camera.
"""

import argparse
import os
import sys

try:
    from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction,
                                 GetScalarBar, Outline, Render, SaveScreenshot,
                                 Show, Text, Xdmf3ReaderS)
except ImportError as e:
    sys.exit("render_frame: ParaView's Python modules are missing (%s); "
             "run tools/install-deps.sh --viz and start this with pvbatch "
             "(tools/render_frame.sh)" % e)


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="render_frame.py",
        description="Render one frame of an XDMF time series to a PNG (pvbatch).")
    p.add_argument("xdmf", help="the run's .xdmf file (e.g. out/sedov3d/sedov3d.xdmf)")
    p.add_argument("--field", default="density",
                   help="cell field to colour by (a point field also works; "
                        "vectors are shown by magnitude), default density")
    p.add_argument("--time", default="last",
                   help="frame index (0-based, negative counts from the end) "
                        "or 'last', default last")
    p.add_argument("--out", default="frame.png", help="PNG to write, default frame.png")
    p.add_argument("--size", default="1200x900", help="image size WxH, default 1200x900")
    p.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"),
                   help="colour range, default the field's range in this frame")
    p.add_argument("--view-from", nargs=3, type=float, default=(-1.0, -1.35, 0.8),
                   metavar=("DX", "DY", "DZ"),
                   help="direction from the grid centre to the camera, "
                        "default -1 -1.35 0.8 (from the low x and y side, above)")
    p.add_argument("--no-edges", action="store_true", help="do not draw the cell edges")
    return p.parse_args(argv)


def fail(msg):
    print("render_frame: " + msg, file=sys.stderr)
    sys.exit(1)


def pick_time(times, spec):
    if not times:
        return 0, None  # a single grid, no time series
    if spec == "last":
        return len(times) - 1, times[-1]
    try:
        i = int(spec)
    except ValueError:
        fail("--time must be an integer index or 'last', got %r" % spec)
    if not -len(times) <= i < len(times):
        fail("--time %d out of range: the series has %d frames (0..%d)"
             % (i, len(times), len(times) - 1))
    return i % len(times), times[i]


def find_field(reader, name):
    """Return ('CELLS'|'POINTS', array info) for the field, cell data first."""
    if name in reader.CellData.keys():
        return "CELLS", reader.CellData[name]
    if name in reader.PointData.keys():
        return "POINTS", reader.PointData[name]
    fail("no field %r; cell fields: %s; point fields: %s"
         % (name, ", ".join(reader.CellData.keys()) or "none",
            ", ".join(reader.PointData.keys()) or "none"))


def main(argv):
    args = parse_args(argv)
    try:
        width, height = (int(s) for s in args.size.lower().split("x"))
    except ValueError:
        fail("--size must look like 1200x900, got %r" % args.size)

    path = os.path.abspath(args.xdmf)  # the XDMF3 reader wants an absolute path
    if not os.path.isfile(path):
        fail("no such file: %s" % path)
    out = os.path.abspath(args.out)

    reader = Xdmf3ReaderS(FileName=[path])
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues or [])
    index, t = pick_time(times, args.time)
    reader.UpdatePipeline(t if t is not None else 0.0)

    assoc, info = find_field(reader, args.field)
    ncomp = info.GetNumberOfComponents()
    lo, hi = info.GetRange(-1 if ncomp > 1 else 0)
    if args.range:
        lo, hi = args.range
    if hi <= lo:
        hi = lo + max(abs(lo), 1.0) * 1e-6  # a uniform field still gets a bar

    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 1
    view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    if t is not None:
        view.ViewTime = t

    surf = Show(reader, view)
    surf.Representation = "Surface" if args.no_edges else "Surface With Edges"
    surf.EdgeColor = [0.25, 0.25, 0.25]
    surf.LineWidth = 0.5
    ColorBy(surf, (assoc, args.field, "Magnitude") if ncomp > 1 else (assoc, args.field))

    lut = GetColorTransferFunction(args.field)
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(lo, hi)
    if ncomp > 1:
        lut.VectorMode = "Magnitude"

    bar = GetScalarBar(lut, view)
    bar.Title = args.field + (" (magnitude)" if ncomp > 1 else "")
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.TitleFontSize = 18
    bar.LabelFontSize = 16
    bar.RangeLabelFormat = "%-#.3g"
    bar.ScalarBarLength = 0.5
    bar.WindowLocation = "Any Location"
    bar.Position = [0.88, 0.25]
    bar.Visibility = 1

    box = Show(Outline(Input=reader), view)
    box.DiffuseColor = box.AmbientColor = [0.0, 0.0, 0.0]
    box.LineWidth = 1.5

    label = "%s   %s" % (os.path.basename(path), args.field)
    if t is not None:
        label += "   frame %d of %d, t = %.6g" % (index, len(times) - 1, t)
    text = Show(Text(Text=label), view)
    text.Color = [0.0, 0.0, 0.0]
    text.FontSize = 18
    text.WindowLocation = "Upper Left Corner"

    # Oblique camera: along --view-from from the centre of the grid, z up
    # (or y up when looking along z), then fitted to the data.
    b = reader.GetDataInformation().GetBounds()
    centre = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
    d = list(args.view_from)
    norm = sum(c * c for c in d) ** 0.5
    if norm == 0.0:
        fail("--view-from must not be the zero vector")
    d = [c / norm for c in d]
    diag = max(((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2) ** 0.5, 1e-30)
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[i] + 3.0 * diag * d[i] for i in range(3)]
    view.CameraViewUp = [0.0, 1.0, 0.0] if abs(d[2]) > 0.99 else [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    view.CameraParallelProjection = 0

    Render(view)
    SaveScreenshot(out, view, ImageResolution=[width, height], TransparentBackground=0)
    print("render_frame: wrote %s (%s, frame %d, t = %s, range %.6g .. %.6g)"
          % (out, args.field, index, "n/a" if t is None else "%.6g" % t, lo, hi))


if __name__ == "__main__":
    main(sys.argv[1:])
