# Sourced by strong_scaling.sh and weak_scaling.sh: runs bench_sph on N ranks
# REPEAT times and prints the CSV row of the fastest run. The machine may be
# shared, so the best of several runs is the one least disturbed by others.
BENCH=${BENCH:-$(dirname "$0")/../build/release/bench/bench_sph}
STEPS=${STEPS:-300}; REPEAT=${REPEAT:-3}
flags=(--oversubscribe); [[ $(id -u) -eq 0 ]] && flags+=(--allow-run-as-root)
[[ -x $BENCH ]] || { echo "no bench_sph at $BENCH (set BENCH)" >&2; exit 2; }

# scaling_row RANKS NX NY -> "ranks,particles,steps,seconds,particle_steps_per_s"
scaling_row() {
  local n=$1 nx=$2 ny=$3 best="" particles="" out secs
  for ((k = 0; k < REPEAT; ++k)); do
    out=$(mpirun -n "$n" "${flags[@]}" "$BENCH" --nx "$nx" --ny "$ny" --steps "$STEPS")
    particles=$(sed -n 's/^case [^:]*: \([0-9]*\) particles.*/\1/p' <<<"$out")
    secs=$(sed -n 's/^loop: *\([0-9.]*\) s.*/\1/p' <<<"$out")
    [[ -n $particles && -n $secs ]] || { echo "unexpected bench_sph output: $out" >&2; exit 1; }
    echo "  $n rank(s), run $((k + 1)): $secs s" >&2
    if [[ -z $best ]] || awk -v a="$secs" -v b="$best" 'BEGIN{exit !(a < b)}'; then best=$secs; fi
  done
  echo "$n,$particles,$STEPS,$best,$(awk -v p="$particles" -v s="$STEPS" -v t="$best" \
    'BEGIN{printf "%.0f", p * s / t}')"
}
