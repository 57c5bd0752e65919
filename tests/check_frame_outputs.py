#!/usr/bin/python3
"""What a frame and its XDMF series give a user (issue 13), checked on runs
of a two-material and a one-material deck.

    check_frame_outputs.py EXE TOOLS WORKDIR VERSION BUILD_TYPE DECK2 DECK1

DECK2 (two materials, a mixed cell) and DECK1 (one material) are run in
WORKDIR with `&run units = 'cm-us-g-Mbar'` added to DECK2 (DECK1 keeps no label).
Checked, and printed with the value found:
- per-material fields vf_<m>, density_<m>, energy_<m>, pressure_<m>: in a
  cell a material fills, the cell's own values; 0 where it is absent; in a
  mixed cell, fractions summing to 1 and the cell density equal to
  sum_m vf_m rho_m (relative 1e-13: the code's own closure, a few
  round-offs); a one-material frame has none of them;
- `material` an integer field in 1..nmat with the legend attributes
  `names` = "1: heavy, 2: light" and `values` = [1, 2];
- the file attributes code, code_version, build_type, title, unit_system,
  material_names;
- a `units` attribute on every dataset but `deck`, whose dimension agrees
  with tools/check_scaling.py's table (the invariance test's independent
  statement of each field's dimension);
- the XDMF lists every cell dataset (volume and material included) with the
  dimensions and number type of the HDF5 dataset it points to, the node
  fields, the field data (time, the legend) and the Information elements.
Exit status 0 pass, 1 fail.
"""
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

failures = []


def check(label, ok, found):
    print(f"{'ok  ' if ok else 'FAIL'} {label}: {found}")
    if not ok:
        failures.append(label)


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def run_deck(exe, deck, workdir, name, extra_run=""):
    with open(deck) as f:
        lines = f.read().splitlines()
    out = []
    for line in lines:
        if line.startswith("&run") and extra_run:
            line = re.sub(r"/\s*$", f", {extra_run} /", line)
        if line.startswith("&output"):
            line = f"&output dir = 'out', name = '{name}' /"
        out.append(line)
    path = os.path.join(workdir, name + ".nml")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    r = subprocess.run([exe, path], cwd=workdir, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout[-2000:], r.stderr[-2000:])
        raise SystemExit(f"FAIL: {exe} {path} exited {r.returncode}")
    frames = sorted(f for f in os.listdir(os.path.join(workdir, "out"))
                    if re.fullmatch(re.escape(name) + r"_\d{5}\.h5", f))
    return [os.path.join(workdir, "out", f) for f in frames], os.path.join(workdir, "out", name + ".xdmf")


def parse_units(u):
    """'mass/(length*time^2)' -> exponents (L, T, M); '1' -> (0, 0, 0)."""
    exps = {"length": 0, "time": 0, "mass": 0}

    def add(part, sign):
        part = part.strip().strip("()")
        for factor in filter(None, part.split("*")):
            base, _, power = factor.partition("^")
            if base not in exps:
                raise ValueError(f"unknown unit {base!r} in {u!r}")
            exps[base] += sign * (int(power) if power else 1)

    if u.strip() != "1":
        num, _, den = u.partition("/")
        if num.strip() != "1":
            add(num, 1)
        if den:
            add(den, -1)
    return exps["length"], exps["time"], exps["mass"]


def check_frame(path, materials, version, build_type, title, units_label, dimension):
    base = os.path.basename(path)
    with h5py.File(path, "r") as f:
        a = {k: text(v) for k, v in f.attrs.items()}
        legend = ", ".join(f"{i + 1}: {m}" for i, m in enumerate(materials))
        check(f"{base} file attributes", a.get("code") == "lsalepm" and a.get("code_version") == version
              and a.get("build_type") == build_type and a.get("title") == title
              and a.get("unit_system") == units_label and a.get("material_names") == legend, a)
        mat = f["material"]
        check(f"{base} material is an integer field", mat.dtype.kind == "i", mat.dtype)
        m = mat[()]
        check(f"{base} material values in 1..{len(materials)}",
              m.min() >= 1 and m.max() <= len(materials), (int(m.min()), int(m.max())))
        check(f"{base} material legend", text(mat.attrs.get("names")) == legend
              and list(mat.attrs.get("values")) == list(range(1, len(materials) + 1)),
              (text(mat.attrs.get("names")), list(mat.attrs.get("values"))))
        # units attributes against the invariance test's dimensions
        names = []
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        bad = []
        for n in names:
            if n == "deck":
                continue
            u = f[n].attrs.get("units")
            if u is None:
                bad.append(f"{n}: no units")
                continue
            try:
                got = parse_units(text(u))
            except ValueError as e:
                bad.append(str(e))
                continue
            if dimension(n) is None or tuple(got) != tuple(dimension(n)):
                bad.append(f"{n}: units {text(u)!r} = {got}, check_scaling says {dimension(n)}")
        check(f"{base} units of all {len(names) - 1} datasets agree with their dimensions", not bad,
              bad or "all agree")
        per = [p + mm for mm in materials for p in ("vf_", "density_", "energy_", "pressure_")]
        if len(materials) == 1:
            check(f"{base} one material: no per-material fields", not any(n in f for n in per),
                  [n for n in per if n in f])
            return
        missing = [n for n in per if n not in f]
        check(f"{base} per-material fields present", not missing, missing or per)
        if missing:
            return
        rho, e, p = f["density"][()], f["energy"][()], f["pressure"][()]
        vf = np.array([f["vf_" + mm][()] for mm in materials])
        rm = np.array([f["density_" + mm][()] for mm in materials])
        em = np.array([f["energy_" + mm][()] for mm in materials])
        pm = np.array([f["pressure_" + mm][()] for mm in materials])
        pure = vf.max(axis=0) == 1.0
        mixed = ~pure
        err_pure = 0.0
        for k in range(len(materials)):
            here = pure & (vf[k] == 1.0)
            err_pure = max(err_pure, float(np.max(np.abs(rm[k][here] - rho[here]), initial=0.0)),
                           float(np.max(np.abs(em[k][here] - e[here]), initial=0.0)),
                           float(np.max(np.abs(pm[k][here] - p[here]), initial=0.0)))
            absent = vf[k] == 0.0
            err_pure = max(err_pure, float(np.max(np.abs(rm[k][absent]), initial=0.0)),
                           float(np.max(np.abs(em[k][absent]), initial=0.0)),
                           float(np.max(np.abs(pm[k][absent]), initial=0.0)))
        check(f"{base} pure cells: the cell's values, 0 where absent (largest difference)",
              err_pure == 0.0, err_pure)
        check(f"{base} material is the largest fraction",
              np.array_equal(m, np.argmax(vf, axis=0) + 1), "index of max vf_<m>")
        nmixed = int(mixed.sum())
        if nmixed:
            s = np.max(np.abs(vf[:, mixed].sum(axis=0) - 1.0))
            r = np.max(np.abs((vf * rm)[:, mixed].sum(axis=0) - rho[mixed]) / rho[mixed])
            check(f"{base} {nmixed} mixed cell(s): fractions sum to 1 (1e-13)", s <= 1e-13, s)
            check(f"{base} {nmixed} mixed cell(s): sum vf_m rho_m = rho (1e-13 relative)", r <= 1e-13, r)
            check(f"{base} {nmixed} mixed cell(s): material states positive",
                  bool(np.all(rm[vf > 0] > 0) and np.all(em[vf > 0] > 0)), "rho_m, e_m > 0")
        return nmixed


def check_xdmf(path, frames, materials, title, units_label):
    base = os.path.basename(path)
    root = ET.parse(path).getroot()
    info = {i.get("Name"): i.get("Value") for i in root.iter("Information")}
    check(f"{base} Information", info.get("title") == title and info.get("unit_system") == units_label
          and info.get("code") == "lsalepm" and "code_version" in info, info)
    grids = [g for g in root.iter("Grid") if g.get("GridType") == "Uniform"]
    check(f"{base} one grid per frame", len(grids) == len(frames), (len(grids), len(frames)))
    for g, frame in zip(grids, frames):
        attrs = {a.get("Name"): a for a in g.findall("Attribute")}
        with h5py.File(frame, "r") as f:
            cell_ds = [n for n in f if isinstance(f[n], h5py.Dataset) and f[n].shape == f["density"].shape]
            listed_cells = [n for n, a in attrs.items() if a.get("Center") == "Cell"]
            check(f"{base} {os.path.basename(frame)}: every cell dataset listed",
                  sorted(cell_ds) == sorted(listed_cells),
                  f"{len(listed_cells)} cell fields: {', '.join(sorted(listed_cells))}")
            bad = []
            for n, a in attrs.items():
                item = a.find("DataItem")
                if item.get("Format") != "HDF":
                    continue
                file_, _, ds = item.text.strip().partition(":")
                ds = ds.lstrip("/")
                if file_ != os.path.basename(frame) or ds not in f:
                    bad.append(f"{n}: {item.text.strip()}")
                    continue
                dims = tuple(int(d) for d in item.get("Dimensions").split())
                kind = {"Float": "f", "Int": "i"}[item.get("NumberType")]
                if dims != f[ds].shape or kind != f[ds].dtype.kind or \
                        int(item.get("Precision")) != f[ds].dtype.itemsize:
                    bad.append(f"{n}: {dims} {item.get('NumberType')}{item.get('Precision')} against "
                               f"{f[ds].shape} {f[ds].dtype}")
            check(f"{base} {os.path.basename(frame)}: DataItems match the HDF5 datasets", not bad,
                  bad or f"{len(attrs)} attributes")
            t = float(f["time"][()])
        # the field data: in the grid's <Information Name="field_data">, which
        # an XInclude brings into the grid (readers without XInclude skip it)
        fd = g.find("Information[@Name='field_data']")
        inc = g.find("{http://www.w3.org/2001/XInclude}include")
        check(f"{base} {os.path.basename(frame)}: field data included",
              fd is not None and inc is not None and "field_data" in inc.get("xpointer", "")
              and not any(a.get("Center") == "Grid" for a in attrs.values()), "Information + xi:include")
        field = {a.get("Name"): float(a.find("DataItem").text) for a in (fd if fd is not None else [])
                 if a.get("Center") == "Grid"}
        want = {"time": t}
        if len(materials) > 0:
            want.update({f"material {i + 1}: {m}": float(i + 1) for i, m in enumerate(materials)})
        check(f"{base} {os.path.basename(frame)}: field data", field == want, field)


def main():
    if len(sys.argv) != 8:
        raise SystemExit(__doc__)
    exe, tools, workdir, version, build_type, deck2, deck1 = sys.argv[1:]
    sys.path.insert(0, tools)
    sys.dont_write_bytecode = True
    from check_scaling import dimension
    os.makedirs(workdir, exist_ok=True)

    frames, xdmf = run_deck(exe, deck2, workdir, "two", "units = 'cm-us-g-Mbar'")
    title2 = re.search(r"title\s*=\s*'([^']*)'", open(deck2).read()).group(1)
    mats2 = re.findall(r"&material\s+name\s*=\s*'([^']*)'", open(deck2).read())
    nmixed = 0
    for fr in frames:
        nmixed += check_frame(fr, mats2, version, build_type, title2, "cm-us-g-Mbar", dimension) or 0
    check("the two-material run has a mixed cell to check", nmixed > 0, nmixed)
    check_xdmf(xdmf, frames, mats2, title2, "cm-us-g-Mbar")

    frames, xdmf = run_deck(exe, deck1, workdir, "one")
    title1 = re.search(r"title\s*=\s*'([^']*)'", open(deck1).read()).group(1)
    mats1 = re.findall(r"&material\s+name\s*=\s*'([^']*)'", open(deck1).read())
    for fr in frames:
        check_frame(fr, mats1, version, build_type, title1, "", dimension)
    check_xdmf(xdmf, frames, mats1, title1, "")

    if failures:
        print(f"FAIL: {len(failures)} check(s): {'; '.join(failures)}")
        return 1
    print("PASS: frames and XDMF as documented")
    return 0


if __name__ == "__main__":
    sys.exit(main())
