#!/usr/bin/env python3
"""The remap's MoF converges on the reference centroids it is given: from a
run log, the Euler steps' lines

    euler N ... MoF X cells, Y iterations, Z capped, centroid error/size E; ...

(Z: reconstructions that hit the iteration cap; E: the step's largest
distance between a material's reference centroid and its reconstructed
region's centroid, over the cell size) must show at most MAX_CAPPED capped
reconstructions in all, a median of E over the steps at most MEDIAN_TOL and
a largest E at most MAX_TOL.

    check_mof_log.py LOG MAX_CAPPED MEDIAN_TOL MAX_TOL

Prints what it compared; fails if a bound is broken or no Euler step did MoF.
"""
import re
import statistics
import sys

log, max_capped, median_tol, max_tol = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
pat = re.compile(r"^euler \d+ at step .*MoF (\d+) cells,\s+([\d.]+) iterations, (\d+) capped, "
                 r"centroid error/size\s+(\S+);")
cells, capped, errs = [], [], []
with open(log) as f:
    for line in f:
        m = pat.search(line)
        if m and int(m.group(1)) > 0:
            cells.append(int(m.group(1)))
            capped.append(int(m.group(3)))
            errs.append(float(m.group(4)))
if not cells:
    sys.exit(f"FAIL: no Euler step with MoF in {log}")
checks = [("capped reconstructions (all steps)", sum(capped), max_capped),
          ("median over the steps of the largest centroid error/size", statistics.median(errs), median_tol),
          ("largest centroid error/size", max(errs), max_tol)]
ok = True
print(f"{len(cells)} Euler steps with MoF, {sum(cells)} reconstructions")
for label, value, bound in checks:
    good = value <= bound
    ok = ok and good
    print(f"{'ok  ' if good else 'FAIL'}  {label}: {value:.3g}, bound {bound:.3g}")
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
