#!/usr/bin/env bash
# Benchmarks (not tests): Lagrangian throughput on Sedov 40^3 with 1 and 2
# threads; the remap (tests/bench_remap.f90: global remap of a 40^3 box, pure
# and mixed cells, MoF reconstructions) with 1 and 2 threads; the Sedov 3D
# octant with global ALE (Euler time per Euler step against Lagrangian time
# per step); L1 density error against wall time for Sod (N = 100..800) and
# Sedov (N^3, N = 10..40) through tools/speed_error.py; and mesh smoothing
# (Sect. 7.1, tests/bench_smooth.f90); the cost of coupled MPM particles
# (issue 14): a gas pushing an elastic block of 64000 particles in a 40^3
# grid, against the same scene without the particles, 1 and 2 threads, and
# through global Euler steps with linear and gimp supports (the particles'
# part of a Lagrangian step and of an Euler step, per particle); 20736
# particles leaving through an open face at one Euler step, one process and
# 2 ranks (the particles' share of the Euler phase); the
# rotating projectile of paper Sect. 7.4 (Table 2) with LSSM against global
# smoothing, n = 4 and 8, to t = 0.1 (tools/projectile_compare.py); the
# Taylor bar's resolution study (issue 15, about 25 minutes; BENCH_ONLY=taylor
# runs only that); MPI (issue 16): Sedov 40^3 Lagrangian and with LSSM, 1
# rank x 2 threads against 2 ranks x 1 thread, the halo's share of the
# Lagrangian time and its messages and bytes per step, and 4 ranks
# oversubscribed for the halo counts; restart dumps and peak memory of Sedov
# 80^3 on 1 process and 2 ranks; peak memory per rank on 4 ranks against one
# process for Sedov 64^3 LSSM, the TNT octant at 64^3 Eulerian and the Gurson
# ring at 192 x 192 x 4, and the Euler phase's messages per rank at a fixed
# block on 1 to 27 ranks with a weak-scaling estimate (issue 35); the
# Comp B cylinder at 40 x 40 x 48 (LSSM near a corner charge) the same way
# (BENCH_ONLY=mpi runs only that); memory
# per cell (issue 40): the marginal peak resident bytes per cell between
# Sedov 40^3 and 60^3 Lagrangian, beside those runs' throughput
# (BENCH_ONLY=memory runs only that); 1 kg TNT in free air against
# Kingery-Bulmash (issue 37, about 8 minutes; BENCH_ONLY=blast runs only
# that): the 1D spherical pre-run alone at 100, 200, 400 and 800 zones per
# charge radius, the 1D run mapped into a 64^3 octant at 1500 us and into an octant
# graded to 10 mm cells along the gauges' axis, the same scene in 3D from
# t = 0 (no &prerun) at BENCH_BLAST_N^3 (56 by default), arrival and peak
# overpressure at 0.5, 1, 2 and 3 m (tools/blast_kb_plot.py:
# blast_kb.png and blast_kb.txt in OUTDIR); the TNT octant of the stability
# matrix in each Euler-phase mode at 16^3 and 32^3 against its converged 1D
# run (issue 33, about 15 minutes; BENCH_ONLY=tnt runs only that); the
# first bubble period of a TNT charge deep in water against Rayleigh-Willis
# (issue 36, input/tnt_bubble.nml at 48^3 and 64^3, about 30 minutes;
# BENCH_ONLY=bubble runs only that); an Euler step's cost against the grid
# size, the same cells changed in 20^3, 40^3, 60^3 and 80^3 (issue 33, 5 minutes;
# BENCH_ONLY=flat runs only that); a TNT charge's shock in free water in the
# 1D run alone, at three zone widths and two linear viscosities, against
# the similitude (issue 36, a few minutes; BENCH_ONLY=water1d runs only that);
# the velocity cut-off's speed-up and field differences on Sedov 40^3 and the
# TNT octant at 32^3 (a few minutes; BENCH_ONLY=cutoff runs only that);
# the paper's garage (input/garage.nml, issue 39): LSSM against global
# smoothing and the global rezone, and 1, 2, 4 ranks (about 4 minutes;
# BENCH_ONLY=garage runs only that); the paper's open-frame building
# (input/building.nml) the same way (BENCH_ONLY=building runs only that).
# Usage: tools/bench.sh LSALEPM OUTDIR [BENCH_REMAP]
# (BENCH_REMAP defaults to tests/bench_remap in LSALEPM's build directory)
# BENCH_ONLY=particles runs only the particle sections.
set -euo pipefail
SECONDS=0
exe=$(realpath "$1"); mkdir -p "$2"; outdir=$(realpath "$2")
remap_exe=$(realpath "${3:-$(dirname "$exe")/tests/bench_remap}")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"

# ---- Coupled particles (issue 14): cost per particle-step ----
# A Lagrangian scene (no Euler phase: coupled particles have none yet): gas
# at rest with a pressure jump at x = 0.25 pushing an elastic block
# [0.3,0.8]x[0.25,0.75]^2 = 20^3 cells at per_cell 2 (64000 particles) in a
# 40^3 box, 120 steps, frames only at the start and the end. The same deck
# without &solid/&particles is the reference, run in the same bench run. The
# particle part of a step is (Lagrangian time per step with particles -
# without), from the run log's timers (the output timer, frames included,
# is apart); cost per particle-step is that over the particle count.
particles_bench() {
  cat > pblock.nml <<'DECK'
&run title = 'bench: gas pushing an elastic block, 40^3', t_end = 100, max_steps = 120, progress_seconds = 600 /
&grid ni = 40, nj = 40, nk = 40, xmin = 0, 0, 0, xmax = 1, 1, 1 /
&material name = 'gas', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'gas', density = 1.0, pressure = 1.0 /
&region shape = 'box', lo = 0, 0, 0, hi = 0.25, 1, 1, material = 'gas', density = 5.0, pressure = 20.0 /
&solid name = 'block', density = 4, youngs_modulus = 200, poisson_ratio = 0.3, strength = 'elastic' /
&particles shape = 'box', lo = 0.3, 0.25, 0.25, hi = 0.8, 0.75, 0.75, solid = 'block', per_cell = 2 /
&boundary xlo = 'wall', xhi = 'wall', ylo = 'wall', yhi = 'wall', zlo = 'wall', zhi = 'wall' /
&output dir = 'out/pblock', frame_dt = 1000 /
DECK
  grep -v '^&solid\|^&particles' pblock.nml | sed -e "s|out/pblock|out/pgas|" > pgas.nml
  echo "## Coupled particles: gas + elastic block in 40^3, 120 steps, with and without particles (Release)"
  for th in 1 2; do
    for scene in pgas pblock; do
      OMP_NUM_THREADS=$th OMP_PROC_BIND=true "$exe" $scene.nml > ${scene}_$th.log
      cp ${scene}_$th.log "$outdir/bench_${scene}_$th.log"
    done
    awk -v th=$th '
      FNR == 1 {f++}
      /^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "lagrange") lag[f] = $(i + 1)}
      /^throughput:/ {steps[f] = $5}
      /^throughput by phase:/ {rate[f] = $5}
      /^particles: [0-9]+ in all/ {np = $2}
      END {
        per0 = lag[1] / steps[1]; per1 = lag[2] / steps[2]
        printf "threads %d: without particles %.3e cell-cycles/s (%.2f ms/step, %d steps); ", th, rate[1], 1e3 * per0, steps[1]
        printf "with %d particles %.3e cell-cycles/s (%.2f ms/step, %d steps)\n", np, rate[2], 1e3 * per1, steps[2]
        printf "threads %d: particle part %.2f ms/step = %.3e s per particle-step (%.2f x the gas step)\n", \
               th, 1e3 * (per1 - per0), (per1 - per0) / np, per1 / per0
      }' pgas_$th.log pblock_$th.log
  done
}
# The particles' supports spread over the cells they overlap (&hydro
# particle_support = 'gimp') against linear shape functions: the block of
# particles_bench pushed through global Euler steps every 10 steps (its
# particles straddle faces after the first), 120 steps, 1 thread, the
# gas alone with the same Euler steps as the reference; the particle part
# of the Lagrangian phase per particle-step, and the ratio gimp / linear;
# and the particles' part of the Euler phase (the log's `euler particles`
# line: placed, the fluid under them filled, their nodal share saved,
# relocated, each cell's particle states fitted, coupled again) per
# particle per Euler step, also in particle-steps of the Lagrangian phase
# (issue 34: what an Euler step costs the particles).
gimp_bench() {
  echo "## Particle supports: linear against gimp, the block of the particle bench through global Euler steps, 1 thread"
  local scene
  for scene in pgas pblock pblock_gimp; do
    sed -e "s|out/pblock|out/$scene|" -e "s|out/pgas|out/$scene|" "${scene%_gimp}.nml" > "e_$scene.nml"
    echo "&rezone mode = 'global', interval_steps = 10 /" >> "e_$scene.nml"
    [[ $scene == pblock ]] && echo "&hydro particle_support = 'linear' /" >> "e_$scene.nml"
    [[ $scene == *_gimp ]] && echo "&hydro particle_support = 'gimp' /" >> "e_$scene.nml"
    OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$exe" "e_$scene.nml" > "e_$scene.log"
    cp "e_$scene.log" "$outdir/bench_euler_$scene.log"
  done
  awk '
    FNR == 1 {f++}
    /^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "lagrange") lag[f] = $(i + 1)}
    /^throughput:/ {steps[f] = $5}
    /^euler steps:/ {neul[f] = $3 + 0}
    /^euler particles:/ {epart[f] = $3}
    /^particles: [0-9]+ in all/ {np = $2}
    END {
      for (k = 2; k <= 3; k++) part[k] = lag[k] / steps[k] - lag[1] / steps[1]
      printf "linear: particle part %.3e s per particle-step; gimp: %.3e s per particle-step; gimp / linear %.2f\n", \
             part[2] / np, part[3] / np, part[3] / part[2]
      for (k = 2; k <= 3; k++) pe[k] = epart[k] / (neul[k] * np)
      printf "Euler steps: the particles%s part %.3e s per particle per Euler step with linear (%d Euler steps; %.2f " \
             "particle-steps), %.3e s with gimp (%d; %.2f particle-steps)\n", "'"'"'", pe[2], neul[2], pe[2] * np / part[2], \
             pe[3], neul[3], pe[3] * np / part[3]
    }' e_pgas.log e_pblock.log e_pblock_gimp.log
}
# Issue 34: the solid's state through global Euler steps, against the gas /
# solid Riemann problem's and the ballistic slab's exact solutions, at three
# resolutions, linear / gimp / gimp with particle_q 0.4 / the default (tools/particles_euler.py;
# about 5 minutes, 1 thread).
particles_euler_bench() {
  echo "## Particles through Euler steps (issue 34): plateau and slab against exact solutions, 1 thread"
  /usr/bin/python3 "$root/tools/particles_euler.py" --exe "$exe" --out "$outdir" | tee "$outdir/particles_euler.txt"
}
# Particles leaving at one Euler step: a slab of 20736 particles carried
# through the outflow face of 40 x 48 x 8 cells before the first Euler step
# (global rezone every 40 steps), one process and 2 ranks (cut across the
# slab) x 1 thread: the particles' share of the Euler phase (the search for
# the hosts of those that left), and no step on the whole grid on 2 ranks.
particles_leaving_bench() {
  echo "## Particles leaving through an open face at one Euler step (20736 particles), 1 thread"
  cat > leaving.nml <<'DECK'
&run title = 'a slab of particles leaving through an open face', t_end = 0.1, blocks = 1, 2, 1 /
&grid ni = 40, nj = 48, nk = 8, xmin = 0, 0, 0, xmax = 2.0, 2.4, 0.4 /
&material name = 'gas', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'gas', density = 1.0, pressure = 1.0, velocity = 4, 0, 0 /
&solid name = 'block', density = 10, youngs_modulus = 1000, poisson_ratio = 0.3, strength = 'bilinear', yield_stress = 100,
  tangent_modulus = 10 /
&particles shape = 'box', lo = 1.8, 0.0, 0.0, hi = 1.9, 2.4, 0.4, solid = 'block', per_cell = 3,
           stress = -1, -1, -1, 0, 0, 0, velocity = 4, 0, 0 /
&boundary xlo = 'inflow', xlo_velocity = 4, 0, 0, inflow_material(1) = 'gas', inflow_density(1) = 1.0,
  inflow_pressure(1) = 1.0, xhi = 'outflow' /
&rezone mode = 'global', interval_steps = 40, side_ratio = 0, cos_angle = 0 /
&output dir = 'out/leaving', frame_dt = 1 /
DECK
  OMP_NUM_THREADS=1 "$exe" leaving.nml > leaving_r1.log
  OMP_NUM_THREADS=1 "$(command -v mpirun)" $([ "$(id -u)" -eq 0 ] && echo --allow-run-as-root) --oversubscribe -np 2 \
    "$exe" leaving.nml > leaving_r2.log
  for f in leaving_r1 leaving_r2; do
    echo "$f: Euler phase $(grep '^timers' $f.log | grep -o 'euler *[0-9.]*' | awk '{print $2}') s" \
         "$(grep -o '^euler particles: *[0-9.]* s' $f.log || true) |" \
         "$(grep -m1 -o 'particles: [0-9]* left the grid' $f.log) | on the whole grid: $(grep -c 'on the whole grid' $f.log || true)"
  done
  echo
}
# Paper Sect. 7.4 (Table 2): the Euler phase of LSSM against global
# smoothing for the rotating projectile, same sitting, 1 thread.
projectile_bench() {
  echo "## Rotating projectile (paper 7.4, Table 2): LSSM against global smoothing, to t = 0.1, 1 thread"
  /usr/bin/python3 "$root/tools/projectile_compare.py" "$exe" "$work/projectile" --n 4,8 --t-end 0.1 \
    | tee "$outdir/projectile_compare.md"
}
# The Taylor bar (PARTICLES.md §2.7 anchor 1, input/taylor_bar.nml):
# resolution study, Release, 1 thread, one run at a time (about 4, 5 and 14
# minutes): cells 0.8 mm with 2 and 3 particles per cell per direction
# (spacings 0.4, 0.267) and cells 0.64 with 3 (0.213, the deck as it is);
# tools/taylor_measure.py measures each against DynELA's L_f 26.52, D_f 11.15.
taylor_bench() {
  echo "## Taylor bar 42CrMo4, 287 m/s, 80 us (input/taylor_bar.nml): resolution study, 1 thread"
  local deck=$root/input/taylor_bar.nml dirs=() v grid ppc
  for v in "h0.80_pc2|ni = 9, nj = 9, nk = 42, xmin = 0, 0, 0, xmax = 7.2, 7.2, 33.6|2" \
           "h0.80_pc3|ni = 9, nj = 9, nk = 42, xmin = 0, 0, 0, xmax = 7.2, 7.2, 33.6|3" \
           "h0.64_pc3||3"; do
    IFS='|' read -r name grid ppc <<< "$v"
    sed -e "s|dir = 'out/taylor_bar'|dir = '$work/taylor/$name'|" -e "s|per_cell = [0-9]*|per_cell = $ppc|" \
        ${grid:+-e "s|^&grid .* /|\&grid $grid /|"} "$deck" > "taylor_$name.nml"
    /usr/bin/time -f "$name: %e s wall" env OMP_NUM_THREADS=1 "$exe" "taylor_$name.nml" > "$outdir/taylor_$name.log" 2>&1 \
      || echo "$name: run failed (see $outdir/taylor_$name.log)"
    tail -1 "$outdir/taylor_$name.log"
    dirs+=("$work/taylor/$name")
  done
  /usr/bin/python3 "$root/tools/taylor_measure.py" "${dirs[@]}" | tee "$outdir/taylor_measure.txt" || true
}
# ---- MPI (issue 16): ranks against threads on the same 2 cores ----
# Sedov 40^3 (input/sedov3d.nml at 40^3) to t = 0.5, Lagrangian and with
# LSSM (input/sedov3d_lssm.nml at 40^3). Each configuration's log gives the
# Lagrangian throughput, the phase timers and, on several ranks, the halo
# line (rank 0: seconds in exchanges and the global step, their share of the
# Lagrangian time, messages and bytes sent per step). 4 ranks on 2 cores are
# oversubscribed: their times mean nothing, their halo counts do.
mpi_bench() {
  local deck name
  for deck in sedov3d sedov3d_lssm; do
    name=${deck/sedov3d/sedov40}
    sed -e 's/ni = 20, nj = 20, nk = 20/ni = 40, nj = 40, nk = 40/' -e 's/t_end = 1.0/t_end = 0.5/' \
        -e "s|^&output.*|\&output dir = 'out/$name' /|" "$root/input/$deck.nml" > $name.nml
    echo "## MPI: $name.nml (Sedov 40^3 to t = 0.5$([[ $deck == *lssm ]] && echo ', LSSM'), Release)"
    mpi_runs $name
  done
  # coupled particles: the Gurson steel ring refined to 96 x 96 x 4 cells
  # (14432 particles), 200 steps with global-ALE Euler steps
  sed -e 's/ni = 24, nj = 24, nk = 1/ni = 96, nj = 96, nk = 4/' -e 's/max_steps = 120/max_steps = 200/' \
      -e "s|^&output dir = '[^']*'|\&output dir = 'out/ring96'|" "$root/tests/decks/strength_shell_small.nml" > ring96.nml
  echo "## MPI: ring96.nml (the Gurson ring of tests/decks/strength_shell_small.nml at 96 x 96 x 4, particles, Release)"
  mpi_runs ring96
  # two materials: the TNT sphere of hardcases/tnt_sphere.nml at 32^3 with an
  # Euler step (global rezone) after every step to 6 us: MoF in the mixed
  # cells, open faces, every cell remapped
  sed -e 's/ni = 16, nj = 16, nk = 16/ni = 32, nj = 32, nk = 32/' -e 's/t_end = 12.0/t_end = 6.0/' \
      -e "s|^&output dir = 'out/tnt_sphere', frame_dt = 1.0,|\&output dir = 'out/tnt32', frame_dt = 10.0,|" \
      "$root/hardcases/tnt_sphere.nml" > tnt32.nml
  echo "&rezone mode = 'global', interval_steps = 1, side_ratio = 0, cos_angle = 0 /" >> tnt32.nml
  echo "## MPI: tnt32.nml (hardcases/tnt_sphere.nml at 32^3, an Euler step every step, two materials, Release)"
  mpi_runs tnt32
  # a blast against a structure: input/c4_plate.nml as it is (the 1D
  # pre-run mapped, LSSM, open faces, 9216 coupled particles)
  sed -e "s|^&output dir = 'out/c4_plate'|\&output dir = 'out/c4mpi'|" "$root/input/c4_plate.nml" > c4mpi.nml
  grep -q "out/c4mpi" c4mpi.nml
  echo "## MPI: c4mpi.nml (input/c4_plate.nml: a C4 charge against an aluminium plate of particles, LSSM, open faces, Release)"
  mpi_runs c4mpi
  # a corner charge's LSSM Euler phase: input/compb_cylinder.nml at 40 x 40
  # x 48 to t = 15 us (the smoothing on blocks cut for its work from its
  # larger Euler steps on, parallel_euler)
  sed -e 's/ni = 20, nj = 20, nk = 24/ni = 40, nj = 40, nk = 48/' -e 's/t_end = 30.0/t_end = 15.0/' \
      -e "s|^&output dir = 'out/compb_cylinder'|\&output dir = 'out/compb40'|" "$root/input/compb_cylinder.nml" > compb40.nml
  grep -q "out/compb40" compb40.nml
  echo "## MPI: compb40.nml (input/compb_cylinder.nml at 40 x 40 x 48 to 15 us, LSSM, Release)"
  mpi_runs compb40
  mpi_dump_bench
  ranks_memory_bench
  messages_bench
}

# The Euler phase's messages and bytes per rank per Euler step at a fixed
# block (27^3 cells per rank) on 1, 2, 4, 8 and 27 ranks (oversubscribed),
# counted by Open MPI's monitoring, and the weak-scaling estimate to 1e7
# cells on 512 ranks (issue 35; tools/messages_table.py: its tables, and
# the runs' logs in OUTDIR/messages).
messages_bench() {
  /usr/bin/python3 "$root/tools/messages_table.py" --exe "$exe" --out "$outdir/messages" --cases global lssm open mixed
  echo
}

# Peak resident memory per rank on 4 ranks (oversubscribed) against one
# process's (issue 35's bar: at most 0.35), each log's `memory:` line, for
# the decks of tools/memory_decks.sh (Sedov 64^3 LSSM, the TNT octant at 64^3
# Eulerian, the Gurson ring at 192 x 192 x 4, the frame of 360k particles at
# 96 x 64 x 64: particles seeded on the blocks).
ranks_memory_bench() {
  local name mpiexec root_flag=()
  mpiexec=$(command -v mpirun)
  [ "$(id -u)" -eq 0 ] && root_flag=(--allow-run-as-root)
  bash "$root/tools/memory_decks.sh" .
  echo "## MPI: peak resident memory per rank on 4 ranks against one process (issue 35)"
  for name in mem_sedov64 mem_tnt64 mem_ring192 mem_frame96; do
    OMP_NUM_THREADS=1 "$exe" $name.nml > ${name}_r1.log
    OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" --oversubscribe -np 4 "$exe" $name.nml > ${name}_r4.log
    cp ${name}_r1.log ${name}_r4.log "$outdir/"
    awk -v n=$name 'FNR == 1 {f++} /^memory: peak resident/ {m[f] = $4}
         END {printf "%s: one process %s MiB, 4 ranks %s MiB per rank (the most loaded): x%.2f\n", n, m[1], m[2], m[2] / m[1]}' \
        ${name}_r1.log ${name}_r4.log
  done
  # the frame continued on 4 ranks from a dump of 4 ranks at step 1 (each
  # block reads its own particles and mixed cells from the file)
  sed -e "s|max_steps = 2 /|max_steps = 1, dump_steps = 1 /|" -e "s|dir = 'out/mem_frame96'|dir = 'out/mem_frame96_dump'|" \
      mem_frame96.nml > mem_frame96_dump.nml
  sed -e "s|max_steps = 2 /|max_steps = 2, restart_from = 'out/mem_frame96_dump/mem_frame96_dump_restart_00000001.h5' /|" \
      -e "s|dir = 'out/mem_frame96'|dir = 'out/mem_frame96_cont'|" mem_frame96.nml > mem_frame96_cont.nml
  OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" --oversubscribe -np 4 "$exe" mem_frame96_dump.nml > mem_frame96_dump.log
  OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" --oversubscribe -np 4 "$exe" mem_frame96_cont.nml > mem_frame96_cont.log
  cp mem_frame96_dump.log mem_frame96_cont.log "$outdir/"
  awk 'FNR == 1 {f++} /^memory: peak resident/ {m[f] = $4}
       END {printf "mem_frame96 restarted on 4 ranks: %s MiB per rank (the most loaded): x%.2f of one process\n", m[2], m[2] / m[1]}' \
      mem_frame96_r1.log mem_frame96_cont.log
  echo
}

# Restart dumps and memory: Sedov 80^3 Lagrangian (512 000 cells), a dump
# at step 6, continued from it to step 8, on 1 process (1 thread) and on 2
# ranks x 1 thread: each log's dump time and peak resident memory (the
# ranks write one file together and hold no whole-grid copy). The two
# dumps must be equal (h5diff).
mpi_dump_bench() {
  local mpiexec root_flag=() n
  mpiexec=$(command -v mpirun)
  [ "$(id -u)" -eq 0 ] && root_flag=(--allow-run-as-root)
  echo "## MPI: restart dumps, Sedov 80^3 Lagrangian (input/sedov3d.nml at 80^3), Release"
  for n in 1 2; do
    sed -e 's/ni = 20, nj = 20, nk = 20/ni = 80, nj = 80, nk = 80/' \
        -e "s|^\(&run .*\)/ *\$|\1, max_steps = 6, dump_steps = 6 /|" \
        -e "s|^&output.*|\&output dir = 'out/dump80_r$n', name = 'd' /|" "$root/input/sedov3d.nml" > dump80_r$n.nml
    sed -e "s|max_steps = 6, dump_steps = 6|max_steps = 8, restart_from = 'out/dump80_r$n/d_restart_00000006.h5'|" \
        dump80_r$n.nml > dump80_r${n}_cont.nml
    if [ "$n" -eq 1 ]; then
      OMP_NUM_THREADS=1 "$exe" dump80_r1.nml > dump80_r1.log
      OMP_NUM_THREADS=1 "$exe" dump80_r1_cont.nml > dump80_r1_cont.log
    else
      OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" -np 2 --bind-to core "$exe" dump80_r2.nml > dump80_r2.log
      OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" -np 2 --bind-to core "$exe" dump80_r2_cont.nml > dump80_r2_cont.log
    fi
    echo "$n rank(s): $(grep '^restart out' dump80_r$n.log) | $(grep '^memory' dump80_r$n.log)"
    echo "  continued: $(grep '^memory' dump80_r${n}_cont.log)"
    cp dump80_r$n.log dump80_r${n}_cont.log "$outdir/"
  done
  if h5diff --exclude-path /deck out/dump80_r1/d_restart_00000006.h5 out/dump80_r2/d_restart_00000006.h5 \
    > /dev/null; then
    echo "the 2-rank dump equals the single process's (h5diff, but the deck naming the output folder)"
  else
    echo "the 2-rank dump DIFFERS from the single process's"
  fi
  echo
}

# One deck on 1 rank x 2 threads, 2 ranks x 1 thread and 4 ranks x 1
# (oversubscribed): the logs' throughput, timers and halo lines, and the
# 2-rank run against the 1-rank one.
mpi_runs() {
  local name=$1 mpiexec root_flag=() c
  mpiexec=$(command -v mpirun)
  [ "$(id -u)" -eq 0 ] && root_flag=(--allow-run-as-root)
  OMP_NUM_THREADS=2 OMP_PROC_BIND=true "$exe" $name.nml > ${name}_r1t2.log
  OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" -np 2 --bind-to core "$exe" $name.nml > ${name}_r2t1.log
  OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" --oversubscribe -np 4 "$exe" $name.nml > ${name}_r4t1.log
  for c in r1t2 r2t1 r4t1; do
    cp ${name}_$c.log "$outdir/bench_mpi_${name}_$c.log"
    echo "$c: $(grep '^throughput:' ${name}_$c.log) | $(grep '^timers' ${name}_$c.log)"
    grep '^halo' ${name}_$c.log || true
    grep '^memory:' ${name}_$c.log || true
    grep '^euler steps:' ${name}_$c.log | sed 's/.*; rezone/  of the Euler phase, rezone/' || true
    grep -c '^lssm: smoothed on blocks cut for its work' ${name}_$c.log | sed 's/^/  Euler steps smoothed on blocks cut for the work: /' || true
  done
  # (the Euler phase's wall time, where there is one: issue 35's bar is 2
  # ranks x 1 thread no slower than 1 rank x 2 threads, Sedov 40^3 LSSM)
  awk 'FNR == 1 {f++} /^timers \[s\]:/ {for (i = 1; i < NF; i++) {if ($i == "total") tot[f] = $(i + 1)
                                                                  if ($i == "euler") eu[f] = $(i + 1)}}
       /^throughput by phase:/ {rate[f] = $5}
       END {printf "2 ranks x 1 thread against 1 rank x 2 threads: Lagrangian throughput x%.2f, total wall time x%.2f", \
            rate[2] / rate[1], tot[1] / tot[2]
            if (eu[1] > 0) printf ", Euler phase wall time x%.2f (%s s against %s s)", eu[2] / eu[1], eu[2], eu[1]
            printf "\n"}' ${name}_r1t2.log ${name}_r2t1.log
  echo
}
# ---- Memory per cell (issue 40): Sedov Lagrangian, 40^3 and 60^3, 20 steps ----
# The marginal bytes per cell, (peak60 - peak40) / (60^3 - 40^3), of the
# peak resident memory (/usr/bin/time's, in KiB; the log's `memory:` line
# is in MiB), beside the Lagrangian throughput of the same two runs
# (1 thread). The fixed part (libraries, MPI, HDF5) cancels; what is left
# is the state and the work arrays per cell (LULESH's is 715 bytes).
memory_bench() {
  local n kib=() rate=() steps
  echo "## Memory per cell: Sedov 3D octant, Lagrangian, 20 steps, 1 thread, 40^3 and 60^3 (Release)"
  for n in 40 60; do
    sed -e "s/ni = 20, nj = 20, nk = 20/ni = $n, nj = $n, nk = $n/" \
        -e "s|^&run .*|\&run title = 'Sedov $n^3, memory', t_end = 1.0, max_steps = 20 /|" \
        -e "s|^&output.*|\&output dir = 'out/mem$n' /|" "$root/input/sedov3d.nml" > mem$n.nml
    OMP_NUM_THREADS=1 /usr/bin/time -f '%M' -o mem$n.kib "$exe" mem$n.nml > mem$n.log
    cp mem$n.log "$outdir/bench_memory_$n.log"
    kib+=("$(tail -1 mem$n.kib)")
    rate+=("$(awk '/^throughput by phase:/ {print $5}' mem$n.log)")
    steps=$(awk '/^throughput:/ {print $5}' mem$n.log)
    echo "$n^3: peak resident $(awk -v k="${kib[-1]}" 'BEGIN {printf "%.1f", k / 1024}') MiB" \
         "($(grep '^memory:' mem$n.log)), Lagrangian ${rate[-1]} cell-cycles/s ($steps steps)"
  done
  awk -v k40="${kib[0]}" -v k60="${kib[1]}" -v r40="${rate[0]}" -v r60="${rate[1]}" 'BEGIN {
    printf "memory per cell (marginal, 40^3 to 60^3): %.0f bytes; throughput 60^3/40^3: %.3f\n", \
           1024 * (k60 - k40) / (60^3 - 40^3), r60 / r40 }'
}

# ---- 1 kg TNT in free air against Kingery-Bulmash (issue 37) ----
# A 1 kg TNT sphere (radius 52.71 mm, 1.63 g/cm^3) in the library's air
# (the ISO standard atmosphere, KB's; 100 kPa before 2026-12-06), units
# mm-us-g/cm^3-GPa, gauges at 0.5, 1, 2 and 3 m on the x axis (and, in 3D,
# at 2 and 3 m on the diagonal). (a) The 1D spherical pre-run alone
# (t_end = &prerun time = 6000 us) at zone widths 0.52710, 0.26355,
# 0.131775 and 0.0658875 mm (100 to 800 zones per charge radius): 1D
# convergence, its
# answers from <name>_prerun_gauges.txt. (b) The 1D run (0.131775 mm zones,
# converged by (a): its peaks within 2 % of the finest at 0.5 to 3 m) mapped
# into a 64^3 octant of 3.3 m at 1500 us, global ALE every 20 steps, to 4600
# us (its gauge file starts with the 1D rows); (d) below, the same mapped
# into a graded octant. (c) The same scene in 3D from t = 0, the charge lit
# at its centre, at BENCH_BLAST_N^3 (default 56: a probe of
# 48^3 suggested about 9 minutes for 56^3; it took 275 s here, 2 threads on
# a shared machine. The cost goes as N^4; the section prints the N that
# would take 10 and 30 minutes by that rule, about 68 and 89 from 275 s;
# the finest grid run in 30 minutes, 96^3 in 905 s, is in the README). Its cells
# (59 mm at 56^3) are larger than the charge: the run shows what the pre-run
# saves, not a converged 3D answer. tools/blast_kb_plot.py puts all of them
# against Kingery-Bulmash free air (KB's free-air fits, and beside them a
# surface burst of W/1.8). 2 threads, one run at a time.
blast_bench() {
  local n=${BENCH_BLAST_N:-56} w name t0 files=() labels=()
  local gauges="gauge = 500, 0, 0, 1000, 0, 0, 2000, 0, 0, 3000, 0, 0"
  local diag="1154.7005383792516, 1154.7005383792516, 1154.7005383792516, 1732.0508075688772, 1732.0508075688772, 1732.0508075688772"
  local scene="&material name = 'tnt', library = 'tnt' /
&material name = 'air', library = 'air' /
&region shape = 'all', material = 'air' /
&region shape = 'sphere', material = 'tnt', center = 0, 0, 0, radius = 52.71, density = 1.63, energy_per_volume = 7.0 /
&detonation material = 'tnt', point = 0, 0, 0 /
&boundary xlo = 'symmetry', ylo = 'symmetry', zlo = 'symmetry', xhi = 'outflow', yhi = 'outflow', zhi = 'outflow' /"
  echo "## 1 kg TNT in free air against Kingery-Bulmash: 1D pre-run alone, 1D mapped into 3D, 3D from t = 0 (2 threads)"
  for w in 0.52710 0.26355 0.131775 0.0658875; do
    name=kb1d_$w
    cat > $name.nml <<DECK
&run title = '1 kg TNT, the 1D run alone, zone width $w mm', units = 'mm-us-g/cm^3-GPa', t_end = 6000 /
&grid ni = 4, nj = 4, nk = 4, xmin = 0, 0, 0, xmax = 4000, 4000, 4000 /
$scene
&prerun time = 6000, zone_width = $w /
&output dir = 'out/$name', $gauges /
DECK
    blast_run $name
    files+=("out/$name/${name}_prerun_gauges.txt"); labels+=("1D dr $w mm")
  done
  name=kb3d64_mapped
  cat > $name.nml <<DECK
&run title = '1 kg TNT in free air, 1D run mapped into 64^3 at 1500 us', units = 'mm-us-g/cm^3-GPa', t_end = 4600 /
&grid ni = 64, nj = 64, nk = 64, xmin = 0, 0, 0, xmax = 3300, 3300, 3300 /
$scene
&prerun time = 1500, zone_width = 0.131775 /
&rezone mode = 'global', interval_steps = 20 /
&output dir = 'out/$name', $gauges,
  $diag /
DECK
  blast_run $name
  files+=("out/$name/${name}_blast.txt"); labels+=("3D 64^3 mapped at 1500 us")
  # (d) the same mapping into a graded octant that keeps cells 10 mm long
  # and 13 mm across where the axis gauges' shock runs after the mapping (x
  # from 1.45 to 3.15 m, within 60 mm of the x axis; growing to 60 mm
  # towards the centre and 158 mm across far from the axis: 206 x 42 x 42
  # cells, the widths as the log gives them), with the 1D run's linear
  # viscosity (0.1) and LSSM: the 3D solver's own error at 2 and 3 m at a
  # resolution this machine affords
  name=kb3d_pencil_mapped
  cat > $name.nml <<DECK
&run title = '1 kg TNT in free air, 1D run mapped at 1500 us into an octant graded to 10 mm cells along the x axis',
     units = 'mm-us-g/cm^3-GPa', t_end = 4600 /
&grid ni = 206, nj = 42, nk = 42, xmin = 0, 0, 0, xmax = 3300, 3300, 3300,
      spacing_x = 1200, 60, 1450, 10, 3150, 10, 3300, 40,
      spacing_y = 60, 10, 1630, 120, spacing_z = 60, 10, 1630, 120 /
$scene
&prerun time = 1500, zone_width = 0.131775 /
&hydro q_linear = 0.1 /
&rezone mode = 'lssm' /
&output dir = 'out/$name', $gauges /
DECK
  blast_run $name
  files+=("out/$name/${name}_blast.txt"); labels+=("3D graded (10 mm on the axis) mapped at 1500 us")
  name=kb3d${n}_unmapped
  cat > $name.nml <<DECK
&run title = '1 kg TNT in free air, 3D from t = 0 at $n^3', units = 'mm-us-g/cm^3-GPa', t_end = 4600 /
&grid ni = $n, nj = $n, nk = $n, xmin = 0, 0, 0, xmax = 3300, 3300, 3300 /
$scene
&rezone mode = 'global', interval_steps = 20 /
&output dir = 'out/$name', $gauges,
  $diag /
DECK
  t0=$SECONDS
  blast_run $name
  awk -v n=$n -v t=$((SECONDS - t0)) 'BEGIN {if (t > 0) printf "3D from t = 0 at %d^3 (BENCH_BLAST_N): %d s; cost ~ N^4, so 10 minutes ~ %.0f^3, 30 minutes ~ %.0f^3\n", n, t, n * (600 / t)^0.25, n * (1800 / t)^0.25}'
  files+=("out/$name/${name}_blast.txt"); labels+=("3D $n^3 from t = 0")
  local lab=() l
  for l in "${labels[@]}"; do lab+=(--label "$l"); done
  /usr/bin/python3 "$root/tools/blast_kb_plot.py" "${files[@]}" "${lab[@]}" --mass-kg 1 --centre 0 0 0 \
    --length-unit mm --pressure-unit GPa --time-unit us --out "$outdir/blast_kb.png" --csv "$outdir/blast_kb.csv" \
    | tee "$outdir/blast_kb.txt"
}
# One blast deck, 2 threads, its wall time; the log kept in OUTDIR.
blast_run() {
  local name=$1 t0=$SECONDS
  OMP_NUM_THREADS=2 OMP_PROC_BIND=true "$exe" $name.nml > $name.log 2>&1 || echo "$name: run failed (see $outdir/bench_$name.log)"
  cp $name.log "$outdir/bench_$name.log"
  echo "$name: $((SECONDS - t0)) s wall; $(grep -m1 '^prerun: 1D spherical run' $name.log || true)"
}

# The TNT octant in each Euler-phase mode at 16^3 and 32^3 against the
# converged 1D run of the same deck (tools/tnt_modes.py): wall time, steps,
# and the gauges' peak and arrival errors.
tnt_modes_bench() {
  echo "== TNT octant: speed against error in each mode (tools/tnt_modes.py, 2 threads) =="
  /usr/bin/python3 "$root/tools/tnt_modes.py" --exe "$exe" --n 16 32 --threads 2 --out "$outdir" \
    | tee "$outdir/tnt_modes.txt"
}

# The bubble of input/tnt_bubble.nml at 48^3 and 64^3 (tools/bubble_period.py):
# the first period and R_max against the Rayleigh-Willis formula.
bubble_bench() {
  echo "== TNT bubble at 10 MPa: first period against Rayleigh-Willis (input/tnt_bubble.nml, 2 threads) =="
  local n name
  for n in 48 64; do
    name=bubble$n
    sed -e "s/ni = 48, nj = 48, nk = 48/ni = $n, nj = $n, nk = $n/" -e "s|out/tnt_bubble|out/$name|" \
      "$root/input/tnt_bubble.nml" > $name.nml
    blast_run $name
    /usr/bin/python3 "$root/tools/bubble_period.py" out/$name/${name}_matsum.txt --material tnt \
      --charge-kg 6.8277e-3 --p-inf 1.0e-2 | tee "$outdir/bench_${name}.txt"
  done
}

# ---- The underwater charge's shock in 1D: what the linear viscosity costs (issue 36) ----
# The 1D pre-run of hardcases/tnt_water_pencil.nml alone to 140 us (&prerun
# time = t_end), zones 0.1, 0.05 and 0.02 mm wide at the charge (wider
# beyond in proportion to the radius, to 1, 0.5 and 0.2 mm at 100 mm and
# that wide further out: the default far_zone_width), with
# the linear viscosity 0.5 (the 3D solver's default) and 0.1 (the 1D run's,
# and the deck's): the peaks at 5 to 20 charge radii (every 2.5) against the
# similitude (tools/water_similitude.py). A weak shock in water is eroded by
# the linear term at a given zone width: with 0.1 the peaks change by 2-3 %
# from 0.05 to 0.02 mm, with 0.5 they are still rising.
water_1d_bench() {
  echo "## TNT in free water, the 1D run alone to 140 us: peak overpressure against the similitude (1 thread)"
  local q zw name
  for q in 0.5 0.1; do
    for zw in 0.1 0.05 0.02; do
      name=water1d_q${q}_z$zw
      sed -e "s|^&prerun .*|\&prerun time = 140.0, zone_width = $zw, radius = 400, q_linear = $q /|" \
          -e "s|out/tnt_water_pencil|out/$name|" "$root/hardcases/tnt_water_pencil.nml" > $name.nml
      OMP_NUM_THREADS=1 "$exe" $name.nml > $name.log 2>&1 || echo "$name: run failed (see $outdir/bench_$name.log)"
      cp $name.log "$outdir/bench_$name.log"
      echo "q_linear $q, zones $zw mm at the charge:"
      /usr/bin/python3 "$root/tools/water_similitude.py" out/$name/${name}_prerun_gauges.txt --charge-kg 6.8277e-3 \
        --radii 50 75 100 125 150 175 200 | sed 's/^/  /'
    done
  done
}

# ---- An Euler step's cost against the grid size (issue 33) ----
# The Sedov blast with a fixed cell of 0.06 (the energy of input/sedov3d.nml)
# in octants of 20^3, 40^3 and 60^3 cells, a global rezone back to the box
# every step, 20 and 100 steps: the blast reaches the same cells in each, so
# every Euler step changes the same cells whatever the grid. Two more grids
# tell where a larger grid's extra cost comes from: 20 x 20 x 60 (the same
# strides as 20^3, the extra cells in planes the blast never reaches: what
# a larger state alone costs) and 60 x 20 x 20 (rows three times as long:
# the changed cells' rows and planes further apart in memory). Each run
# three times, interleaved, the fastest kept (1 thread). Printed: the Euler
# phase's wall time per Euler step over the first 20 steps (the grid-sized
# work, the global rezone's target grid and the remap's marks, is done with
# the grid, before the first step: `euler_init`), and over steps
# 21 to 100 alone (the difference of the two runs: what each further Euler
# step costs), each with its ratio to 20^3's (flat: 1). And 80^3, with
# 40^3 and 60^3 the three grids whose state (about 700 bytes a cell: 45,
# 150 and 360 MB) is larger than this machine's last-level cache (32 MiB
# here, printed), which 20^3's (5.6 MB) fits in: what the cost does past
# that size is printed as the ratios to 40^3's.
flat_bench() {
  echo "## An Euler step's cost against the grid size: Sedov, fixed cell 0.06, global rezone every step"
  echo "last-level cache: $(lscpu | awk -F: '/^L3 cache/ {gsub(/^ +/, "", $2); print $2}')"
  local shapes="20x20x20 40x40x40 60x60x60 80x80x80 20x20x60 60x20x20" sh ni nj nk st rep
  for sh in $shapes; do
    IFS=x read -r ni nj nk <<< "$sh"
    for st in 20 100; do
      cat > flat${sh}_$st.nml <<DECK
&run title = 'Sedov, fixed cell 0.06, ${sh} cells, an Euler step every step', t_end = 1.0, max_steps = $st /
&grid ni = $ni, nj = $nj, nk = $nk, xmin = 0, 0, 0,
      xmax = $(awk -v n=$ni 'BEGIN {printf "%.2f", 0.06 * n}'), $(awk -v n=$nj 'BEGIN {printf "%.2f", 0.06 * n}'), $(awk -v n=$nk 'BEGIN {printf "%.2f", 0.06 * n}') /
&material name = 'air', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'air', density = 1.0, pressure = 1.0e-6 /
&source position = 0, 0, 0, energy = 0.106384 /
&boundary xlo = 'symmetry', ylo = 'symmetry', zlo = 'symmetry', xhi = 'wall', yhi = 'wall', zhi = 'wall' /
&rezone mode = 'global', interval_steps = 1 /
&output dir = 'out/flat${sh}_$st', frame_dt = 100 /
DECK
    done
  done
  for rep in 1 2 3; do
    for st in 20 100; do
      for sh in $shapes; do
        OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$exe" flat${sh}_$st.nml > flat${sh}_${st}_$rep.log
      done
    done
  done
  cp flat60x60x60_20_1.log "$outdir/bench_flat60.log"
  for sh in $shapes; do
    for st in 20 100; do
      awk -v sh=$sh -v st=$st '/^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "euler") {e = $(i + 1); if (best == "" || e < best) best = e}}
           /^euler steps:/ {steps = $3 + 0; cells = $6 + 0}
           END {printf "%s %d %d %d %.6f\n", sh, st, steps, cells, best}' flat${sh}_${st}_1.log flat${sh}_${st}_2.log \
        flat${sh}_${st}_3.log
    done
  done | awk '$2 == 20 {s20[$1] = $3; c20[$1] = $4; e20[$1] = $5; if (!($1 in seen)) {seen[$1] = 1; order[++n] = $1}}
              $2 == 100 {s100[$1] = $3; c100[$1] = $4; e100[$1] = $5}
              END {
                for (i = 1; i <= n; i++) {
                  g = order[i]
                  a = e20[g] / s20[g]; b = (e100[g] - e20[g]) / (s100[g] - s20[g])
                  if (i == 1) {a0 = a; b0 = b}
                  if (g == "40x40x40") b40 = b
                  printf "%s: first %d Euler steps (%d cells remapped) %.3f ms per step, %.2f times 20^3'"'"'s; " \
                         "steps %d-%d (%d cells) %.3f ms per step, %.2f times 20^3'"'"'s", g, s20[g], c20[g], 1e3 * a, \
                         a / a0, s20[g] + 1, s100[g], c100[g] - c20[g], 1e3 * b, b / b0
                  if (g == "60x60x60" || g == "80x80x80") printf ", %.2f times 40^3'"'"'s", b / b40
                  printf "\n"
                }
              }'
}

# ---- The velocity cut-off (&hydro velocity_cutoff): 1 thread ----
# Each deck with velocity_cutoff = 0 and with the default, one after the
# other, twice: the Lagrangian throughput of each (the better of two) and
# their ratio, and the last frames' largest field differences (max|a-b| over
# max|b|, tools/compare_frames.py against the run without it). Sedov 40^3 to
# t = 0.5 (Lagrangian) and the TNT octant of the stability matrix at 32^3
# with LSSM on the paper's triggers.
cutoff_bench() {
  local name cut rep
  echo "## The velocity cut-off: velocity_cutoff = 0 against the default 1e-14 (1 thread)"
  sed -e 's/ni = 20, nj = 20, nk = 20/ni = 40, nj = 40, nk = 40/' -e 's/t_end = 1.0/t_end = 0.5/' \
      -e "s|^&output.*|\&output dir = 'out/cut_sedov', frame_dt = 0.5 /|" "$root/input/sedov3d.nml" > cut_sedov.nml
  sed -e 's/ni = 16, nj = 16, nk = 16/ni = 32, nj = 32, nk = 32/' \
      -e "s|^&output dir = 'out/tnt_sphere', frame_dt = 1.0,|\&output dir = 'out/cut_tnt', frame_dt = 12.0,|" \
      "$root/hardcases/tnt_sphere.nml" > cut_tnt.nml
  echo "&rezone mode = 'lssm', side_ratio = 4, cos_angle = 0.7 /" >> cut_tnt.nml
  printf 'density 1e-10 1e-10\npressure 1e-10 1e-10\nvelocity 1e-10 1e-10\nx 1e-10 1e-10\n' > cut_tol.txt
  for name in cut_sedov cut_tnt; do
    sed -e "s|out/$name'|out/${name}_0'|" $name.nml > ${name}_0.nml
    echo "&hydro velocity_cutoff = 0 /" >> ${name}_0.nml
    for rep in 1 2; do
      for cut in _0 ''; do
        OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$exe" $name$cut.nml > $name${cut}_$rep.log
      done
    done
    awk -v name=$name 'FNR == 1 {f = (FILENAME ~ /_0_[12][.]log$/) ? 1 : 2}
         /^throughput by phase:/ {if ($5 > r[f]) r[f] = $5}
         /^timers \[s\]:/ {if (t[f] == "" || $NF < t[f]) t[f] = $NF}
         END {printf "%s: Lagrangian %.3e cell-cycles/s without the cut-off, %.3e with it (x%.2f); total wall %.1f s " \
                     "against %.1f s (x%.2f)\n", name, r[1], r[2], r[2] / r[1], t[1], t[2], t[1] / t[2]}' \
      ${name}_0_1.log ${name}_0_2.log ${name}_1.log ${name}_2.log
    cp ${name}_1.log "$outdir/bench_$name.log"
    /usr/bin/python3 "$root/tools/compare_frames.py" "$(ls out/$name/*_000*.h5 | tail -1)" \
      "$(ls out/${name}_0/*_000*.h5 | tail -1)" --tolerances cut_tol.txt || true
  done
}

# ---- The paper's engineering scenes (Sects. 7.7, 7.8, issue 39) ----
# scene_bench NAME TITLE T_RANKS: input/NAME.nml (an &rezone mode = 'lssm'
# deck) with LSSM against global smoothing (&rezone mode 'smooth', the
# paper's ALEPM) and the global rezone to the initial grid ('global'), each
# to the deck's t_end on 1 rank x 2 threads: the Euler-phase wall time and
# Euler-step count of each and the ratio to LSSM's; then LSSM to T_RANKS on
# 1, 2 and 4 ranks (4 oversubscribed: its times mean little): peak memory
# per rank and the run's rank-seconds per cell-cycle and per particle-step
# (the same time over cells x steps and over particles x steps).
scene_bench() {
  local name=$1 title=$2 t_ranks=$3 mode n mpiexec root_flag=()
  echo "## $title, 1 rank x 2 threads"
  for mode in lssm smooth global; do
    sed -e "s|^&rezone mode = 'lssm'|\&rezone mode = '$mode'|" -e "s|dir = 'out/$name'|dir = 'out/${name}_$mode'|" \
        "$root/input/$name.nml" > ${name}_$mode.nml
    grep -q "mode = '$mode'" ${name}_$mode.nml
    OMP_NUM_THREADS=2 OMP_PROC_BIND=true "$exe" ${name}_$mode.nml > ${name}_$mode.log || echo "$mode: run failed"
    cp ${name}_$mode.log "$outdir/bench_${name}_$mode.log"
  done
  awk -v name=$name 'FNR == 1 {f++; m[f] = FILENAME; sub("^" name "_", "", m[f]); sub(/[.]log$/, "", m[f])}
       /^timers \[s\]:/ {for (i = 1; i < NF; i++) {if ($i == "total") tot[f] = $(i + 1); if ($i == "euler") eu[f] = $(i + 1)}}
       /^euler steps:/ {n[f] = $3; sub(/,/, "", n[f]); c[f] = $6}
       END {for (k = 1; k <= f; k++)
              printf "%-7s Euler phase %8.1f s in %4d Euler steps (%s cells remapped), total %8.1f s; Euler phase / LSSM'"'"'s x%.2f\n", \
                     m[k], eu[k], n[k], c[k], tot[k], eu[k] / eu[1]}' ${name}_lssm.log ${name}_smooth.log ${name}_global.log
  echo
  echo "## $name with LSSM to t = $t_ranks on 1, 2 and 4 ranks x 1 thread (4 oversubscribed)"
  mpiexec=$(command -v mpirun)
  [ "$(id -u)" -eq 0 ] && root_flag=(--allow-run-as-root)
  sed -e "s/t_end = [0-9.]*/t_end = $t_ranks/" -e "s|dir = 'out/$name'|dir = 'out/${name}_ranks'|" "$root/input/$name.nml" \
    > ${name}_ranks.nml
  for n in 1 2 4; do
    OMP_NUM_THREADS=1 "$mpiexec" "${root_flag[@]}" --oversubscribe -np $n "$exe" ${name}_ranks.nml > ${name}_r$n.log \
      || echo "$n ranks: run failed"
    cp ${name}_r$n.log "$outdir/bench_${name}_r$n.log"
    # (the whole grid's cells from the one-process log: a rank's `grid:` line is its block's)
    awk -v n=$n -v cells="$(awk '/^grid:/ {print $2 * $4 * $6; exit}' ${name}_r1.log)" '/^particles: [0-9]+ in all/ {np = $2}
         /^memory:/ {mem = $0} /^done:/ {steps = $(NF - 1)}
         /^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "total") tot = $(i + 1)}
         END {printf "%d rank(s): %d steps, total %.1f s: %.3g s per cell-cycle, %.3g s per particle-step (rank-seconds); %s\n", \
                     n, steps, tot, n * tot / (cells * steps), n * tot / (np * steps), mem}' ${name}_r$n.log
  done
}

# The garage (Sect. 7.8): to 4 ms, ranks to 1 ms (the paper: Euler phase 2,408 s
# against 112,980 s, 0.021); about 4 minutes; BENCH_ONLY=garage runs only that.
garage_bench() {
  scene_bench garage "The garage (input/garage.nml: half model, 0.4 m cells, 45.4 kg TNT mapped from 1D), to 4 ms" 1.0
}

# The open-frame building (Sect. 7.7): to the deck's t_end, ranks to 0.5 ms
# (the paper: Euler phase 49,400 s against 332,615 s, 0.1485, in 104 and
# 101 Euler steps); BENCH_ONLY=building runs only that.
building_bench() {
  scene_bench building "The open-frame building (input/building.nml: half model, 45 mm cells, 2.11 kg TNT)" 0.5
}

if [[ "${BENCH_ONLY:-}" == garage ]]; then
  garage_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == building ]]; then
  building_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == cutoff ]]; then
  cutoff_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == flat ]]; then
  flat_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == water1d ]]; then
  water_1d_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == bubble ]]; then
  bubble_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == tnt ]]; then
  tnt_modes_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == blast ]]; then
  blast_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == memory ]]; then
  memory_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == mpi ]]; then
  mpi_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == taylor ]]; then
  taylor_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi
if [[ "${BENCH_ONLY:-}" == particles ]]; then
  particles_bench
  echo
  gimp_bench
  echo
  particles_leaving_bench
  projectile_bench
  echo "bench wall time: ${SECONDS} s"
  exit 0
fi

sed -e 's/ni = 20, nj = 20, nk = 20/ni = 40, nj = 40, nk = 40/' \
    -e "s|^&output.*|\&output dir = 'out/sedov40' /|" "$root/input/sedov3d.nml" > sedov40.nml

echo "## Lagrangian throughput, Sedov 40^3 to t = 1 (Release)"
declare -A rate
for th in 1 2; do
  OMP_NUM_THREADS=$th OMP_PROC_BIND=true "$exe" sedov40.nml > sedov40_$th.log
  rate[$th]=$(awk '/^throughput by phase:/ {print $5}' sedov40_$th.log)
  steps=$(awk '/^throughput:/ {print $5}' sedov40_$th.log)
  echo "threads $th: ${rate[$th]} cell-cycles/s ($steps steps)"
done
echo "2-thread speed-up: $(awk -v a="${rate[1]}" -v b="${rate[2]}" 'BEGIN {printf "%.2f", b/a}')"

echo
memory_bench

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
     /^throughput:/ {nlag = $5}
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
echo "## A remapped cell in Lagrangian cell-cycles (1 thread): Sedov octant 20^3, an Euler step every step"
echo "## (global rezone back to the box), 40 steps, swept-face path (default) and intersection (swept_max = 0);"
echo "## then 200 steps on the default path (about 2000 cells remapped per Euler step against 370 in the first"
echo "## 40: the Euler steps' fixed costs, about 0.1-0.3 ms each here, spread over more cells); and the first"
echo "## and the last with &hydro velocity_cutoff = 0 (the still gas ahead of the blast, at rest with the"
echo "## cut-off and then cheaper than moving gas, costs a moving cell's cell-cycle again; not quite: the nodes"
echo "## exactly at rest still skip their terms)"
for sm in default 0 default200 cut0 cut0200; do
  deck=sedov20_every_$sm.nml
  nsteps=40
  lab=$sm
  [[ $sm == default200 ]] && nsteps=200 && lab="default, 200 steps"
  [[ $sm == cut0 ]] && lab="default, velocity_cutoff = 0"
  [[ $sm == cut0200 ]] && nsteps=200 && lab="default, 200 steps, velocity_cutoff = 0"
  sed -e "s|^&output.*|\&output dir = 'out/sedov20_every_$sm' /|" -e "s|^&run .*|\&run title = 'Sedov 20^3, Euler every step', t_end = 1.0, max_steps = $nsteps /|" \
      -e "s|^&grid .*|\&grid ni = 20, nj = 20, nk = 20, xmin = 0, 0, 0, xmax = 1.2, 1.2, 1.2 /|" "$root/input/sedov3d.nml" > "$deck"
  if [[ $sm == default* || $sm == cut0* ]]; then
    echo "&rezone mode = 'global', interval_steps = 1 /" >> "$deck"
    [[ $sm == cut0* ]] && echo "&hydro velocity_cutoff = 0 /" >> "$deck"
  else
    echo "&rezone mode = 'global', interval_steps = 1, swept_max = $sm /" >> "$deck"
  fi
  OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$exe" "$deck" > "$outdir/sedov20_every_$sm.log"
  awk -v lab="$lab" '/^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "euler") eul = $(i + 1)}
       /^throughput by phase:/ {rate = $5}
       /^euler steps:/ {cells = $6 + 0}
       / cells remapped by swept faces/ {nsw++}
       END {
         cyc = 1e6 / rate; per = 1e6 * eul / cells
         printf "swept_max %-7s: Lagrangian %.3f us per cell-cycle; Euler %.3f s for %d remapped cells = %.2f us " \
                "per cell = %.1f cell-cycles (%d Euler steps by swept faces)\n", lab, cyc, eul, cells, per, per / cyc, nsw
       }' "$outdir/sedov20_every_$sm.log"
done

echo
echo "## The same measure where every cell moves and is remapped (1 thread): a gas in rigid rotation about z"
echo "## (0.5 rad per unit time) with a denser, hotter sphere in it (radius 0.5; 2 and 3 times the density and"
echo "## pressure), in a box [-1, 1]^3 with symmetry faces, an Euler step every step (global rezone back to the"
echo "## box): every node but the box's corners moves (at most about 0.15 of a cell per step; the four edges along z"
echo "## once the sphere's wave reaches them), every cell is remapped at every Euler step, and no cell is at rest,"
echo "## so the Euler phase's cost per remapped cell and the Lagrangian cell-cycle are those of the same moving"
echo "## cells; 24^3 (60 steps) and 48^3 (30 steps, a state larger than the last-level cache)"
for n in 24 48; do
  cat > rotating$n.nml <<DECK
&run title = 'rotating gas with a hot sphere, ${n}^3, an Euler step every step', t_end = 10.0, max_steps = $((1440 / n)) /
&grid ni = $n, nj = $n, nk = $n, xmin = -1, -1, -1, xmax = 1, 1, 1 /
&material name = 'air', eos = 'ideal_gas', gamma = 1.4 /
&region shape = 'all', material = 'air', density = 1.0, pressure = 1.0, velocity_field = 'rotation', axis = 'z',
        angular_velocity = 0.5 /
&region shape = 'sphere', material = 'air', radius = 0.5, density = 2.0, pressure = 3.0, velocity_field = 'rotation',
        axis = 'z', angular_velocity = 0.5 /
&boundary xlo = 'symmetry', ylo = 'symmetry', zlo = 'symmetry', xhi = 'symmetry', yhi = 'symmetry', zhi = 'symmetry' /
&rezone mode = 'global', interval_steps = 1 /
&output dir = 'out/rotating$n', frame_dt = 100 /
DECK
  OMP_NUM_THREADS=1 OMP_PROC_BIND=true "$exe" rotating$n.nml > "$outdir/rotating$n.log"
  awk -v n=$n '/^timers \[s\]:/ {for (i = 1; i < NF; i++) if ($i == "euler") eul = $(i + 1)}
       /^throughput by phase:/ {rate = $5}
       /^euler steps:/ {steps = $3 + 0; cells = $6 + 0}
       END {
         cyc = 1e6 / rate; per = 1e6 * eul / cells
         printf "rotating %d^3: Lagrangian %.3f us per cell-cycle; Euler %.3f s for %d remapped cells in %d Euler steps = " \
                "%.2f us per cell = %.1f cell-cycles\n", n, cyc, eul, cells, steps, per, per / cyc
       }' "$outdir/rotating$n.log"
done

echo
flat_bench

echo
cutoff_bench

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
particles_bench
echo
gimp_bench
echo
particles_euler_bench
echo
particles_leaving_bench
echo
projectile_bench
echo
taylor_bench
echo
mpi_bench
echo
blast_bench
echo
tnt_modes_bench
echo
bubble_bench
echo
water_1d_bench
echo
garage_bench
echo
building_bench

echo
echo "bench wall time: ${SECONDS} s"
