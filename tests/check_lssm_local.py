#!/usr/bin/env python3
"""Localization and accuracy of an LSSM Sedov run (A) against the same deck
with the whole grid smoothed (B, &rezone mode = 'smooth', the paper's global
MMALE).

    check_lssm_local.py LOG_A FRAME_A LOG_B FRAME_B NCELL SHARE_MAX L1_MAX L1_RATIO

A must remap on average at most SHARE_MAX of the NCELL cells per Euler step
(the `euler steps:` summary line of its log: cells remapped over Euler steps
times NCELL), its volume-weighted L1 density error of the last frame against
the exact Sedov solution (tools/profile_plot.py's sedov_l1, E = 0.851072 for
the full sphere, gamma 1.4, rho0 1) must be at most L1_MAX, and at most
L1_RATIO times B's.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lssm_runs import cells_remapped, sedov_l1  # noqa: E402


log_a, frame_a, log_b, frame_b = sys.argv[1:5]
ncell, share_max, l1_max, l1_ratio = int(sys.argv[5]), float(sys.argv[6]), float(sys.argv[7]), float(sys.argv[8])
(ea, ca), (eb, cb) = cells_remapped(log_a), cells_remapped(log_b)
(la, pa), (lb, pb) = sedov_l1(frame_a), sedov_l1(frame_b)
share_a = ca / max(ea, 1) / ncell
share_b = cb / max(eb, 1) / ncell
print(f"A (LSSM):   {ea} Euler steps, {ca} cells remapped, {share_a:.3f} of the grid per Euler step, "
      f"L1 {la:.4f}, peak density {pa:.2f}")
print(f"B (smooth): {eb} Euler steps, {cb} cells remapped, {share_b:.3f} of the grid per Euler step, "
      f"L1 {lb:.4f}, peak density {pb:.2f}")
print(f"share per Euler step {share_a:.3f} (bound {share_max}), L1 {la:.4f} (bound {l1_max}), "
      f"L1 ratio to B {la / lb:.3f} (bound {l1_ratio})")
ok = ea > 0 and share_a <= share_max and la <= l1_max and la <= l1_ratio * lb
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
