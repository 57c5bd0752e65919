#!/usr/bin/python3
"""tools/render_frame.py's choice of view, without ParaView (its
paraview.simple import is stubbed): a grid one cell thick in some direction
is drawn as a 2D slice across that direction, a quasi-1D strip lies
horizontal and is stretched across when thinner than 1/20 of its length,
a 3D grid keeps the oblique view; the particles' series is found beside the
grid's, frames are counted from 1 in the label, and particle points are
about their spacing wide. Usage: test_render_plan.py TOOLS_DIR
"""
import os
import sys
import tempfile
import types

sys.dont_write_bytecode = True
failures = []


def check(label, got, want):
    ok = got == want
    print(f"{'ok  ' if ok else 'FAIL'} {label}: got {got}, expected {want}")
    if not ok:
        failures.append(label)


def main():
    tools = sys.argv[1]
    stub = types.ModuleType("paraview.simple")
    for name in ("ColorBy", "CreateView", "GetColorTransferFunction", "GetScalarBar", "Outline",
                 "PythonCalculator", "Render", "SaveScreenshot", "Show", "Slice", "Text", "Xdmf3ReaderS"):
        setattr(stub, name, None)
    sys.modules["paraview"] = types.ModuleType("paraview")
    sys.modules["paraview.simple"] = stub
    sys.path.insert(0, tools)
    import render_frame as rf

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "s.xdmf")
        with open(path, "w") as f:
            f.write('<Xdmf Version="3.0"><Domain><Grid GridType="Collection"><Grid>'
                    '<Topology TopologyType="3DSMesh" Dimensions="2 2 101"/></Grid></Grid>'
                    '</Domain></Xdmf>')
        check("cells of a 100 x 1 x 1 series", rf.grid_cells(path), (100, 1, 1))
        check("no particles' series beside it", rf.particle_series(path), None)
        ppath = os.path.join(tmp, "s_particles.xdmf")
        open(ppath, "w").close()
        check("the particles' series beside it", rf.particle_series(path), ppath)
    check("the label counts frames from 1: the last of 4", rf.frame_label(3, 4), "frame 4 of 4")
    check("the first of 4", rf.frame_label(0, 4), "frame 1 of 4")
    check("particle points 0.9 of their spacing", rf.point_diameter(0.05, 420.0), 0.9 * 0.05 * 420.0)
    check("particle points at least 3 pixels", rf.point_diameter(1e-6, 420.0), 3.0)
    check("particle points at most 40 pixels", rf.point_diameter(1.0, 420.0), 40.0)
    # (ni, nj, nk), bounds -> (normal, up, stretched, stretch)
    sod = (0.0, 1.0, 0.0, 0.01, 0.0, 0.01)
    check("Sod 100 x 1 x 1: slice across z, y up, y stretched to 1/8 of the length",
          rf.slice_plan((100, 1, 1), sod), (2, 1, 1, (1.0 / 8.0) / 0.01))
    check("1 x 100 x 1 (along y): slice across z, x up (the strip horizontal)",
          rf.slice_plan((1, 100, 1), (0, 0.01, 0, 1, 0, 0.01))[:3], (2, 0, 0))
    check("1 x 1 x 100 (along z): slice across y, x up",
          rf.slice_plan((1, 1, 100), (0, 0.01, 0, 0.01, 0, 1))[:3], (1, 0, 0))
    check("a wide strip 100 x 1 x 1 of 1 x 0.2: not stretched",
          rf.slice_plan((100, 1, 1), (0, 1, 0, 0.2, 0, 0.2)), (2, 1, None, 1.0))
    check("quasi-2D 50 x 40 x 1: slice across z, y up, no stretch",
          rf.slice_plan((50, 40, 1), (0, 1, 0, 1, 0, 0.02)), (2, 1, None, 1.0))
    check("quasi-2D 50 x 1 x 40: slice across y, z up",
          rf.slice_plan((50, 1, 40), (0, 1, 0, 0.02, 0, 1)), (1, 2, None, 1.0))
    check("3D 20 x 20 x 20: the oblique view", rf.slice_plan((20, 20, 20), (0, 1, 0, 1, 0, 1)), None)
    check("3D with --view 2d: the mid-plane across z",
          rf.slice_plan((20, 20, 20), (0, 1, 0, 1, 0, 1), force=True), (2, 1, None, 1.0))
    if failures:
        print(f"FAIL: {len(failures)} check(s)")
        return 1
    print("PASS: render_frame view plans")
    return 0


if __name__ == "__main__":
    sys.exit(main())
