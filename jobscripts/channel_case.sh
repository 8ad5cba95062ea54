#!/bin/bash
# Writes bench_sph's periodic 2D channel (the LAMMPS peer deck, same text as
# its channel_case()) with NX x NY resin particles as a case file, for
# `sphdem run` (timings per rank) and `sphdem partition`:
#   jobscripts/channel_case.sh 1440 140 > channel.yaml
#   mpirun -n 2 sphdem run channel.yaml --steps 300 -o out/channel   # out/channel/timings.csv
set -euo pipefail
awk -v nx="${1:?usage: channel_case.sh NX NY}" -v ny="${2:?usage: channel_case.sh NX NY}" 'BEGIN {
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
  print "output: {every_steps: 1000000, progress_every: 1000000, fields: [velocity]}"
}'
