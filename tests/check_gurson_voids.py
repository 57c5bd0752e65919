#!/usr/bin/env python3
"""Random initial porosity of a gurson solid (tests/decks/gurson_voids_*.nml),
from frame 0: usage check_gurson_voids.py iid|corr frame.h5.

iid (void_length 0): 512 i.i.d. N(0.005, 0.0003^2) values (no truncation
at these numbers): sample mean within 4 sigma/sqrt(N) of 0.005, sample
standard deviation within 4 sigma/sqrt(2(N - 1)) of 0.0003, and the two
z layers of the plane-strain model independent (no equal pair).
corr (void_length 0.5 = 4 spacings, Gaussian): the grid is one cell
thick, so the field is 2D: the two particles at the same (x, y) have the
same f0 exactly; and in-plane neighbours (lag 0.125) are correlated,
sample correlation > 0.8 (the field's exp(-(0.125/0.5)^2) = 0.94, raised
by the interpolation; i.i.d. would give about 0).
Both: f0 positive, no particle failed at t = 0."""
import sys
import h5py
import numpy as np

kind, path = sys.argv[1], sys.argv[2]
with h5py.File(path, 'r') as h:
    f = np.array(h['particles/porosity'])
    x = np.array(h['particles/x'])
    failed = np.array(h['particles/failed'])
n = len(f)
ok = True


def check(cond, what):
    global ok
    print(('ok    ' if cond else 'FAIL  ') + what)
    ok = ok and bool(cond)


check(n == 512, f'512 particles ({n})')
check(f.min() > 0.0, f'f0 > 0 (min {f.min():.4e})')
check(not failed.any(), 'no particle failed at t = 0')
key = {}
for i in range(n):
    key.setdefault((round(x[i, 0], 6), round(x[i, 1], 6)), []).append(i)
pairs = [v for v in key.values() if len(v) == 2]
check(len(pairs) == 256, f'256 (x, y) columns of two particles ({len(pairs)})')
same = sum(1 for a, b in pairs if f[a] == f[b])
if kind == 'iid':
    m, s = f.mean(), f.std(ddof=1)
    tm, ts = 4 * 0.0003 / np.sqrt(n), 4 * 0.0003 / np.sqrt(2 * (n - 1))
    check(abs(m - 0.005) <= tm, f'mean {m:.6e} within {tm:.2e} of 0.005')
    check(abs(s - 0.0003) <= ts, f'std {s:.6e} within {ts:.2e} of 0.0003')
    check(same == 0, f'z layers independent (equal pairs: {same})')
else:
    check(same == len(pairs), f'2D field: equal f0 through the thickness ({same} of {len(pairs)})')
    a, b = [], []
    for (px, py), v in key.items():
        nb = key.get((round(px + 0.125, 6), py))
        if nb:
            a.append(f[v[0]])
            b.append(f[nb[0]])
    r = np.corrcoef(a, b)[0, 1]
    check(r > 0.8, f'neighbour correlation at lag 0.125: {r:.3f} > 0.8 ({len(a)} pairs)')
sys.exit(0 if ok else 1)
