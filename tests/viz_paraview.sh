#!/usr/bin/env bash
# The frames in ParaView, headless (issue 13): a two-material run's XDMF
# series opened with pvbatch shows the per-material fields, volume, the
# integer material and the field data (tests/check_paraview.py), and
# tools/render_frame.sh draws the quasi-1D run as a coloured 2D strip.
# Skipped (exit 77, ctest SKIP_RETURN_CODE) when pvbatch or xvfb-run is
# missing: tools/install-deps.sh installs them.
# Usage: viz_paraview.sh EXE DECK MATERIALS WORKDIR
#   MATERIALS: the deck's material names, comma-separated, in deck order.
set -u
exe=$1 deck=$2 materials=$3 dir=$4
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for tool in pvbatch xvfb-run; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "SKIP: $tool not found (tools/install-deps.sh installs ParaView and xvfb)"
    exit 77
  fi
done
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
sed -e "s|^&output.*|\&output dir = 'out', name = 'viz' /|" "$deck" > viz.nml
OMP_NUM_THREADS=1 "$exe" viz.nml > run.log 2>&1 || { echo "FAIL: the run failed (see $dir/run.log)"; exit 1; }
# A virtual X server that is slow to start on a loaded machine gives "bad X
# server connection" (seen under parallel ctest): such a start is retried,
# any other failure is a failure.
with_x() {
  local try out rc
  for try in 1 2 3; do
    out=$("$@" 2>&1); rc=$?
    printf '%s\n' "$out"
    printf '%s\n' "$out" | grep -q "bad X server connection" || return $rc
    echo "note: the virtual X server was not ready (try $try of 3)"
    sleep 2
  done
  return 1
}
with_x "$here/../tools/render_frame.sh" out/viz.xdmf --field density --out viz.png --size 800x400 ||
  { echo "FAIL: tools/render_frame.sh failed"; exit 1; }
with_x xvfb-run -a pvbatch "$here/check_paraview.py" out/viz.xdmf "$materials" viz.png
