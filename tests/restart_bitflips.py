#!/usr/bin/env python3
"""Random bit flips in a restart file: each trial flips one bit of a fresh
copy and continues the run from it. A trial must either be refused (exit
status 2, an ERROR line, "cannot restart", no step taken) or run to the end
with a final frame bit-identical to the continuation from the unflipped file;
a changed result, a crash or a hang (timeout) fails the test.

    restart_bitflips.py EXE COMPARE DUMP DECK REF_FRAME TRIALS SEED

DECK continues from 'r.h5' with &output dir = 'out', name = 'c'; REF_FRAME is
that continuation's final frame from the unflipped file. Each trial runs in
its own folder trial_NNN. Prints one line per trial (offset, bit, what the
byte belongs to, the outcome) and the counts.
"""
import os
import random
import re
import shutil
import subprocess
import sys

import h5py


def regions(path):
    """(start, end, name) of every dataset's stored data in the file."""
    out = []

    def visit(name, obj):
        if not isinstance(obj, h5py.Dataset):
            return
        dsid = obj.id
        try:
            if obj.chunks is not None:
                for k in range(dsid.get_num_chunks()):
                    info = dsid.get_chunk_info(k)
                    out.append((info.byte_offset, info.byte_offset + info.size, name))
            else:
                off = dsid.get_offset()
                if off is not None:
                    out.append((off, off + dsid.get_storage_size(), name))
        except Exception:
            pass

    with h5py.File(path, "r") as f:
        f.visititems(visit)
    return out


def where(offset, regs):
    for a, b, name in regs:
        if a <= offset < b:
            return "data of " + name
    return "metadata or free space"


def main():
    exe, compare, dump, deck, ref, trials, seed = sys.argv[1:8]
    trials, seed = int(trials), int(seed)
    rng = random.Random(seed)
    size = os.path.getsize(dump)
    regs = regions(dump)
    ndata = sum(b - a for a, b, _ in regs)
    print(f"{dump}: {size} bytes, {ndata} of them dataset data ({len(regs)} datasets)")
    counts = {"refused": 0, "harmless": 0}
    kinds = {}
    bad = []
    for k in range(trials):
        d = f"trial_{k:03d}"
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        shutil.copy(dump, os.path.join(d, "r.h5"))
        shutil.copy(deck, os.path.join(d, "cont.nml"))
        off, bit = rng.randrange(size), rng.randrange(8)
        with open(os.path.join(d, "r.h5"), "r+b") as f:
            f.seek(off)
            byte = f.read(1)[0]
            f.seek(off)
            f.write(bytes([byte ^ (1 << bit)]))
        what = where(off, regs)
        try:
            p = subprocess.run([exe, "cont.nml"], cwd=d, capture_output=True, text=True, timeout=120,
                               env=dict(os.environ, OMP_NUM_THREADS="1"))
            rc, text = p.returncode, p.stdout + p.stderr
        except subprocess.TimeoutExpired:
            rc, text = "timeout", ""
        if rc == 2 and re.search(r"ERROR: cannot restart", text) and not re.search(r"^step ", text, re.M):
            msg = [l for l in text.splitlines() if l.startswith("ERROR:")][0]
            outcome = "refused: " + msg[:150]
            counts["refused"] += 1
            key = "refused, flip in " + ("dataset data" if what.startswith("data") else "metadata/free space")
        elif rc == 0:
            frames = sorted(f for f in os.listdir(os.path.join(d, "out")) if re.fullmatch(r"c_\d{5}\.h5", f))
            same = frames and subprocess.run([sys.executable, compare, os.path.join(d, "out", frames[-1]), ref,
                                              "--exact"], capture_output=True).returncode == 0
            if same:
                outcome = "harmless: ran to the end, final frame bit-identical"
                counts["harmless"] += 1
                key = "harmless, flip in " + ("dataset data" if what.startswith("data") else "metadata/free space")
            else:
                outcome = "CHANGED THE RESULT SILENTLY"
                bad.append(k)
                key = "silent change"
        else:
            outcome = f"FAILED: exit status {rc}: " + " | ".join(text.strip().splitlines()[-3:])[:300]
            bad.append(k)
            key = "crash, hang or wrong status"
        kinds[key] = kinds.get(key, 0) + 1
        print(f"trial {k:3d}: byte {off:6d} bit {bit} ({what}): {outcome}")
    print(f"bit flips: {trials} trials, seed {seed}: {counts['refused']} refused, {counts['harmless']} harmless, "
          f"{len(bad)} bad")
    for key in sorted(kinds):
        print(f"  {key}: {kinds[key]}")
    if bad:
        print("FAIL: trials " + ", ".join(map(str, bad)))
        sys.exit(1)
    print("PASS restart_bitflips")


main()
