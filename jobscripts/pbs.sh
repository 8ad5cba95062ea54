#!/bin/bash
# PBS/Torque template for a sphdem run that chains itself across the
# walltime (docs/checkpoint.md):
#   qsub -v CASE=inputs/plate.yaml,OUT=out/plate jobscripts/pbs.sh
#PBS -N sphdem
#PBS -l select=1:ncpus=32:mpiprocs=32
#PBS -l walltime=24:00:00
#PBS -j oe
# PBS gives only seconds between SIGTERM and SIGKILL at the walltime, so the
# run is asked to stop earlier: after RUN_MINUTES (default 23 h 45 min)
# `timeout` sends SIGUSR1 to mpirun, which forwards it to every rank; sphdem
# finishes its step, writes a checkpoint and exits 0, and the job submits
# itself again to continue with --restart latest. A checkpoint every
# SPHDEM_CHECKPOINT_MINUTES (default 60) bounds what a node failure costs.
set -euo pipefail
cd "${PBS_O_WORKDIR:-.}"
SPHDEM=${SPHDEM:-build/release/sphdem}
ranks=$(wc -l < "${PBS_NODEFILE:-/dev/null}" || echo 1)
restart=()
if compgen -G "${OUT:?set OUT}/checkpoints/*.ckpt.h5" >/dev/null; then restart=(--restart latest); fi
log=$(mktemp)
timeout --preserve-status --signal=USR1 "${RUN_MINUTES:-1425}m" \
  mpirun -n "$ranks" "$SPHDEM" run "${CASE:?set CASE}" -o "$OUT" "${restart[@]}" \
  --set "checkpoint.every_minutes=${SPHDEM_CHECKPOINT_MINUTES:-60}" | tee "$log"
if grep -q '^stopped by signal' "$log"; then
  qsub -v "CASE=$CASE,OUT=$OUT" "${SPHDEM_JOBSCRIPT:-jobscripts/pbs.sh}"
fi
rm -f "$log"
