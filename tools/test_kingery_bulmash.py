#!/usr/bin/env python3
"""Test of tools/kingery_bulmash.py (Swisdak 1994 fits, hemispherical TNT).

Values worked out by hand from the coefficients (ln Z = 0 at Z = 1 and
1 at Z = e, so Y = exp(A) and exp(A + B + C + D + E + F) there):
  - Z = 1 (ln Z = 0), 1 kg: overpressure exp(7.2106) = 1353.70 kPa;
    arrival exp(-0.7604) = 0.46748 ms; duration (range 0.2-1.02)
    exp(0.5426) = 1.72047 ms; impulse (range 0.96-2.38) exp(5.465) =
    236.276 kPa ms.
  - Z = e = 2.71828 (ln Z = 1), arrival (range 1.5-40): exp(-0.7137 + 1.5732
    + 0.5561 - 0.4213 + 0.1054 - 0.00929) = exp(1.09041) = 2.97549 ms.
  - Z = 100, overpressure (range 23.8-198.5): exp(6.0536 - 1.4066 ln 100) =
    exp(6.0536 - 6.47763) = exp(-0.42403) = 0.65440 kPa.
  - Z = 50, impulse (range 33.7-158.7): exp(5.9825 - 1.062 ln 50) =
    exp(5.9825 - 4.15457) = exp(1.82793) = 6.22101 kPa ms.
  - Mass scaling: 8 kg at 2 m is Z = 1: overpressure 1353.70 kPa (not
    scaled), arrival 2 x 0.46748 = 0.93496 ms, impulse 2 x 236.276 =
    472.552 kPa ms.
  - Free air, 1 kg at 1 m with reflection 2: a surface burst of 0.5 kg,
    Z = 1 / 0.5^(1/3) = 1.259921; the same as 0.5 kg hemispherical.
    With 1.8: Z = 1.8^(1/3) = 1.216440.
Continuity: at every boundary between two ranges the two fits agree within
3 % (measured: arrival 0.16 %, overpressure 0.04 % and 0.70 %, duration
1.2 % and 0.90 %, impulse 0.24 %, 2.4 % and 0.18 %): a mistyped
coefficient moves a fit by far more than that at one end of its range.
Out of range (Z = 0.1 for the overpressure, 41 for the arrival) raises
ValueError, and the command line exits non-zero with the message.
"""
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kingery_bulmash as kb  # noqa: E402

bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


def near(got, want, rel=1e-5):
    return abs(got - want) <= rel * abs(want)


E = math.e
for param, z, want in [("overpressure", 1.0, 1353.70), ("arrival", 1.0, 0.46748), ("duration", 1.0, 1.72047),
                       ("impulse", 1.0, 236.276), ("arrival", E, 2.97549), ("overpressure", 100.0, 0.65440),
                       ("impulse", 50.0, 6.22101)]:
    got = kb.scaled(param, z)
    check(near(got, want), f"{param} at Z = {z:.5g}: {got:.6g} (by hand {want})")

for param, want in [("overpressure", 1353.70), ("arrival", 0.93496), ("impulse", 472.552)]:
    got = kb.hemispherical(param, 2.0, 8.0)
    check(near(got, want), f"8 kg at 2 m, {param}: {got:.6g} (by hand {want})")

for param in kb.PARAMS:
    fa = kb.free_air(param, 1.0, 1.0, reflection=2.0)
    check(near(fa, kb.hemispherical(param, 1.0, 0.5), 1e-12), f"free air 1 kg, F = 2, {param} = 0.5 kg surface burst")
    y = kb.scaled(param, 1.8 ** (1 / 3))
    y = y * (1 / 1.8) ** (1 / 3) if kb.CUBE_ROOT_SCALED[param] else y
    check(near(kb.free_air(param, 1.0, 1.0), y, 1e-12), f"free air 1 kg, F = 1.8 (default), {param}: Z = 1.21644")

for param, ranges in kb.RANGES.items():
    for (lo1, hi1, c1), (lo2, hi2, c2) in zip(ranges, ranges[1:]):
        check(hi1 == lo2, f"{param}: ranges meet at {hi1}")
        a, b = kb.fit(c1, hi1), kb.fit(c2, hi1)
        check(abs(b / a - 1) < 0.03, f"{param}: continuous at Z = {hi1} within 3 % ({a:.5g} against {b:.5g}, "
                                     f"{100 * (b / a - 1):+.2f} %)")
    check(kb.scaled(param, ranges[1][0]) == kb.fit(ranges[0][2], ranges[1][0]),
          f"{param}: the lower range at the boundary Z = {ranges[1][0]}")

for param, z in [("overpressure", 0.1), ("arrival", 41.0), ("impulse", 200.0), ("duration", 0.19)]:
    try:
        kb.scaled(param, z)
        check(False, f"{param} at Z = {z}: no error")
    except ValueError as e:
        check("outside the fitted range" in str(e), f"{param} at Z = {z}: {e}")

tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "kingery_bulmash.py")
r = subprocess.run([sys.executable, tool, "--mass", "1", "--distance", "1", "2"], capture_output=True, text=True)
rows = [l.split() for l in r.stdout.splitlines() if not l.startswith("#")]
check(r.returncode == 0 and len(rows) == 2 and near(float(rows[0][3]), 1353.7, 1e-4),
      f"command line, 1 kg at 1 and 2 m: overpressure {rows[0][3] if rows else '?'} at 1 m")
r = subprocess.run([sys.executable, tool, "--mass", "1", "--distance", "0.1"], capture_output=True, text=True)
check(r.returncode != 0 and "outside the fitted range" in r.stderr, "command line, Z = 0.1: exits with the message")
r = subprocess.run([sys.executable, tool, "--mass", "1", "--distance", "1", "--free-air", "--reflection", "2"],
                   capture_output=True, text=True)
rows = [l.split() for l in r.stdout.splitlines() if not l.startswith("#")]
check(r.returncode == 0 and near(float(rows[0][3]), kb.hemispherical("overpressure", 1.0, 0.5), 1e-4),
      "command line --free-air --reflection 2: the 0.5 kg surface burst")

print(f"{bad} failure(s)")
sys.exit(1 if bad else 0)
