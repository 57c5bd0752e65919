#!/usr/bin/env python3
"""Tests of the dimensional-rescaling tools (tools/scale_deck.py and
tools/check_scaling.py): the test of the tester for the `dimension_*` tests.

    test_scaling_tools.py TOOLS_DIR

scale_deck.py: every dimensional variable is multiplied by its power of two
and reads back exactly; dimensionless values, integers and strings are left
as written; a default that is not zero (&grid xmax) is written in full and
scaled; multi-line groups, comments, repeats and element assignments are
read; an unknown variable or group and a product that would overflow are
refused. check_scaling.py: a frame scaled exactly passes; a one-ulp change
of any one element, a missing dataset and a changed shape fail; a dataset
of unknown dimension is refused.
"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

TOOLS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "tools")
sys.path.insert(0, TOOLS)
import scale_deck  # noqa: E402

failures = []


def check(label, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {label}" + (f": {detail}" if detail else ""))
    if not ok:
        failures.append(label)


def run(tool, *args):
    p = subprocess.run([sys.executable, os.path.join(TOOLS, tool), *args], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def values(groups, group, name, nth=0):
    """The value tokens of `name` in the nth group `group` of a parsed deck."""
    found = [items for g, items in groups if g == group][nth]
    for target, vals in found:
        if target == name:
            return vals
    return None


DECK = """! header comment with a number 1.5 that must not matter
&run title = 'a / title! with ''quotes''', t_end = 0.2, cfl = 0.3, max_steps = 7 /
&grid ni = 4, nj = 1, nk = 1, xmin = -1.0d0, 0, 0,
      xmax(2) = 0.1 /   ! xmax(1) and xmax(3) keep their default 1
&material name = 'w', eos = 'mie_gruneisen', rho0 = 1.0, c0 = 1.48, s1 = 1.75, gamma0 = 0.28,
  p_min = -0.5 /
&material name = 'g', gamma = 1.4 /
&region material = 'w', density = 1.2, energy = 0.060632, velocity = 3*0.7 /
&region shape = 'sphere', material = 'g', density = 0.001, pressure = 1e-4, center = 0.25, 0, 0,
  radius = 0.1 /
&source position = 0, 0, 0, energy = 0.106384 /
&boundary xlo = 'inflow', xlo_velocity = 1.0, 0, 0, inflow_material(1) = 'g',
  inflow_density(1) = 1.0, inflow_pressure(1) = 2.5, xhi = 'pressure', xhi_pressure = 0.75 /
&rezone mode = 'global', interval_time = 0.04, d_max = 3, move_min = 0.1 /
&output dir = 'out/x', frame_dt = 0.05, gauge_dt = 0.01, gauge = 0.5, 0.05, 0.05 /
"""

with tempfile.TemporaryDirectory() as tmp:
    src = os.path.join(tmp, "deck.nml")
    out = os.path.join(tmp, "scaled.nml")
    with open(src, "w") as f:
        f.write(DECK)
    L, T, M = 3, -2, 5
    rc, msg = run("scale_deck.py", src, out, "--L", str(L), "--T", str(T), "--M", str(M))
    check("scale_deck writes a scaled deck", rc == 0, msg.strip())
    with open(out) as f:
        text = f.read()
    g = scale_deck.parse(text, out)
    f = lambda l, t, m: 2.0 ** (l * L + t * T + m * M)  # noqa: E731
    expect = [  # (group, name, nth group, original values, factor)
        ("run", "t_end", 0, [0.2], f(0, 1, 0)),
        ("grid", "xmin", 0, [-1.0, 0.0, 0.0], f(1, 0, 0)),
        ("grid", "xmax", 0, [1.0, 0.1, 1.0], f(1, 0, 0)),
        ("material", "rho0", 0, [1.0], f(-3, 0, 1)),
        ("material", "c0", 0, [1.48], f(1, -1, 0)),
        ("material", "p_min", 0, [-0.5], f(-1, -2, 1)),
        ("region", "density", 0, [1.2], f(-3, 0, 1)),
        ("region", "energy", 0, [0.060632], f(2, -2, 0)),
        ("region", "velocity", 0, [0.7, 0.7, 0.7], f(1, -1, 0)),
        ("region", "pressure", 1, [1e-4], f(-1, -2, 1)),
        ("region", "center", 1, [0.25, 0.0, 0.0], f(1, 0, 0)),
        ("region", "radius", 1, [0.1], f(1, 0, 0)),
        ("source", "energy", 0, [0.106384], f(2, -2, 1)),
        ("boundary", "xlo_velocity", 0, [1.0, 0.0, 0.0], f(1, -1, 0)),
        ("boundary", "inflow_density(1)", 0, [1.0], f(-3, 0, 1)),
        ("boundary", "inflow_pressure(1)", 0, [2.5], f(-1, -2, 1)),
        ("boundary", "xhi_pressure", 0, [0.75], f(-1, -2, 1)),
        ("rezone", "interval_time", 0, [0.04], f(0, 1, 0)),
        ("output", "frame_dt", 0, [0.05], f(0, 1, 0)),
        ("output", "gauge_dt", 0, [0.01], f(0, 1, 0)),
        ("output", "gauge", 0, [0.5, 0.05, 0.05], f(1, 0, 0)),
    ]
    for group, name, nth, orig, factor in expect:
        got = values(g, group, name, nth)
        want = [v * factor for v in orig]
        ok = got is not None and [float(v) for v in got] == want
        check(f"&{group} {name} scaled by {factor!r}", ok, f"got {got}, want {want}")
    unchanged = [("run", "title", "'a / title! with ''quotes'''"), ("run", "cfl", "0.3"),
                 ("run", "max_steps", "7"), ("material", "s1", "1.75"), ("material", "gamma0", "0.28"),
                 ("rezone", "d_max", "3"), ("rezone", "move_min", "0.1"), ("output", "dir", "'out/x'"),
                 ("boundary", "inflow_material(1)", "'g'")]
    for group, name, tok in unchanged:
        got = values(g, group, name)
        check(f"&{group} {name} left as written", got == [tok], f"got {got}")

    # zero exponents: every number reads back as the same double
    rc, msg = run("scale_deck.py", src, out, "--L", "0", "--T", "0", "--M", "0")
    g0 = scale_deck.parse(open(out).read(), out)
    check("zero exponents reproduce the deck", rc == 0 and
          [float(v) for v in values(g0, "region", "energy")] == [0.060632], msg.strip())

    # refusals
    for label, deck, pattern in [
            ("an unknown variable is refused", "&run t_end = 1, t_stop = 2 /\n", "'t_stop' is not known"),
            ("an unknown group is refused", "&run t_end = 1 /\n&physics g = 9.81 /\n",
             "group &physics is not known"),
            ("an unterminated group is refused", "&run t_end = 1\n", "no closing '/'"),
            ("a number that overflows when scaled is refused", "&run t_end = 1e308 /\n", "not exact")]:
        with open(src, "w") as fh:
            fh.write(deck)
        rc, msg = run("scale_deck.py", src, out, "--T", "30")
        check(label, rc == 1 and pattern in msg, msg.strip())

    # check_scaling.py on a synthetic frame
    rng = np.random.default_rng(1)
    fields = {"x": ((4, 3), (1, 0, 0)), "velocity": ((4, 3), (1, -1, 0)), "density": ((3,), (-3, 0, 1)),
              "pressure": ((3,), (-1, -2, 1)), "energy": ((3,), (2, -2, 0)), "vf_a": ((3,), (0, 0, 0)),
              "time": ((), (0, 1, 0)), "totals/momentum": ((3,), (1, -1, 1)),
              "totals/kinetic_energy": ((), (2, -2, 1))}
    data = {k: rng.uniform(0.1, 3.0, shape) for k, (shape, _) in fields.items()}

    def write(path, scale, perturb=None, extra=None, drop=None, reshape=None):
        with h5py.File(path, "w") as h:
            for k, (shape, d) in fields.items():
                if k == drop:
                    continue
                v = np.array(data[k] * 2.0 ** (d[0] * scale[0] + d[1] * scale[1] + d[2] * scale[2]))
                if k == perturb:
                    v.flat[0] = np.nextafter(v.flat[0], np.inf)
                if k == reshape:
                    v = v.reshape(-1)[:-1]
                h[k] = v
            h["step"] = np.int32(12)
            h["deck"] = "&run t_end = 1 /"
            if extra:
                h[extra] = 1.0

    a, b = os.path.join(tmp, "a.h5"), os.path.join(tmp, "b.h5")
    write(a, (0, 0, 0))
    write(b, (L, T, M))
    args = ["--L", str(L), "--T", str(T), "--M", str(M)]
    rc, msg = run("check_scaling.py", a, b, *args)
    check("an exactly scaled frame passes", rc == 0 and "PASS" in msg, msg.strip().splitlines()[-1])
    rc, msg = run("check_scaling.py", a, b, "--L", str(L + 1), "--T", str(T), "--M", str(M))
    check("the wrong exponent fails", rc == 1, msg.strip().splitlines()[-1])
    for k in fields:
        write(b, (L, T, M), perturb=k)
        rc, msg = run("check_scaling.py", a, b, *args)
        line = [s for s in msg.splitlines() if s.startswith(k + " ")]
        check(f"one ulp in {k} fails", rc == 1 and line and "DIFFERENT" in line[0], msg.strip().splitlines()[-1])
    write(b, (L, T, M), drop="density")
    rc, msg = run("check_scaling.py", a, b, *args)
    check("a missing dataset fails", rc == 1 and "only in" in msg, msg.strip().splitlines()[-1])
    write(b, (L, T, M), reshape="pressure")
    rc, msg = run("check_scaling.py", a, b, *args)
    check("a changed shape fails", rc == 1 and "shapes" in msg, msg.strip().splitlines()[-1])
    write(a, (0, 0, 0), extra="surface_tension")
    write(b, (L, T, M), extra="surface_tension")
    rc, msg = run("check_scaling.py", a, b, *args)
    check("a dataset of unknown dimension is refused", rc == 2 and "surface_tension" in msg, msg.strip())

if failures:
    print(f"FAIL: {len(failures)} check(s): {', '.join(failures)}")
    sys.exit(1)
print("PASS: all checks")
