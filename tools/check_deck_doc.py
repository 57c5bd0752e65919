#!/usr/bin/python3
"""Check input/README.md against the namelist variables the code declares.

    check_deck_doc.py LSALEPM README.md

`LSALEPM --defaults` prints every namelist group with each variable at its
default, exactly as the packages' config modules declare and set them. This
script parses that and the README's tables (one `## &group` section each,
rows `| variable(s) | default | meaning |`) and checks both ways:
  - every variable the code reads is documented under its group;
  - every documented variable exists in the code;
  - the documented default equals the code's default.
README default cells are read as: `'text'` a string; `.true.`/`.false.`;
numbers (comma separated, one number stands for every element); `-huge`,
`+huge` the largest double; `none` an unset value (the largest double);
**required** (no default is compared); "the deck's file name" (the output
name, which the defaults printer resolves for a deck called deck.nml).
A row may name several variables (`a`, `b`) or a range over the six faces
(`xlo_velocity(3)` ... `zhi_velocity(3)`). Exit status 0: consistent.
"""
import re
import subprocess
import sys

FACES = ["xlo", "xhi", "ylo", "yhi", "zlo", "zhi"]
HUGE = 1.7976931348623157e308


def code_defaults(exe, required=None):
    """The code's defaults by group and variable; `required` (a set) gets
    the (group, variable) pairs that --defaults marks `! required`."""
    out = subprocess.run([exe, "--defaults"], check=True, capture_output=True, text=True).stdout
    groups, group, var = {}, None, None
    for line in out.splitlines():
        s = line.strip()
        m = re.search(r"\s*!\s*required.*$", s)
        if m:
            s = s[:m.start()]
            r = re.match(r"([A-Z_0-9]+)=", s)
            if required is not None and r and group is not None:
                required.add((group, r.group(1).lower()))
        if s.startswith("&"):
            group = s[1:].lower()
            groups[group] = {}
            continue
        if s == "/" or group is None:
            continue
        m = re.match(r"([A-Z_0-9]+)=(.*)$", s)
        if m:
            var = m.group(1).lower()
            groups[group][var] = m.group(2)
        else:
            groups[group][var] += s
    return {g: {v: parse_values(t) for v, t in vs.items()} for g, vs in groups.items()}


def parse_values(text):
    """gfortran namelist values: comma separated, n*value repeats."""
    vals = []
    for tok in re.findall(r'"[^"]*"|[^,\s]+', text):
        rep, val = 1, tok
        m = re.match(r"^(\d+)\*(.*)$", tok)
        if m:
            rep, val = int(m.group(1)), m.group(2)
        vals += [convert(val)] * rep
    return vals


def convert(tok):
    tok = tok.strip()
    if tok.startswith('"') or tok.startswith("'"):
        return tok[1:-1]
    if tok in ("T", ".true."):
        return True
    if tok in ("F", ".false."):
        return False
    return float(tok)


def readme_rows(path):
    rows, group = [], None
    for n, line in enumerate(open(path), 1):
        m = re.match(r"^## &(\w+)", line)
        if m:
            group = m.group(1)
            continue
        if line.startswith("## "):
            group = None
        if group is None or not line.startswith("| `"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rows.append((n, group, cells[0], cells[1], line))
    return rows


def expand_names(cell):
    names = re.findall(r"`([a-z_0-9]+)(?:\([^)]*\))?`", cell)
    if "..." in cell and len(names) == 2:
        a, b = names
        if a[:3] in FACES and b[:3] in FACES and a[3:] == b[3:]:
            return [f + a[3:] for f in FACES]
    return names


def readme_value(cell):
    """The documented default as a list of values, or None (not compared)."""
    c = cell.strip()
    if c.startswith("**required**") or "required" in c.split("(")[0]:
        return None
    if "deck's file name" in c:
        return ["deck"]
    m = re.match(r"^`'([^']*)'`", c)
    if m:
        return [m.group(1).replace("<N>", "1")]
    m = re.match(r"^`?(\.true\.|\.false\.)`?", c)
    if m:
        return [m.group(1) == ".true."]
    if c.startswith("none"):
        return [HUGE]
    lead = re.match(r"^([-+0-9.e, huge]+)", c)
    if not lead:
        return "unparsed"
    vals = []
    for tok in lead.group(1).split(","):
        tok = tok.strip()
        if not tok:
            continue
        if tok in ("-huge", "+huge", "huge"):
            vals.append(-HUGE if tok == "-huge" else HUGE)
            continue
        try:
            vals.append(float(tok))
        except ValueError:
            return "unparsed"
    return vals


def same(doc, code):
    if len(doc) == 1 and len(code) > 1:
        doc = doc * len(code)
    return len(doc) == len(code) and all(a == b for a, b in zip(doc, code))


def main():
    exe, readme = sys.argv[1], sys.argv[2]
    required = set()
    code = code_defaults(exe, required)
    problems, documented, checked = [], set(), 0
    for n, group, names_cell, default_cell, row in readme_rows(readme):
        names = expand_names(names_cell)
        doc = readme_value(default_cell)
        for name in names:
            documented.add((group, name))
            # `--defaults` marks `! required` what an empty group is refused
            # for: the README must say so (**required**, or "required" in
            # the row for a conditional one), and mark no other
            marked = (group, name) in required
            if marked and "required" not in row:
                problems.append(f"README line {n}: &{group} {name}: --defaults marks it required, the README does not")
            if default_cell.startswith("**required**") and not marked:
                problems.append(f"README line {n}: &{group} {name}: **required** in the README, not marked "
                                f"'! required' by --defaults")
            if group not in code or name not in code[group]:
                problems.append(f"README line {n}: &{group} {name} is documented but the code reads no such variable")
                continue
            if doc is None:
                continue
            if doc == "unparsed":
                problems.append(f"README line {n}: &{group} {name}: cannot read the default '{default_cell}'")
                continue
            checked += 1
            if not same(doc, code[group][name]):
                problems.append(f"README line {n}: &{group} {name}: documented default {default_cell!r}, "
                                f"the code's is {code[group][name][:6]}")
    for group, vs in code.items():
        for name in vs:
            if (group, name) not in documented:
                problems.append(f"&{group} {name}: the code reads it but input/README.md does not document it")
    nvars = sum(len(v) for v in code.values())
    for p in problems:
        print("FAIL:", p)
    print(f"{nvars} variables in {len(code)} groups; {len(documented)} documented; {checked} defaults compared; "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
