#!/usr/bin/env bash
# Stopping a run and continuing it from the command line (issue 38). A run
# to step M stopped part-way and continued with `lsalepm --restart FILE
# deck.nml` (the deck unedited) ends with the final frame and the gauge
# file of the straight run to step M, bit for bit.
#   cli       the first part stops at step N = M/2 by max_steps (dump_steps
#             = N); the second part's deck names a restart_from that does not
#             exist, which --restart replaces (the command line wins; logged)
#   stopfile  <dir>/<name>.stop made before the start: the run stops at
#             step 1 with exit status 3 and a restart, the file removed
#   sigterm   SIGTERM (or SIGUSR1 with SIG=USR1) sent once the run has
#             taken a step: exit status 3 and a restart, at whatever step
# With MPIEXEC and NP the stopped run and its continuation run on NP ranks
# (the straight run on one process: ranks give bit-identical results).
# SIG=USR1 sends SIGUSR1 instead of SIGTERM (to mpirun with MPIEXEC).
# Usage: restart_stop.sh MODE EXE PYTHON COMPARE DECK M WORKDIR [MPIEXEC NP]
set -u
mode=$1 exe=$2 py=$3 cmp=$4 deck=$5 m=$6 dir=$7 mpiexec=${8:-} np=${9:-1}
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir/out"; cd "$dir" || exit 1
trap 'rc=$?; if [ $rc -ne 0 ]; then for f in *.log; do echo "== $f"; tail -8 "$f"; done; fi' EXIT
export OMP_NUM_THREADS=1
# derive NEW BASE RUN_VARS NAME (restart_lib.sh's, but the deck's &output kept:
# its gauges, and an energy history every 0.002 added: the histories compared)
derive() {
  local new=$1 base=$2 vars=$3 name=$4
  sed -e "s|^\(&run .*\)/ *\$|\1, $vars /|" \
      -e "s|^\(&output.*\)dir = '[^']*'|\1dir = 'out', name = '$name', history_dt = 0.002|" "$base" > "$new.nml"
  grep -q "$vars" "$new.nml" && grep -q "name = '$name'" "$new.nml" || fail "could not derive $new.nml from $base"
}
run() {   # run [args...]: the program, on NP ranks if asked
  if [ -n "$mpiexec" ]; then
    local root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
    timeout 600 "$mpiexec" "${root[@]}" --oversubscribe -np "$np" "$exe" "$@"
  else
    timeout 600 "$exe" "$@"
  fi
}
derive straight "$deck" "max_steps = $m" straight
case $mode in
cli)
  n=$((m/2)); dump=$(printf 'out/split_restart_%08d.h5' "$n")
  derive part1 "$deck" "max_steps = $n, dump_steps = $n" split
  derive whole "$deck" "max_steps = $m, restart_from = 'out/no_such_dump.h5'" split
  run part1.nml > part1.log 2>&1 || fail "the first part failed"
  [ -f "$dump" ] || fail "no dump $dump"
  run --restart "$dump" whole.nml > more.log 2>&1 || fail "lsalepm --restart $dump whole.nml failed"
  grep -q "restart: --restart $dump replaces the deck's restart_from = 'out/no_such_dump.h5'" more.log ||
    fail "the log does not say that --restart replaced the deck's restart_from"
  step=$n ;;
stopfile|sigterm)
  if [ "$mode" = stopfile ]; then
    derive whole "$deck" "max_steps = $m, progress_steps = 1" split
  else
    # (long enough to be running when the signal comes: t_end out of reach)
    derive whole "$deck" "max_steps = $m, progress_steps = 100" split
    sed -i -e 's/t_end = [0-9.eEdD+-]*/t_end = 1e3/' whole.nml straight.nml
  fi
  if [ "$mode" = stopfile ]; then
    touch out/split.stop
    run whole.nml > stopped.log 2>&1; rc=$?
  else
    # (the program itself, or mpirun, which passes SIGUSR1 on to its
    # processes: `timeout` would take the signal)
    if [ -n "$mpiexec" ]; then
      root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
      "$mpiexec" "${root[@]}" --oversubscribe -np "$np" "$exe" whole.nml > stopped.log 2>&1 &
    else
      "$exe" whole.nml > stopped.log 2>&1 &
    fi
    pid=$!
    # a step taken (its progress line), then the signal
    for i in $(seq 1 600); do grep -q '^step ' stopped.log 2> /dev/null && break; sleep 0.05; done
    kill -"${SIG:-TERM}" "$pid"
    wait "$pid"; rc=$?
  fi
  [ "$rc" -eq 3 ] || fail "exit status $rc, expected 3"
  dump=$(sed -n 's/^restart written: //p' stopped.log | tail -1)
  [ -n "$dump" ] && [ -f "$dump" ] || fail "no 'restart written:' line naming an existing file"
  grep -q "to continue: lsalepm --restart $dump whole.nml" stopped.log || fail "no advice to continue with --restart"
  step=$(sed -n 's/.* at step \([0-9]*\), t = .*/\1/p' stopped.log | tail -1)
  if [ "$mode" = stopfile ]; then
    grep -q "stop file out/split.stop found at step 1, t = .* (the file is removed)" stopped.log ||
      fail "the log does not say the stop file stopped the run at step 1"
    [ ! -e out/split.stop ] || fail "the stop file was not removed"
  else
    grep -q "SIG${SIG:-TERM} received at step $step" stopped.log || fail "the log does not name the signal"
  fi
  [ "$step" -lt "$m" ] || fail "the run reached step $m before it was stopped: make M larger"
  echo "stopped at step $step with exit status 3: $dump"
  run --restart "$dump" whole.nml > more.log 2>&1 || fail "lsalepm --restart $dump whole.nml failed" ;;
*) fail "unknown mode $mode" ;;
esac
grep -q "restarted from $dump at step $step" more.log || fail "the log does not report the restart"
"$exe" straight.nml > straight.log 2>&1 || fail "the straight run failed"
"$py" "$cmp" "$(final_frame straight)" "$(final_frame split)" --exact > frames.cmp || { cat frames.cmp; fail "final frames differ"; }
ls out/straight_*.txt > /dev/null 2>&1 || fail "the straight run wrote no history"
for f in out/straight_*.txt; do
  g=out/split_${f#out/straight_}
  cmp "$f" "$g" || fail "$g differs from $f"
  echo "ok: $g equals $f byte for byte"
done
echo "PASS restart_stop $mode${SIG:+ (SIG$SIG)} (stopped at step $step of $m; final frame and histories bit for bit)"
