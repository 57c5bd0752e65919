#!/usr/bin/python3
"""Write a copy of a deck with every dimensional input rescaled: lengths by
2^L, times by 2^T, masses by 2^M (the dimensional-rescaling invariance test,
tests/dimension_invariance.sh; ARCHITECTURE.md §6).

    scale_deck.py DECK OUT --L 3 --T -2 --M 5

A variable of dimension L^l T^t M^m is multiplied by 2^(l L + t T + m M).
Multiplying by a power of two is exact in binary floating point, so a
dimensionally consistent code run on the copy must give every output field
equal to the original's times the power of two of its dimension, bit for
bit (tools/check_scaling.py compares the frames).

The dimension of every variable the code reads (the config modules,
input/README.md) is in the table DIMENSIONS below. A group or variable that
is not in the table is refused (exit status 1, naming it), so a variable
added to the code cannot silently stay unscaled: add it to the table with
its dimension. Wall-clock settings (progress_seconds, wall_time_limit) are
wall seconds, not simulated time, and are not scaled. A dimensional
variable whose default is not zero (&grid xmax, default 1, 1, 1) is written
out in full, so that its defaults are scaled too; other defaults are 0
(scale to 0), sentinels (-1, +-huge) or derived from scaled inputs (dt_min:
1e-12 t_end).

The deck is parsed, not edited as text: each group is written on one line,
`&group name = value, ... /`, numbers of scaled variables with repr() of
the scaled double (which reads back exactly), all other values as they were
written. Comments are dropped (their numbers would no longer be true); a
header line names the original deck and the exponents. The parser covers
what decks use: groups `&name ... /` over one or several lines, `!`
comments, quoted strings ('' inside '...' is a quote), numbers, logicals,
`r*value` repeats, and element assignments such as `inflow_density(1) = 1`.
Exit status: 0 written, 1 refused (unknown name, unparsable deck, a scaled
number that would overflow or underflow), 2 usage error.
"""
import argparse
import math
import re
import sys

# dimension exponents (L, T, M)
NONE = (0, 0, 0)              # dimensionless number or ratio
LEN = (1, 0, 0)
TIME = (0, 1, 0)
VEL = (1, -1, 0)
DENS = (-3, 0, 1)
PRES = (-1, -2, 1)            # pressure, energy per volume
SPEC_E = (2, -2, 0)           # specific energy
ENERGY = (2, -2, 1)
RATE = (0, -1, 0)             # per unit time (an angular velocity)
INT = "int"                   # integer: passed through
STR = "str"                   # string: passed through
LOGICAL = "logical"           # logical: passed through
WALL = "wall"                 # wall-clock seconds, not simulated time: passed through
FILE = "file"                 # a file of dimensional data (a grid): refused unless empty

DIMENSIONS = {
    "run": {
        "title": STR, "units": STR, "t_end": TIME, "max_steps": INT, "cfl": NONE, "dt_init": TIME,
        "dt_max": TIME, "dt_min": TIME, "dt_growth": NONE, "progress_steps": INT,
        "progress_seconds": WALL, "velocity_noise": VEL, "seed": INT, "restart_from": STR,
        "wall_time_limit": WALL, "dump_steps": INT, "dump_dt": TIME, "dump_keep": INT,
    },
    "grid": {"ni": INT, "nj": INT, "nk": INT, "xmin": LEN, "xmax": LEN, "subsamples": INT, "file": FILE},
    "hydro": {"viscosity": STR, "q_linear": NONE, "q_quad": NONE, "hourglass": NONE,
              "dv_max": NONE, "relax": NONE, "dv_vf_min": NONE},
    "material": {
        "name": STR, "eos": STR, "library": STR, "gamma": NONE, "a": PRES, "b": PRES, "r1": NONE, "r2": NONE,
        "omega": NONE, "rho0": DENS, "c0": VEL, "s1": NONE, "gamma0": NONE, "p_min": PRES,
        "rho_min": DENS, "detonation_velocity": VEL, "burn_width": NONE,
    },
    "region": {
        "shape": STR, "material": STR, "density": DENS, "energy": SPEC_E, "pressure": PRES,
        "energy_per_volume": PRES, "velocity": VEL, "velocity_field": STR, "speed": VEL,
        "angular_velocity": RATE, "lo": LEN, "hi": LEN, "center": LEN,
        "radius": LEN, "axis": STR,
        # half space: the points p with (p - center) . normal >= 0; only the
        # direction of normal matters, so it is left as written
        "normal": NONE,
    },
    "source": {"position": LEN, "energy": ENERGY},
    "detonation": {"material": STR, "shape": STR, "point": LEN, "point2": LEN, "normal": NONE, "time": TIME,
                   "path": STR},
    "boundary": dict(
        [(f, STR) for f in ("xlo", "xhi", "ylo", "yhi", "zlo", "zhi")]
        + [(f + "_velocity", VEL) for f in ("xlo", "xhi", "ylo", "yhi", "zlo", "zhi")]
        + [(f + "_pressure", PRES) for f in ("xlo", "xhi", "ylo", "yhi", "zlo", "zhi")]
        + [("inflow_material", STR), ("inflow_density", DENS), ("inflow_pressure", PRES)]),
    "rezone": {
        "mode": STR, "side_ratio": NONE, "cos_angle": NONE, "interval_steps": INT,
        "interval_time": TIME, "reconstruction": STR, "mof_max_iter": INT,
        "conservation_tol": NONE, "quality": NONE, "quality_target": NONE,
        "smooth_iterations": INT,
        "d_max": NONE,        # in cells
        "move_min": NONE,     # a fraction of the shortest edge
        "swept_max": NONE,    # a fraction of the shortest edge
        "swept_parts": INT, "swept_mixed": STR, "hysteresis": NONE,
        "nodal_mass": STR,
    },
    "output": {"dir": STR, "name": STR, "frame_dt": TIME, "frame_steps": INT, "gauge_dt": TIME, "history_dt": TIME,
               "gauge": LEN, "gauge_line": LEN, "gauge_count": INT, "fields": STR, "particle_fields": STR, "precision": STR, "compress": INT},
}

# dimensional variables whose default is neither 0 nor a sentinel: written in
# full (defaults filled in) so that the defaults are scaled too
NONZERO_DEFAULTS = {("grid", "xmax"): [1.0, 1.0, 1.0]}


class DeckError(Exception):
    pass


def tokenize(text, path):
    """Tokens of a deck: ('group', name), ('end',), ('name', text), ('eq',),
    ('comma',), ('value', text). Comments are dropped."""
    tokens = []
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif c in " \t\r":
            i += 1
        elif c == "!":
            while i < n and text[i] != "\n":
                i += 1
        elif c in "'\"":
            j = i + 1
            while True:
                if j >= n:
                    raise DeckError(f"{path}:{line}: unterminated string")
                if text[j] == c:
                    if j + 1 < n and text[j + 1] == c:
                        j += 2
                        continue
                    break
                if text[j] == "\n":
                    line += 1
                j += 1
            tokens.append(("value", text[i:j + 1], line))
            i = j + 1
        elif c == "&":
            m = re.match(r"&([A-Za-z_]\w*)", text[i:])
            if not m:
                raise DeckError(f"{path}:{line}: '&' not followed by a group name")
            tokens.append(("group", m.group(1).lower(), line))
            i += m.end()
        elif c == "/":
            tokens.append(("end", None, line))
            i += 1
        elif c == "=":
            tokens.append(("eq", None, line))
            i += 1
        elif c == ",":
            tokens.append(("comma", None, line))
            i += 1
        else:
            m = re.match(r"[A-Za-z_]\w*\s*(\([^)]*\))?(?=\s*=)", text[i:])
            if m:
                tokens.append(("name", re.sub(r"\s+", "", m.group(0)), line))
                i += m.end()
                continue
            m = re.match(r"[^\s,/=!&'\"]+", text[i:])
            if not m:
                raise DeckError(f"{path}:{line}: cannot read {text[i:i + 20]!r}")
            tokens.append(("value", m.group(0), line))
            i += m.end()
    return tokens


def parse(text, path):
    """Groups as (name, [(target, [value tokens])]) in deck order; a null
    value (two commas in a row) is None."""
    groups = []
    toks = tokenize(text, path)
    k = 0
    while k < len(toks):
        kind, val, line = toks[k]
        if kind != "group":
            raise DeckError(f"{path}:{line}: text outside a group")
        group, items = val, []
        k += 1
        while True:
            if k >= len(toks):
                raise DeckError(f"{path}: group &{group} has no closing '/'")
            kind, val, line = toks[k]
            if kind == "end":
                k += 1
                break
            if kind == "comma":
                k += 1
                continue
            if kind != "name" or k + 1 >= len(toks) or toks[k + 1][0] != "eq":
                raise DeckError(f"{path}:{line}: &{group}: expected 'name =', found {val!r}")
            target, values, k = val, [], k + 2
            prev_comma = True       # a comma right after '=' is a null value
            while k < len(toks) and toks[k][0] in ("value", "comma"):
                if toks[k][0] == "value":
                    values.append(toks[k][1])
                    prev_comma = False
                else:
                    if prev_comma:
                        values.append(None)
                    prev_comma = True
                k += 1
            # the comma separating this item from the next name is not a null
            if values and values[-1] is None and k < len(toks) and toks[k][0] == "name":
                values.pop()
            items.append((target, values))
        groups.append((group, items))
    return groups


def expand(values):
    """Expand r*value repeats."""
    out = []
    for v in values:
        if v is not None and re.fullmatch(r"\d+\*.*", v):
            r, rest = v.split("*", 1)
            if rest == "":
                out.extend([None] * int(r))
            else:
                out.extend([rest] * int(r))
        else:
            out.append(v)
    return out


def to_float(tok, where):
    t = tok.lower().replace("d", "e")
    try:
        v = float(t)
    except ValueError:
        raise DeckError(f"{where}: {tok!r} is not a number") from None
    if not math.isfinite(v):
        raise DeckError(f"{where}: {tok!r} is not finite")
    return v


def scale_value(tok, factor, where):
    if tok is None:
        return None
    v = to_float(tok, where)
    s = v * factor
    # exact only if neither overflow nor underflow (no subnormal, no flush)
    if not math.isfinite(s) or (v != 0.0 and (s == 0.0 or abs(s) < sys.float_info.min)) \
            or s / factor != v:
        raise DeckError(f"{where}: {tok} times {factor!r} is not exact in double precision")
    return repr(s)


def scale_groups(groups, path, le, te, me):
    out = []
    for group, items in groups:
        table = DIMENSIONS.get(group)
        if table is None:
            raise DeckError(f"{path}: group &{group} is not known to scale_deck.py; add its "
                            f"variables and their dimensions to DIMENSIONS")
        new_items = []
        full = {}     # variables written in full with their defaults
        for target, values in items:
            m = re.fullmatch(r"([A-Za-z_]\w*)(?:\((.*)\))?", target)
            base, index = m.group(1).lower(), m.group(2)
            where = f"{path}: &{group} {target}"
            if base not in table:
                raise DeckError(f"{where}: variable '{base}' is not known to scale_deck.py (its "
                                f"dimension is not in DIMENSIONS); add it with its dimension")
            dim = table[base]
            values = expand(values)
            if base == "library" and any(v is not None and v.strip("'\"") for v in values):
                raise DeckError(f"{where}: a library material takes its values in the deck's &run units, which "
                                f"a scaled deck no longer has: write the entry's values out first")
            if dim == FILE:
                if any(v is not None and v.strip("'\"") for v in values):
                    raise DeckError(f"{where}: the grid's node coordinates are in the file, which this tool "
                                    f"does not scale (scale its dataset x by 2^L and name the copy)")
                new_items.append((target, values))
                continue
            if not isinstance(dim, tuple) or dim == NONE:
                new_items.append((target, values))
                continue
            factor = 2.0 ** (dim[0] * le + dim[1] * te + dim[2] * me)
            if (group, base) in NONZERO_DEFAULTS:
                arr = full.setdefault(base, list(NONZERO_DEFAULTS[(group, base)]))
                start = 0
                if index is not None:
                    if not re.fullmatch(r"\s*\d+\s*", index):
                        raise DeckError(f"{where}: only a single integer index is supported here")
                    start = int(index) - 1
                for j, v in enumerate(values):
                    if start + j >= len(arr):
                        raise DeckError(f"{where}: too many values")
                    if v is not None:
                        arr[start + j] = to_float(v, where)
                continue
            new_items.append((target, [scale_value(v, factor, where) for v in values]))
        for (g, base), default in NONZERO_DEFAULTS.items():
            if g == group:
                arr = full.get(base, list(default))
                dim = table[base]
                factor = 2.0 ** (dim[0] * le + dim[1] * te + dim[2] * me)
                new_items.append((base, [scale_value(repr(v), factor, f"{path}: &{group} {base}")
                                         for v in arr]))
        out.append((group, new_items))
    return out


def format_groups(groups):
    lines = []
    for group, items in groups:
        parts = []
        for target, values in items:
            parts.append(f"{target} = " + ", ".join("" if v is None else v for v in values))
        lines.append(f"&{group} " + ", ".join(parts) + " /")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("deck")
    ap.add_argument("out")
    ap.add_argument("--L", type=int, default=0, help="lengths are scaled by 2^L")
    ap.add_argument("--T", type=int, default=0, help="times are scaled by 2^T")
    ap.add_argument("--M", type=int, default=0, help="masses are scaled by 2^M")
    args = ap.parse_args(argv)
    try:
        with open(args.deck) as f:
            text = f.read()
        groups = scale_groups(parse(text, args.deck), args.deck, args.L, args.T, args.M)
    except (OSError, DeckError) as e:
        print(f"scale_deck: {e}", file=sys.stderr)
        return 1
    with open(args.out, "w") as f:
        f.write(f"! {args.deck} with lengths scaled by 2^{args.L}, times by 2^{args.T}, "
                f"masses by 2^{args.M} (tools/scale_deck.py; comments dropped)\n")
        f.write(format_groups(groups))
    return 0


if __name__ == "__main__":
    sys.exit(main())
