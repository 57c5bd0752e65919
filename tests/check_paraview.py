"""Opens a run's XDMF series in ParaView, headless, and checks what a user
sees there (run under pvbatch by tests/viz_paraview.sh):

    xvfb-run -a pvbatch check_paraview.py SERIES.xdmf MAT1,MAT2 [PNG]

- every frame's cell arrays include density, pressure, energy, sound_speed,
  viscosity, volume, material (an integer array, values 1..nmat) and, per
  material m, vf_m, density_m, energy_m, pressure_m;
- the node array velocity (3 components);
- the field data: time (equal to the reader's time step) and the legend
  "material i: name" = i;
- the values ParaView reads are the frame's: the fractions sum to 1 in each
  cell and sum_m vf_m density_m equals density (relative 1e-13), material
  is the index of the largest fraction;
- PNG (tools/render_frame.sh's picture of the quasi-1D run): at least 2 %
  of its pixels are coloured (neither white background nor black lines),
  so the run shows as a coloured 2D strip, not a black line.
Prints each check with the value found; exit status 0 pass, 1 fail.
"""
import os
import sys

from paraview import servermanager
from paraview.simple import Xdmf3ReaderS
from vtkmodules.numpy_interface import dataset_adapter as dsa
import numpy as np

failures = []


def check(label, ok, found):
    print("%s %s: %s" % ("ok  " if ok else "FAIL", label, found))
    if not ok:
        failures.append(label)


def first_block(data):
    """The dataset itself, or the first leaf of a multiblock."""
    if data.IsA("vtkMultiBlockDataSet") or data.IsA("vtkCompositeDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        return it.GetCurrentDataObject()
    return data


def main(argv):
    if len(argv) not in (2, 3):
        raise SystemExit(__doc__)
    path = os.path.abspath(argv[0])  # the XDMF3 reader wants an absolute path
    materials = argv[1].split(",")
    png = argv[2] if len(argv) == 3 else None
    reader = Xdmf3ReaderS(FileName=[path])
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues or [])
    check("time steps", len(times) >= 2, times)
    want_cells = ["density", "pressure", "energy", "sound_speed", "viscosity", "volume", "material"]
    for m in materials:
        want_cells += ["vf_" + m, "density_" + m, "energy_" + m, "pressure_" + m]
    legend = {"material %d: %s" % (i + 1, m): float(i + 1) for i, m in enumerate(materials)}
    for t in times:
        reader.UpdatePipeline(t)
        cells = list(reader.CellData.keys())
        missing = [n for n in want_cells if n not in cells]
        check("t = %g: cell arrays" % t, not missing, "missing %s" % missing if missing else cells)
        check("t = %g: node array velocity" % t, "velocity" in reader.PointData.keys()
              and reader.PointData["velocity"].GetNumberOfComponents() == 3,
              list(reader.PointData.keys()))
        fields = list(reader.FieldData.keys())
        check("t = %g: field data" % t, "time" in fields and all(k in fields for k in legend), fields)
        data = dsa.WrapDataObject(first_block(servermanager.Fetch(reader)))
        fd = {k: float(np.asarray(data.FieldData[k]).ravel()[0]) for k in fields}
        check("t = %g: field data values" % t, abs(fd.get("time", -1.0) - t) <= 1e-12 * max(1.0, abs(t))
              and all(fd.get(k) == v for k, v in legend.items()), fd)
        if missing:
            continue
        mat = np.asarray(data.CellData["material"])
        check("t = %g: material is an integer array in 1..%d" % (t, len(materials)),
              mat.dtype.kind == "i" and mat.min() >= 1 and mat.max() <= len(materials),
              "%s %d..%d" % (mat.dtype, mat.min(), mat.max()))
        vf = np.array([np.asarray(data.CellData["vf_" + m]) for m in materials])
        rm = np.array([np.asarray(data.CellData["density_" + m]) for m in materials])
        rho = np.asarray(data.CellData["density"])
        s = float(np.max(np.abs(vf.sum(axis=0) - 1.0)))
        r = float(np.max(np.abs((vf * rm).sum(axis=0) - rho) / rho))
        check("t = %g: fractions sum to 1 (1e-13)" % t, s <= 1e-13, s)
        check("t = %g: sum vf_m density_m = density (1e-13)" % t, r <= 1e-13, r)
        check("t = %g: material = largest fraction" % t, np.array_equal(mat, np.argmax(vf, axis=0) + 1),
              "%d cells" % mat.size)
        vol = np.asarray(data.CellData["volume"])
        check("t = %g: volume positive" % t, vol.min() > 0.0, float(vol.min()))
    if png:
        from vtkmodules.vtkIOImage import vtkPNGReader
        rd = vtkPNGReader()
        rd.SetFileName(png)
        rd.Update()
        img = dsa.WrapDataObject(rd.GetOutput())
        px = np.asarray(img.PointData[0])[:, :3].astype(float)
        white = np.all(px > 245.0, axis=1)
        black = np.all(px < 40.0, axis=1)
        grey = (px.max(axis=1) - px.min(axis=1)) < 12.0
        coloured = float(np.mean(~white & ~black & ~grey))
        check("%s: coloured pixels (at least 2 %%)" % os.path.basename(png), coloured >= 0.02,
              "%.1f %%" % (100.0 * coloured))
    if failures:
        print("FAIL: %d check(s): %s" % (len(failures), "; ".join(failures)))
        return 1
    print("PASS: ParaView shows the per-material fields, volume, material and field data")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
