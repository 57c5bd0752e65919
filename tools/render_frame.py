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

A grid one cell thick in some direction (a quasi-2D or quasi-1D deck, e.g.
100 x 1 x 1 cells for Sod) is shown as a 2D slice instead: the mid-plane
across its (last) one-cell direction, seen face on with a parallel camera. A
quasi-1D strip thinner than a twentieth of its length is stretched across
for display (the label says by how much), and cell edges are left out when
cells would be narrower than 10 pixels. `--view 3d` keeps the oblique view.

A run with particles has their own series, NAME_particles.xdmf beside
NAME.xdmf: it is opened too and the frame's particles are drawn on top as
round points, coloured by a particle field (`--particle-field`, default
von_mises, computed from the stress like `pressure`; any particle point
array works) on a colour map of their own (orange to dark red, with its own
bar below the picture), which no colour of the grid's map (viridis) comes near.
On a 2D slice every particle is drawn, on the camera's side of the slice,
its point about the particles' spacing wide; in a 3D view the grid's
surface is drawn see-through (opacity 0.35, `--grid-opacity`). `--no-particles` leaves them
out.
"""

import argparse
import os
import sys
import xml.etree.ElementTree as ET

try:
    from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction,
                                 GetScalarBar, Outline, PythonCalculator, Render,
                                 SaveScreenshot, Show, Slice, Text, Xdmf3ReaderS)
except ImportError as e:
    sys.exit("render_frame: ParaView's Python modules are missing (%s); "
             "run tools/install-deps.sh and start this with pvbatch "
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
    p.add_argument("--view", choices=("auto", "3d", "2d"), default="auto",
                   help="auto (default): a 2D slice for a grid one cell thick in some "
                        "direction, else 3d (oblique, --view-from); 2d: always the slice")
    p.add_argument("--particle-field", default="von_mises",
                   help="particle field to colour the particles by (runs with particles, "
                        "NAME_particles.xdmf): von_mises or pressure (from the stress) or "
                        "any particle array (density, energy, failed, ...), default von_mises")
    p.add_argument("--particle-range", nargs=2, type=float, metavar=("MIN", "MAX"),
                   help="the particles' colour range, default their field's range in this frame")
    p.add_argument("--particle-size", type=float, metavar="PIXELS",
                   help="particle point diameter in pixels, default about their spacing")
    p.add_argument("--grid-opacity", type=float,
                   help="opacity of the grid's surface, default 1, but 0.35 in a 3D view "
                        "with particles (they are inside it)")
    p.add_argument("--no-particles", action="store_true",
                   help="draw the grid only, even when the run has particles")
    return p.parse_args(argv)


def grid_cells(path):
    """Cells (ni, nj, nk) of the first grid of the series, from the XDMF's
    3DSMesh topology (Dimensions = "nk+1 nj+1 ni+1", slowest first)."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        fail("cannot read %s: %s" % (path, e))
    for topo in root.iter("Topology"):
        dims = topo.get("Dimensions") or topo.get("NumberOfElements")
        if dims:
            nodes = [int(d) for d in dims.split()]
            if len(nodes) == 3:
                nk, nj, ni = (max(n - 1, 0) for n in nodes)
                return ni, nj, nk
    fail("%s: no 3D structured topology found" % path)


def slice_plan(cells, bounds, force=False):
    """The 2D view of a grid one cell thick in some direction: (normal axis,
    axis shown upwards, axis stretched or None, stretch factor); None for a
    3D grid (unless `force`: then the mid-plane across z). The normal is the
    last one-cell axis (z before y before x), so a quasi-1D run along x is
    seen in its x-y face. Upwards is the in-plane axis across a quasi-1D
    strip (the strip lies horizontal), else the later in-plane axis (y in an
    x-y plane, z in x-z and y-z planes)."""
    thin = [a for a in range(3) if cells[a] == 1]
    if not thin:
        if not force:
            return None
        thin = [2]
    normal = thin[-1]
    others = [a for a in range(3) if a != normal]
    ext = [bounds[2 * a + 1] - bounds[2 * a] for a in range(3)]
    stretched, stretch = None, 1.0
    if sum(1 for a in others if cells[a] == 1) == 1:
        # quasi-1D: the strip along its long axis, stretched across if thin
        long_axis = [a for a in others if cells[a] > 1][0]
        up = [a for a in others if a != long_axis][0]
        if 0.0 < ext[up] < ext[long_axis] / 20.0:
            stretched, stretch = up, (ext[long_axis] / 8.0) / ext[up]
    else:
        up = others[1]
    return normal, up, stretched, stretch


# The particles' colour map: orange to dark red, far from every colour of
# viridis (whose red never exceeds its blue by 0.2 and whose green is never
# 0.2 below its red) and from grey; tests/viz_render_particles.py counts it.
PARTICLE_RGB = [0.0, 1.0, 0.55, 0.0,
                0.5, 0.85, 0.1, 0.05,
                1.0, 0.5, 0.0, 0.1]

# Fields computed from the particles' stress (XDMF Tensor6 order xx, xy, xz,
# yy, yz, zz; tension positive): the von Mises stress and the pressure.
DERIVED = {
    "von_mises": "sqrt(0.5*((stress[:,0]-stress[:,3])**2 + (stress[:,3]-stress[:,5])**2"
                 " + (stress[:,5]-stress[:,0])**2) + 3.0*(stress[:,1]**2 + stress[:,2]**2"
                 " + stress[:,4]**2))",
    "pressure": "-(stress[:,0] + stress[:,3] + stress[:,5])/3.0",
}


def particle_series(path):
    """The particles' series beside the grid's NAME.xdmf: NAME_particles.xdmf
    if it exists, else None."""
    root, ext = os.path.splitext(path)
    cand = root + "_particles" + ext
    return cand if os.path.isfile(cand) else None


def frame_label(index, count):
    """'frame K of N' counting from 1: the last of N frames is 'N of N'."""
    return "frame %d of %d" % (index + 1, count)


def point_diameter(spacing, pixels_per_length):
    """Particle points about as wide as their spacing (0.9 of it, so that
    neighbours stay apart), 3 to 40 pixels."""
    return min(max(0.9 * spacing * pixels_per_length, 3.0), 40.0)


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

    parts = None if args.no_particles else particle_series(path)
    if parts is not None:
        parts = open_particles(parts, t, args)

    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 1
    view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    if t is not None:
        view.ViewTime = t

    b = reader.GetDataInformation().GetBounds()
    cells = grid_cells(path)
    plan = slice_plan(cells, b, force=args.view == "2d") if args.view != "3d" else None
    edges = not args.no_edges
    scale = [1.0, 1.0, 1.0]
    if plan is not None:
        normal, _, stretched, stretch = plan
        centre = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
        cut = Slice(Input=reader)
        cut.SliceType = "Plane"
        cut.SliceType.Origin = centre
        cut.SliceType.Normal = [1.0 if a == normal else 0.0 for a in range(3)]
        try:
            cut.Triangulatetheslice = 0  # keep the cells' quadrilaterals
        except AttributeError:
            pass
        shown = cut
        if stretched is not None:
            scale[stretched] = stretch
        # cells narrower than 10 pixels: the edges would paint the slice dark
        n_along = max(cells[a] for a in range(3) if a != normal)
        if n_along * 10 > width:
            edges = False
    else:
        shown = reader

    surf = Show(shown, view)
    surf.Representation = "Surface With Edges" if edges else "Surface"
    surf.EdgeColor = [0.25, 0.25, 0.25]
    surf.LineWidth = 0.5
    surf.Scale = scale
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

    pshow = None
    if parts is not None:
        pshow = show_particles(parts, view, scale)
    if args.grid_opacity is not None:
        surf.Opacity = args.grid_opacity
    elif pshow is not None and plan is None:
        surf.Opacity = 0.35  # the particles are inside the grid: see through it

    box = Show(Outline(Input=shown), view)
    box.DiffuseColor = box.AmbientColor = [0.0, 0.0, 0.0]
    box.LineWidth = 1.5
    box.Scale = scale

    label = "%s   %s" % (os.path.basename(path), args.field)
    if t is not None:
        label += "   %s, t = %.6g" % (frame_label(index, len(times)), t)
    if plan is not None:
        label += "\n2D slice across %s (%d x %d x %d cells)" % ("xyz"[plan[0]], *cells)
        if plan[2] is not None:
            label += ", %s stretched x%.3g for display" % ("xyz"[plan[2]], plan[3])
    if parts is not None:
        label += "\nparticles: %s" % (("%d, coloured by %s" % (parts["count"], parts["field"]))
                                      if parts["count"] else "none in this frame")
    text = Show(Text(Text=label), view)
    text.Color = [0.0, 0.0, 0.0]
    text.FontSize = 18
    text.WindowLocation = "Upper Left Corner"

    centre = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
    if plan is not None:
        # face on, along the slice's normal, parallel projection
        Render(view)  # the first render resets the camera: have it before placing ours
        normal = plan[0]
        diag = max(((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2) ** 0.5, 1e-30)
        view.CameraFocalPoint = [centre[i] * scale[i] for i in range(3)]
        up = [1.0 if a == plan[1] else 0.0 for a in range(3)]
        # the side to look from: the remaining in-plane axis must point right
        # (right = view direction x up, the view direction being -side*normal)
        right = [a for a in range(3) if a not in (normal, plan[1])][0]
        side = 1.0 if (normal, plan[1], right) in ((2, 1, 0), (0, 2, 1), (1, 0, 2)) else -1.0
        view.CameraPosition = [centre[i] * scale[i] + (side * 3.0 * diag if i == normal else 0.0)
                               for i in range(3)]
        view.CameraViewUp = up
        view.CameraParallelProjection = 1
        view.ResetCamera(False)
        # fit the slice to the left three quarters (the colour bar is on the
        # right) and leave room for the label above it
        w_ext = (b[2 * right + 1] - b[2 * right]) * scale[right]
        h_ext = (b[2 * plan[1] + 1] - b[2 * plan[1]]) * scale[plan[1]]
        half_h = max(0.5 * w_ext / 0.75 * height / width, h_ext / 1.4, 1e-30)
        shift = [0.0, 0.0, 0.0]
        shift[right] = 0.08 * 2.0 * half_h * width / height
        view.CameraFocalPoint = [centre[i] * scale[i] + shift[i] for i in range(3)]
        view.CameraPosition = [centre[i] * scale[i] + shift[i] + (side * 3.0 * diag if i == normal else 0.0)
                               for i in range(3)]
        view.CameraParallelScale = half_h
        if pshow is not None:
            # every particle on the camera's side of the slice, as wide as their spacing
            off = [0.0, 0.0, 0.0]
            off[normal] = side * ((b[2 * normal + 1] - b[2 * normal]) * scale[normal] + 1e-3 * diag)
            pshow.Position = off
            size_particles(parts, pshow, height / (2.0 * half_h), args)
        Render(view)
        SaveScreenshot(out, view, ImageResolution=[width, height], TransparentBackground=0)
        print("render_frame: wrote %s (%s, frame %d, t = %s, range %.6g .. %.6g, 2D slice across %s)"
              % (out, args.field, index, "n/a" if t is None else "%.6g" % t, lo, hi, "xyz"[normal]))
        report_particles(parts)
        return

    # Oblique camera: along --view-from from the centre of the grid, z up
    # (or y up when looking along z), then fitted to the data.
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
    if pshow is not None:
        # (perspective: about the pixels per length at the grid's centre)
        size_particles(parts, pshow, height / (1.2 * diag), args)

    Render(view)
    SaveScreenshot(out, view, ImageResolution=[width, height], TransparentBackground=0)
    print("render_frame: wrote %s (%s, frame %d, t = %s, range %.6g .. %.6g)"
          % (out, args.field, index, "n/a" if t is None else "%.6g" % t, lo, hi))
    report_particles(parts)


def open_particles(path, t, args):
    """The particles' series at time t: a dict with the calculator that
    makes their colouring array, its name and range, their count and mean
    spacing (from their volumes); the count is 0 in a frame without
    particles."""
    from paraview import servermanager
    reader = Xdmf3ReaderS(FileName=[path])
    reader.UpdatePipelineInformation()
    reader.UpdatePipeline(t if t is not None else 0.0)
    count = reader.GetDataInformation().GetNumberOfPoints()
    parts = {"path": path, "field": args.particle_field, "count": count}
    if count == 0:
        parts["count"] = 0
        return parts
    arrays = list(reader.PointData.keys())
    name = args.particle_field
    if name in DERIVED:
        if "stress" not in arrays:
            fail("%s: no stress to compute %s from; particle fields: %s"
                 % (path, name, ", ".join(arrays)))
        expr = DERIVED[name]
    elif name in arrays:
        ncomp = reader.PointData[name].GetNumberOfComponents()
        expr = name if ncomp == 1 else "mag(%s)" % name
    else:
        fail("no particle field %r; particle fields: %s (and von_mises, pressure)"
             % (name, ", ".join(arrays)))
    colour = "particle " + name  # not the grid's array name: a LUT of its own
    calc = PythonCalculator(Input=reader, Expression=expr, ArrayName=colour, ArrayAssociation="Point Data")
    calc.UpdatePipeline(t if t is not None else 0.0)
    lo, hi = calc.PointData[colour].GetRange(0)
    if args.particle_range:
        lo, hi = args.particle_range
    if hi <= lo:
        hi = lo + max(abs(lo), 1.0) * 1e-6
    d = servermanager.Fetch(reader)
    vol = d.GetPointData().GetArray("volume")
    spacing = None
    if vol is not None and vol.GetNumberOfTuples() > 0:
        mean = sum(vol.GetValue(i) for i in range(vol.GetNumberOfTuples())) / vol.GetNumberOfTuples()
        spacing = abs(mean) ** (1.0 / 3.0)
    parts.update(source=calc, colour=colour, range=(lo, hi), spacing=spacing)
    return parts


def show_particles(parts, view, scale):
    """The particles as round points coloured by their field on their own
    colour map (PARTICLE_RGB) with a bar of their own; None without any."""
    if not parts["count"]:
        return None
    show = Show(parts["source"], view)
    show.Representation = "Points"
    show.RenderPointsAsSpheres = 1
    show.Scale = scale
    ColorBy(show, ("POINTS", parts["colour"]))
    lut = GetColorTransferFunction(parts["colour"])
    lo, hi = parts["range"]
    lut.RGBPoints = [lo + (hi - lo) * PARTICLE_RGB[i] if i % 4 == 0 else PARTICLE_RGB[i]
                     for i in range(len(PARTICLE_RGB))]
    lut.ColorSpace = "RGB"
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(lo, hi)
    bar = GetScalarBar(lut, view)
    bar.Title = "particles: " + parts["field"]
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.TitleFontSize = 18
    bar.LabelFontSize = 16
    bar.RangeLabelFormat = "%-#.3g"
    bar.ScalarBarLength = 0.45
    bar.Orientation = "Horizontal"  # below the picture: the grid's bar is on the right
    bar.WindowLocation = "Any Location"
    bar.Position = [0.2, 0.02]
    bar.Visibility = 1
    return show


def size_particles(parts, show, pixels_per_length, args):
    """The particles' point diameter (pixels): --particle-size, else about
    their spacing on the screen."""
    if args.particle_size:
        size = args.particle_size
    elif parts.get("spacing"):
        size = point_diameter(parts["spacing"], pixels_per_length)
    else:
        size = 5.0
    show.PointSize = size
    parts["size"] = size


def report_particles(parts):
    if parts is None:
        return
    if not parts["count"]:
        print("render_frame: particles: none in this frame (%s)" % os.path.basename(parts["path"]))
        return
    print("render_frame: particles: %d drawn as %.3g-pixel points, %s range %.6g .. %.6g"
          % (parts["count"], parts["size"], parts["field"], parts["range"][0], parts["range"][1]))


if __name__ == "__main__":
    main(sys.argv[1:])
