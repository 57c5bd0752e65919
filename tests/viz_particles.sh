#!/usr/bin/env bash
# The particles in ParaView, headless: the two XDMF series of a run with
# particles (the grid's SERIES.xdmf, the particles' SERIES_particles.xdmf)
# opened with pvbatch show the hex grid and, as a dataset of its own, the
# particles as vertices with their fields (tests/check_paraview_particles.py). Skipped
# (exit 77) when pvbatch or xvfb-run is missing.
# Usage: viz_particles.sh SERIES.xdmf FRAME.h5 [STEP]   (absolute or relative to the test's folder;
# FRAME.h5 the series' time step STEP, default the last)
set -u
for tool in pvbatch xvfb-run; do
  command -v "$tool" > /dev/null 2>&1 || { echo "SKIP: $tool not found"; exit 77; }
done
series=$(readlink -f "$1") frame=$(readlink -f "$2")
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
for try in 1 2 3; do
  out=$(xvfb-run -a pvbatch "$here/check_paraview_particles.py" "$series" "$frame" "${3:--1}" 2>&1); rc=$?
  printf '%s\n' "$out"
  printf '%s\n' "$out" | grep -q "bad X server connection" || exit $rc
  sleep 2
done
exit $rc
