#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds and runs the downstream projects against an installed sonarsynth:
#   tests/consumer/run.sh <install prefix> <scratch directory>
# 1. every component (one program each), the umbrella target, every installed header alone;
# 2. find_package(sonarsynth COMPONENTS <c>) for every component alone (tests/consumer/alone); for
#    core, io, xtf, jsf and registry with GDAL and yaml-cpp made unfindable, and no GDAL or yaml-cpp on the
#    compile and link lines.
set -euo pipefail
prefix=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$out"
mkdir -p "$out"

cmake -S "$here" -B "$out/all" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$out/all" >/dev/null
for program in consumer consumer_core consumer_io consumer_xtf consumer_jsf consumer_registry consumer_raster \
  consumer_products consumer_config; do
  "$out/all/$program"
done

for only in core io xtf jsf registry raster products config; do
  lean=OFF
  case $only in core | io | xtf | jsf | registry) lean=ON ;; esac
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
done
