#!/usr/bin/env bash
# The disk fills while the ranks write (issue 40): 2 ranks dump a restart
# every step (and a frame every 100) into a small tmpfs that another process
# fills at a random moment, at a random rate. The space of a file of several
# ranks is reserved before it is written (io_hdf5 `reserve_space`), so every
# trial must end with exit 4 on every rank within the timeout (no hang: a
# rank failing alone inside HDF5's collective calls used to leave the other
# waiting for ever), a FATAL line naming the file, no `.tmp` left behind, and
# the last complete dump must read completely and continue (exit 0).
# Needs root (mount); exits 77 (skipped) otherwise.
# Usage: restart_disk_race.sh EXE PYTHON DECK WORKDIR MPIEXEC [TRIALS]   (DECK: ni = 100 in &grid)
set -u
exe=$(realpath "$1") py=$2 deck=$(realpath "$3") dir=$4 mpiexec=$5 trials=${6:-20}
run=("$mpiexec"); [ "$(id -u)" -eq 0 ] && run+=(--allow-run-as-root)
run+=(--oversubscribe -np 2)
export OMP_NUM_THREADS=1
. "$(dirname "$0")/restart_lib.sh"
[ "$(id -u)" -eq 0 ] || { echo "SKIP: needs root to mount a tmpfs"; exit 77; }
rm -rf "$dir"; mkdir -p "$dir/mnt"; cd "$dir" || exit 1
mount -t tmpfs -o size=24m tmpfs mnt 2> /dev/null || { echo "SKIP: cannot mount a tmpfs"; exit 77; }
trap 'umount "$PWD/mnt" 2> /dev/null' EXIT
derive race "$deck" "max_steps = 100000, dump_steps = 1, dump_keep = 2" race
sed -i -e "s|^&run title = '[^']*', t_end = [^,]*,|\&run title = 'disk race', t_end = 100,|" \
       -e "s|^&output .*|\&output dir = 'mnt/race', name = 'race', frame_steps = 100 /|" -e "s/ni = 100,/ni = 3000,/" race.nml
RANDOM=40
for t in $(seq 1 "$trials"); do
  rm -rf mnt/* out
  # the filler: 0-1.5 s after the first dump is complete (on a loaded
  # machine the run may take long to start), chunks of 4-256 KiB every
  # 0-2 ms until the disk is full
  delay=$(printf '0.%03d' $((RANDOM % 1000))); [ $((RANDOM % 3)) -eq 0 ] && delay=1.$((RANDOM % 5))
  chunk=$((4096 << (RANDOM % 7))) pause=$((RANDOM % 3))
  "$py" - "$delay" "$chunk" "$pause" <<'PY' &
import glob, sys, time
delay, chunk, pause = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]) * 1e-3
start = time.time()
while not glob.glob("mnt/race/race_restart_*.h5") and time.time() - start < 60:
    time.sleep(0.01)
time.sleep(delay)
try:
    with open("mnt/filler", "wb", buffering=0) as f:
        while True:
            f.write(b"\0" * chunk)
            time.sleep(pause)
except OSError:
    pass
PY
  filler=$!
  out=$(timeout 120 "${run[@]}" "$exe" race.nml 2>&1); rc=$?
  wait "$filler"
  printf '%s\n' "$out" > "trial_$t.out"
  [ "$rc" -eq 124 ] && fail "trial $t (fill after $delay s, $chunk B every $pause ms): hung (killed after 120 s)"
  printf '%s\n' "$out" | grep -E -q "Segmentation|Backtrace|SIGSEGV|Program received" && \
    { tail -20 "trial_$t.out"; fail "trial $t: crashed"; }
  [ "$rc" -eq 4 ] || { tail -8 "trial_$t.out"; fail "trial $t: exit status $rc, expected 4 (I/O failure)"; }
  grep -E -q "^FATAL .*'mnt/race/[^']+'" "trial_$t.out" || { tail -8 "trial_$t.out"; fail "trial $t: no FATAL line naming the file"; }
  [ "$(grep -c "^FATAL" "trial_$t.out")" -eq 1 ] || fail "trial $t: not one FATAL line"
  ls mnt/race/*.tmp > /dev/null 2>&1 && fail "trial $t: a temporary file was left behind: $(ls mnt/race/*.tmp)"
  last=$(ls mnt/race/race_restart_*.h5 2> /dev/null | sort | tail -1)
  [ -n "$last" ] || fail "trial $t: no complete dump"
  "$py" - "$last" <<'PY' || fail "trial $t: the last dump $last does not read completely"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    f.visititems(lambda k, o: o[()] if isinstance(o, h5py.Dataset) else None)
PY
  # continue it for 3 steps, the disk freed
  rm -f mnt/filler
  step=$(basename "$last" .h5); step=$((10#${step##*_}))
  sed -e "s|max_steps = 100000, dump_steps = 1, dump_keep = 2|max_steps = $((step + 3)), restart_from = '$last'|" \
      -e "s|^&output .*|\&output dir = 'out', name = 'cont' /|" race.nml > cont.nml
  timeout 120 "${run[@]}" "$exe" cont.nml > "cont_$t.out" 2>&1 || { tail -5 "cont_$t.out"; fail "trial $t: the last dump $last does not continue"; }
  echo "ok: trial $t (fill after $delay s, $chunk B every $pause ms): $(grep -E '^FATAL' "trial_$t.out" | cut -c1-140); $last continued"
done
echo "PASS restart_disk_race ($trials trials)"
