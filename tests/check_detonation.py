#!/usr/bin/env python3
"""The programmed burn's detonation front in a 1D slab lit on a face.

    check_detonation.py OUTDIR NAME PEAK_TOL

From the run log: the CJ velocity D and pressure p_CJ of the JWL (the line
`detonation: ... CJ velocity D, pressure P`), and the energy report. From
every frame after the first: the front, the leading point where the
pressure crosses p_CJ/2 (linear between cell centres), must lie within one
cell of D t (the initial cell width: the burn ramp and the viscosity smear
the front over 2-3 cells but do not move it); the last frame's peak pressure
must be within PEAK_TOL of p_CJ (the smearing of the Taylor wave's steep
start by the viscosity: 3.1 % with 415 cells behind the front, 1.1 % with
830, 0.7 % with 1660: it converges); total energy is conserved to 1e-12
(closed walls: the burn only releases the pressure of energy already there).
"""
import glob
import re
import sys

import h5py
import numpy as np

out, name, peak_tol = sys.argv[1], sys.argv[2], float(sys.argv[3])
log = open(f"{out}/{name}.log").read()
m = re.search(r"CJ velocity\s+([^,\s]+), pressure\s+([^,\s]+)", log)
if not m:
    sys.exit("FAIL: no CJ state in the log")
D, pcj = float(m.group(1)), float(m.group(2))
drift = [abs(float(v)) for v in re.findall(r"relative energy drift\s+(\S+)", log)]
bad = 0
frames = sorted(glob.glob(f"{out}/{name}_0*.h5"))[1:]
if len(frames) < 3:
    sys.exit(f"FAIL: {len(frames)} frames after the first")
dx0 = None
for f in frames:
    with h5py.File(f, "r") as h:
        t = float(h["time"][()])
        p = h["pressure"][()].ravel()
        x = h["x"][()][0, 0, :, 0]
    xc = 0.5 * (x[1:] + x[:-1])
    if dx0 is None:
        with h5py.File(sorted(glob.glob(f"{out}/{name}_0*.h5"))[0], "r") as h0:
            x0 = h0["x"][()][0, 0, :, 0]
        dx0 = x0[1] - x0[0]
    j = np.where(p > 0.5 * pcj)[0].max()
    xf = xc[j] + (p[j] - 0.5 * pcj) / (p[j] - p[j + 1]) * (xc[j + 1] - xc[j])
    ok = abs(xf - D * t) <= dx0
    bad += not ok
    print(f"{'ok  ' if ok else 'FAIL'} t = {t:.3f}: front {xf:.4f}, D t = {D * t:.4f}, "
          f"difference {xf - D * t:+.4f} (one cell {dx0:.4f})")
peak = p.max()
ok = abs(peak / pcj - 1) <= peak_tol
bad += not ok
print(f"{'ok  ' if ok else 'FAIL'} peak pressure {peak:.4f} against p_CJ {pcj:.4f}: {100 * (peak / pcj - 1):+.2f} % "
      f"(tolerance {100 * peak_tol:g} %)")
ok = bool(drift) and max(drift) <= 1e-12
bad += not ok
print(f"{'ok  ' if ok else 'FAIL'} energy drift {max(drift) if drift else float('nan'):.2e} (tolerance 1e-12)")
sys.exit(1 if bad else 0)
