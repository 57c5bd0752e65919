#!/usr/bin/env bash
# No rank holds the whole grid's state (issue 35): each deck of
# tools/memory_decks.sh named here runs under a limit on the data part of
# the address space (ulimit -d: the heap and private mappings, not the
# shared libraries and Open MPI's shared-memory segments, which are the
# same whatever the grid) that one process exceeds and 4 ranks fit in. One
# process must end with exit status 1 and the log's `out of memory` line
# (never a signal); 4 ranks (oversubscribed) must finish. Each limit lies
# between what the two need (measured: Sedov 64^3 LSSM, one process fails
# at 600 MiB and runs at 900, 4 ranks run at 260 and fail at 200; the TNT
# octant at 64^3, one process fails at 400 and runs at 700, 4 ranks run at
# 300 and fail at 250; the Gurson ring at 192 x 192 x 4, one process fails
# at 200 and runs at 300, 4 ranks run at 130 and fail at 110, the most
# loaded rank the one that builds the correlated void field). With
# NAME:LIMIT_MIB:fail the 4 ranks must run out of memory too, and end alike
# (exit status 1, never a signal, never a hang: a rank that fails alone
# during the set-up or the failure frame once left the others waiting in a
# collective call).
# Usage: memory_limit.sh MPIEXEC EXE WORKDIR NAME:LIMIT_MIB[:fail]...
set -u
mpiexec=$1; exe=$2; work=$3; shift 3
root_flag=()
[ "$(id -u)" -eq 0 ] && root_flag=(--allow-run-as-root)
mkdir -p "$work" && cd "$work" || exit 1
bash "$(dirname "$0")/../tools/memory_decks.sh" . || { echo "FAIL: the memory decks"; exit 1; }
bad=0
for spec in "$@"; do
  IFS=: read -r name lim want4 <<< "$spec"
  rm -rf "out/$name"
  (ulimit -d $((lim * 1024)); OMP_NUM_THREADS=1 timeout 600 "$exe" "$name.nml" > "${name}_r1.log" 2>&1); rc1=$?
  (ulimit -d $((lim * 1024)); OMP_NUM_THREADS=1 timeout 300 "$mpiexec" "${root_flag[@]}" --oversubscribe -np 4 \
    "$exe" "$name.nml" > "${name}_r4.log" 2>&1); rc4=$?
  why=$(grep -m1 -o 'FATAL .*out of memory.*' "${name}_r1.log")
  peak=$(grep -m1 '^memory: peak resident' "${name}_r4.log")
  [ "${want4:-}" = fail ] && peak=$(grep -m1 -o 'FATAL .*out of memory.*' "${name}_r4.log")
  echo "$name, data limit $lim MiB: one process exit status $rc1 (${why:-no out-of-memory line}); 4 ranks exit status $rc4 (${peak:-no line})"
  if [ "$rc1" -ne 1 ] || [ -z "$why" ]; then
    echo "FAIL: one process should run out of memory under $lim MiB (exit status 1)"; tail -5 "${name}_r1.log"; bad=1
  fi
  if [ "${want4:-}" = fail ]; then
    if [ "$rc4" -ne 1 ] || [ -z "$peak" ]; then
      echo "FAIL: 4 ranks should run out of memory under $lim MiB (exit status 1)"
      grep -v '^ [A-Z_]*=' "${name}_r4.log" | tail -8; bad=1
    fi
  elif [ "$rc4" -ne 0 ]; then
    echo "FAIL: 4 ranks should fit in $lim MiB each"; grep -v '^ [A-Z_]*=' "${name}_r4.log" | tail -8; bad=1
  fi
done
exit $bad
