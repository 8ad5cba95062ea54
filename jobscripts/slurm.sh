#!/bin/bash
# SLURM template for a sphdem run. Copy, edit the #SBATCH lines, submit:
#   sbatch jobscripts/slurm.sh inputs/plate.yaml out/plate
#SBATCH --job-name=sphdem
#SBATCH --nodes=1
#SBATCH --ntasks-per-node=32
#SBATCH --cpus-per-task=1
#SBATCH --time=24:00:00
#SBATCH --output=sphdem-%j.log
# SLURM sends SIGTERM shortly before the time limit; with checkpointing
# (issue 6) sphdem will write a checkpoint and exit 0 so the job can chain.
set -euo pipefail
case_file=${1:?usage: sbatch slurm.sh CASE.yaml OUTPUT_DIR}
out=${2:?usage: sbatch slurm.sh CASE.yaml OUTPUT_DIR}
SPHDEM=${SPHDEM:-$(dirname "$0")/../build/release/sphdem}
srun "$SPHDEM" run "$case_file" -o "$out"
