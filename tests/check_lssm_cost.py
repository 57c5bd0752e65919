#!/usr/bin/env python3
"""Cost and accuracy of one Sedov run (A) against another (B) with other
&rezone settings (e.g. move_min).

    check_lssm_cost.py LOG_A FRAME_A LOG_B FRAME_B CELL_RATIO L1_RATIO

Run A must remap at most CELL_RATIO times the cells run B remaps in its
Euler steps (the `euler steps:` summary line of each log), and its
volume-weighted L1 density error of the last frame against the exact Sedov
solution (tools/profile_plot.py's sedov_l1, E = 0.851072 for the full
sphere, gamma 1.4, rho0 1) must be at most L1_RATIO times B's.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lssm_runs import cells_remapped, sedov_l1  # noqa: E402


log_m, frame_m, log_p, frame_p = sys.argv[1:5]
cell_ratio, l1_ratio = float(sys.argv[5]), float(sys.argv[6])
(em, cm), (ep, cp) = cells_remapped(log_m), cells_remapped(log_p)
lm, lp = sedov_l1(frame_m)[0], sedov_l1(frame_p)[0]
print(f"A: {em} Euler steps, {cm} cells remapped, L1 {lm:.5e}")
print(f"B: {ep} Euler steps, {cp} cells remapped, L1 {lp:.5e}")
print(f"cells ratio {cm / cp:.3f} (bound {cell_ratio}), L1 ratio {lm / lp:.4f} (bound {l1_ratio})")
ok = cm <= cell_ratio * cp and lm <= l1_ratio * lp
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
