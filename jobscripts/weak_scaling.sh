#!/bin/bash
# (bench_sph's channel only; any case file: `sphdem scaling`, docs/scaling.md.)
# Weak scaling: a 2D channel with about 100k particles per rank (720 x 132
# resin particles per rank, stacked along x); the best of REPEAT runs
# (default 3) per rank count. CSV as strong_scaling.sh.
#   jobscripts/weak_scaling.sh [RANKS...] > weak.csv   (default: 1 2)
#   tools/plot_scaling.py weak.csv --weak -o weak.png
set -euo pipefail
source "$(dirname "$0")/scaling_common.sh"
NX=${NX:-720}; NY=${NY:-132}
ranks=("$@"); [[ ${#ranks[@]} -eq 0 ]] && ranks=(1 2)
echo "ranks,particles,steps,seconds,particle_steps_per_s"
for n in "${ranks[@]}"; do scaling_row "$n" $((NX * n)) "$NY"; done
