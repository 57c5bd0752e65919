#!/usr/bin/env bash
# The (1 - theta_c) scaling of the virtual fluid's artificial viscosity
# (PARTICLES.md 1.7, risk R2): the deck (a bar of particles filling its
# cells, theta_c = 1) run with &hydro particle_viscosity = 'scaled' and
# 'full'. The gas is all virtual fluid, so its internal energy changes only
# by the viscous heating (its compression work goes back through the
# virtual-fluid work, 1.12): with 'full' it is heated (the viscosity damps
# the solid), with 'scaled' the change must be below RATIO times that, and
# the kinetic energy left must be larger (less damped ringing).
# Usage: particles_viscosity.sh EXE DECK WORKDIR RATIO
set -u
exe=$1 deck=$2 dir=$3 ratio=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
for v in scaled full; do
  sed -e "s|^&output.*|\&output dir = 'out_$v', frame_dt = 1 /|" -e "/^&hydro/d" "$deck" > $v.nml
  echo "&hydro particle_viscosity = '$v' /" >> $v.nml
  "$exe" $v.nml > $v.log 2>&1 || { tail -20 $v.log; fail "run $v failed"; }
done
# gas internal energy gained and final kinetic energy of a run's log
gains() {
  awk '/^conservation \(initial\)/ {s = 1} /^conservation \(final\)/ {s = 2}
       s && /material 1 / {for (i = 1; i < NF - 1; i++) if ($i == "internal" && $(i + 1) == "energy") e[s] = $(i + 2)}
       s == 2 && /energy: internal/ {k = $5}
       END {if (e[1] == "" || e[2] == "" || k == "") exit 1; printf "%.17g %.17g\n", e[2] - e[1], k}' "$1"
}
read -r ds ks < <(gains scaled.log) || fail "no conservation report (scaled)"
read -r df kf < <(gains full.log) || fail "no conservation report (full)"
awk -v ds="$ds" -v df="$df" -v ks="$ks" -v kf="$kf" -v r="$ratio" 'BEGIN {
  a = ds; if (a < 0) a = -a
  printf "virtual fluid heated: scaled %.4e, full %.4e (bound |scaled| <= %s x full)\n", ds, df, r
  printf "kinetic energy: scaled %.6e, full %.6e (scaled must be larger)\n", ks, kf
  if (!(df > 0)) {print "FAIL: no viscous heating with full"; exit 1}
  if (!(a <= r*df)) {print "FAIL: scaled viscosity heats the covered cells"; exit 1}
  if (!(ks > kf)) {print "FAIL: scaled viscosity does not damp less"; exit 1}
  print "PASS"}'
