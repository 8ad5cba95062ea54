#!/usr/bin/env bash
# Installs what is missing (Debian packages), builds the test configuration
# (warnings as errors) and runs the whole test suite with ctest: unit,
# validation, MPI (1-4 ranks), I/O (h5py) and ParaView checks.
#   scripts/test.sh              # what CI runs (.ci/run)
#   scripts/test.sh --sanitize   # the same suite under AddressSanitizer + UBSan (generic x86-64)
#   scripts/test.sh --sanitize-native   # the same, with this CPU's vector paths (-march=native)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=test
case "${1:-}" in
  "") ;;
  --sanitize) preset=sanitize ;;
  --sanitize-native) preset=sanitize-native ;;
  -h | --help)
    sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
    ;;
  *)
    echo "scripts/test.sh: unknown option '$1' (--sanitize, --sanitize-native or none)" >&2
    exit 2
    ;;
esac
scripts/install-deps.sh
# A fresh test build takes about 1 GB of disk (the sanitize one more): say so
# before the build rather than fail in the linker halfway through it.
if [[ ! -d "build/$preset" ]]; then
  free_mb=$(df -Pm . | awk 'NR == 2 { print $4 }')
  if (( free_mb < 3072 )); then
    echo "scripts/test.sh: only ${free_mb} MB free on the disk of $(pwd); the $preset build needs about 3 GB" >&2
    exit 1
  fi
fi
if [[ $(id -u) -eq 0 ]]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# Open MPI's own allocations are reported by LeakSanitizer; they are not ours.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset"
