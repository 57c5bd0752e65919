#!/usr/bin/env bash
# A full disk: runs writing frames (or restart dumps) into a small tmpfs until
# it fills must end with a FATAL line naming the file, the exit status of an
# I/O failure (4: base_errors ERR_IO; issue 13 says 1, but issue 11 gave I/O
# failures their own status), a word about the failure frame, no crash
# (HDF5's exit handler used to segfault after a failed close: exit 139), and
# no file with its final name left truncated: every *.h5 there
# must open and read completely (outputs go to NAME.tmp, then are renamed).
# The XDMF sidecar must parse too.
# Needs root (mount); exits 77 (skipped) otherwise or if the mount fails.
# With MPIEXEC and NP the runs are on NP ranks, which write each file
# together: one rank failing alone inside HDF5's collective calls would leave
# the others waiting for ever, so the ranks refuse a file the disk has no
# room for before they start it (the timeout below catches a hang).
# Usage: restart_disk_full.sh EXE PYTHON DECK WORKDIR [MPIEXEC NP]   (DECK: ni = 100 in &grid)
set -u
exe=$1 py=$2 deck=$3 dir=$4
run=()
if [ $# -ge 6 ]; then
  run=("$5"); [ "$(id -u)" -eq 0 ] && run+=(--allow-run-as-root)
  run+=(--oversubscribe -np "$6")
  export OMP_NUM_THREADS=1
fi
. "$(dirname "$0")/restart_lib.sh"
[ "$(id -u)" -eq 0 ] || { echo "SKIP: needs root to mount a tmpfs"; exit 77; }
rm -rf "$dir"; mkdir -p "$dir/mnt"; cd "$dir" || exit 1
mount -t tmpfs -o size=3m tmpfs mnt 2> /dev/null || { echo "SKIP: cannot mount a tmpfs"; exit 77; }
trap 'umount "$PWD/mnt" 2> /dev/null' EXIT
full() { # NAME NI RUN_VARS OUTPUT_VARS
  local name=$1 ni=$2 out rc
  rm -rf mnt/*
  derive "$name" "$deck" "$3" "$name"
  sed -i -e "s|^&output .*|\&output dir = 'mnt/$name', name = '$name', $4 /|" -e "s/ni = 100,/ni = $ni,/" "$name.nml"
  out=$(timeout 300 "${run[@]}" "$exe" "$name.nml" 2>&1); rc=$?
  [ "$rc" -eq 124 ] && fail "$name: hung (killed after 300 s)"
  printf '%s\n' "$out" > "$name.out"
  printf '%s\n' "$out" | grep -E -q "Segmentation|Backtrace|SIGSEGV|Program received" && \
    { tail -20 "$name.out"; fail "$name: crashed"; }
  [ "$rc" -eq 4 ] || { tail -8 "$name.out"; fail "$name: exit status $rc, expected 4 (I/O failure)"; }
  grep -E -q "^FATAL .*'mnt/$name/[^']+'" "$name.out" || { tail -8 "$name.out"; fail "$name: no FATAL line naming the file"; }
  grep -E -q "state at failure (written to|could not be written)" "$name.out" || \
    { tail -8 "$name.out"; fail "$name: nothing said about the failure frame"; }
  "$py" - "mnt/$name" <<'PY' || fail "$name: a file with its final name is damaged"
import glob, os, sys, xml.etree.ElementTree as ET
import h5py
n = 0
for p in sorted(glob.glob(os.path.join(sys.argv[1], "*.h5"))):
    with h5py.File(p, "r") as f:
        f.visititems(lambda k, o: o[()] if isinstance(o, h5py.Dataset) else None)
    n += 1
print(f"  {n} final-named .h5 files open and read completely")
# the XDMF sidecar too (gfortran reports no error when a formatted write
# runs out of space; io_xdmf reads its last line back before the rename)
for p in glob.glob(os.path.join(sys.argv[1], "*.xdmf")):
    try:
        ET.parse(p)
    except ET.ParseError as e:
        sys.exit(f"  {os.path.basename(p)} is truncated ({e})")
PY
  ls mnt/"$name"/*_restart_*.tmp > /dev/null 2>&1 && fail "$name: a failed dump left its temporary file"
  echo "ok: $name (ni = $ni): $(grep -E '^FATAL' "$name.out" | head -1)"
  echo "    $(grep -E 'state at failure' "$name.out" | head -1)"
}
# frames every step: the disk fills while a dataset is written, at a close
# (the case that crashed) or at a create, depending on the frame size
full frames_a 1000 "max_steps = 400" "frame_steps = 1"
full frames_b 3000 "max_steps = 400" "frame_steps = 1"
full frames_c 7000 "max_steps = 400" "frame_steps = 1"
# restart dumps every step
full dumps 3000 "max_steps = 400, dump_steps = 1, dump_keep = 1000" "frame_dt = 0"
echo "PASS restart_disk_full"
