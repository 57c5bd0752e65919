#!/usr/bin/env bash
# SIGKILL in the middle of a restart dump leaves the previous dump readable:
# dumps are written to NAME.tmp and renamed. The run dumps every step; the
# test kills it as soon as a .tmp file exists (so during a dump), then
# restarts from the newest complete dump.
# Usage: restart_kill.sh EXE DECK CELLS WORKDIR
set -u
exe=$1 deck=$2 cells=$3 dir=$4
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
for attempt in 1 2 3; do
  rm -rf out
  derive dumping "$deck" "dump_steps = 1, dump_keep = 2" k
  sed -i -e "s/ni = [0-9]*, nj = [0-9]*, nk = [0-9]*/ni = $cells, nj = $cells, nk = $cells/" dumping.nml
  "$exe" dumping.nml > dumping.log 2>&1 &
  pid=$!
  caught=""
  # wait for the first complete dump, then for a dump in progress
  for i in $(seq 1 6000); do
    if ls out/k_restart_*.h5 > /dev/null 2>&1 && ls out/*.h5.tmp > /dev/null 2>&1; then
      kill -9 "$pid"; caught=yes; break
    fi
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.005
  done
  wait "$pid" 2> /dev/null
  [ -n "$caught" ] && break
  echo "attempt $attempt: no dump caught in progress, trying again"
done
[ -n "$caught" ] || fail "could not kill the run during a dump"
tmp=$(ls out/*.h5.tmp)
last=$(ls out/k_restart_*.h5 | sort | tail -1)
echo "killed while writing $tmp; newest complete dump: $last"
step=$(echo "$last" | sed 's/.*_restart_0*\([0-9]*\)\.h5/\1/')
derive resume "$deck" "max_steps = $((step + 1)), restart_from = '$last'" k
sed -i -e "s/ni = [0-9]*, nj = [0-9]*, nk = [0-9]*/ni = $cells, nj = $cells, nk = $cells/" resume.nml
"$exe" resume.nml > resume.log 2>&1 || { tail resume.log; fail "restart from $last failed"; }
grep -q "restarted from $last" resume.log || fail "restart not reported"
echo "PASS restart_kill"
