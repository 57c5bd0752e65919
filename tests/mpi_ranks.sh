#!/usr/bin/env bash
# Rank invariance: a deck run as one process (no mpirun), then on 2 MPI
# ranks of 2 OpenMP threads and on 4 ranks of 1 (oversubscribed; the
# environment's RANKS, e.g. "1 3 8", replaces the counts 1 2 4: its first
# must be 1, other counts run one thread per rank), must give final frames
# bit-identical to the single process's (`compare_frames.py --exact`: node
# positions, velocities, cell fields, the conservation totals, time, step;
# and h5diff: the whole file but the deck, which names the output
# directory), and the same XDMF series.
# With --fail the deck must fail (a tangled cell in one block): every run
# ends with exit status 1, the FATAL line names the rank that failed, which
# on 2 and 4 ranks is not rank 0, and the failure frame is written and is
# the single process's failure frame bit for bit. The energy history
# (&output history_dt = t_end/8), the deck's gauge histories, its
# tracked-particle histories and its tracer histories must be the same
# text on every rank count.
# Usage: mpi_ranks.sh MPIEXEC EXE PYTHON TOOLS DECK WORKDIR [--fail] [FILE...]
# FILEs (a deck's grid file) are copied into WORKDIR, where the decks run.
set -u
mpiexec=$1 exe=$2 py=$3 tools=$4 deck=$5 dir=$6
shift 6
mode=''
if [ "${1:-}" = --fail ]; then mode=--fail; shift; fi
# (on a failure the run's last lines, for a diagnosis from the CI log)
fail() { [ -n "${out:-}" ] && [ -f "$out" ] && tail -15 "$out"; echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"
for extra in "$@"; do cp "$extra" "$dir"/ || fail "cannot copy $extra"; done
cd "$dir" || exit 1
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
export OMP_NUM_THREADS=1
t_end=$(grep -o 't_end = [^,/ ]*' "$deck" | head -1 | awk '{print $3}')
hdt=$(awk -v t="$t_end" 'BEGIN {printf "%.6e", t/8}')
ranks=${RANKS:-1 2 4}
[ "${ranks%% *}" = 1 ] || fail "RANKS must start with 1 (the single process), got '$ranks'"
for n in $ranks; do
  out=r$n.out
  # (a progress line every 5 steps and none by wall time: the lines of
  # every rank count name the same step-limiting cell)
  sed -e "s|^&output dir = '[^']*'|\&output dir = 'r$n', name = 'run', history_dt = $hdt|" \
      -e "s|^\(&run .*\)/ *\$|\1, progress_steps = 5, progress_seconds = 1e9 /|" "$deck" > "r$n.nml"
  if [ "$n" -eq 1 ]; then
    timeout 600 "$exe" r1.nml > r1.out 2>&1; rc=$?
  else
    OMP_NUM_THREADS=$((n == 2 ? 2 : 1)) timeout 600 "$mpiexec" "${root[@]}" --oversubscribe -np "$n" \
      "$exe" "r$n.nml" > "r$n.out" 2>&1; rc=$?
    grep -q "^run: $n MPI ranks" "r$n.out" || fail "$n ranks: no layout line in the log"
    grep -q ", $((n == 2 ? 2 : 1)) OpenMP thread(s)" "r$n.out" || fail "$n ranks: not the OpenMP threads asked for"
  fi
  grep -E -q "Segmentation|Backtrace|SIGSEGV|Program received" "r$n.out" && fail "$n ranks: crashed"
  last=$(ls r$n/run_[0-9][0-9][0-9][0-9][0-9].h5 2> /dev/null | sort | tail -1)
  [ -n "$last" ] || fail "$n ranks: no frame written"
  if [ "$mode" = --fail ]; then
    [ "$rc" -eq 1 ] || fail "$n rank(s): exit status $rc, expected 1"
    fatal=$(grep -E '^FATAL \[rank [0-9]+' "r$n.out" | head -1)
    [ -n "$fatal" ] || fail "$n rank(s): no FATAL line"
    [ "$(grep -c '^FATAL' "r$n.out")" -eq 1 ] || fail "$n rank(s): the FATAL line is printed more than once"
    if [ "$n" -gt 1 ]; then
      [[ "$fatal" =~ ^FATAL\ \[rank\ 0, ]] && fail "$n ranks: the failure is not reported from the rank that failed: $fatal"
    fi
    grep -q "state at failure written to r$n/" "r$n.out" || fail "$n rank(s): no failure frame"
    echo "ok: $n rank(s): exit 1, $fatal"
  else
    [ "$rc" -eq 0 ] || fail "$n rank(s): exit status $rc"
  fi
  if [ "$n" -gt 1 ]; then
    "$py" "$tools/compare_frames.py" "$last" "$ref" --exact > "cmp$n.txt" || \
      { cat "cmp$n.txt"; fail "$n ranks: final frame differs from the single process's"; }
    echo "ok: $n ranks: $(basename "$last") bit-identical to one process's"
    # (the file the ranks wrote together: every dataset and attribute, but
    # the deck, whose output directory differs)
    h5diff --exclude-path /deck "$last" "$ref" > "h5diff$n.txt" || { head -5 "h5diff$n.txt"; \
      fail "$n ranks: final frame file differs from the single process's (h5diff)"; }
    cmp -s "r$n/run.xdmf" r1/run.xdmf || fail "$n ranks: the XDMF series differs from one process's"
    if [ -e r1/run_particles.xdmf ]; then
      cmp -s "r$n/run_particles.xdmf" r1/run_particles.xdmf || fail "$n ranks: the particles' XDMF series differs"
    fi
    cmp -s "r$n/run_history.txt" r1/run_history.txt || { diff "r$n/run_history.txt" r1/run_history.txt | head; \
      fail "$n ranks: the energy history differs from one process's"; }
    cmp -s "r$n/run_matsum.txt" r1/run_matsum.txt || { diff "r$n/run_matsum.txt" r1/run_matsum.txt | head; \
      fail "$n ranks: the material and body sums differ from one process's"; }
    echo "ok: $n ranks: energy history ($(grep -vc '^#' r1/run_history.txt) rows) the same as one process's"
    if grep -q 'progress_steps = 5' r1.nml; then
      limits() { grep -E '^step +[0-9]+ .* dt by ' "$1" | sed -E 's/^step +([0-9]+) .* dt by (.*)$/\1 \2/'; }
      [ "$(limits "r$n.out")" = "$(limits r1.out)" ] || { diff <(limits "r$n.out") <(limits r1.out) | head -4; \
        fail "$n ranks: the progress lines name other step limits than one process's"; }
      echo "ok: $n ranks: the step limits of $(limits r1.out | wc -l) progress lines the same as one process's"
    fi
    # why each Euler step was due (the worst cells by shape: whole-grid indices)
    dues() { grep -E '^euler [0-9]+ due at step' "$1"; }
    [ "$(dues "r$n.out")" = "$(dues r1.out)" ] || { diff <(dues "r$n.out") <(dues r1.out) | head -4; \
      fail "$n ranks: the Euler steps' triggers are logged otherwise than one process's"; }
    # what each smoothing rezone did (distorted cells, subdomains, cells
    # smoothed, Q_min, iterations, guard, nodes put back: whole-grid counts)
    smooths() { grep -E '^(lssm|smooth) at step' "$1"; }
    [ "$(smooths "r$n.out")" = "$(smooths r1.out)" ] || { diff <(smooths "r$n.out") <(smooths r1.out) | head -4; \
      fail "$n ranks: the smoothing rezones are logged otherwise than one process's"; }
    if [ -f r1/run_gauges.txt ]; then
      cmp -s "r$n/run_gauges.txt" r1/run_gauges.txt || { diff "r$n/run_gauges.txt" r1/run_gauges.txt | head -4; \
        fail "$n ranks: the gauge histories differ from one process's"; }
      echo "ok: $n ranks: gauge histories ($(grep -vc '^#' r1/run_gauges.txt) rows) the same as one process's"
    fi
    if [ -f r1/run_tracers.txt ]; then
      cmp -s "r$n/run_tracers.txt" r1/run_tracers.txt || { diff "r$n/run_tracers.txt" r1/run_tracers.txt | head -4; \
        fail "$n ranks: the tracer histories differ from one process's"; }
      echo "ok: $n ranks: tracers ($(grep -vc '^#' r1/run_tracers.txt) rows) the same as one process's"
    fi
    if [ -f r1/run_tracks.txt ]; then
      cmp -s "r$n/run_tracks.txt" r1/run_tracks.txt || { diff "r$n/run_tracks.txt" r1/run_tracks.txt | head -4; \
        fail "$n ranks: the tracked-particle histories differ from one process's"; }
      echo "ok: $n ranks: tracked particles ($(grep -vc '^#' r1/run_tracks.txt) rows) the same as one process's"
    fi
  else
    ref=$last
  fi
done
echo "PASS mpi_ranks $(basename "$deck") $mode"
