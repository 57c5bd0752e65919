#!/usr/bin/python3
"""Write the particle groups of input/building.nml (paper Sect. 7.7, the
open-frame building) from the dimensions below, between the deck's lines
'! --- geometry: tools/building_deck.py ---' and '! --- end of geometry ---'.

    building_deck.py input/building.nml          # rewrite the groups in place
    building_deck.py input/building.nml --check  # exit 1 if they differ

The frame: two storeys of a one-bay-deep frame, a quarter-scale model
(Woodson and Baylot's structure as the paper describes it: two floors, four
columns in the half model). Units mm. The deck's header says which numbers
are the paper's and which were chosen here. Rebar as lines of particles
(&particles shape = 'line') with Table 8's areas: D5 column bars, W0.5
column ties, D1 slab bars both ways, top and bottom.
"""
import argparse
import sys

COL = 90.0                 # column side
STOREY = 900.0             # storey height, floor to floor
SLAB = 45.0                # slab thickness (the top SLAB of each storey)
FRONT_X = 1440.0           # the front columns' face towards the charge
BAY = 1215.0               # column spacing, centre to centre, in x and y
COVER = 15.0               # bar centre to the concrete face (columns)
SLAB_COVER = 12.0          # bar centre to the slab's face
TIE_SPACING = 90.0
SLAB_BAR_SPACING = 150.0
AREA = {"D5": 32.2, "D1": 6.45, "W0.5": 3.22}   # Table 8, mm^2
BEGIN = "! --- geometry: tools/building_deck.py ---"
END = "! --- end of geometry ---"


def fmt(v):
    return ("%.2f" % v).rstrip("0").rstrip(".")


def box(lo, hi, body):
    return ("&particles shape = 'box', lo = %s, hi = %s, solid = 'concrete', body = %d,\n"
            "           stress = -0.1, -0.1, -0.1, 0, 0, 0 /"
            % (", ".join(fmt(v) for v in lo), ", ".join(fmt(v) for v in hi), body))


def line(p, q, kind):
    return ("&particles shape = 'line', point = %s, point2 = %s, area = %s, solid = '%s', body = 3 /"
            % (", ".join(fmt(v) for v in p), ", ".join(fmt(v) for v in q), fmt(AREA[kind]), kind.lower().replace('.', '')))


def columns():
    """(x0, y0, y1, halved) of each column's plan: the centre columns on the
    symmetry plane y = 0 are halves."""
    out = []
    for x0 in (FRONT_X, FRONT_X + BAY):
        out.append((x0, 0.0, COL / 2, True))
        out.append((x0, BAY - COL / 2, BAY + COL / 2, False))
    return out


def groups():
    g = ["! concrete: body 1 the front centre column's lower storey (the column measured), body 2 the rest"]
    xe = FRONT_X + BAY + COL       # the slabs' far edge
    ye = BAY + COL / 2
    for s in range(2):
        z0 = s * STOREY
        for k, (x0, y0, y1, _) in enumerate(columns()):
            body = 1 if (s == 0 and k == 0) else 2
            g.append(box((x0, y0, z0), (x0 + COL, y1, z0 + STOREY - SLAB), body))
        g.append(box((FRONT_X, 0.0, z0 + STOREY - SLAB), (xe, ye, z0 + STOREY), 2))
    g.append("! column bars (D5), full height, 15 mm cover; a centre column's bars at y < 0 are its mirror's")
    for x0, y0, y1, half in columns():
        ys = (y1 - COVER,) if half else (y0 + COVER, y1 - COVER)
        for xb in (x0 + COVER, x0 + COL - COVER):
            for yb in ys:
                g.append(line((xb, yb, 0.0), (xb, yb, 2 * STOREY), "D5"))
    g.append("! column ties (W0.5) every 90 mm in each storey, through the bars' centres")
    for s in range(2):
        z = s * STOREY + TIE_SPACING / 2
        while z < (s + 1) * STOREY - SLAB:
            for x0, y0, y1, half in columns():
                xa, xb = x0 + COVER, x0 + COL - COVER
                ya, yb = (0.0 if half else y0 + COVER), y1 - COVER
                g.append(line((xa, ya, z), (xa, yb, z), "W0.5"))
                g.append(line((xa, yb, z), (xb, yb, z), "W0.5"))
                g.append(line((xb, ya, z), (xb, yb, z), "W0.5"))
                if not half:
                    g.append(line((xa, ya, z), (xb, ya, z), "W0.5"))
            z += TIE_SPACING
    g.append("! slab bars (D1) both ways every 150 mm, bottom and top layers")
    for s in range(2):
        top = (s + 1) * STOREY
        for zb in (top - SLAB + SLAB_COVER, top - SLAB_COVER):
            y = SLAB_BAR_SPACING / 2
            while y < ye:
                g.append(line((FRONT_X + COVER, y, zb), (xe - COVER, y, zb), "D1"))
                y += SLAB_BAR_SPACING
            x = FRONT_X + COVER + 10.0
            while x < xe:
                g.append(line((x, 0.0, zb), (x, ye - COVER, zb), "D1"))
                x += SLAB_BAR_SPACING
    return g


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("deck")
    ap.add_argument("--check", action="store_true", help="exit 1 if the deck's groups differ")
    a = ap.parse_args()
    text = open(a.deck).read().split("\n")
    try:
        i, j = text.index(BEGIN), text.index(END)
    except ValueError:
        sys.exit("%s: no '%s' ... '%s' lines" % (a.deck, BEGIN, END))
    new = "\n".join(text[:i + 1] + groups() + text[j:])
    if a.check:
        sys.exit(0 if new == "\n".join(text) else 1)
    open(a.deck, "w").write(new)


if __name__ == "__main__":
    main()
