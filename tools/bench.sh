#!/usr/bin/env bash
# Benchmarks (not tests): Lagrangian throughput on Sedov 40^3 with 1 and 2
# threads, and L1 density error against wall time for Sod (N = 100..800) and
# Sedov (N^3, N = 10..40) through tools/speed_error.py.
# Usage: tools/bench.sh LSALEPM OUTDIR
set -euo pipefail
exe=$(realpath "$1"); mkdir -p "$2"; outdir=$(realpath "$2")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
sed -e 's/ni = 20, nj = 20, nk = 20/ni = 40, nj = 40, nk = 40/' \
    -e "s|^&output.*|\&output dir = 'out/sedov40' /|" "$root/input/sedov3d.nml" > sedov40.nml

echo "## Lagrangian throughput, Sedov 40^3 to t = 1 (Release)"
declare -A rate
for th in 1 2; do
  OMP_NUM_THREADS=$th OMP_PROC_BIND=true "$exe" sedov40.nml > sedov40_$th.log
  rate[$th]=$(awk '/^throughput:/ {print $2}' sedov40_$th.log)
  steps=$(awk '/^throughput:/ {print $5}' sedov40_$th.log)
  echo "threads $th: ${rate[$th]} cell-cycles/s ($steps steps)"
done
echo "2-thread speed-up: $(awk -v a="${rate[1]}" -v b="${rate[2]}" 'BEGIN {printf "%.2f", b/a}')"

echo
echo "## Speed against error (1 thread): tables, CSV and PNG in $outdir"
py=/usr/bin/python3
"$py" "$root/tools/speed_error.py" --exe "$exe" --case sod --n 100 200 400 800 --threads 1 --out "$outdir"
"$py" "$root/tools/speed_error.py" --exe "$exe" --case sedov --n 10 20 30 40 --threads 1 --out "$outdir"

# ---- Mesh smoothing benchmark (Sect. 7.1, Fig. 16): tests/bench_smooth.f90, tools/plot_smoothing.py ----
# One thread: the paper compares CPU times. Boundary nodes slide (faces in
# their plane, edges along their line, corners fixed); writes smoothing.csv,
# smoothing.png and bench_smooth.txt to OUTDIR.
echo
echo "## Mesh smoothing (Sect. 7.1): 50^3 grid, interior nodes moved by up to 0.399 (tangled: 0.45, 0.7), 1 thread"
smooth_exe=$(dirname "$exe")/tests/bench_smooth
OMP_NUM_THREADS=1 "$smooth_exe" 50 100 "$outdir/smoothing.csv" | tee "$outdir/bench_smooth.txt"
/usr/bin/python3 "$root/tools/plot_smoothing.py" "$outdir/smoothing.csv" --out "$outdir/smoothing.png"
