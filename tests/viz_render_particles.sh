#!/usr/bin/env bash
# tools/render_frame.sh draws a particle run's grid and particles, both
# coloured (issue 38): a short run of a quasi-2D particle deck, its last
# frame rendered headless, and the PNG's pixels counted by
# check_render_particles.py (the particles' colour map against the
# footprint of their points, the grid's viridis against the slice's area).
# Skipped (exit 77, ctest SKIP_RETURN_CODE) when pvbatch or xvfb-run is
# missing (tools/install-deps.sh installs ParaView and xvfb).
# Usage: viz_render_particles.sh EXE PYTHON DECK WORKDIR
set -u
exe=$1 py=$2 deck=$3 dir=$4
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for tool in pvbatch xvfb-run; do
  command -v "$tool" > /dev/null 2>&1 || { echo "SKIP: $tool not found"; exit 77; }
done
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
# 20 steps, a frame every 10: three frames, the last rendered
sed -e "s|max_steps *= *[0-9]*|max_steps = 20|" \
    -e "s|^&output.*|\&output dir = 'out', name = 'run', frame_steps = 10 /|" "$deck" > run.nml
OMP_NUM_THREADS=1 "$exe" run.nml > run.log 2>&1 || { tail -5 run.log; echo "FAIL: the run failed"; exit 1; }
[ -f out/run_particles.xdmf ] || { echo "FAIL: no out/run_particles.xdmf"; exit 1; }
last=$(ls out/run_[0-9][0-9][0-9][0-9][0-9].h5 | tail -1)
# a virtual X server slow to start ("bad X server connection") is retried
for try in 1 2 3; do
  out=$("$here/../tools/render_frame.sh" out/run.xdmf --field pressure --out run.png --size 800x600 2>&1); rc=$?
  printf '%s\n' "$out" | grep -v '^ *[0-9]* *0x'
  printf '%s\n' "$out" | grep -q "bad X server connection" || break
  sleep 2
done
[ "$rc" -eq 0 ] || { echo "FAIL: tools/render_frame.sh failed"; exit 1; }
size=$(printf '%s\n' "$out" | sed -n 's/^render_frame: particles: [0-9]* drawn as \([0-9.]*\)-pixel points.*/\1/p')
[ -n "$size" ] || { echo "FAIL: render_frame.sh reported no particles"; exit 1; }
printf '%s\n' "$out" | grep -q "frame 2," || { echo "FAIL: not the last frame (index 2)"; exit 1; }
"$py" "$here/check_render_particles.py" run.png "$last" "$size"
