#!/usr/bin/env python3
"""Paper Sect. 7.5, Table 4: the shock-driven flexible plate.

    plate_compare.py LABEL=TRACKS [LABEL=TRACKS ...] [--png FILE]

Each TRACKS is a <name>_tracks.txt written by a run of
input/flexible_plate.nml (or a variant of it) whose first track point is
the plate's upper-left corner particle. LABEL names the run and must
start with `rho1` or `rho2` (the fluid density, which picks the
reference row); the rest is free (e.g. rho1-decoupled-h0.05).

For each run: the largest x displacement of the tracked particle
(x(t) - x(t_0), t_0 the first row) and the time it is reached, against
AUTODYN-r (the paper's reference, Table 4) with the relative errors, and
the paper's own figures for its decoupled and original schemes (cell
0.01) for comparison. If the last row is the maximum, the run may have
stopped before the peak: it is flagged.

With --png (and matplotlib: run with /usr/bin/python3) the displacement
histories are plotted.
"""
import argparse
import sys

REF = {  # Table 4: (max displacement, time)
    "rho1": {"AUTODYN-r": (0.264, 5.859), "paper decoupled": (0.246, 6.080),
             "paper original": (0.233, 6.520)},
    "rho2": {"AUTODYN-r": (0.451, 5.723), "paper decoupled": (0.447, 5.590),
             "paper original": (0.500, 7.390)},
}


def read_tracks(path):
    """Times and the first tracked particle's x (columns: time id x y z ...)."""
    t, x = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            w = line.split()
            t.append(float(w[0]))
            x.append(float(w[2]))
    if not t:
        sys.exit(f"{path}: no rows")
    return t, x


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="LABEL=TRACKS")
    ap.add_argument("--png", default="", help="write the displacement histories here")
    a = ap.parse_args()
    curves = []
    print(f"{'run':28s} {'t_end':>6s} {'max dx':>8s} {'t(max)':>7s} | {'ref dx':>6s} {'ref t':>6s} "
          f"{'err dx':>7s} {'err t':>7s} | paper dec dx/t  orig dx/t")
    for run in a.runs:
        label, _, path = run.partition("=")
        key = label[:4]
        if key not in REF:
            sys.exit(f"{label}: the label must start with rho1 or rho2")
        t, x = read_tracks(path)
        d = [xi - x[0] for xi in x]
        k = max(range(len(d)), key=lambda i: d[i])
        ref_d, ref_t = REF[key]["AUTODYN-r"]
        pd, po = REF[key]["paper decoupled"], REF[key]["paper original"]
        flag = "  (last row: peak not reached?)" if k == len(d) - 1 else ""
        print(f"{label:28s} {t[-1]:6.2f} {d[k]:8.4f} {t[k]:7.3f} | {ref_d:6.3f} {ref_t:6.3f} "
              f"{100 * (d[k] - ref_d) / ref_d:+6.1f}% {100 * (t[k] - ref_t) / ref_t:+6.1f}% | "
              f"{pd[0]:.3f}/{pd[1]:.3f} {po[0]:.3f}/{po[1]:.3f}{flag}")
        curves.append((label, t, d))
    if a.png:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib not available: no PNG")
            return
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for label, t, d in curves:
            ax.plot(t, d, label=label)
        for key, mk in (("rho1", "o"), ("rho2", "s")):
            if any(c[0].startswith(key) for c in curves):
                rd, rt = REF[key]["AUTODYN-r"]
                ax.plot([rt], [rd], "k" + mk, label=f"AUTODYN-r max ({key})")
        ax.set_xlabel("t")
        ax.set_ylabel("x displacement of the upper-left corner")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.png, dpi=120)
        print(f"wrote {a.png}")


if __name__ == "__main__":
    main()
