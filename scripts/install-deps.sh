#!/usr/bin/env bash
# Installs the Debian packages sphdem needs (build, tests, tools). Idempotent:
# packages already present are skipped, so a second run costs a few seconds.
# Usage: scripts/install-deps.sh [--no-paraview] [--peer]
#   --peer: also what tools/bench_vs_lammps.sh needs to build and time the
#           LAMMPS peer from Debian's source package (not needed otherwise)
set -euo pipefail
want=(
  build-essential cmake pkg-config clang-format
  openmpi-bin libopenmpi-dev libhdf5-openmpi-dev hdf5-tools
  libmetis-dev libeigen3-dev libyaml-cpp-dev libcli11-dev libfmt-dev libmuparser-dev
  libgtest-dev libgmock-dev libbenchmark-dev hyperfine  # hyperfine: tools/bench_vs_lammps.sh and its test
  python3 python3-numpy python3-h5py python3-matplotlib python3-yaml python3-scipy
)
# ParaView needs an X display: tools/render.py runs under xvfb-run (xvfb, xauth);
# ffmpeg encodes its animations.
paraview=1
for a in "$@"; do
  case "$a" in
    --no-paraview) paraview=0 ;;
    --peer) want+=(dpkg-dev debian-archive-keyring) ;;
    *) echo "install-deps: unknown option '$a' (--no-paraview, --peer)" >&2; exit 2 ;;
  esac
done
if ((paraview)); then want+=(python3-paraview paraview xvfb xauth ffmpeg); fi
missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}"
else
  echo "install-deps: all packages present"
fi
