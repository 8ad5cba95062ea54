#!/bin/bash
# PBS/Torque template for a sphdem run:
#   qsub -v CASE=inputs/plate.yaml,OUT=out/plate jobscripts/pbs.sh
#PBS -N sphdem
#PBS -l select=1:ncpus=32:mpiprocs=32
#PBS -l walltime=24:00:00
#PBS -j oe
set -euo pipefail
cd "${PBS_O_WORKDIR:-.}"
SPHDEM=${SPHDEM:-build/release/sphdem}
mpirun -n "$(wc -l < "${PBS_NODEFILE:-/dev/null}" || echo 1)" "$SPHDEM" run "${CASE:?set CASE}" -o "${OUT:?set OUT}"
