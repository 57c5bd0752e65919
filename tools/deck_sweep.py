#!/usr/bin/python3
"""The deck sweep: every deck of tests/decks and input/ (but the bad_* decks
made to be refused and the oom_* ones made to exceed a memory limit), as it
is and in the variants a user may choose, for a
limited number of steps, one line per run; a robustness check of settings
the decks' own tests do not combine, not a test of answers.

    deck_sweep.py --exe build/release/lsalepm --out build/deck-sweep
                  [--variants asis,global,lssm,smooth] [--steps 300]
                  [--ranks 1] [--jobs 2] [--timeout 300] [PATTERN ...]

Variants (each deck's &rezone mode replaced, Euler steps every 3 steps, its
other &rezone settings kept; or a setting added to a group):
  asis      the deck as it is
  global    &rezone mode = 'global', interval_steps = 3
  lssm      &rezone mode = 'lssm', interval_steps = 3
  smooth    &rezone mode = 'smooth', interval_steps = 3
  cube      &rezone mode = 'lssm', interval_steps = 3, smooth_target = 'cube'
  original  &hydro stress_update = 'original'
  linear    &hydro particle_support = 'linear'
  q4        &hydro particle_q = 0.4
Each run gets &run max_steps = STEPS (or the deck's own, if fewer) and its
own &output dir under OUT; the deck's other files (points, surfaces) are
linked beside it. PATTERNs (regular expressions) keep the decks whose names
match one. --ranks N runs each on N MPI ranks (oversubscribed), one run at a
time.

A run passes when it ends with exit status 0; it is refused when the deck
so changed is refused (exit status 2: a rank count its grid cannot take, a
setting a variant adds that the deck cannot have), listed apart; it fails on
a runtime failure (1), an internal error (5), a signal or the timeout, but
for the decks built to fail (EXPECTED_FAIL), which must fail with status 1
(in the variants listed there).
Prints one line per run (name, outcome, status, its last FATAL or ERROR
line, else its last line) and a summary; also OUT/deck_sweep.txt. Exit
status 1 if any run fails.
"""
import argparse
import concurrent.futures as cf
import os
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
VARIANTS = {
    "asis": None,
    "global": ("rezone", "mode = 'global', interval_steps = 3"),
    "lssm": ("rezone", "mode = 'lssm', interval_steps = 3"),
    "smooth": ("rezone", "mode = 'smooth', interval_steps = 3"),
    "cube": ("rezone", "mode = 'lssm', interval_steps = 3, smooth_target = 'cube'"),
    "original": ("hydro", "stress_update = 'original'"),
    "linear": ("hydro", "particle_support = 'linear'"),
    "q4": ("hydro", "particle_q = 0.4"),
}
# decks whose run fails by design (their tests check the failure report),
# and the variants in which it must: a grid tangled from the start fails in
# any; the water's runaway needs the deck's own Euler steps
EXPECTED_FAIL = {"tangle_block": set(VARIANTS), "water_tnt_tangle": {"asis"}}


def drop_setting(text, group, key):
    """The deck text with `key = value` taken out of its first &group."""
    return re.sub(rf"(&{group}\b[^/]*?)\b{key}\s*=\s*('[^']*'|[^,/]+)\s*,?", r"\1", text, count=1,
                  flags=re.I | re.S)


def set_group(text, group, settings):
    """The deck text with settings (`a = 1, b = 'x'`) at the start of its
    first &group (the same keys taken out of it), or a new group."""
    if not re.search(rf"&{group}\b", text, flags=re.I):
        return text + f"\n&{group} {settings} /\n"
    for kv in settings.split(","):
        text = drop_setting(text, group, kv.split("=")[0].strip())
    return re.sub(rf"&{group}\b", f"&{group} {settings},", text, count=1, flags=re.I)


def variant_deck(text, variant, steps, outdir):
    """A deck's text as the variant runs it (for at most `steps` steps, or
    the deck's own max_steps if fewer: a deck made short stays so)."""
    own = re.search(r"&run\b[^/]*?\bmax_steps\s*=\s*(\d+)", text, flags=re.I | re.S)
    if own:
        steps = min(steps, int(own.group(1)))
    text = set_group(text, "run", f"max_steps = {steps}")
    text = drop_setting(text, "output", "dir")
    text = set_group(text, "output", f"dir = '{outdir}'")
    if VARIANTS[variant] is not None:
        text = set_group(text, *VARIANTS[variant])
    return text


def run_one(exe, deck, variant, a):
    name = deck.stem + ("" if variant == "asis" else "_" + variant)
    d = pathlib.Path(a.out) / "runs" / name
    d.mkdir(parents=True, exist_ok=True)
    for f in deck.parent.iterdir():
        if f.is_file() and f.suffix != ".nml" and not (d / f.name).exists():
            (d / f.name).symlink_to(f)
    path = d / (name + ".nml")
    path.write_text(variant_deck(deck.read_text(), variant, a.steps, d))
    cmd = [exe, str(path)]
    if a.ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(a.ranks)] + cmd
        if os.geteuid() == 0:
            cmd.insert(1, "--allow-run-as-root")
    try:
        r = subprocess.run(cmd, cwd=d, capture_output=True, text=True, timeout=a.timeout,
                           env=dict(os.environ, OMP_NUM_THREADS="1"))
        status, tail = r.returncode, (r.stdout + r.stderr)[-3000:]
    except subprocess.TimeoutExpired:
        status, tail = "timeout", ""
    (d / "run.txt").write_text(f"{status}\n{tail}")
    lines = [s for s in tail.splitlines() if s.strip()]
    said = [s for s in lines if "FATAL" in s or "ERROR" in s] or lines
    if variant in EXPECTED_FAIL.get(deck.stem, ()):
        outcome = "pass" if status == 1 else "FAIL"
    else:
        outcome = {0: "pass", 2: "refused"}.get(status, "FAIL")
    return name, status, outcome, said[-1][:200] if said else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--exe", default=str(ROOT / "build/release/lsalepm"))
    ap.add_argument("--out", default=str(ROOT / "build/deck-sweep"))
    ap.add_argument("--variants", default="asis,global,lssm,smooth")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("patterns", nargs="*")
    a = ap.parse_args()
    variants = a.variants.split(",")
    bad = [v for v in variants if v not in VARIANTS]
    if bad:
        ap.error(f"unknown variant(s) {', '.join(bad)}; known: {', '.join(VARIANTS)}")
    decks = [p for p in sorted((ROOT / "tests/decks").glob("*.nml")) + sorted((ROOT / "input").glob("*.nml"))
             if not p.stem.startswith(("bad_", "oom_"))
             and (not a.patterns or any(re.search(q, p.stem) for q in a.patterns))]
    exe = str(pathlib.Path(a.exe).resolve())
    a.out = str(pathlib.Path(a.out).resolve())
    pathlib.Path(a.out).mkdir(parents=True, exist_ok=True)
    jobs = 1 if a.ranks > 1 else a.jobs
    rows = []
    with cf.ThreadPoolExecutor(jobs) as ex, open(pathlib.Path(a.out) / "deck_sweep.txt", "w") as log:
        futures = [ex.submit(run_one, exe, d, v, a) for d in decks for v in variants]
        for f in cf.as_completed(futures):
            name, status, outcome, said = f.result()
            rows.append((name, outcome))
            line = f"{name:40s} {outcome:8s} {str(status):8s} {said}"
            print(line, flush=True)
            log.write(line + "\n")
        refused = sorted(n for n, o in rows if o == "refused")
        failed = sorted(n for n, o in rows if o == "FAIL")
        line = (f"{len(rows) - len(refused) - len(failed)} of {len(rows)} runs pass"
                + (f"; refused: {' '.join(refused)}" if refused else "")
                + (f"; failed: {' '.join(failed)}" if failed else ""))
        print(line)
        log.write(line + "\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
