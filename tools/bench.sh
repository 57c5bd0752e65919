#!/usr/bin/env bash
# Benchmarks (not tests): Lagrangian throughput on Sedov 40^3 with 1 and 2
# threads; the remap (tests/bench_remap.f90: global remap of a 40^3 box, pure
# and mixed cells, MoF reconstructions) with 1 and 2 threads; the Sedov 3D
# octant with global ALE (Euler time per Euler step against Lagrangian time
# per step); L1 density error against wall time for Sod (N = 100..800) and
# Sedov (N^3, N = 10..40) through tools/speed_error.py; and mesh smoothing
# (Sect. 7.1, tests/bench_smooth.f90).
# Usage: tools/bench.sh LSALEPM OUTDIR [BENCH_REMAP]
# (BENCH_REMAP defaults to tests/bench_remap in LSALEPM's build directory)
set -euo pipefail
SECONDS=0
exe=$(realpath "$1"); mkdir -p "$2"; outdir=$(realpath "$2")
remap_exe=$(realpath "${3:-$(dirname "$exe")/tests/bench_remap}")
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
echo "## Remap: global remap of a 40^3 box, pure and mixed cells; MoF (tests/bench_remap.f90, Release)"
for th in 1 2; do
  echo "### OMP_NUM_THREADS=$th"
  OMP_NUM_THREADS=$th OMP_PROC_BIND=true "$remap_exe" > "$outdir/bench_remap_$th.txt"
  cat "$outdir/bench_remap_$th.txt"
  echo
done
# speed-up: the wall time (column 3) of a row with 1 thread over that with 2
awk 'FNR == 1 {f++} !((f, $1) in t) {t[f, $1] = $3}
     END {printf "2-thread speed-up (wall time, 1 thread / 2 threads):"
          n = split("remap_pure remap_two general_pure mof_cube mof_perturb mof_sheared", r, " ")
          for (i = 1; i <= n; i++) printf " %s %.2f%s", r[i], t[1, r[i]] / t[2, r[i]], (i < n ? "," : "\n")}' \
    "$outdir/bench_remap_1.txt" "$outdir/bench_remap_2.txt"

echo
echo "## Sedov 3D octant 20^3 with global ALE to t = 1: Euler step against Lagrangian step (2 threads)"
if [[ -f "$root/input/sedov3d_ale.nml" ]]; then
  ale_deck="$root/input/sedov3d_ale.nml"
else
  ale_deck=sedov3d_ale.nml
  sed -e "s|^&output.*|\&output dir = 'out/sedov3d_ale' /|" "$root/input/sedov3d.nml" > "$ale_deck"
  echo "&rezone mode = 'global', side_ratio = 4, cos_angle = 0.7 /" >> "$ale_deck"
fi
echo "deck: $ale_deck"
OMP_NUM_THREADS=2 OMP_PROC_BIND=true "$exe" "$ale_deck" > "$outdir/sedov3d_ale.log"
awk '/^timers \[s\]:/ {for (i = 1; i < NF; i++) {if ($i == "lagrange") lag = $(i + 1); if ($i == "euler") eul = $(i + 1)}}
     /^throughput:/ {nlag = $(NF - 1)}
     /^euler steps:/ {neul = $3 + 0; line = $0}
     END {
       if (neul == 0) {print "no Euler step in the run"; exit}
       printf "Lagrangian: %.3f s over %d steps = %.2f ms per step\n", lag, nlag, 1e3 * lag / nlag
       printf "Euler:      %.3f s over %d Euler steps = %.2f ms per Euler step\n", eul, neul, 1e3 * eul / neul
       printf "Euler step / Lagrangian step: %.1f (an Euler step every %.1f Lagrangian steps)\n", \
              (eul / neul) / (lag / nlag), nlag / neul
       print line
     }' "$outdir/sedov3d_ale.log"

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

echo
echo "bench wall time: ${SECONDS} s"
