"""Opens a run with particles in ParaView, headless, and checks that the
grid and the particles are two datasets, each readable on its own (run
under pvbatch by viz_particles.sh):

    xvfb-run -a pvbatch check_paraview_particles.py SERIES.xdmf FRAME.h5 [STEP]

SERIES.xdmf is the grid's series; the particles' is SERIES_particles.xdmf
beside it. FRAME.h5 is the series' time step STEP (default -1, the last;
particles that left the grid make the frames' particle counts differ).

- the grid's series gives one structured grid (the hex cells), no
  multiblock, with the frame's time as field data;
- the particles' series gives one unstructured grid with one vertex cell
  per particle (so ParaView draws them), the same time steps, the frame's
  time as field data, a point array for every particle field the frame
  holds (by default velocity (3), density, volume, mass, material, body,
  id, cell and stress (6); fewer where &output particle_fields chose), and
  its points and velocities are the frame's particles/x and
  particles/velocity exactly (float32 and compressed frames too).
Exit status 0 pass, 1 fail.
"""
import os
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
tf = float(frame["time"][()])
step = int(sys.argv[3]) if len(sys.argv) > 3 else -1
series = os.path.abspath(sys.argv[1])
pseries = series[:-len(".xdmf")] + "_particles.xdmf"
check(os.path.isfile(pseries), f"the particles' series {os.path.basename(pseries)} exists")


def read(path):
    r = Xdmf3ReaderS(FileName=[path])
    r.UpdatePipelineInformation()
    times = list(r.TimestepValues)
    r.UpdatePipeline(times[step])
    return times, servermanager.Fetch(r)


def field_time(d):
    a = d.GetFieldData().GetArray("time")
    return None if a is None else a.GetValue(0)


times, grid = read(series)
check(grid.GetClassName() == "vtkStructuredGrid", f"grid series: {grid.GetClassName()}, one structured grid")
check(grid.GetNumberOfCells() == ncell, f"grid: {grid.GetNumberOfCells()} cells, expected {ncell}")
check(field_time(grid) == tf, f"grid: field data time {field_time(grid)}, the frame's {tf}")
ptimes, p = read(pseries)
check(ptimes == times, f"the particles' series has the grid's {len(times)} time steps")
check(p.GetClassName() == "vtkUnstructuredGrid", f"particle series: {p.GetClassName()}, one unstructured grid")
check(field_time(p) == tf, f"particles: field data time {field_time(p)}, the frame's {tf}")
check(p.GetNumberOfPoints() == len(xp), f"particles: {p.GetNumberOfPoints()} points, expected {len(xp)}")
check(p.GetNumberOfCells() == len(xp), f"particles: {p.GetNumberOfCells()} vertex cells, expected {len(xp)}")
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
