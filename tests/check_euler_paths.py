#!/usr/bin/python3
"""The end-of-run `euler paths:` line against the run's own Euler lines.

    check_euler_paths.py LOG [LOG...]

For each log, every `euler N at step` line gives its cells remapped, how
many of them went by swept faces (all of them "by swept faces", none "by
intersection ...", the count "(S by swept faces" of a step in parts or in
two remaps) and its remap time (printed to 1 ms). Their sums must equal the
summary's: the cells by swept faces and by intersection exactly, the steps
that intersected some cells exactly, the cells remapped in those steps
exactly, and the remap times to the rounding of the printed lines (half a
millisecond per line). The same numbers would differ if the summary missed
a path or counted a step twice.
"""
import re
import sys

STEP = re.compile(r"euler (\d+) at step \d+, t = [^:]+: (\d+) cells remapped([^,]*),.*"
                  r"remap +([0-9.]+) s \(prepare")
SUMMARY = re.compile(r"euler paths: (\d+) cells by swept faces, (\d+) by intersection; (\d+) of the (\d+) "
                     r"Euler steps intersected some cells \((\d+) cells remapped in them, +([0-9.]+) s of the "
                     r"remap's +([0-9.]+) s\)")


def swept_of(cells, path):
    """Cells of a step that went by swept faces, from its path text."""
    m = re.search(r"\((\d+) by swept faces", path)
    if m:
        return int(m.group(1))
    if path.strip() == "by swept faces":
        return cells
    if "by intersection" in path or path.strip() == "":
        return 0
    raise ValueError(f"unknown path text: {path!r}")


def check(log):
    steps, summary = [], None
    with open(log) as f:
        for line in f:
            m = STEP.match(line)
            if m:
                cells = int(m.group(2))
                steps.append((cells, swept_of(cells, m.group(3)), float(m.group(4))))
            m = SUMMARY.match(line)
            if m:
                summary = [int(m.group(i)) for i in range(1, 6)] + [float(m.group(6)), float(m.group(7))]
    if summary is None or not steps:
        print(f"FAIL {log}: no summary or no Euler step")
        return False
    swept = sum(s for _, s, _ in steps)
    inter = sum(c - s for c, s, _ in steps)
    hit = [(c, t) for c, s, t in steps if c > s]
    want = [swept, inter, len(hit), len(steps), sum(c for c, _ in hit)]
    ok = summary[:5] == want
    tol = 5.0e-4 * len(steps) + 1.0e-3
    t_hit, t_all = sum(t for _, t in hit), sum(t for _, _, t in steps)
    ok = ok and abs(summary[5] - t_hit) <= tol and abs(summary[6] - t_all) <= tol
    print(f"{'ok' if ok else 'FAIL'} {log}: summary {summary}, from the steps {want} and "
          f"{t_hit:.3f} / {t_all:.3f} s (tolerance {tol:.4f} s)")
    return ok


if __name__ == "__main__":
    results = [check(log) for log in sys.argv[1:]]
    sys.exit(0 if results and all(results) else 1)
