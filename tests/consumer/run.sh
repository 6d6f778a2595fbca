#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds and runs the downstream projects against an installed sonarsynth:
#   tests/consumer/run.sh <install prefix> <scratch directory>
# 1. every component (one program each), the umbrella target, every installed header alone;
# 2. find_package(sonarsynth COMPONENTS <c>) for every component alone (tests/consumer/alone); for
#    those that need neither GDAL nor yaml-cpp (core, io, the codecs, registry) with GDAL and
#    yaml-cpp made unfindable, and no GDAL or yaml-cpp on the compile and link lines. The
#    components and their kind come from the installed package (components.txt of step 1).
set -euo pipefail
prefix=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$out"
mkdir -p "$out"

cmake -S "$here" -B "$out/all" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$out/all" >/dev/null
"$out/all/consumer"
while read -r only kind <&3; do
  "$out/all/consumer_$only"
done 3<"$out/all/components.txt"

while read -r only kind <&3; do
  lean=OFF
  [ "$kind" = lean ] && lean=ON
  flags=()
  if [ $lean = ON ]; then
    flags=(-DCMAKE_DISABLE_FIND_PACKAGE_GDAL=ON -DCMAKE_DISABLE_FIND_PACKAGE_yaml-cpp=ON)
  fi
  cmake -S "$here/alone" -B "$out/$only" -G Ninja --no-warn-unused-cli -DCMAKE_PREFIX_PATH="$prefix" \
    -DSONARSYNTH_COMPONENT=$only -DWITHOUT_GDAL_YAML=$lean "${flags[@]}" >/dev/null
  cmake --build "$out/$only" >/dev/null
  if [ $lean = ON ]; then
    commands=$(ninja -C "$out/$only" -t commands consumer_$only)
    if grep -qiE 'gdal|yaml' <<<"$commands"; then
      echo "consumer: the $only-only project compiles or links with GDAL or yaml-cpp:" >&2
      echo "$commands" >&2
      exit 1
    fi
    if ldd "$out/$only/consumer_$only" | grep -qiE 'gdal|yaml'; then
      echo "consumer: consumer_$only loads GDAL or yaml-cpp" >&2
      exit 1
    fi
  fi
  "$out/$only/consumer_$only"
  echo "find_package(sonarsynth COMPONENTS $only) alone: built and ran"
done 3<"$out/all/components.txt"
