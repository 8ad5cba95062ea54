#!/bin/bash
# The inputs of the efficiency model of docs/scaling.md, from `sphdem
# partition` (no run): the plate at --scale 8 (strong scaling, 665k
# particles) and the bench_sph channel weak-scaled in 2D (720 sqrt(P) x
# 132 sqrt(P) resin particles, about 95k per rank) for P in CHANNEL_RANKS
# (default 4 16 64; 256 takes 4 GB and 20 s, 1024 would need 16 GB).
# Writes CSVs to OUT (default .).
#   jobscripts/partition_scaling.sh [OUT]
#   tools/plot_scaling.py --predict OUT/partition_plate_s8.csv --tp 1.41e-7 --allgathers 2
set -euo pipefail
SPHDEM=${SPHDEM:-$(dirname "$0")/../build/release/sphdem}
src=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-.}; mkdir -p "$out"

"$SPHDEM" partition "$src/inputs/plate.yaml" --scale 8 --ranks 64,256,1024,4096 \
  --csv "$out/partition_plate_s8.csv"

for p in ${CHANNEL_RANKS:-4 16 64}; do
  s=$(awk -v p="$p" 'BEGIN{printf "%d", sqrt(p) + 0.5}')
  case_file="$out/channel_weak_$p.yaml"
  "$(dirname "$0")/channel_case.sh" $((720 * s)) $((132 * s)) > "$case_file"
  "$SPHDEM" partition "$case_file" --ranks "$p" --csv "$out/partition_channel_weak_$p.csv"
done
