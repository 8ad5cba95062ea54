#!/bin/bash
# Weak scaling: a 2D channel with about 100k particles per rank (720 x 132
# resin particles per rank, stacked along x). CSV as strong_scaling.sh.
#   jobscripts/weak_scaling.sh [RANKS...]   (default: 1 2)
set -euo pipefail
BENCH=${BENCH:-$(dirname "$0")/../build/release/bench/bench_sph}
NX=${NX:-720}; NY=${NY:-132}; STEPS=${STEPS:-300}
ranks=("$@"); [[ ${#ranks[@]} -eq 0 ]] && ranks=(1 2)
flags=(--oversubscribe); [[ $(id -u) -eq 0 ]] && flags+=(--allow-run-as-root)
echo "ranks,particles,steps,seconds,particle_steps_per_s"
for n in "${ranks[@]}"; do
  out=$(mpirun -n "$n" "${flags[@]}" "$BENCH" --nx $((NX * n)) --ny "$NY" --steps "$STEPS")
  particles=$(sed -n 's/^case [^:]*: \([0-9]*\) particles.*/\1/p' <<<"$out")
  secs=$(sed -n 's/^loop: *\([0-9.]*\) s.*/\1/p' <<<"$out")
  rate=$(sed -n 's/^loop: *[0-9.]* s *\([0-9.]*\) M.*/\1/p' <<<"$out")
  echo "$n,$particles,$STEPS,$secs,$(awk -v r="$rate" 'BEGIN{printf "%.0f", r*1e6}')"
done
