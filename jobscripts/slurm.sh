#!/bin/bash
# SLURM template for a sphdem run that chains itself across the time limit
# (docs/checkpoint.md). Copy, edit the #SBATCH lines, submit from the
# repository's root:
#   sbatch jobscripts/slurm.sh inputs/plate.yaml out/plate
#SBATCH --job-name=sphdem
#SBATCH --nodes=1
#SBATCH --ntasks-per-node=32
#SBATCH --cpus-per-task=1
#SBATCH --time=24:00:00
#SBATCH --output=sphdem-%j.log
# Ten minutes before the time limit SLURM sends SIGUSR1 to every task: sphdem
# finishes its step, writes a checkpoint and exits 0, and this script submits
# itself again; the next job continues with --restart latest. A checkpoint
# every SPHDEM_CHECKPOINT_MINUTES (default 60) bounds what a node failure
# costs. A run that reaches end_time ends the chain.
#SBATCH --signal=USR1@600
set -euo pipefail
case_file=${1:?usage: sbatch slurm.sh CASE.yaml OUTPUT_DIR}
out=${2:?usage: sbatch slurm.sh CASE.yaml OUTPUT_DIR}
cd "${SLURM_SUBMIT_DIR:-.}"
SPHDEM=${SPHDEM:-build/release/sphdem}
restart=()
# Continue the run in $out if it wrote a checkpoint (an earlier job of the
# chain); otherwise start it (refused if $out holds another run's output).
if compgen -G "$out/checkpoints/*.ckpt.h5" >/dev/null; then restart=(--restart latest); fi
log=$(mktemp)
srun "$SPHDEM" run "$case_file" -o "$out" "${restart[@]}" \
  --set "checkpoint.every_minutes=${SPHDEM_CHECKPOINT_MINUTES:-60}" | tee "$log"
if grep -q '^stopped by signal' "$log"; then
  sbatch "${SPHDEM_JOBSCRIPT:-jobscripts/slurm.sh}" "$case_file" "$out"
fi
rm -f "$log"
