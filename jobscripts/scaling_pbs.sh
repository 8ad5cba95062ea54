#!/bin/bash
# A `sphdem scaling` study on a PBS/Torque cluster (docs/scaling.md, "On a
# cluster"): one job per rank count, each running `sphdem scaling --ranks P`
# with mpiexec on the job's nodes, then one job that waits for all of them
# (depend=afterok) and collects the rows into OUT/scaling.csv (`sphdem
# scaling --collect`). Run it on the login node from the repository's root:
#   jobscripts/scaling_pbs.sh CASE.yaml OUT 1,2,4,8,16 STEPS [sphdem scaling options...]
#   PPN=32 jobscripts/scaling_pbs.sh inputs/plate_fibers_3.8.yaml out/strong 1,8,32,64 200 --repeat 3
# PPN: MPI ranks per node (default 32); QSUB_ARGS (e.g. "-q workq -l
# walltime=01:00:00") go to every qsub; SPHDEM (default
# build/release/sphdem) is the binary. The job scripts are in OUT/jobs/.
set -euo pipefail
if [[ $# -lt 4 || $1 == -h || $1 == --help ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  [[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && exit 0 || exit 2
fi
case_file=$1 out=$2 ranks=$3 steps=$4; shift 4
SPHDEM=${SPHDEM:-build/release/sphdem}
PPN=${PPN:-32}
# The study's own checks first (rank list, case, weak refinement); nothing
# is submitted on bad input. Each job checks the memory of its own nodes
# (or --memory-gb, the memory of a job's nodes in all).
"$SPHDEM" scaling "$case_file" --ranks "$ranks" --steps "$steps" -o "$out" "$@" \
  --collect --dry-run >/dev/null
mkdir -p "$out/jobs"
quoted=$(printf ' %q' "$@")
here=$(printf '%q' "$PWD")
deps=""
for p in ${ranks//,/ }; do
  per_node=$((p < PPN ? p : PPN))
  nodes=$(((p + per_node - 1) / per_node))
  job="$out/jobs/ranks_$p.pbs"
  cat > "$job" <<JOB
#!/bin/bash
#PBS -N scaling_$p
#PBS -l select=$nodes:ncpus=$per_node:mpiprocs=$per_node
#PBS -j oe
#PBS -o $out/jobs/ranks_$p.log
set -euo pipefail
cd $here
$(printf '%q' "$SPHDEM") scaling $(printf '%q' "$case_file") --ranks $p --steps $steps -o $(printf '%q' "$out") \\
  --csv $(printf '%q' "$out/jobs/ranks_$p.csv") --launcher 'mpiexec -n {n}'$quoted
JOB
  # shellcheck disable=SC2086
  id=$(qsub ${QSUB_ARGS:-} "$job")
  echo "rank count $p: job $id"
  deps+=":$id"
done
collect="$out/jobs/collect.pbs"
cat > "$collect" <<JOB
#!/bin/bash
#PBS -N scaling_collect
#PBS -l select=1:ncpus=1:mpiprocs=1
#PBS -j oe
#PBS -o $out/jobs/collect.log
set -euo pipefail
cd $here
$(printf '%q' "$SPHDEM") scaling $(printf '%q' "$case_file") --ranks $ranks --steps $steps -o $(printf '%q' "$out") --collect$quoted
JOB
# shellcheck disable=SC2086
id=$(qsub ${QSUB_ARGS:-} -W "depend=afterok$deps" "$collect")
echo "collect: job $id -> $out/scaling.csv"
