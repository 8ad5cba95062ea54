#!/bin/bash
# Old against new on the coupled plate, alternated in one script (issue 19,
# docs/performance.md "The coupled plate"): each round runs OLD then NEW,
# `mpirun -n RANKS sphdem run inputs/plate_fibers_3.8.yaml --steps STEPS`,
# under /usr/bin/time -v, and prints one line per run: user and system CPU
# (all ranks), wall time, and the DEM and coupling phases of rank 0
# (timings.csv).
#   tools/plate_alternate.sh OLD_SPHDEM NEW_SPHDEM [ROUNDS] [STEPS] [RANKS] [OUT]
set -euo pipefail
old=${1:?usage: plate_alternate.sh OLD_SPHDEM NEW_SPHDEM [ROUNDS] [STEPS] [RANKS] [OUT]}
new=${2:?usage: plate_alternate.sh OLD_SPHDEM NEW_SPHDEM [ROUNDS] [STEPS] [RANKS] [OUT]}
rounds=${3:-2}
steps=${4:-4000}
ranks=${5:-2}
out=${6:-out/plate_alternate}
case_file=$(dirname "$0")/../inputs/plate_fibers_3.8.yaml
mkdir -p "$out"
printf "%-5s %-4s %8s %8s %8s %8s %8s %s\n" round run user_s sys_s wall_s dem_s coupl_s load
for r in $(seq 1 "$rounds"); do
  for which in old new; do
    bin=$old
    [ "$which" = new ] && bin=$new
    dir=$out/$which.$r
    /usr/bin/time -v -o "$out/time.$which.$r" mpirun --oversubscribe -n "$ranks" "$bin" run \
      "$case_file" -q --overwrite -o "$dir" --steps "$steps" --set output.every_time=1.0 \
      >"$out/log.$which.$r" 2>&1
    user=$(awk -F': ' '/User time/ {print $2}' "$out/time.$which.$r")
    sys=$(awk -F': ' '/System time/ {print $2}' "$out/time.$which.$r")
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$out/time.$which.$r" |
      awk -F: '{s = 0; for (i = 1; i <= NF; ++i) s = 60 * s + $i; print s}')
    # timings.csv: a header, then one row per rank; the columns named dem and coupling.
    phases=$(awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
      NR == 2 {print $col["dem"], $col["coupling"]}' "$dir/timings.csv")
    printf "%-5s %-4s %8s %8s %8s %8s %8s %s\n" "$r" "$which" "$user" "$sys" "$wall" $phases \
      "$(cut -d' ' -f1 /proc/loadavg)"
  done
done
