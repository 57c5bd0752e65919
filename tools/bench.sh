#!/usr/bin/env bash
# Benchmarks (not tests): Lagrangian throughput on Sedov 40^3 with 1 and 2
# threads, and Sod L1 density error against wall time at N = 100..800.
# Usage: tools/bench.sh LSALEPM CHECK_SOD
set -euo pipefail
exe=$(realpath "$1"); check=$(realpath "$2")
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
echo "## Sod (gamma 1.4, t = 0.2) L1 density error against wall time (1 thread)"
printf '%6s %14s %10s %10s\n' N L1 order wall_s
prev=""
for n in 100 200 400 800; do
  h=$(awk -v n=$n 'BEGIN {printf "%.6g", 1.0/n}')
  cat > sod$n.nml <<DECK
&run title = 'Sod N = $n', t_end = 0.2 /
&grid ni = $n, nj = 1, nk = 1, xmin = 0, 0, 0, xmax = 1, $h, $h /
&material name = 'gas', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'gas', density = 1.0, pressure = 1.0 /
&region shape = 'box', material = 'gas', density = 0.125, pressure = 0.1, lo = 0.5, -1, -1, hi = 2, 2, 2 /
&boundary xlo = 'wall', xhi = 'wall' /
&output dir = 'out/sod$n' /
DECK
  t0=$(date +%s.%N)
  OMP_NUM_THREADS=1 "$exe" sod$n.nml > sod$n.log
  t1=$(date +%s.%N)
  l1=$("$check" l1 out/sod$n/sod${n}_00001.h5 1 1 | awk '/L1 density error/ {print $8}' | tr -d ,)
  order=""
  [ -n "$prev" ] && order=$(awk -v a="$prev" -v b="$l1" 'BEGIN {printf "%.3f", log(a/b)/log(2)}')
  printf '%6d %14s %10s %10.3f\n' "$n" "$l1" "$order" "$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b-a}')"
  prev=$l1
done
