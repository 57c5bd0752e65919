#!/usr/bin/python3
"""Deck fuzzer: broken decks must be refused cleanly.

    fuzz_decks.py WORKDIR DECK_DIR... -- EXE [EXE...]

Every shipped deck (the *.nml files in the DECK_DIRs, except bad_* ones) is
mutated in ways that each make it wrong for certain, plus fixed cases from
the hardening issue; every broken deck is run by every EXE (the Debug and
the Release build). Issue 40 adds classes whose mistake is in a file the
deck names or in how it is written: particle point files and grid files
damaged at random (bad numbers, shapes, byte-order marks, long lines,
tangled cells), a wrong value at the end of a line thousands of characters
long (the refusal must name that variable), and restart dumps of a
particle run edited with h5py (checksums valid) into values no run can
produce (the refusal must say the restart cannot be used). Each run must end with exit status 2, before step 0
(no progress line), with an ERROR line that names the group, the variable
or the line, and without a crash (no Fortran runtime error, no signal) or
a hang (20 s). A run that exits 0 accepted a mistake silently. Prints the
counts per mutation class and exits 1 on any failure.
"""
import os
import random
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tools'))
import debian_python  # noqa: E402  Debian's python3 if this one lacks the packages
debian_python.require("h5py", "numpy")
import h5py  # noqa: E402
import numpy as np  # noqa: E402

TIMEOUT = 20
SEED = 20261123
WORK = '.'   # the work folder (main)


def scan_groups(text):
    """[(name, start, end)] of the groups: `&name ... /` outside quotes and
    `!` comments; end is the index just past the '/'."""
    groups, i, q, start, name = [], 0, None, None, None
    while i < len(text):
        ch = text[i]
        if q:
            if ch == q:
                q = None
        elif ch == '!':
            j = text.find('\n', i)
            i = len(text) if j < 0 else j
            continue
        elif start is not None and ch in "'\"":
            q = ch
        elif start is None and ch == '&':
            m = re.match(r'&(\w+)', text[i:])
            if m:
                start, name = i, m.group(1).lower()
                i += len(m.group(0))
                continue
        elif start is not None and ch == '/':
            groups.append((name, start, i + 1))
            start = None
        i += 1
    return groups


def assignments(text, g):
    """[(variable, start of the value, end of the value)] in group g."""
    name, s, e = g
    body = text[s:e]
    out = []
    for m in re.finditer(r"(?<![\w'\"])([a-zA-Z]\w*)(\([^)]*\))?\s*=", body):
        # skip matches inside quotes
        if body[:m.start()].count("'") % 2 or body[:m.start()].count('"') % 2:
            continue
        vstart = s + m.end()
        nxt = re.search(r"(?<![\w'\"])[a-zA-Z]\w*(\([^)]*\))?\s*=|/\s*$", text[vstart:e])
        vend = vstart + (nxt.start() if nxt else e - 1 - vstart)
        out.append((m.group(1).lower(), vstart, vend))
    return out


# (group, variable, bad value, why) for the value-range class
RANGE = [
    ('run', 't_end', '-1.0', 'negative end time'), ('run', 'cfl', '2.0', 'cfl > 1'),
    ('run', 'dt_growth', '0.5', 'growth < 1'), ('run', 'max_steps', '-3', 'negative steps'),
    ('run', 'dump_keep', '0', 'no dumps kept'), ('run', 'dt_min', '-1', 'negative dt_min'),
    ('grid', 'ni', '0', 'no cells'), ('grid', 'nj', '-2', 'negative cells'), ('grid', 'subsamples', '0', 'no samples'),
    ('grid', 'subsamples', '2000', 'too many samples'), ('grid', 'ni', '2147483647', 'too many nodes'),
    ('hydro', 'q_linear', '-0.5', 'negative viscosity'), ('hydro', 'dv_max', '0', 'zero volume change'),
    ('hydro', 'relax', '1.5', 'relax > 1'), ('material', 'gamma', '0.5', 'gamma < 1'),
    ('material', 'rho_min', '-1', 'negative void density'), ('region', 'density', '-1.0', 'negative density'),
    ('region', 'radius', '-0.1', 'negative radius'), ('rezone', 'side_ratio', '0.5', 'side ratio < 1'),
    ('rezone', 'cos_angle', '1.5', 'cosine > 1'), ('rezone', 'quality', '2', 'quality > 1'),
    ('rezone', 'mof_max_iter', '0', 'no MoF iterations'), ('rezone', 'move_min', '0.7', 'move_min >= 0.5'),
    ('output', 'frame_dt', '-0.1', 'negative interval'), ('output', 'frame_steps', '-1', 'negative steps'),
    ('output', 'frame_dt', '1e-300', 'interval that would loop for ever'),
    ('output', 'gauge_dt', '1e-300', 'interval that would loop for ever'),
    ('output', 'compress', '10', 'deflate level > 9'),
    ('run', 'dump_dt', '1e-300', 'interval that would loop for ever'),
    ('source', 'energy', '-1', 'negative energy'), ('boundary', 'xlo_pressure', '-1', 'negative pressure'),
]
ENUMS = [('material', 'eos', "'stiffened'"), ('region', 'shape', "'cube'"), ('rezone', 'mode', "'euler'"),
         ('hydro', 'viscosity', "'artificial'"), ('boundary', 'xlo', "'open'"), ('region', 'material', "'nosuch'"),
         ('rezone', 'reconstruction', "'cubic'"), ('region', 'axis', "'w'"),
         ('region', 'velocity_field', "'spiral'"), ('output', 'precision', "'half'"),
         ('output', 'fields', "'density', 'densty'"), ('output', 'particle_fields', "'plastic'")]
NONFINITE = ['NaN', 'Inf', '-Infinity', '1e300', '-1.0e+45', 'nan']
# values of the wrong type: for a real, for an integer variable
TYPES_REAL = ["'abc'", '.true.', '1.2.3', 'abc']
TYPES_INT = ['10.5', "'abc'", '1.5e3', '.false.']
INT_VARS = {'ni', 'nj', 'nk', 'subsamples', 'max_steps', 'seed', 'dump_steps', 'dump_keep', 'progress_steps',
            'frame_steps', 'interval_steps', 'mof_max_iter', 'smooth_iterations', 'compress'}


def mutations(text, rng):
    """(class, deck text) pairs, each certainly wrong."""
    out = []
    gs = scan_groups(text)
    if not gs:
        return out
    names = [g[0] for g in gs]
    # unknown variable
    g = rng.choice(gs)
    asg = assignments(text, g)
    if asg:
        v, vs, ve = rng.choice(asg)
        k = text.rfind(v, gs[gs.index(g)][1], vs) if False else None
        m = list(re.finditer(r'\b%s\b' % re.escape(v), text[g[1]:vs], re.I))
        if m:
            p = g[1] + m[-1].start()
            out.append(('unknown variable', text[:p] + v + 'zz' + text[p + len(v):]))
    # unknown group
    g = rng.choice(gs)
    out.append(('unknown group', text[:g[1]] + '&' + g[0] + 'x' + text[g[1] + 1 + len(g[0]):]))
    # value out of range / unknown choice (where the deck has the group)
    for cls, table in (('value out of range', RANGE), ('unknown choice', ENUMS)):
        cand = [t for t in table if t[0] in names]
        if cand:
            t = rng.choice(cand)
            g = gs[names.index(t[0])]
            if t[1] == 'gamma' and re.search(r"eos\s*=\s*['\"](jwl|mie_gruneisen)", text[g[1]:g[2]], re.I):
                continue   # gamma is the ideal gas's: another EOS does not use it
            out.append((cls, text[:g[2] - 1] + ', %s = %s /' % (t[1], t[2]) + text[g[2]:]))
    # non-finite or huge real; wrong type
    reals = [(g, a) for g in gs for a in assignments(text, g)
             if re.fullmatch(r'\s*[-+]?(\d+\.\d*|\.\d+|\d+)([eEdD][-+]?\d+)?\s*,?\s*', text[a[1]:a[2]])]
    if reals:
        g, (v, vs, ve) = rng.choice(reals)
        out.append(('non-finite or huge value', text[:vs] + ' ' + rng.choice(NONFINITE) + ', ' + text[ve:]))
        g, (v, vs, ve) = rng.choice(reals)
        bad = rng.choice(TYPES_INT if v in INT_VARS else TYPES_REAL)
        out.append(('wrong type', text[:vs] + ' ' + bad + ' ' + text[ve:]))
    # missing '/', lost '&', stray assignment, second single group
    g = rng.choice(gs)
    out.append(("missing '/'", text[:g[2] - 1] + ' ' + text[g[2]:]))
    g = rng.choice(gs)
    out.append(("group without '&'", text[:g[1]] + text[g[1] + 1:]))
    out.append(('stray text', text + '\nt_end = 5\n'))
    single = [g for g in gs if g[0] in ('run', 'grid', 'hydro', 'boundary', 'rezone', 'output')]
    if single:
        g = rng.choice(single)
        out.append(('second single group', text + '\n' + text[g[1]:g[2]] + '\n'))
    # a required group removed
    req = [g for g in gs if g[0] in ('run', 'grid')] or [g for g in gs if g[0] in ('material', 'region')]
    if req:
        g = rng.choice(req)
        if names.count(g[0]) == 1:
            out.append(('required group missing', text[:g[1]] + text[g[2]:]))
    # a string longer than its variable; an unclosed quote
    g = gs[names.index('run')] if 'run' in names else gs[0]
    out.append(('string too long', text[:g[2] - 1] + ", title = '" + 'x' * 300 + "' /" + text[g[2]:]))
    out.append(('unclosed quote', text[:g[2] - 1] + ", title = 'abc /" + text[g[2]:]))
    return out


FIXED = [
    ('empty deck', ''),
    ('binary garbage', '\x00\x01\x02&run t_end = 1 /\n'),
    ('only comments', '! nothing here\n'),
    ('region uncovered', "&run t_end = 0.1 /\n&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n"
                         "&region shape = 'box', lo = 0, 0, 0, hi = 0.5, 1, 1, density = 1, pressure = 1 /\n"
                         "&output dir = 'out/f' /\n"),
    ('restart from a missing file', "&run t_end = 0.1, restart_from = 'no/such/file.h5' /\n"
                                    "&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n"
                                    "&region density = 1, pressure = 1 /\n&output dir = 'out/f' /\n"),
    ('restart name too long', "&run t_end = 0.1, restart_from = '" + 'r' * 300 + "' /\n"
                              "&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n"
                              "&region density = 1, pressure = 1 /\n"),
    ('source at NaN', "&run t_end = 0.1 /\n&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n"
                      "&region density = 1, pressure = 1 /\n&source position = NaN, 0, 0, energy = 1 /\n"),
    ('t_end infinite', "&run t_end = Inf /\n&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n"
                       "&region density = 1, pressure = 1 /\n"),
]


SMALL = ("&run t_end = 0.01 /\n&grid ni = 4, nj = 4, nk = 4 /\n&material name = 'gas' /\n"
         "&region density = 1, pressure = 1 /\n&output dir = 'out/f' /\n")
SOLID = "&solid name = 'steel', density = 7.8, youngs_modulus = 200, poisson_ratio = 0.3 /\n"


def file_cases(rng, n):
    """(class, deck, {file: bytes}, expected) cases whose mistake is in a
    particle point file or a grid file the deck names."""
    out = []
    good = [b'0.3 0.3 0.3', b'0.6 0.4 0.5', b'0.2 0.7 0.6']
    tokens = [b'nan', b'Inf', b'-1e300', b'1' * 5000, b'12345678901234567890123456789012345', b'0.5.5',
              b'abc', b'0x10', b'1e']
    bad_lines = [b'0.5 0.5 ' + t for t in tokens] + [b'0.5 0.5', b'0.5 0.5 0.5 0.5 0.5', b'0.5 0.5 0.5 -1',
                                                     b'0.5 0.5 0.5 0', b'0.5 0.5 5.0']
    for k in range(n):
        lines = list(good)
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(bad_lines))
        data = b'\n'.join(lines) + b'\n'
        if rng.random() < 0.3:
            data = b'\xef\xbb\xbf' + data
        out.append(('bad point file', SMALL + SOLID + "&particles shape = 'file', file = 'p%d.txt' /\n" % k,
                    {'p%d.txt' % k: data}, r"file of points|of file 'p[0-9]*.txt'"))
    x = np.stack(np.meshgrid(*(np.linspace(0, 1, 5),) * 3, indexing='ij')[::-1], axis=-1)   # (k, j, i, 3)
    for k in range(n):
        bad = x.copy()
        node = tuple(rng.randrange(1, 4) for _ in range(3))
        kind = rng.randrange(4)
        if kind == 0:
            bad[node + (rng.randrange(3),)] = rng.choice([np.nan, np.inf, 1e300, -1e31])
            why = 'not finite or of magnitude 1e30'
        elif kind == 1:
            d = rng.randrange(3)
            bad[node + (2 - d,)] += rng.choice([-1, 1]) * rng.uniform(0.27, 0.6)   # past a neighbour
            why = 'inverted or self-intersecting'
        elif kind == 2:
            bad = bad * 1e-32
            why = 'volume of'
        else:
            bad = bad[:, :, :-1, :]
            why = 'has shape'
        files = {}
        with h5py.File(os.path.join(WORK, 'g%d.h5' % k), 'w') as f:
            f['x'] = bad
        out.append(('bad grid file', SMALL.replace('ni = 4, nj = 4, nk = 4', "ni = 4, nj = 4, nk = 4, file = 'g%d.h5'" % k),
                    files, why))
    return out


def long_line_cases(rng, n):
    """A wrong value at the end of a line of thousands of characters: the
    refusal must name it (a reader that cut the line would not see it)."""
    out = []
    for k in range(n):
        pad = ' ' * rng.randrange(1100, 6000)
        var, val = rng.choice([('cfl', '2.0'), ('dt_growth', '0.5'), ('max_steps', '-3'), ('t_end', '-1')])
        text = SMALL.replace('&run t_end = 0.01 /', "&run title = 'long'," + pad + ('t_end = 0.01, ' if var != 't_end' else '')
                             + '%s = %s /' % (var, val))
        out.append(('long line', text, {}, r'&run: %s = ' % var))
    return out


def restart_cases(exe, rng, n):
    """A particle run's dump edited into values no run can produce."""
    deck = (SMALL.replace('t_end = 0.01', 't_end = 1, max_steps = 3, dump_steps = 3')
            .replace("dir = 'out/f'", "dir = 'out/r', name = 'r'") + SOLID
            + "&particles shape = 'box', lo = 0.3, 0.3, 0.3, hi = 0.7, 0.7, 0.7, solid = 'steel', per_cell = 2 /\n")
    with open(os.path.join(WORK, 'restart_base.nml'), 'w') as fh:
        fh.write(deck)
    subprocess.run([exe, 'restart_base.nml'], cwd=WORK, capture_output=True, timeout=120)
    dump = os.path.join(WORK, 'out/r/r_restart_00000003.h5')
    if not os.path.exists(dump):
        print('note: no particle dump to edit (the run failed): restart class skipped')
        return []
    cont = deck.replace('max_steps = 3, dump_steps = 3', "max_steps = 6, restart_from = 'e%d.h5'")
    edits = [('particle_mass', -1.0), ('particle_volume', 0.0), ('particle_density', np.nan),
             ('particle_velocity', 1e300), ('particle_stress', -1e40), ('particle_x', np.inf),
             ('particle_xi', 1.5), ('particle_xi', -0.5), ('particle_cell', 0), ('particle_cell', 10 ** 6),
             ('particle_id', 0), ('particle_id', -7), ('particle_material', 2), ('particle_body', -1),
             ('particle_body', 99), ('particle_energy', np.nan), ('particle_cell', None), ('fewer', None)]
    out = []
    for k in range(n):
        name, value = rng.choice(edits)
        path = os.path.join(WORK, 'e%d.h5' % k)
        shutil.copy(dump, path)
        with h5py.File(path, 'r+') as f:
            if name == 'fewer':      # one particle fewer in every dataset of a closed box
                for key in [q for q in f['state'].keys() if q.startswith('particle_')]:
                    v = f['state/' + key][()]
                    del f['state/' + key]
                    f.create_dataset('state/' + key, data=v[:-1], fletcher32=True, chunks=True)
            else:
                d = f['state/' + name]
                v = d[()]
                p = rng.randrange(v.shape[0])
                if value is None:    # another host cell for the same natural coordinates
                    v[p] = v[p] + 1 if v[p] < 64 else v[p] - 1
                elif v.ndim == 1:
                    v[p] = value
                else:
                    v[p, rng.randrange(v.shape[1])] = value
                d[...] = v
        out.append(('edited particle restart', cont % k, {}, r'cannot restart|restart_from'))
    return out


def run(exe, deck, work, expect=None):
    try:
        p = subprocess.run([exe, deck], cwd=work, capture_output=True, text=True, timeout=TIMEOUT,
                           errors='replace')
    except subprocess.TimeoutExpired:
        return 'hang', ''
    out = p.stdout + p.stderr
    if p.returncode < 0 or re.search(r'Fortran runtime error|Error termination|Backtrace|Segmentation', out):
        return 'crash (status %d)' % p.returncode, out
    if p.returncode == 0:
        return 'accepted silently', out
    if p.returncode != 2:
        return 'exit status %d, not 2' % p.returncode, out
    if re.search(r'^step ', out, re.M):
        return 'a step was taken', out
    errors = [l for l in out.splitlines() if l.startswith('ERROR: ')]
    if not errors or not any(re.search(r"&\w|:\d+:|'\S", l) for l in errors[:-1] or errors):
        return 'no ERROR line naming the group, variable or line', out
    if expect and not any(re.search(expect, l) for l in errors):
        return 'no ERROR line matching /%s/' % expect, out
    return 'ok', out


def main():
    args = sys.argv[1:]
    sep = args.index('--')
    work, dirs, exes = args[0], args[1:sep], args[sep + 1:]
    exes = [e for e in exes if e]
    missing = [e for e in exes if not os.path.exists(e)]
    for e in missing:
        print('note: %s does not exist (not built): not fuzzed' % e)
    exes = [e for e in exes if os.path.exists(e)]
    global WORK
    WORK = work
    os.makedirs(work, exist_ok=True)
    rng = random.Random(SEED)
    cases = [(cls, t, {}, None) for cls, t in FIXED]
    for d in dirs:
        for f in sorted(os.listdir(d)):
            if f.endswith('.nml') and not f.startswith('bad_'):
                text = open(os.path.join(d, f), encoding='utf-8', errors='replace').read()
                cases += [(cls, t, {}, None) for cls, t in mutations(text, rng)]
    cases += file_cases(rng, 30) + long_line_cases(rng, 10)
    if exes:
        cases += restart_cases(exes[0], rng, 40)
    counts, failures = {}, 0
    for k, (cls, text, files, expect) in enumerate(cases):
        path = os.path.join(work, 'fuzz_%04d.nml' % k)
        with open(path, 'w', encoding='utf-8', errors='replace') as fh:
            fh.write(text)
        for name, data in files.items():
            with open(os.path.join(work, name), 'wb') as fh:
                fh.write(data)
        for exe in exes:
            verdict, out = run(exe, path, work, expect)
            c = counts.setdefault(cls, [0, 0])
            c[0] += 1
            if verdict != 'ok':
                c[1] += 1
                failures += 1
                print('FAIL %s [%s] %s: %s' % (os.path.basename(path), cls, os.path.basename(os.path.dirname(exe)),
                                               verdict))
                print('  ' + '\n  '.join(out.strip().splitlines()[-4:]))
    ndecks = len(cases)
    print('%d broken decks x %d build(s) = %d runs' % (ndecks, len(exes), ndecks * len(exes)))
    for cls in sorted(counts):
        print('  %-28s %4d runs, %d failed' % (cls, counts[cls][0], counts[cls][1]))
    print('%s: %d failure(s)' % ('PASS' if failures == 0 else 'FAIL', failures))
    return 1 if failures or ndecks < 300 or not exes else 0


if __name__ == '__main__':
    sys.exit(main())
