#!/usr/bin/env bash
# Installs the Debian packages sphdem needs (build, tests, tools). Idempotent:
# packages already present are skipped, so a second run costs a few seconds.
# Usage: scripts/install-deps.sh [--no-paraview]
set -euo pipefail
want=(
  build-essential cmake pkg-config clang-format
  openmpi-bin libopenmpi-dev libhdf5-openmpi-dev hdf5-tools
  libmetis-dev libeigen3-dev libyaml-cpp-dev libcli11-dev libfmt-dev libmuparser-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-h5py python3-matplotlib python3-yaml
)
# ParaView needs an X display: tools/render.py runs under xvfb-run (xvfb, xauth);
# ffmpeg encodes its animations.
if [[ "${1:-}" != "--no-paraview" ]]; then want+=(python3-paraview paraview xvfb xauth ffmpeg); fi
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
