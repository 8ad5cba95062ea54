#!/usr/bin/env bash
# Installs what is missing (Debian packages), builds sphdem (Release) and runs
# the default case on 2 MPI ranks (SPHDEM_RANKS=N for another count): the
# paper's plate mold with 175 fibers (3.8 %), its first 5 ms (resin and
# fibers pushed into the nozzle, about a minute), writing
# out/plate_fibers/plate_fibers_short.xdmf for ParaView.
#   scripts/quickstart.sh [--full] [extra sphdem run options, e.g. --steps 2000]
# --full: the whole injection to 0.12 s (inputs/plate_fibers_3.8.yaml, about
# 20-30 minutes on 2 cores), into out/plate_fibers_full.
set -euo pipefail
cd "$(dirname "$0")/.."
case_file=inputs/plate_fibers_short.yaml
out=out/plate_fibers
if [[ ${1:-} == --full ]]; then
  case_file=inputs/plate_fibers_3.8.yaml
  out=out/plate_fibers_full
  shift
fi
scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target sphdem
ranks=${SPHDEM_RANKS:-2}  # any count gives the same particles (docs/parallel.md)
mpirun_flags=(--oversubscribe)
[[ $(id -u) -eq 0 ]] && mpirun_flags+=(--allow-run-as-root)
# --overwrite: a second quickstart replaces the first one's output (to
# continue it instead: --restart latest, docs/checkpoint.md).
exec mpirun -n "$ranks" "${mpirun_flags[@]}" build/release/sphdem run "$case_file" -o "$out" \
  --overwrite "$@"
