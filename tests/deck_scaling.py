#!/usr/bin/python3
"""The deck reader's cost is linear in the number of groups.

    deck_scaling.py EXE WORKDIR [N_SMALL N_LARGE MAX_RATIO]

Writes two decks of N_SMALL and N_LARGE (default 5,000 and 20,000) small box
&region groups (one per cell of a square pattern, as a deck that sets a
state per node or cell would) and times `EXE --check` on each (its CPU
time, user plus system), five times in turn, keeping each deck's fastest. A reader linear in the number of
groups takes N_LARGE/N_SMALL times as long (4; start-up makes it less); one
that scans the deck per group or appends to arrays one group at a time is
quadratic (16, and the reader before the fix took 25 times as long for 4
times the regions: 7 s for 2,601 regions, 174 s for 10,201). The ratio is
measured in one run, so it does not depend on the machine's speed; the
bound MAX_RATIO (default 8) is the geometric mean of linear and quadratic,
so noise must double or halve one timing to turn either into the other
(wall-time ratios of 3.1 to 5.7 were seen for the same binary on a shared
machine, where 3.9 is usual). Exit status 0 pass.
"""
import os
import subprocess
import sys


def write_deck(path, n):
    m = max(1, int(round(n ** 0.5)))
    with open(path, "w") as f:
        f.write("! %d box regions\n&run t_end = 1 /\n&grid ni = 10, nj = 10, nk = 1 /\n&material name = 'gas' /\n" % n)
        f.write("&region shape = 'all', density = 1, pressure = 1 /\n")
        for k in range(n):
            i, j = k % m, k // m
            f.write("&region shape = 'box', lo = %.6g, %.6g, 0, hi = %.6g, %.6g, 1,\n"
                    "        density = 1, pressure = 1 /\n" % (i / m, j / m, (i + 1) / m, (j + 1) / m))


def check_time(exe, deck):
    """CPU seconds (user + system) of `exe --check deck`: unlike the wall
    time, not lengthened by other processes or by the host taking the core."""
    p = subprocess.Popen([exe, "--check", deck], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit("FAIL: %s --check %s exited %d: %s" % (exe, deck, p.returncode, err[-500:]))
    return usage.ru_utime + usage.ru_stime


def main():
    exe, work = sys.argv[1], sys.argv[2]
    n_small = int(sys.argv[3]) if len(sys.argv) > 3 else 5000
    n_large = int(sys.argv[4]) if len(sys.argv) > 4 else 20000
    max_ratio = float(sys.argv[5]) if len(sys.argv) > 5 else 8.0
    os.makedirs(work, exist_ok=True)
    decks = {}
    for n in (n_small, n_large):
        decks[n] = os.path.join(work, "regions_%d.nml" % n)
        write_deck(decks[n], n)
    best = {n_small: float("inf"), n_large: float("inf")}
    for _ in range(5):
        for n in (n_small, n_large):
            best[n] = min(best[n], check_time(exe, decks[n]))
    ratio = best[n_large] / best[n_small]
    print("lsalepm --check: %d regions %.3f s, %d regions %.3f s; ratio %.2f for %.0f times the groups "
          "(linear %.0f, quadratic %.0f), bound %.2f"
          % (n_small, best[n_small], n_large, best[n_large], ratio, n_large / n_small, n_large / n_small,
             (n_large / n_small) ** 2, max_ratio))
    if not ratio <= max_ratio:
        print("FAIL: the deck reader is not linear in the number of groups")
        return 1
    print("PASS deck_scaling")
    return 0


if __name__ == "__main__":
    sys.exit(main())
