#!/usr/bin/env bash
# Energy balance with coupled particles: the deck (a gas pushing an
# elastic-plastic block) run to t_end with the given stress update; the
# final conservation report's energy budget residual (the total change of
# the cells' and particles' internal energy and the kinetic energy with the
# full nodal mass, less boundary work, decoupling work and Euler-step
# transfer) must be within DRIFT, and the decoupling
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
  fin && /energy budget over/ {d = $NF; c = $7}
  /^conservation \(initial\)/ {ini = 1}
  ini && !fin && /total/ && /energy: internal/ {e0 = $NF; ini = 0}
  fin && /^  particles:/ {for (i = 1; i < NF; i++) if ($i == "decoupling" && $(i + 1) == "work") w = $(i + 2)}
  END {
    if (d == "" || w == "" || e == "") {print "FAIL: no final conservation report"; exit 1}
    r = w/e; if (r < 0) r = -r; a = d; if (a < 0) a = -a
    printf "budget residual %s (bound %s), total change %s, decoupling work %s = %.3e of the energy (bound %s)\n", d, b, c, w, r, db
    if (!(a <= b)) {print "FAIL: the energy budget does not close"; exit 1}
    # the stated change is that of the totals (to the 4 digits printed)
    ch = (e - e0)/(e0 < 0 ? -e0 : e0); dc = c - ch; if (dc < 0) dc = -dc
    if (!(dc <= 1e-3*(ch < 0 ? -ch : ch) + 1e-15)) {printf "FAIL: total change %s, the totals say %.6e\n", c, ch; exit 1}
    if (!(r <= db)) {print "FAIL: decoupling work"; exit 1}
  }' run.log
