#!/usr/bin/python3
"""The kinetic energy of a closed box of gas at rest whose nodes were given
random velocities (tests/decks/hourglass_q01.nml), from its energy history:
it may never exceed its initial value (in a closed box the waves' energy,
kinetic plus compression, only falls; the kinetic part alone starts with all
of it), and it must have fallen below `final` of it by the end.

    check_hourglass.py HISTORY.txt FINAL
"""
import sys


def main(path, final):
    rows = [list(map(float, line.split())) for line in open(path) if line.strip() and not line.startswith("#")]
    ke = [r[1] for r in rows]
    k0 = ke[0]
    peak = max(ke[1:])
    print(f"kinetic energy: initial {k0:.6e}, largest after {peak:.6e} ({peak / k0:.4f} of it), "
          f"final {ke[-1]:.6e} ({ke[-1] / k0:.4f}; bound {final})")
    ok = k0 > 0 and peak <= k0 and ke[-1] <= final * k0
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], float(sys.argv[2])))
