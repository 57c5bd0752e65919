#!/usr/bin/env python3
"""Tests of tools/hardcases.py's parts, on synthetic logs and frames (no
solver run): the deck editor, the log parser, the run outcome, the frame
scan (only cells where a material's vf > 0 count; NaN is caught), the bars,
the entry selection (and --sweep's), two error metrics and Taylor's plate.

    test_hardcases.py TOOLS_DIR
"""
import math
import os
import sys
import tempfile

import h5py
import numpy as np

TOOLS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "tools")
sys.path.insert(0, os.path.abspath(TOOLS))
sys.dont_write_bytecode = True
import hardcases as hc  # noqa: E402

failures = []


def check(label, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {label}" + (f": {detail}" if detail else ""))
    if not ok:
        failures.append(label)


# ---------------------------------------------------------------- decks
DECK = """! header: &notagroup in a comment, and a slash / too
&run title = 'a / title! with ''quotes''', t_end = 0.2 /
&grid ni = 4, nj = 1, nk = 1,
      xmax = 1, 0.25, 0.25 /   ! trailing comment
&region shape = 'all', density = 1 /
&region shape = 'box', density = 0.125, lo = 0.5, -1, -1 /
&rezone mode = 'lssm' /
&output dir = 'out/x', gauge = 0.1, 0, 0, 0.2, 0, 0 /
"""
d = hc.Deck(DECK)
check("deck: groups found", [p[0] for p in d.parts if isinstance(p, list)]
      == ["run", "grid", "region", "region", "rezone", "output"])
check("deck: string with / and ! kept", d.get("run", "title") == "'a / title! with ''quotes'''", d.get("run", "title"))
check("deck: multi-line array value", d.get("grid", "xmax") == "1, 0.25, 0.25", d.get("grid", "xmax"))
check("deck: second region", d.get("region", "density", 1) == "0.125")
d.set("grid", "ni", "100")
d.set("region", "density", "1e3", 1)
d.set("output", "name", "'e'")
d.remove_groups("rezone")
d.add_group("rezone", [("mode", "'global'"), ("interval_steps", "1")])
text = d.text()
check("deck: header kept", text.startswith("! header: &notagroup"))
check("deck: edits written", "ni = 100" in text and "density = 1e3" in text and "name = 'e'" in text)
check("deck: one &rezone, the new one", text.count("&rezone") == 1 and "interval_steps = 1" in text)
check("deck: re-read gives the same", hc.Deck(text).text() == text)

# every entry's deck is made (sizes' edits name groups the base decks have)
with tempfile.TemporaryDirectory() as tmp:
    bad = []
    for e in hc.entries(hc._cases()):
        try:
            t = hc.make_deck(e, os.path.join(tmp, e.name), tmp)
            dd = hc.Deck(t)
            if dd.get("output", "name") != f"'{e.name}'":
                bad.append(e.name + ": name")
            if (e.mode == "lagrange") != (dd.get("rezone", "mode") is None):
                bad.append(e.name + ": rezone")
        except Exception as exc:  # noqa: BLE001
            bad.append(f"{e.name}: {exc}")
    check("every entry's deck is made", not bad, "; ".join(bad))

# ---------------------------------------------------------------- selection
names = [e.name for e in hc.entries(hc._cases(), quick=True)]
check("quick: first sizes", "sod2_100_ale" in names and "sod2_1000_ale" not in names and "tnt_64_euler" not in names)
sweep = [e.name for e in hc.entries(hc._cases(), sweep=True)]
check("sweep: small sizes, modes the matrix leaves out, variants",
      "saltzman_100x10_lssm_h2" in sweep and "triple_70x30_euler_mixed" in sweep and "sedov_20_lssm" not in sweep
      and "sedov_20_euler" in sweep and "sedov_40_euler" not in sweep and "sedov_20_euler_mixed" not in sweep,
      f"{len(sweep)} entries")
with tempfile.TemporaryDirectory() as tmp:
    d = hc.Deck(hc.make_deck([e for e in hc.entries(hc._cases(), sweep=True) if e.name == "sedov_20_lssm_h2"][0],
                             tmp, tmp))
    check("sweep: a variant's &rezone", d.get("rezone", "hysteresis") == "0.2" and d.get("rezone", "mode") == "'lssm'")
check("only: substring and wildcard", [e.name for e in hc.entries(hc._cases(), only=["sod2_100_l*", "tnt_16_e"])]
      == ["tnt_16_euler", "tnt_16_euler_quarter", "sod2_100_lagrange", "sod2_100_lssm"])

# ---------------------------------------------------------------- the log
LOG = """resolved input:
&MATERIAL
 NAME="tnt",
 EOS="jwl",
 P_MIN= -1.7976931348623157E+308,
 /
&MATERIAL
 NAME="air",
 EOS="ideal_gas",
 P_MIN=  0.0000000000000000     ,
 /
grid: 10 x 2 x 1 cells, 66 nodes, 2 material(s)
euler 1 due at step 3: interval
euler 1 at step 3, t =  1.0E-01: 5 cells remapped, 15 copied, reach 1; rezone    0.100 s, remap    0.200 s (prepare 0)
  conservation: relative change of mass  1.00E-15, momentum  3.00E-14, total energy  2.00E-16; momentum taken 0 0 0
euler 2 at step 4, t =  2.0E-01: 20 cells remapped, 0 copied, reach 1; rezone    0.000 s, remap    0.300 s (prepare 0)
  conservation: relative change of mass  1.00E-15, momentum  1.00E-16, total energy  7.00E-13; momentum taken 0 0 0
euler step skipped at step 5: no cell has Q < 0.5
timers [s]: setup     0.1  lagrange     1.0  euler     0.700  output     0.1  total     2.0
done: t = 2.0000000E-01 after 5 steps
"""
g = hc.parse_log(LOG)
check("log: materials", [(m["name"], m["eos"]) for m in g["materials"]] == [("tnt", "jwl"), ("air", "ideal_gas")])
check("log: unset p_min", g["materials"][0]["p_min"] <= hc.P_MIN_UNSET and g["materials"][1]["p_min"] == 0.0)
check("log: Euler steps (a skipped one not counted)", g["euler_steps"] == 2, g["euler_steps"])
check("log: cells remapped and shares", g["cells_remapped"] == 25 and g["shares"] == [0.25, 1.0])
check("log: conservation worst", max(max(c) for c in g["conservation"]) == 7.0e-13)
check("log: Euler seconds", g["euler_seconds"] == 0.7 and abs(g["euler_step_seconds"] - 0.6) < 1e-12)
check("log: done", g["done"] == (0.2, 5))
check("log: skipped Euler steps", g["skipped"] == 1 and hc.euler_steps_text(g) == "2 (1 skipped)")

NAN_LOG = "  conservation: relative change of mass        NaN, momentum  1.00E-16, total energy  1.00E-16; x\n"
check("log: NaN conservation read as NaN", math.isnan(hc.parse_log(NAN_LOG)["conservation"][0][0]))

FATAL = LOG.replace("done: t = 2.0000000E-01 after 5 steps\n", "") + (
    "FATAL [rank 0, step 7] lagrange_step: cell 4 has a non-positive volume (tangled grid) at t = 1.0E-01\n"
    "state at failure written to /x/y/run_00003.h5\n")


def outcome(mode, rc, text, wall=1.0):
    e = [x for x in hc.entries(hc._cases()) if x.mode == mode][0]
    r = hc.Run(e, "/x/y", rc=rc, wall=wall)
    return hc.status_of(r, hc.parse_log(text))


check("status: ok", outcome("euler", 0, LOG) == (True, False, "ok"))
s = outcome("lagrange", 1, FATAL)
check("status: Lagrangian tangle allowed", s[:2] == (False, True) and s[2].startswith("tangle (Lagrangian): step 7:"), s)
s = outcome("euler", 1, FATAL)
check("status: tangle with an Euler phase fails", s[:2] == (False, False) and "cell 4" in s[2], s)
check("status: failure frame", hc.parse_log(FATAL)["failure_frame"] == "/x/y/run_00003.h5")
check("status: timeout", outcome("euler", "timeout", "", 12.0)[2] == "timeout after 12 s (killed)")
s = outcome("euler", 2, "ERROR: /x/y/d.nml:3: &grid: ni = 0 must be >= 1\nERROR: the deck has 1 problem(s)\n")
check("status: refused", s[2] == "refused (exit 2): d.nml:3: &grid: ni = 0 must be >= 1", s)
check("status: signal", outcome("euler", -11, "")[2] == "killed by signal SIGSEGV")
s = outcome("euler", 5, "Fortran runtime error: Index '0' of dimension 1 of array 'a' below lower bound of 1\n")
check("status: runtime error", s[2].startswith("crashed (exit 5): Fortran runtime error"), s)
check("status: exit 0 without done", outcome("euler", 0, "")[2] == "exit 0 without a 'done:' line")


# ---------------------------------------------------------------- frames
def write_frame(path, names, fields, extra=None):
    with h5py.File(path, "w") as f:
        f.attrs["material_names"] = ", ".join(f"{k + 1}: {n}" for k, n in enumerate(names)).encode()
        for k, v in fields.items():
            f[k] = np.asarray(v, dtype=float)
        for k, v in (extra or {}).items():
            f[k] = v


with tempfile.TemporaryDirectory() as tmp:
    two = dict(vf_a=[[[1.0, 0.5, 0.0]]], vf_b=[[[0.0, 0.5, 1.0]]],
               density_a=[[[1.0, 2.0, -5.0]]], density_b=[[[-7.0, 0.1, 0.2]]],
               energy_a=[[[1.0, 1.0, 1.0]]], energy_b=[[[9.0, -0.5, 3.0]]],
               pressure_a=[[[3.0, 2.0, 1.0]]], pressure_b=[[[0.0, -1.0, 2.0]]],
               x=np.zeros((2, 2, 4, 3)), velocity=np.zeros((2, 2, 4, 3)))
    write_frame(os.path.join(tmp, "r_00000.h5"), ["a", "b"], two)
    later = dict(two, density_a=[[[0.5, 2.0, -5.0]]])
    write_frame(os.path.join(tmp, "r_00001.h5"), ["a", "b"], later)
    write_frame(os.path.join(tmp, "r_00002.h5"), ["a", "b"], dict(two, density_a=[[[-1e9, 2.0, 1.0]]]))
    paths = hc.frame_paths(tmp, "r", failure_frame=os.path.join(tmp, "r_00002.h5"))
    check("frames: the failure frame left out", [os.path.basename(p) for p in paths] == ["r_00000.h5", "r_00001.h5"])
    mins, nan = hc.scan_frames(paths)
    check("frames: vf > 0 only, min over frames", mins["a"]["density"] == 0.5 and mins["b"]["density"] == 0.1, mins)
    check("frames: energy and pressure", mins["b"]["energy"] == -0.5 and mins["b"]["pressure"] == -1.0, mins)
    check("frames: overall min names the material", hc.overall_min(mins, "energy") == (-0.5, "b"))
    check("frames: nothing NaN", nan == "")
    mats = [dict(name="a", eos="jwl", p_min=hc.P_MIN_UNSET * 2), dict(name="b", eos="ideal_gas", p_min=-2.0)]
    probs = hc.material_bars(mins, mats)
    check("bars: ideal gas energy < 0 caught, its pressure above its p_min, JWL unbarred",
          probs == ["energy -0.5 of b"], probs)
    mats[0]["p_min"] = 0.5
    mats[1]["p_min"] = hc.P_MIN_UNSET * 2
    probs = hc.material_bars(mins, mats)
    check("bars: JWL p_min, ideal gas floor 0",
          "pressure -1 of b < 0" in probs and not any("of a" in s for s in probs), probs)
    mats[0]["p_min"] = 2.5
    check("bars: JWL below its p_min", "pressure 2 of a < p_min 2.5" in hc.material_bars(mins, mats))

    one = dict(density=[[[1.0, np.nan]]], energy=[[[1.0, 1.0]]], pressure=[[[1.0, 1.0]]])
    write_frame(os.path.join(tmp, "s_00000.h5"), ["gas"], one)
    mins, nan = hc.scan_frames(hc.frame_paths(tmp, "s"))
    check("frames: one material uses the cell fields; NaN caught",
          math.isnan(mins["gas"]["density"]) and "density_gas not finite" in nan, (mins, nan))
    check("bars: NaN density fails", any("NaN" in s for s in hc.material_bars(mins, [])))

    # judge: conservation bar and the outcome
    row = dict(completed=True, allowed=False, nan="", mins={}, log=dict(materials=[]), conservation=2e-12,
               problems=[])
    hc.judge(row)
    check("judge: conservation above 1e-12 fails", not row["pass"] and "conservation" in row["problems"][0])
    row = dict(completed=False, allowed=True, nan="", mins={}, log=dict(materials=[]), conservation=None,
               problems=[])
    hc.judge(row)
    check("judge: a Lagrangian tangle passes", row["pass"])

    # error metrics on synthetic quasi-1D / quasi-2D frames
    def tube(path, edges, rho):
        n = len(rho)
        x = np.zeros((2, 2, n + 1, 3))
        x[..., 0] = edges
        x[:, 1, :, 1] = 1.0
        x[1, :, :, 2] = 1.0
        with h5py.File(path, "w") as f:
            f["x"], f["velocity"] = x, np.zeros_like(x)
            for k in ("density", "pressure", "energy"):
                f[k] = np.asarray(rho, dtype=float).reshape(1, 1, n)
            f["volume"] = np.diff(edges).reshape(1, 1, n)
            f["time"], f["step"] = 0.1, 1

    fine_edges = np.linspace(0.0, 1.0, 9)
    fine = np.array([1, 1, 2, 4, 4, 4, 3, 1], dtype=float)
    tube(os.path.join(tmp, "fine.h5"), fine_edges, fine)
    tube(os.path.join(tmp, "coarse.h5"), fine_edges[::2], 0.5 * (fine[0::2] + fine[1::2]))
    v = hc.tube_relative_l1(os.path.join(tmp, "coarse.h5"), os.path.join(tmp, "fine.h5"))
    check("metric: the averaged fine tube is 0 from itself", abs(v) < 1e-14, v)
    tube(os.path.join(tmp, "coarse2.h5"), fine_edges[::2], 0.5 * (fine[0::2] + fine[1::2]) + [0, 0, 0, 1])
    v = hc.tube_relative_l1(os.path.join(tmp, "coarse2.h5"), os.path.join(tmp, "fine.h5"))
    check("metric: relative L1 of a known difference", abs(v - 0.25 / 2.5) < 1e-14, v)

    def plate(path, ni, nj, rho):
        xs, ys = np.meshgrid(np.linspace(0, 1, ni + 1), np.linspace(0, 1, nj + 1))
        x = np.zeros((2, nj + 1, ni + 1, 3))
        x[..., 0], x[..., 1] = xs, ys
        x[1, ..., 2] = 0.1
        with h5py.File(path, "w") as f:
            f["x"], f["velocity"] = x, np.zeros_like(x)
            f["density"] = rho.reshape(1, nj, ni)
            f["volume"] = np.full((1, nj, ni), 0.1 / (ni * nj))
            f["time"], f["step"] = 1.0, 1

    rf = np.arange(32.0).reshape(4, 8)
    plate(os.path.join(tmp, "pf.h5"), 8, 4, rf)
    rc = rf.reshape(2, 2, 4, 2).mean(axis=(1, 3))
    plate(os.path.join(tmp, "pc.h5"), 4, 2, rc)
    l1, how = hc.triple_l1(os.path.join(tmp, "pc.h5"), os.path.join(tmp, "pf.h5"), True)
    check("metric: 2x2 average of the fine plate", abs(l1) < 1e-13 and how == "2x2 average", (l1, how))
    l1, how = hc.triple_l1(os.path.join(tmp, "pc.h5"), os.path.join(tmp, "pf.h5"), False)
    check("metric: interpolation of a linear field is exact", abs(l1) < 1e-12 and how == "interpolated", (l1, how))

# Taylor's free plate under an exponential wave: the closed form
# u_max = (2 P0 theta / m) beta^(beta / (1 - beta)), beta = z theta / m, is
# reached when the face pressure 2 p_i - z u falls to zero (cut-off 0)
for beta in (0.3, 2.0):
    theta, p0, z = 10.0, 0.05, 1.48
    m = z * theta / beta
    tt = np.linspace(0.0, 200.0, 40001)
    u_num = hc.taylor_plate(tt, p0 * np.exp(-tt / theta), m, z, 0.0)
    u_exact = 2 * p0 * theta / m * beta ** (beta / (1 - beta))
    check(f"metric: Taylor plate, exponential wave, beta {beta}", abs(u_num / u_exact - 1) < 1e-4,
          (u_num, u_exact))

print(f"{len(failures)} failure(s)" if failures else "all hardcases tool checks pass")
sys.exit(1 if failures else 0)
