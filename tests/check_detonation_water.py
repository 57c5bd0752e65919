#!/usr/bin/env python3
"""The TNT sphere lit in water (tests/decks/detonation_water.nml) runs to its
end: the log says done at t_end, the total energy closes to 1e-12 of the
initial (the outflow faces' work booked), and the shock reaches the gauges
on the x and y axes at the same time with the same peak (the octant is
symmetric under x <-> y; by default to 1e-9 relative: round-off orders).

    check_detonation_water.py OUT/NAME T_END [SYMMETRY_TOL]
"""
import re
import sys

prefix, t_end = sys.argv[1], float(sys.argv[2])
sym = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-9
log = open(prefix + ".log").read()
bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


m = re.search(r"done: t =\s+(\S+)", log)
check(m is not None and abs(float(m.group(1)) - t_end) <= 1e-12 * t_end, f"the run is done at t = {t_end}")
drift = [abs(float(v)) for v in re.findall(r"relative energy drift\s+(\S+)", log)]
check(bool(drift) and max(drift) <= 1e-12, f"energy drift {max(drift) if drift else 'none'} (tolerance 1e-12)")
rows = [l.split() for l in open(prefix + "_blast.txt") if not l.startswith("#")]
check(len(rows) == 2, f"{len(rows)} gauges")
if len(rows) == 2:
    a, b = [list(map(float, r[4:7])) for r in rows]
    check(a[1] > 0 and all(abs(x - y) <= sym * abs(x) for x, y in zip(a[1:], b[1:])),
          f"gauges on x and y: arrival {a[1]:.6f} / {b[1]:.6f}, peak {a[2]:.6e} / {b[2]:.6e}")
sys.exit(1 if bad else 0)
