#!/usr/bin/env python3
"""The Euler-step triggers on cells made long (tests/decks/sod_long_cells*.nml).

    check_long_cells.py LOG_SIDE4 LOG_SIDE2

LOG_SIDE4 (side_ratio 4, the default): no Euler step at all (`euler steps:
0`): the cells' side ratio is measured against their side ratio as made
(10), and the shock compresses them about 2.1 times. LOG_SIDE2 (side_ratio
2): Euler steps are made due by the shape, and the first such step's note
gives a side ratio between 2 and 2.5 (the compression, not the cell's own
side ratio of about 21).
"""
import re
import sys


def euler_steps(text):
    m = re.search(r"^euler steps:\s+(\d+)", text, re.M)
    return int(m.group(1)) if m else None


def main():
    bad = 0
    four, two = (open(p).read() for p in sys.argv[1:3])
    n4, n2 = euler_steps(four), euler_steps(two)
    ok = n4 == 0
    print(f"{'ok  ' if ok else 'FAIL'} side_ratio 4: {n4} Euler steps (want 0)")
    bad += not ok
    m = re.search(r"^euler \d+ due at step \d+: side ratio ([0-9.]+) in cell", two, re.M)
    r = float(m.group(1)) if m else float("nan")
    ok = n2 is not None and n2 > 0 and 2.0 <= r < 2.5
    print(f"{'ok  ' if ok else 'FAIL'} side_ratio 2: {n2} Euler steps, the first due at side ratio {r} "
          "(want some, at 2 to 2.5)")
    bad += not ok
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
