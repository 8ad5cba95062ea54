#!/usr/bin/env bash
# Installs what is missing (Debian packages), builds sphdem (Release) and runs
# the default case, the paper's plate mold filled with resin, writing
# out/plate/plate.xdmf for ParaView,
# on 2 MPI ranks (SPHDEM_RANKS=N for another count).
#   scripts/quickstart.sh [extra sphdem run options, e.g. --steps 2000]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target sphdem
ranks=${SPHDEM_RANKS:-2}  # any count gives the same particles (docs/parallel.md)
mpirun_flags=(--oversubscribe)
[[ $(id -u) -eq 0 ]] && mpirun_flags+=(--allow-run-as-root)
# --overwrite: a second quickstart replaces the first one's out/plate (to
# continue it instead: --restart latest, docs/checkpoint.md).
exec mpirun -n "$ranks" "${mpirun_flags[@]}" build/release/sphdem run inputs/plate.yaml -o out/plate \
  --overwrite "$@"
