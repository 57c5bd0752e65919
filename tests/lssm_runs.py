"""What tests/check_lssm_cost.py and tests/check_lssm_local.py read from a
Sedov run: the `euler steps:` summary of its log and the L1 density error of
a frame against the exact solution (tools/profile_plot.py's sedov_l1,
E = 0.851072 for the full sphere, gamma 1.4, rho0 1)."""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import profile_plot  # noqa: E402


def cells_remapped(log):
    """(Euler steps, cells remapped) of the log's summary line."""
    with open(log) as f:
        for line in f:
            m = re.match(r"euler steps: (\d+), cells remapped (\d+)", line)
            if m:
                return int(m.group(1)), int(m.group(2))
    print(f"FAIL: no 'euler steps:' summary in {log}")
    sys.exit(1)


def sedov_l1(frame):
    """(volume-weighted L1 density error, peak density) of the frame."""
    fr = profile_plot.read_frame(frame)
    sol = profile_plot.make_sedov(1.4, 0.851072, 1.0)
    return profile_plot.sedov_l1(profile_plot.radial_cells(fr), sol, fr["time"])[0], float(fr["density"].max())
