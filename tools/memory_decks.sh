#!/usr/bin/env bash
# Writes the memory decks of issue 35 into DIR (the current directory if
# not given), from the project's decks under ROOT (this script's parent):
#   mem_sedov64  Sedov 64^3 with the paper's LSSM settings
#                (hardcases/sedov_paper.nml), 60 steps;
#   mem_tnt64    the TNT octant of hardcases/tnt_sphere.nml at 64^3,
#                Eulerian (an Euler step every step: open faces, two
#                materials), 10 steps;
#   mem_ring192  the Gurson ring of tests/decks/strength_shell_small.nml at
#                192 x 192 x 4 (particles, a correlated void field), 10 steps;
#   mem_frame96  the frame of tests/decks/particles_frame.nml at 96 x 64 x 64
#                (a column and a slab of 360k particles, two bars as lines
#                of particles), 2 steps.
# Each writes its frames to out/<name>. Used by `make bench`
# (ranks_memory_bench) and ctest ranks_memory_limit.
# Usage: memory_decks.sh [DIR]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "${1:-.}"
sed -e 's/ni = 20, nj = 20, nk = 20/ni = 64, nj = 64, nk = 64/' \
    -e "s|^&run .*|\&run title = 'Sedov 64^3, LSSM, memory', t_end = 1.0, max_steps = 60 /|" \
    -e "s|^&output .*|\&output dir = 'out/mem_sedov64', frame_dt = 100 /|" "$root/hardcases/sedov_paper.nml" > mem_sedov64.nml
echo "&rezone mode = 'lssm', side_ratio = 4, cos_angle = 0.7, quality = 0.999, quality_target = 0.999, smooth_iterations = 20 /" \
  >> mem_sedov64.nml
sed -e 's/ni = 16, nj = 16, nk = 16/ni = 64, nj = 64, nk = 64/' \
    -e "s|^&run \(.*\) /|\&run \1, max_steps = 10 /|" \
    -e "s|^&output dir = 'out/tnt_sphere', frame_dt = 1.0,|\&output dir = 'out/mem_tnt64', frame_dt = 100.0,|" \
    "$root/hardcases/tnt_sphere.nml" > mem_tnt64.nml
echo "&rezone mode = 'global', interval_steps = 1, side_ratio = 0, cos_angle = 0 /" >> mem_tnt64.nml
sed -e 's/ni = 24, nj = 24, nk = 1/ni = 192, nj = 192, nk = 4/' -e 's/max_steps = 120/max_steps = 10/' \
    -e "s|^&output dir = '[^']*'|\&output dir = 'out/mem_ring192'|" "$root/tests/decks/strength_shell_small.nml" \
    > mem_ring192.nml
sed -e 's/ni = 12, nj = 8, nk = 8/ni = 96, nj = 64, nk = 64/' -e 's/max_steps = 30/max_steps = 2/' \
    -e "s|^&output dir = '[^']*'|\&output dir = 'out/mem_frame96'|" "$root/tests/decks/particles_frame.nml" > mem_frame96.nml
# each sed must have changed its deck (a deck edited upstream would else
# give a memory figure of the wrong size)
grep -q 'ni = 64, nj = 64, nk = 64' mem_sedov64.nml
grep -q 'ni = 64, nj = 64, nk = 64' mem_tnt64.nml
grep -q 'max_steps = 10' mem_tnt64.nml
grep -q 'ni = 192, nj = 192, nk = 4' mem_ring192.nml
grep -q 'ni = 96, nj = 64, nk = 64' mem_frame96.nml
