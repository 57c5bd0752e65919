#!/usr/bin/env bash
# Restarts across rank counts: a run to step N on 2 MPI ranks dumps the
# whole grid; continued to step 2N on 1 process and on 4 ranks, both final
# frames equal the straight single-process run to step 2N bit for bit. The
# dump itself equals the one a single process writes at step N (every
# dataset, h5diff). The environment's RESTART_WRITE (ranks, e.g. 3) and
# RESTART_CONTINUE (e.g. "1 8") replace the counts 2 and "1 4".
# Usage: mpi_restart.sh MPIEXEC EXE PYTHON COMPARE DECK N WORKDIR
set -u
mpiexec=$1 exe=$2 py=$3 cmp=$4 deck=$5 n=$6 dir=$7
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
export OMP_NUM_THREADS=1
ranks() { local np=$1; shift; timeout 600 "$mpiexec" "${root[@]}" --oversubscribe -np "$np" "$exe" "$@"; }
m=$((2*n)); dump=$(printf 'out/split_restart_%08d.h5' "$n")
write=${RESTART_WRITE:-2}
cont=${RESTART_CONTINUE:-1 4}
derive straight "$deck" "max_steps = $m" straight
derive part1 "$deck" "max_steps = $n, dump_steps = $n" split
for q in $cont; do derive on$q "$deck" "max_steps = $m, restart_from = '$dump'" on$q; done
"$exe" straight.nml > straight.log 2>&1 || fail "straight run failed (see $dir/straight.log)"
# the same deck on one process, in one/ (the same names inside the dump)
mkdir one; (cd one && "$exe" ../part1.nml > ../one.log 2>&1) || fail "single-process run to step $n failed"
ranks "$write" part1.nml > part1.log 2>&1 || { tail -20 part1.log; fail "$write ranks to step $n failed"; }
[ -f "$dump" ] || fail "no dump $dump from $write ranks"
h5diff "$dump" "one/$dump" > diff.txt 2>&1 || { head -20 diff.txt; fail "the $write-rank dump differs from one process's"; }
echo "ok: the dump of $write ranks at step $n equals one process's (h5diff)"
for q in $cont; do
  r=on$q
  if [ "$q" -eq 1 ]; then
    "$exe" $r.nml > $r.log 2>&1 || { tail -20 $r.log; fail "restart on 1 process failed"; }
  else
    ranks "$q" $r.nml > $r.log 2>&1 || { tail -20 $r.log; fail "restart on $q ranks failed"; }
  fi
  grep -q "restarted from $dump at step $n" $r.log || fail "$r: the log does not report the restart"
  "$py" "$cmp" "$(final_frame straight)" "$(final_frame $r)" --exact > $r.cmp || { cat $r.cmp; fail "$r differs"; }
  echo "ok: $write ranks to step $n, then $r to step $m: bit-identical to the straight run"
done
echo "PASS mpi_restart $(basename "$deck")"
