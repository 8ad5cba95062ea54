#!/bin/bash
# A `sphdem scaling` study on a SLURM cluster (docs/scaling.md, "On a
# cluster"): one job per rank count, each running `sphdem scaling --ranks P`
# with srun, then one job that waits for all of them (afterok) and collects
# the rows into OUT/scaling.csv (`sphdem scaling --collect`). Run it on the
# login node from the repository's root:
#   jobscripts/scaling_slurm.sh CASE.yaml OUT 1,2,4,8,16 STEPS [sphdem scaling options...]
#   jobscripts/scaling_slurm.sh inputs/plate_fibers_3.8.yaml out/weak 1,4,16,64 200 --weak --repeat 3
# SBATCH_ARGS (e.g. "--partition=compute --time=01:00:00 --exclusive") go to
# every sbatch; SPHDEM (default build/release/sphdem) is the binary. Each job
# writes its script to OUT/jobs/ first, so what ran can be read there.
set -euo pipefail
if [[ $# -lt 4 || $1 == -h || $1 == --help ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  [[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && exit 0 || exit 2
fi
case_file=$1 out=$2 ranks=$3 steps=$4; shift 4
SPHDEM=${SPHDEM:-build/release/sphdem}
# The study's own checks first (rank list, case, weak refinement); nothing
# is submitted on bad input. Each job checks the memory of its own nodes
# (or --memory-gb, the memory of a job's nodes in all).
"$SPHDEM" scaling "$case_file" --ranks "$ranks" --steps "$steps" -o "$out" "$@" \
  --collect --dry-run >/dev/null
mkdir -p "$out/jobs"
quoted=$(printf ' %q' "$@")
deps=""
for p in ${ranks//,/ }; do
  job="$out/jobs/ranks_$p.sh"
  cat > "$job" <<JOB
#!/bin/bash
#SBATCH --job-name=scaling_$p
#SBATCH --ntasks=$p
#SBATCH --output=$out/jobs/ranks_$p.log
set -euo pipefail
cd $(printf '%q' "$PWD")
$(printf '%q' "$SPHDEM") scaling $(printf '%q' "$case_file") --ranks $p --steps $steps -o $(printf '%q' "$out") \\
  --csv $(printf '%q' "$out/jobs/ranks_$p.csv") --launcher 'srun -n {n}'$quoted
JOB
  # shellcheck disable=SC2086
  id=$(sbatch --parsable ${SBATCH_ARGS:-} "$job")
  echo "rank count $p: job $id"
  deps+=":$id"
done
collect="$out/jobs/collect.sh"
cat > "$collect" <<JOB
#!/bin/bash
#SBATCH --job-name=scaling_collect
#SBATCH --ntasks=1
#SBATCH --output=$out/jobs/collect.log
set -euo pipefail
cd $(printf '%q' "$PWD")
$(printf '%q' "$SPHDEM") scaling $(printf '%q' "$case_file") --ranks $ranks --steps $steps -o $(printf '%q' "$out") --collect$quoted
JOB
# shellcheck disable=SC2086
id=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok$deps" "$collect")
echo "collect: job $id -> $out/scaling.csv"
