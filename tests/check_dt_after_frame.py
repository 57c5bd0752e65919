#!/usr/bin/env python3
"""The step after a frame is not held back by the short step that landed
on it (&run dt_growth grows from the last full step).

Usage: check_dt_after_frame.py LOG FRAME_DT

LOG is a run's log with a progress line every step (progress_steps = 1).
For every step k that landed on a frame time and was cut short there (its
dt below the step before it over dt_growth's default 1.1), and whose next
step did not land on a frame itself, the next step must be a cell's stable
step or, if the controller set it, at least the step before the frame: the
old control grew it from the short step only (1.1 times it), so every such
frame failed this. At least one such frame must be checked."""
import re
import sys


def main():
    log, frame_dt = sys.argv[1], float(sys.argv[2])
    steps = []
    for line in open(log):
        m = re.match(r"step\s+(\d+)\s+t\s+(\S+)\s+dt\s+(\S+)\s.*dt by (\S+)", line)
        if m:
            steps.append((int(m.group(1)), float(m.group(2)), float(m.group(3)), m.group(4)))

    def on_frame(t):
        return abs(t / frame_dt - round(t / frame_dt)) < 1e-9

    checked = bad = 0
    for i in range(1, len(steps) - 1):
        (_, _, dt_before, _), (k, t, dt, _), (_, t_next, dt_next, by_next) = steps[i - 1], steps[i], steps[i + 1]
        if not (on_frame(t) and dt < dt_before / 1.1) or on_frame(t_next):
            continue
        checked += 1
        ok = by_next == "cell" or dt_next >= dt_before * (1.0 - 1e-12)
        bad += not ok
        print(f"frame at step {k} (t = {t:.6g}): dt {dt_before:.4e} -> {dt:.4e} (landing) -> {dt_next:.4e}"
              f" (by {by_next}) {'ok' if ok else 'FAIL: held back'}")
    print(f"{checked} frames checked, {bad} held back")
    sys.exit(0 if checked > 0 and bad == 0 else 1)


if __name__ == "__main__":
    main()
