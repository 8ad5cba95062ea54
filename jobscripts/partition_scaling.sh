#!/bin/bash
# The inputs of the efficiency model of docs/scaling.md, from `sphdem
# partition` (no run): the plate at --scale 8 (strong scaling, 665k
# particles) and the bench_sph channel weak-scaled in 2D (720 sqrt(P) x
# 132 sqrt(P) resin particles, about 100k per rank, built for P = 4, 16, 64;
# larger P do not fit one node's memory). Writes CSVs to OUT (default .).
#   jobscripts/partition_scaling.sh [OUT]
#   tools/plot_scaling.py --predict OUT/partition_plate_s8.csv --tp 1.41e-7
set -euo pipefail
SPHDEM=${SPHDEM:-$(dirname "$0")/../build/release/sphdem}
src=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-.}; mkdir -p "$out"

"$SPHDEM" partition "$src/inputs/plate.yaml" --scale 8 --ranks 64,256,1024,4096 \
  --csv "$out/partition_plate_s8.csv"

# The channel of bench_sph (same text as its channel_case()), nx x ny resin.
channel_case() {
  awk -v nx="$1" -v ny="$2" 'BEGIN {
    dx = 3e-4; lx = nx * dx; ly = ny * dx
    print "name: channel"
    print "dimension: 2"
    print "resin: {density: 900, viscosity: 0.1, sound_speed: 50}"
    print "numerics: {spacing: 3.0e-4, h_over_spacing: 1.2, fixed_dt: 1.4e-6, end_time: 1.0, anti_clump: true}"
    printf "mold: {wall_layers: 3, shapes: [{box: {min: [0, 0], max: [%.10g, %.10g]}}]}\n", lx, ly
    printf "fill: [{box: {min: [0, 0], max: [%.10g, %.10g]}}]\n", lx, ly
    print "body_force: [1000, 0]"
    print "periodic: [x]"
    printf "domain: {min: [0, %.10g], max: [%.10g, %.10g]}\n", -4 * dx, lx, ly + 4 * dx
  }'
}

for p in ${CHANNEL_RANKS:-4 16 64}; do
  s=$(awk -v p="$p" 'BEGIN{printf "%d", sqrt(p) + 0.5}')
  case_file="$out/channel_weak_$p.yaml"
  channel_case $((720 * s)) $((132 * s)) > "$case_file"
  "$SPHDEM" partition "$case_file" --ranks "$p" --csv "$out/partition_channel_weak_$p.csv"
done
