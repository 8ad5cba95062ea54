#!/bin/bash
# Submit a large case (the 3D molds: inputs/plate_3d_fibers.yaml,
# inputs/ribbed_part_fibers.yaml) to SLURM on RANKS tasks, with the memory
# per task that `sphdem check --ranks RANKS` estimates (docs/scaling.md,
# "Memory per rank") plus a margin, as a chain of jobscripts/slurm.sh jobs
# that checkpoint before the time limit and continue. Run it on the login
# node from the repository's root:
#   jobscripts/mold3d_slurm.sh CASE.yaml OUT RANKS [--dry-run]
#   jobscripts/mold3d_slurm.sh inputs/plate_3d_fibers.yaml out/plate3d 64
# PPN (default 32) tasks per node; MARGIN (default 1.25) times the estimate
# is asked per task (--mem-per-cpu); SBATCH_ARGS (e.g. "--partition=compute
# --time=24:00:00") go to sbatch; SPHDEM (default build/release/sphdem).
# --dry-run prints the job script and the sbatch command only.
set -euo pipefail
if [[ $# -lt 3 || $1 == -h || $1 == --help ]]; then
  sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'
  [[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && exit 0 || exit 2
fi
case_file=$1 out=$2 ranks=$3
dry=${4:-}
SPHDEM=${SPHDEM:-build/release/sphdem}
PPN=${PPN:-32}
MARGIN=${MARGIN:-1.25}
if ! [[ $ranks =~ ^[1-9][0-9]*$ ]]; then
  echo "mold3d_slurm.sh: error: RANKS must be a positive integer (got '$ranks')" >&2
  exit 2
fi
# The estimate for RANKS ranks, nothing built (the case is checked too:
# nothing is submitted on bad input). "memory: about 1.2 GiB per rank".
est=$("$SPHDEM" check "$case_file" --ranks "$ranks" --memory-per-rank 1T | grep 'memory: about')
mib=$(echo "$est" | awk -v m="$MARGIN" '{
  for (i = 1; i <= NF; ++i) if ($i == "about") { v = $(i + 1); u = $(i + 2); break }
  f = (u == "GiB") ? 1024 : (u == "MiB") ? 1 : (u == "KiB") ? 1 / 1024 : (u == "TiB") ? 1048576 : 0
  if (f == 0) exit 1
  printf "%d", v * f * m + 1 }')
nodes=$(((ranks + PPN - 1) / PPN))
per_node=$((ranks < PPN ? ranks : PPN))
mkdir -p "$out/jobs"
job="$out/jobs/run.sh"
sed -e "s/^#SBATCH --nodes=1$/#SBATCH --nodes=$nodes/" \
    -e "s/^#SBATCH --ntasks-per-node=32$/#SBATCH --ntasks-per-node=$per_node\n#SBATCH --ntasks=$ranks\n#SBATCH --mem-per-cpu=${mib}M/" \
    -e "s/^#SBATCH --job-name=sphdem$/#SBATCH --job-name=$(basename "$case_file" .yaml)/" \
    jobscripts/slurm.sh > "$job"
chmod +x "$job"
echo "$est" | sed 's/^ *//'
echo "$ranks tasks on $nodes node(s), ${mib} MiB per task ($MARGIN x the estimate): $job"
if [[ $dry == --dry-run ]]; then
  echo "SPHDEM_JOBSCRIPT=$job sbatch ${SBATCH_ARGS:-} $job $case_file $out"
  exit 0
fi
# shellcheck disable=SC2086
SPHDEM=$SPHDEM SPHDEM_JOBSCRIPT=$job sbatch ${SBATCH_ARGS:-} "$job" "$case_file" "$out"
