#!/usr/bin/env python3
"""Per-material mass, internal and kinetic energy and momentum in the
conservation report add up to the totals.

    check_material_totals.py LOG REL_TOL

Each `conservation (...)` block of the log gives the total mass and
internal and kinetic energy and momentum, and then one `material m name:
mass M internal energy E kinetic energy K momentum px py pz` line per
material (pure cells plus the material's slots in mixed cells; kinetic
energy and momentum through the mass share of the cells' corners). The
sums over the materials must equal the totals within REL_TOL (relative;
momentum relative to the materials' summed |momentum| components, since a
symmetric scene's total momentum is round-off). Runs with particles also
book the particles' nodal share in the totals: for them only mass and
internal energy of the grid are compared (no particle body lines allowed).
"""
import re
import sys

path, tol = sys.argv[1], float(sys.argv[2])
blocks, cur = [], None
for line in open(path):
    m = re.match(r"conservation \((\w+)\): mass\s+(\S+)", line)
    if m:
        cur = {"label": m.group(1), "mass": float(m.group(2)), "mats": [],
               "momentum": [float(v) for v in line.split("momentum")[1].split()]}
        blocks.append(cur)
        continue
    if cur is None:
        continue
    m = re.match(r"\s+energy: internal\s+(\S+)\s+kinetic\s+(\S+)", line)
    if m:
        cur["internal"], cur["kinetic"] = float(m.group(1)), float(m.group(2))
    m = re.match(r"\s+material (\d+) (\S+): mass\s+(\S+)\s+internal energy\s+(\S+)\s+kinetic energy\s+(\S+)"
                 r"\s+momentum\s+(\S+)\s+(\S+)\s+(\S+)", line)
    if m:
        cur["mats"].append((m.group(2), float(m.group(3)), float(m.group(4)), float(m.group(5)),
                            [float(m.group(k)) for k in (6, 7, 8)]))
    if re.match(r"\s+particle body", line):
        sys.exit(f"FAIL: {path} has particle bodies: this check is for grid materials only")
if not blocks:
    sys.exit(f"FAIL: no conservation report in {path}")
bad = 0
for b in blocks:
    if not b["mats"]:
        print(f"FAIL: conservation ({b['label']}) has no per-material lines")
        bad += 1
        continue
    checks = [("mass", b["mass"], sum(m[1] for m in b["mats"]), abs(b["mass"])),
              ("internal", b["internal"], sum(m[2] for m in b["mats"]), abs(b["internal"])),
              ("kinetic", b["kinetic"], sum(m[3] for m in b["mats"]), abs(b["kinetic"]))]
    for d in range(3):
        checks.append((f"momentum_{'xyz'[d]}", b["momentum"][d], sum(m[4][d] for m in b["mats"]),
                       sum(abs(m[4][d]) for m in b["mats"])))
    for key, total, s, scale in checks:
        rel = abs(s - total) / max(scale, 1e-300)
        ok = rel <= tol
        bad += not ok
        names = "+".join(m[0] for m in b["mats"])
        print(f"{'ok  ' if ok else 'FAIL'} {b['label']}: {key} {names} = {s:.15e}, total {total:.15e}, "
              f"relative difference {rel:.2e}, tolerance {tol:.1e}")
sys.exit(1 if bad else 0)
