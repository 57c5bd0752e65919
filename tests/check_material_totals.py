#!/usr/bin/env python3
"""Per-material mass and internal energy in the conservation report add up
to the totals.

    check_material_totals.py LOG REL_TOL

Each `conservation (...)` block of the log gives the total mass and
internal energy and then one `material m name: mass M internal energy E`
line per material (pure cells plus the material's slots in mixed cells).
The sums over the materials must equal the totals within REL_TOL (relative).
"""
import re
import sys

path, tol = sys.argv[1], float(sys.argv[2])
blocks, cur = [], None
for line in open(path):
    m = re.match(r"conservation \((\w+)\): mass\s+(\S+)", line)
    if m:
        cur = {"label": m.group(1), "mass": float(m.group(2)), "mats": []}
        blocks.append(cur)
        continue
    if cur is None:
        continue
    m = re.match(r"\s+energy: internal\s+(\S+)", line)
    if m:
        cur["internal"] = float(m.group(1))
    m = re.match(r"\s+material (\d+) (\S+): mass\s+(\S+)\s+internal energy\s+(\S+)", line)
    if m:
        cur["mats"].append((m.group(2), float(m.group(3)), float(m.group(4))))
if not blocks:
    sys.exit(f"FAIL: no conservation report in {path}")
bad = 0
for b in blocks:
    if not b["mats"]:
        print(f"FAIL: conservation ({b['label']}) has no per-material lines")
        bad += 1
        continue
    for key, k in (("mass", 1), ("internal", 2)):
        s = sum(m[k] for m in b["mats"])
        rel = abs(s - b[key]) / max(abs(b[key]), 1e-300)
        ok = rel <= tol
        bad += not ok
        names = "+".join(m[0] for m in b["mats"])
        print(f"{'ok  ' if ok else 'FAIL'} {b['label']}: {key} {names} = {s:.15e}, total {b[key]:.15e}, "
              f"relative difference {rel:.2e}, tolerance {tol:.1e}")
sys.exit(1 if bad else 0)
