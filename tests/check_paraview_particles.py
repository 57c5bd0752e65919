"""Opens a run with particles in ParaView, headless, and checks that the
particles show next to the grid (run under pvbatch by viz_particles.sh):

    xvfb-run -a pvbatch check_paraview_particles.py SERIES.xdmf FRAME.h5 [STEP]

FRAME.h5 is the series' time step STEP (default -1, the last; particles
that left the grid make the frames' particle counts differ).

- the time step is a multiblock of a structured grid (the hex cells)
  and an unstructured grid with one vertex cell per particle (so ParaView
  draws them);
- the particle block has a point array for every particle field the frame
  holds (by default velocity (3), density, volume, mass, material, body,
  id, cell and stress (6); fewer where &output particle_fields chose), and
  its points and velocities are the frame's particles/x and
  particles/velocity exactly (float32 and compressed frames too).
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np
from paraview import servermanager
from paraview.simple import Xdmf3ReaderS
from vtkmodules.numpy_interface import dataset_adapter as dsa

fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


frame = h5py.File(sys.argv[2], "r")
xp, vp = frame["particles/x"][()], frame["particles/velocity"][()]
ncell = frame["density"].size
r = Xdmf3ReaderS(FileName=[sys.argv[1]])
r.UpdatePipelineInformation()
step = int(sys.argv[3]) if len(sys.argv) > 3 else -1
r.UpdatePipeline(r.TimestepValues[step])
d = servermanager.Fetch(r)
blocks = []
it = d.NewIterator()
it.InitTraversal()
while not it.IsDoneWithTraversal():
    blocks.append(it.GetCurrentDataObject())
    it.GoToNextItem()
kinds = sorted(b.GetClassName() for b in blocks)
check(kinds == ["vtkStructuredGrid", "vtkUnstructuredGrid"], f"blocks {kinds}: the grid and the particles")
grid = [b for b in blocks if b.GetClassName() == "vtkStructuredGrid"]
part = [b for b in blocks if b.GetClassName() == "vtkUnstructuredGrid"]
if grid:
    check(grid[0].GetNumberOfCells() == ncell, f"grid block: {grid[0].GetNumberOfCells()} cells, expected {ncell}")
if part:
    p = part[0]
    check(p.GetNumberOfPoints() == len(xp), f"particle block: {p.GetNumberOfPoints()} points, expected {len(xp)}")
    check(p.GetNumberOfCells() == len(xp), f"particle block: {p.GetNumberOfCells()} vertex cells, expected {len(xp)}")
    w = dsa.WrapDataObject(p)
    names = set(w.PointData.keys())
    # every particle field the frame holds (all by default; &output
    # particle_fields may choose fewer), but the positions and vertex numbers
    want = set(frame["particles"]) - {"x", "vertex"}
    check(want <= names, f"particle arrays {sorted(names)}, the frame's {sorted(want)}")
    if "stress" in names:
        check(np.asarray(w.PointData["stress"]).shape == (len(xp), 6), "stress has 6 components")
    check(np.array_equal(np.asarray(w.Points), xp), "particle positions are the frame's particles/x")
    if "velocity" in names:
        check(np.array_equal(np.asarray(w.PointData["velocity"]), vp), "particle velocities are the frame's")
print("FAIL" if fails else "PASS")
sys.exit(1 if fails else 0)
