#!/usr/bin/env python3
"""Test of tools/blast_kb_plot.py on synthetic inputs with known answers.

A blast file in deck units mm-us-GPa (the columns of modules/io's
<name>_blast.txt), with the charge centre at (100, 0, 0) mm (--centre) and
8 kg TNT (--mass-kg 8, W^(1/3) = 2):
  gauge 1 at (1100, 0, 0):      R = 1 m, Z = 0.5, arrival 200 us = 0.2 ms,
                                peak 3.0e-3 GPa = 3000 kPa;
  gauge 2 at (100, 1200, 1600): R = 2 m, Z = 1.0, arrival 1100 us = 1.1 ms,
                                peak 8.0e-4 GPa = 800 kPa.
A 1D pre-run gauge file (`# gauge 1 at radius 3.0E+03`, the distance
itself: the centre is not subtracted): R = 3 m, Z = 1.5, the pressure 1e-4
GPa to t = 3990 us, 1.6e-4 at 4000, back to 1e-4 by 6000: peak 6e-5 GPa =
60 kPa, arrival at half the peak, midway between 3990 and 4000: 3.995 ms
(tools/blast_gauges.py's definition).
Expected in the table (stdout) and the CSV: those R, Z, arrivals and peaks;
the KB columns equal tools/kingery_bulmash.py's free_air(param, R, 8) (the
free-air fits, columns _free) and free_air(param, R, 8, 1.8) (a surface
burst of W/1.8, columns _F1.8), and diff% = 100 (run / KB - 1); the PNG is
written (a PNG signature, more than 10 kB). A gauge beyond the fits (R =
200 m, Z = 100: the free-air fits stop at Z = 40) gets nan KB arrival and
the note, without failing.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import kingery_bulmash as kb  # noqa: E402

bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


def near(a, b, rel=1e-9):
    return (math.isnan(a) and math.isnan(b)) or abs(a - b) <= rel * max(abs(b), 1e-300)


work = tempfile.mkdtemp(prefix="blast_kb_plot_")
blast = os.path.join(work, "synthetic_blast.txt")
with open(blast, "w") as f:
    f.write("# blast answers at the gauges (synthetic, deck units)\n")
    f.write("# gauge x y z ambient_pressure arrival peak_overpressure peak_time positive_duration positive_impulse ended\n")
    f.write("1 1.1e3 0 0 1.0e-4 2.0e2 3.0e-3 2.1e2 3.0e2 1.0e-1 1\n")
    f.write("2 1.0e2 1.2e3 1.6e3 1.0e-4 1.1e3 8.0e-4 1.12e3 9.0e2 1.0e-1 1\n")
    f.write("3 2.001e5 0 0 1.0e-4 5.0e5 1.0e-7 5.1e5 9.0e2 1.0e-1 0\n")
prerun = os.path.join(work, "synthetic_prerun_gauges.txt")
with open(prerun, "w") as f:
    f.write("# the 1D spherical pre-run's gauges (synthetic)\n# gauge 1 at radius 3.0000000E+03\n")
    f.write("# time density_1 pressure_1 energy_1 sound_speed_1 velocity_1\n")
    for t, p in [(0, 1e-4), (3990, 1e-4), (4000, 1.6e-4), (5000, 1.3e-4), (6000, 1e-4), (6500, 0.9e-4)]:
        f.write(f"{t:.17e} 1.225e-3 {p:.17e} 0.2 0.34 0\n")
png, table = os.path.join(work, "kb.png"), os.path.join(work, "kb.csv")
r = subprocess.run([sys.executable, os.path.join(HERE, "blast_kb_plot.py"), blast, prerun,
                    "--label", "synthetic 3D", "--label", "synthetic 1D", "--mass-kg", "8", "--centre", "100", "0", "0",
                    "--length-unit", "mm", "--pressure-unit", "GPa", "--time-unit", "us", "--out", png, "--csv", table],
                   capture_output=True, text=True)
print(r.stdout + r.stderr)
check(r.returncode == 0, "blast_kb_plot.py ran")
check(os.path.isfile(png) and os.path.getsize(png) > 10000 and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n",
      f"PNG written ({os.path.getsize(png) if os.path.isfile(png) else 0} bytes)")
rows = list(csv.DictReader(open(table))) if os.path.isfile(table) else []
check(len(rows) == 4, f"4 rows in the CSV ({len(rows)})")
expect = [("synthetic 3D", 1, 1.0, 0.2, 3000.0), ("synthetic 3D", 2, 2.0, 1.1, 800.0),
          ("synthetic 3D", 3, 200.0, 500.0, 0.1), ("synthetic 1D", 1, 3.0, 3.995, 60.0)]
printed = [l.split() for l in r.stdout.splitlines() if l.startswith("synthetic")]
for (run, g, rm, arr, peak), row, line in zip(expect, rows, printed):
    z = rm / 2.0
    ok = row["run"] == run and int(row["gauge"]) == g and near(float(row["R_m"]), rm) and near(float(row["Z"]), z)
    ok = ok and near(float(row["arrival_ms"]), arr) and near(float(row["peak_kPa"]), peak)
    check(ok, f"{run} gauge {g}: R {row['R_m']} m (want {rm}), Z {row['Z']} (want {z}), arrival {row['arrival_ms']} ms "
              f"(want {arr}), peak {row['peak_kPa']} kPa (want {peak})")
    for f, col in ((None, "free"), (1.8, "F1.8")):
        for param, key, val in [("arrival", "arrival", arr), ("overpressure", "peak", peak)]:
            try:
                want = kb.free_air(param, rm, 8.0, f)
            except ValueError:
                want = float("nan")
            got = float(row[f"{key}_KB_{col}"])
            d = float(row[f"{key}_diff%_{col}"])
            check(near(got, want) and near(d, 100 * (val / want - 1) if want == want else want),
                  f"{run} gauge {g} {key}, {col}: KB {got:.6g} (kingery_bulmash.py {want:.6g}), diff {d:+.3f} %")
    # the printed table: run (two words), gauge, R, Z, arrival ... peak at column 9 after the run's words
    vals = [float(v) for v in line[2:]]
    check(int(vals[0]) == g and near(vals[1], rm, 1e-3) and near(vals[3], arr, 1e-3) and near(vals[8], peak, 1e-3),
          f"printed row {' '.join(line[:7])} ... peak {line[10]}")
check(float(rows[2]["arrival_KB_free"]) != float(rows[2]["arrival_KB_free"]) and "outside the fits' range" in r.stdout,
      "Z = 100: nan KB arrival and the note")
print(f"{bad} failure(s)")
sys.exit(1 if bad else 0)
