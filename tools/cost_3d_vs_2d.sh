#!/bin/bash
# Cost per resin particle-step of a 3D coupled mold against the 2D
# plate's, measured alternately in one script so that both see the same
# machine load (docs/performance.md, "3D molds"). Each round runs, on RANKS
# ranks: the 2D case for N2 steps and for B2 steps (default 0: set-up
# only), then the 3D case for N3 steps and for B3 steps; a case's cost is
#   (cost of N steps - cost of B steps) / (resin particles x (N - B))
# with the resin count from the run's banner. Every run writes the
# snapshot of step 0 and one at its last step, so with B = 0 the cost holds
# that last snapshot's user CPU; B > 0 cancels it, and the first steps' own
# costs, in both cases (docs/performance.md, "The last snapshot in the 3D
# cost": no difference beyond the noise). The cost is the user CPU on
# one rank, and the wall time x RANKS (core-seconds, on a quiet machine:
# waiting ranks poll) with more. Prints every round and the median and
# range of the 3D / 2D ratio.
#   tools/cost_3d_vs_2d.sh [SPHDEM] [ROUNDS]
# Environment: CASE2 (default inputs/plate_fibers_3.8.yaml), CASE3 (default
# inputs/plate_3d_fibers_coarse.yaml), SET3 (default
# "numerics.spacing=5e-4": 72,000 resin particles, the size of issue 19's
# 3D mold), N2 (default 1000), N3 (default 120: fewer steps are noisy),
# B2 and B3 (default 0; each below its N), RANKS (default 1; more runs
# under mpiexec -n RANKS), OUT (scratch directory).
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
SPHDEM=${1:-build/test/sphdem}
ROUNDS=${2:-3}
CASE2=${CASE2:-inputs/plate_fibers_3.8.yaml}
CASE3=${CASE3:-inputs/plate_3d_fibers_coarse.yaml}
SET3=${SET3:-numerics.spacing=5e-4}
N2=${N2:-1000}
N3=${N3:-120}
B2=${B2:-0}
B3=${B3:-0}
RANKS=${RANKS:-1}
for v in N2 N3 B2 B3; do
  if ! [[ ${!v} =~ ^[0-9]+$ ]]; then
    echo "cost_3d_vs_2d.sh: $v must be a whole number of steps, got '${!v}'" >&2
    exit 2
  fi
done
if ((B2 >= N2 || B3 >= N3)); then
  echo "cost_3d_vs_2d.sh: B2 and B3 must be below N2 and N3 (got B2=$B2 N2=$N2 B3=$B3 N3=$N3)" >&2
  exit 2
fi
if ! [[ $RANKS =~ ^[1-9][0-9]*$ ]]; then
  echo "cost_3d_vs_2d.sh: RANKS must be a positive integer, got '$RANKS'" >&2
  exit 2
fi
launch=()
fmt="%U"
if ((RANKS > 1)); then
  launch=(mpiexec -n "$RANKS")
  fmt="%e"
fi
OUT=${OUT:-$(mktemp -d)}
mkdir -p "$OUT"

# cost in core-seconds and resin particles of one run: "COST RESIN"
run() {
  local tag=$1 case_file=$2 steps=$3; shift 3
  /usr/bin/time -f "$fmt" -o "$OUT/$tag.time" "${launch[@]}" "$SPHDEM" run "$case_file" \
    --steps "$steps" --overwrite -o "$OUT/$tag" "$@" > "$OUT/$tag.log"
  local resin
  resin=$(grep -o '[0-9]* resin' "$OUT/$tag.log" | head -1 | cut -d' ' -f1)
  echo "$(awk -v t="$(tail -1 "$OUT/$tag.time")" -v r="$RANKS" 'BEGIN{print t * r}') $resin"
}

ratios=()
printf "%-6s %-26s %-26s %s\n" round "2D [ns/resin particle-step]" "3D [ns/resin particle-step]" "3D/2D"
for r in $(seq 1 "$ROUNDS"); do
  read -r u2 n2 < <(run 2d "$CASE2" "$N2")
  read -r z2 _ < <(run 2d0 "$CASE2" "$B2")
  read -r u3 n3 < <(run 3d "$CASE3" "$N3" --set "$SET3")
  read -r z3 _ < <(run 3d0 "$CASE3" "$B3" --set "$SET3")
  c2=$(awk -v u="$u2" -v z="$z2" -v n="$n2" -v s="$((N2 - B2))" 'BEGIN{printf "%.1f", 1e9*(u-z)/(n*s)}')
  c3=$(awk -v u="$u3" -v z="$z3" -v n="$n3" -v s="$((N3 - B3))" 'BEGIN{printf "%.1f", 1e9*(u-z)/(n*s)}')
  ratio=$(awk -v a="$c3" -v b="$c2" 'BEGIN{printf "%.2f", a/b}')
  ratios+=("$ratio")
  printf "%-6s %-26s %-26s %s   (2D: %s resin, %.2f-%.2f s; 3D: %s resin, %.2f-%.2f s)\n" \
    "$r" "$c2" "$c3" "$ratio" "$n2" "$u2" "$z2" "$n3" "$u3" "$z3"
done
printf "%s\n" "${ratios[@]}" | sort -g | awk '{a[NR]=$1} END{
  printf "3D / 2D per resin particle-step: median %s, range %s-%s (%d rounds)\n",
    a[int((NR+1)/2)], a[1], a[NR], NR}'
