#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian packages sonarsynth needs, only those that are missing (non-interactive).
# Usage: scripts/install-deps.sh [--dev]   (--dev adds the CI/developer tools: clang, clang-format,
# universal-ctags (scripts/code_size.sh),
# OpenCV for the optional `sonarsynth match`, the ROS 1 bag reader and message packages that
# python/tests/test_rosbag.py checks the bags with, and roscpp with the master (ros-core) for the
# optional live node sonarsynth_ros and its test, ros/)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  python3-pip python3-venv python3-setuptools python3-wheel python3-mypy
  libeigen3-dev libgdal-dev libpng-dev libisal-dev gdal-bin libgeographiclib-dev libboost-program-options-dev
  libyaml-cpp-dev libhwy-dev libzstd-dev zlib1g-dev libassimp-dev nlohmann-json3-dev libssl-dev libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox python3-dev python3-numpy python3-gdal python3-pytest python3-distributed pybind11-dev
  python3-torch python3-torchvision
)
# Node.js and npm for the tests' independent MCAP reader (tests/mcap_reader): Debian's only where
# no npm is installed (a NodeSource nodejs brings its own npm, which Debian's npm conflicts with).
if ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi
if [[ "${1:-}" == "--dev" ]]; then
  packages+=(clang libclang-rt-dev clang-format universal-ctags libopencv-dev
    python3-rosbag python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-tf2-msgs
    ros-core libroscpp-dev libstd-msgs-dev libsensor-msgs-dev libnav-msgs-dev python3-rospy
    python3-nav-msgs)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
