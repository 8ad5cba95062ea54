#!/bin/bash
# Strong scaling: the same 2D channel (default 1440 x 140 resin particles,
# 210k with walls) on 1, 2, ... ranks. Writes CSV: ranks,particles,steps,seconds,particle_steps_per_s
#   jobscripts/strong_scaling.sh [RANKS...]        (default: 1 2)
#   RANKS come from the arguments; NX, NY, STEPS and BENCH from the environment.
#   tools/plot_scaling.py strong.csv -o strong.png
set -euo pipefail
BENCH=${BENCH:-$(dirname "$0")/../build/release/bench/bench_sph}
NX=${NX:-1440}; NY=${NY:-140}; STEPS=${STEPS:-300}
ranks=("$@"); [[ ${#ranks[@]} -eq 0 ]] && ranks=(1 2)
flags=(--oversubscribe); [[ $(id -u) -eq 0 ]] && flags+=(--allow-run-as-root)
echo "ranks,particles,steps,seconds,particle_steps_per_s"
for n in "${ranks[@]}"; do
  out=$(mpirun -n "$n" "${flags[@]}" "$BENCH" --nx "$NX" --ny "$NY" --steps "$STEPS")
  particles=$(sed -n 's/^case [^:]*: \([0-9]*\) particles.*/\1/p' <<<"$out")
  secs=$(sed -n 's/^loop: *\([0-9.]*\) s.*/\1/p' <<<"$out")
  rate=$(sed -n 's/^loop: *[0-9.]* s *\([0-9.]*\) M.*/\1/p' <<<"$out")
  echo "$n,$particles,$STEPS,$secs,$(awk -v r="$rate" 'BEGIN{printf "%.0f", r*1e6}')"
done
