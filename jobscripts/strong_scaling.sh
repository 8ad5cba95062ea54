#!/bin/bash
# (bench_sph's channel only; any case file: `sphdem scaling`, docs/scaling.md.)
# Strong scaling: the same 2D channel (default 1440 x 140 resin particles,
# 207k with walls) on 1, 2, ... ranks; the best of REPEAT runs (default 3)
# per rank count. Writes CSV: ranks,particles,steps,seconds,particle_steps_per_s
#   jobscripts/strong_scaling.sh [RANKS...] > strong.csv     (default: 1 2)
#   RANKS come from the arguments; NX, NY, STEPS, REPEAT and BENCH from the environment.
#   tools/plot_scaling.py strong.csv -o strong.png
set -euo pipefail
source "$(dirname "$0")/scaling_common.sh"
NX=${NX:-1440}; NY=${NY:-140}
ranks=("$@"); [[ ${#ranks[@]} -eq 0 ]] && ranks=(1 2)
echo "ranks,particles,steps,seconds,particle_steps_per_s"
for n in "${ranks[@]}"; do scaling_row "$n" "$NX" "$NY"; done
