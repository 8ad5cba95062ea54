#!/usr/bin/env bash
# DEM throughput (docs/performance.md, "DEM"): the peer deck's 3D fibers
# (175 and 4800) and the paper's 2D bath (175 and 10k fibers), on 1 and 2
# ranks, REPEAT times each (best of them is what the doc quotes).
#   BENCH=build/h-bench/bench/bench_dem REPEAT=3 jobscripts/dem_bench.sh > dem.txt
set -euo pipefail
BENCH=${BENCH:-build/release/bench/bench_dem}
REPEAT=${REPEAT:-3}
export OMPI_ALLOW_RUN_AS_ROOT=${OMPI_ALLOW_RUN_AS_ROOT:-1}
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=${OMPI_ALLOW_RUN_AS_ROOT_CONFIRM:-1}
cases=(
  "--dim 3 --fibers 175 --steps 20000"
  "--dim 3 --fibers 4800 --steps 20000"
  "--dim 2 --fibers 175 --steps 20000"
  "--dim 2 --fibers 10000 --steps 5000"
)
for c in "${cases[@]}"; do
  for n in 1 2; do
    for r in $(seq "$REPEAT"); do
      echo "### ranks $n run $r: $c"
      # shellcheck disable=SC2086
      mpirun -n "$n" --oversubscribe "$BENCH" $c
    done
  done
done
