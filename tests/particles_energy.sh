#!/usr/bin/env bash
# Energy balance with coupled particles (PARTICLES.md 1.12): the deck (a
# gas pushing an elastic-plastic block) run to t_end with the given stress
# update; the final conservation report's relative drift (cells' and
# particles' internal energy, kinetic energy with the full nodal mass, less
# boundary and decoupling work) must be within DRIFT, and the decoupling
# work over the initial energy within DECOUPLING (original update: the
# trial stress at n+1/2 of the forces against the trapezoid of the
# constitutive work, a time-integration difference; decoupled: the virtual
# against the real strain).
# Usage: particles_energy.sh EXE DECK WORKDIR UPDATE T_END DRIFT DECOUPLING
set -u
exe=$1 deck=$2 dir=$3 update=$4 tend=$5 bound=$6 dbound=$7
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
sed -e "s|^&output.*|\&output dir = 'out', frame_dt = 1 /|" -e "s|t_end = [0-9.eE+-]*|t_end = $tend|" \
  -e "/^&hydro/d" "$deck" > run.nml
echo "&hydro stress_update = '$update' /" >> run.nml
"$exe" run.nml > run.log 2>&1 || { tail -20 run.log; fail "run failed"; }
awk -v b="$bound" -v db="$dbound" '
  /^conservation \(final\)/ {fin = 1}
  fin && /total/ && /energy: internal/ {e = $NF}
  fin && /relative energy drift/ {d = $NF}
  fin && /decoupling work/ {for (i = 1; i < NF; i++) if ($i == "decoupling" && $(i + 1) == "work") w = $(i + 2)}
  END {
    if (d == "" || w == "" || e == "") {print "FAIL: no final conservation report"; exit 1}
    r = w/e; if (r < 0) r = -r; a = d; if (a < 0) a = -a
    printf "relative energy drift %s (bound %s), decoupling work %s = %.3e of the energy (bound %s)\n", d, b, w, r, db
    if (!(a <= b)) {print "FAIL: energy drift"; exit 1}
    if (!(r <= db)) {print "FAIL: decoupling work"; exit 1}
  }' run.log
