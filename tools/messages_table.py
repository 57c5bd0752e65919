#!/usr/bin/python3
"""The Euler phase's messages and bytes per rank per Euler step at a fixed
block size, on 1, 2, 4, 8 and 27 ranks (issue 35), and from them a
weak-scaling estimate.

    messages_table.py --exe build/release/lsalepm --out DIR
                      [--block 27] [--ranks 1 2 4 8 27] [--steps 20]
                      [--cases global lssm open] [--target-cells 1e7]
                      [--target-ranks 512]

Each case is the Sedov octant (input/sedov3d.nml's gas and energy) with
cells of 0.06 and block^3 cells per rank: the grid grows with the ranks
(`&run blocks`: 2 x 1 x 1 blocks on 2 ranks, 2 x 2 x 1 on 4, 2 x 2 x 2 on
8, 3 x 3 x 3 on 27, whose middle rank has a neighbour on every face), so
each rank's block is the same. Cases:

* `global`: `&rezone mode = 'global', interval_steps = 1`: an Euler step
  at every step, every moved cell remapped (windows, no moving face);
* `lssm`: the paper's LSSM settings (side ratio 4, cosine 0.7, quality
  0.999, 20 iterations): Euler steps where the grid distorts;
* `open`: `global` with the three far faces outflow: the open faces' gap
  search on each window (`window_zone_open` in `driver_whole`), with one
  gather of every window's description per set-up;
* `mixed` (not run unless asked for): `global` with a sphere of helium in
  the middle of each block (0.3 of its side in radius), so that every block
  holds mixed cells, as many at any count of ranks: a window's copy takes
  only the mixed cells in it (`mixed_gather`).

Counts come from Open MPI's own monitoring (`--mca pml_monitoring_enable
2`: every point-to-point message a rank sends, by the program itself and
inside its collectives, with their bytes), so nothing in the program is
instrumented. Each case runs twice for `--steps` steps, with its rezone and
with `mode = 'none'`; the difference, divided by the Euler steps the log
counts, is the Euler phase's, per rank per Euler step (the largest over the
ranks, and their mean), beside the Lagrangian step's own (the `none` run's
per step) and the peak resident memory per rank (the log's `memory:` line,
the most loaded rank).

The estimate for --target-cells on --target-ranks (--block 27 is about
that block: 1e7/512 = 19531 cells) starts from the most loaded rank of the
27-rank run, an interior block with all 26 neighbours: its point-to-point
messages (the halo and the window gathers go to the blocks a window meets)
as measured, their bytes scaled by the block's surface; the messages
inside collectives by log2 of the ranks (their rounds); the bytes inside
collectives and the Euler phase's memory (the run with Euler steps less
the run without) as c0 + c1 P fitted to the two largest rank counts, so a
whole-grid gather (c1 > 0) grows with the ranks (a rise in memory within
MEM_NOISE, the spread of repeated runs here, counts as none); the memory
per rank is the 27-rank run's without Euler steps plus that. All ranks here
share one machine, whose MPI keeps buffers per local peer: the runs
without Euler steps grow with the ranks for that reason, which the
difference leaves out. A model from measured points, stated as one.
"""
import argparse
import glob
import math
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CELL = 0.06
#: MiB: the spread of a run's peak resident memory between repeats on this
#: machine (Sedov 64^3 LSSM on 4 ranks: 135 to 143 MiB), within which the
#: estimate takes no trend
MEM_NOISE = 8.0
LAYOUT = {1: (1, 1, 1), 2: (2, 1, 1), 4: (2, 2, 1), 8: (2, 2, 2), 27: (3, 3, 3)}
REZONE = {
    'global': "&rezone mode = 'global', interval_steps = 1 /",
    'lssm': "&rezone mode = 'lssm', side_ratio = 4, cos_angle = 0.7, quality = 0.999, "
            "quality_target = 0.999, smooth_iterations = 20 /",
    'open': "&rezone mode = 'global', interval_steps = 1 /",
    'mixed': "&rezone mode = 'global', interval_steps = 1 /",
    'none': "",
}


def deck(path, case, kind, block, nranks, steps, outdir):
    """The Sedov deck of case at block^3 cells per rank on nranks ranks; kind
    'none': the same without Euler steps."""
    lay = LAYOUT[nranks]
    n = [block * b for b in lay]
    faces = "'outflow'" if case == 'open' else "'wall'"
    # (mixed: a sphere of a second gas in the middle of each block, 0.3 of
    # its side in radius: mixed cells on every block, as many per block at
    # any count of ranks)
    balls = ''
    if case == 'mixed':
        balls = "&material name = 'helium', eos = 'ideal_gas', gamma = 1.6666666666666667 /\n"
        side = block * CELL
        for bk in range(lay[2]):
            for bj in range(lay[1]):
                for bi in range(lay[0]):
                    balls += (f"&region shape = 'sphere', material = 'helium', center = {(bi + 0.5) * side:.4f}, "
                              f"{(bj + 0.5) * side:.4f}, {(bk + 0.5) * side:.4f}, radius = {0.3 * side:.4f}, "
                              "density = 0.2, pressure = 1.0e-6 /\n")
    text = f"""&run title = 'messages {case} {nranks}', t_end = 10.0, max_steps = {steps}, blocks = {lay[0]}, {lay[1]}, {lay[2]} /
&grid ni = {n[0]}, nj = {n[1]}, nk = {n[2]}, xmin = 0, 0, 0, xmax = {n[0] * CELL:.4f}, {n[1] * CELL:.4f}, {n[2] * CELL:.4f} /
&material name = 'air', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'air', density = 1.0, pressure = 1.0e-6 /
{balls}&source position = 0, 0, 0, energy = 0.106384 /
&boundary xlo = 'symmetry', ylo = 'symmetry', zlo = 'symmetry', xhi = {faces}, yhi = {faces}, zhi = {faces} /
&output dir = '{outdir}', frame_dt = 100 /
{REZONE[kind]}
"""
    with open(path, 'w') as f:
        f.write(text)


def run(exe, work, name, nranks):
    """Runs work/name.nml on nranks ranks with Open MPI's monitoring; returns
    the log's text and per rank (messages, bytes) sent."""
    prof = os.path.join(work, name + '_prof')
    for old in glob.glob(prof + '.*.prof'):
        os.remove(old)
    env = dict(os.environ, OMP_NUM_THREADS='1')
    cmd = ['mpirun', '--oversubscribe', '--mca', 'pml_monitoring_enable', '2',
           '--mca', 'pml_monitoring_enable_output', '3', '--mca', 'pml_monitoring_filename', prof,
           '-np', str(nranks), exe, name + '.nml']
    if os.geteuid() == 0:
        cmd.insert(1, '--allow-run-as-root')
    res = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True)
    with open(os.path.join(work, name + '.log'), 'w') as f:
        f.write(res.stdout + res.stderr)
    if res.returncode != 0:
        sys.exit(f'{name} on {nranks} rank(s) failed (exit {res.returncode}); see {work}/{name}.log')
    counts = []
    for r in range(nranks):
        # per kind: E, point to point sent by the program (halo exchanges,
        # window gathers); I, sent inside the collectives (C repeats it):
        # [messages, bytes] summed over the peers
        c = {'E': [0, 0], 'I': [0, 0]}
        path = f'{prof}.{r}.prof'
        if os.path.exists(path):
            for line in open(path):
                m = re.match(r'^([EI])\t\d+\t\d+\t(\d+) bytes\t(\d+) msgs sent', line)
                if m:
                    c[m.group(1)][0] += int(m.group(3))
                    c[m.group(1)][1] += int(m.group(2))
        counts.append(c)
    return res.stdout, counts


def euler_steps(log):
    m = re.search(r'^euler steps: (\d+)', log, re.M)
    return int(m.group(1)) if m else 0


def memory(log):
    m = re.search(r'^memory: peak resident (\d+) MiB', log, re.M)
    return int(m.group(1)) if m else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--exe', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--block', type=int, default=27)
    ap.add_argument('--ranks', type=int, nargs='+', default=[1, 2, 4, 8, 27])
    ap.add_argument('--steps', type=int, default=20)
    ap.add_argument('--cases', nargs='+', default=['global', 'lssm', 'open'])
    ap.add_argument('--target-cells', type=float, default=1e7)
    ap.add_argument('--target-ranks', type=int, default=512)
    a = ap.parse_args()
    if shutil.which('mpirun') is None:
        sys.exit('mpirun not found')
    exe = os.path.abspath(a.exe)
    os.makedirs(a.out, exist_ok=True)
    rows = {}
    for case in a.cases:
        for p in a.ranks:
            if p not in LAYOUT:
                sys.exit(f'--ranks: {p} has no layout here ({", ".join(map(str, LAYOUT))})')
            res = {}
            for kind in (case, 'none'):
                name = f'{case}_r{p}' if kind == case else f'{case}_none_r{p}'
                deck(os.path.join(a.out, name + '.nml'), case, kind, a.block, p, a.steps, 'out/' + name)
                res[kind] = run(exe, a.out, name, p)
            log, with_euler = res[case]
            log0, without = res['none']
            ne = euler_steps(log)
            # per rank and kind: [messages, bytes] per Euler step
            per = [{k: [(w[k][i] - o[k][i]) / max(ne, 1) for i in (0, 1)] for k in 'EI'}
                   for w, o in zip(with_euler, without)]
            lag = [[(o['E'][i] + o['I'][i]) / a.steps for i in (0, 1)] for o in without]
            rows[(case, p)] = dict(ne=ne, per=per, lag=lag, mem=memory(log), mem0=memory(log0))
    bc = a.block ** 3
    print(f'## Euler phase, messages and bytes sent per rank per Euler step at {a.block}^3 cells per rank')
    print(f'## ({a.steps} steps with and without Euler steps; Open MPI\'s monitoring: the program\'s own '
          'point-to-point messages, and those inside its collectives)')
    print()
    print('| case | ranks | layout | cells | Euler steps | point-to-point msgs (max, mean) | bytes (max, mean) | '
          'in collectives msgs (max) | bytes (max) | Lagrangian step msgs, bytes (max) | peak MiB per rank |')
    print('|---|---|---|---|---|---|---|---|---|---|---|')
    for (case, p), r in rows.items():
        e = [x['E'] for x in r['per']]
        i = [x['I'] for x in r['per']]
        lay = 'x'.join(str(v) for v in LAYOUT[p])
        print(f'| {case} | {p} | {lay} | {p * bc} | {r["ne"]} | {max(x[0] for x in e):.0f}, '
              f'{sum(x[0] for x in e) / p:.0f} | {max(x[1] for x in e):.3g}, {sum(x[1] for x in e) / p:.3g} | '
              f'{max(x[0] for x in i):.0f} | {max(x[1] for x in i):.3g} | '
              f'{max(x[0] for x in r["lag"]):.0f}, {max(x[1] for x in r["lag"]):.3g} | {r["mem"]} |')
    print()
    ps = sorted(a.ranks)
    if len(ps) < 2:
        return
    p1, p2 = ps[-2], ps[-1]
    pt = a.target_ranks
    tb = a.target_cells / pt
    surf = (tb / bc) ** (2.0 / 3.0)
    rounds = math.log2(pt) / max(math.log2(p2), 1.0)
    print(f'## Weak-scaling estimate: {a.target_cells:.3g} cells on {pt} ranks ({tb:.0f} cells per rank), for '
          f'the most loaded rank of the {p2}-rank run (on 3 x 3 x 3 its middle block has all 26 neighbours) and '
          f'the trend from {p1} to {p2} ranks:')
    print(f'## point-to-point as measured (it goes to the blocks its window meets), bytes x {surf:.2f} (the '
          f'block\'s surface); messages inside collectives x {rounds:.2f} (log2 of the ranks: their rounds); '
          'their bytes and the Euler phase\'s memory (over the run without Euler steps) c0 + c1 P fitted to the '
          f'two largest counts (c1 > 0: something whole-grid); memory: the run without Euler steps\' on {p2} '
          'ranks plus that')
    print()
    print('| case | msgs/rank/Euler step | bytes/rank/Euler step (of them in collectives; c1 per rank) | '
          'peak MiB per rank (Euler phase; c1 per rank) |')
    print('|---|---|---|---|')

    def fit(q1, q2, noise=0.0):
        # (a fall between the two counts, or a rise within the noise, is
        # not a trend: kept flat)
        c1 = (q2 - q1) / (p2 - p1) if q2 - q1 > noise else 0.0
        return q2 + c1 * (pt - p2), c1

    for case in a.cases:
        if (case, p1) not in rows or (case, p2) not in rows:
            continue
        r1, r2 = rows[(case, p1)], rows[(case, p2)]
        em = max(x['E'][0] for x in r2['per'])
        eb = max(x['E'][1] for x in r2['per'])
        im = max(x['I'][0] for x in r2['per'])
        ib, cb = fit(max(x['I'][1] for x in r1['per']), max(x['I'][1] for x in r2['per']))
        # (peak resident memory repeats to about +-4 MiB here)
        de, cm = fit(r1['mem'] - r1['mem0'], r2['mem'] - r2['mem0'], MEM_NOISE)
        print(f'| {case} | {em + im * rounds:.0f} | {eb * surf + ib:.3g} ({ib:.3g}; {cb:.3g}) | '
              f'{r2["mem0"] + de:.0f} ({de:.0f}; {cm:.2f}) |')


if __name__ == '__main__':
    main()
