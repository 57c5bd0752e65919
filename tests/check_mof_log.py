#!/usr/bin/env python3
"""The remap's interfaces in the mixed cells it changes: from a run log, the
Euler steps' lines

    euler N ... MoF X cells (C by their carried planes), Y iterations, Z capped,
    centroid error/size E; ...

(C: cells cut by the interface planes the Lagrangian steps carried, each
moved to its material's fraction, no search; the other X - C fitted by MoF
to their reference centroids, Y their mean iterations; Z: reconstructions
that failed or hit the iteration cap; E: the step's largest distance
between a fitted material's reference centroid and its region's centroid,
over the cell size) must show at most MAX_CAPPED capped reconstructions in
all, a median of E over the steps at most MEDIAN_TOL, a largest E at most
MAX_TOL, and at least CARRIED_MIN of all the cells cut by their carried
planes.

    check_mof_log.py LOG MAX_CAPPED MEDIAN_TOL MAX_TOL CARRIED_MIN

Prints what it compared; fails if a bound is broken or no Euler step did MoF.
"""
import re
import statistics
import sys

log, max_capped, median_tol, max_tol, carried_min = (sys.argv[1], int(sys.argv[2]), float(sys.argv[3]),
                                                     float(sys.argv[4]), float(sys.argv[5]))
pat = re.compile(r"^euler \d+ at step .*MoF (\d+) cells \((\d+) by their carried planes\),\s+([\d.]+) iterations, "
                 r"(\d+) capped, centroid error/size\s+(\S+);")
cells, carried, capped, errs = [], [], [], []
with open(log) as f:
    for line in f:
        m = pat.search(line)
        if m and int(m.group(1)) > 0:
            cells.append(int(m.group(1)))
            carried.append(int(m.group(2)))
            capped.append(int(m.group(4)))
            errs.append(float(m.group(5)))
if not cells:
    sys.exit(f"FAIL: no Euler step with MoF in {log}")
checks = [("capped reconstructions (all steps)", sum(capped), max_capped, False),
          ("median over the steps of the largest centroid error/size", statistics.median(errs), median_tol, False),
          ("largest centroid error/size", max(errs), max_tol, False),
          ("share of the cells cut by their carried planes", sum(carried) / sum(cells), carried_min, True)]
ok = True
print(f"{len(cells)} Euler steps with MoF, {sum(cells)} cells, {sum(carried)} by their carried planes")
for label, value, bound, at_least in checks:
    good = value >= bound if at_least else value <= bound
    ok = ok and good
    print(f"{'ok  ' if good else 'FAIL'}  {label}: {value:.3g}, {'at least' if at_least else 'bound'} {bound:.3g}")
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
