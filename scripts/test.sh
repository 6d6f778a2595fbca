#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs what is missing, builds with warnings as errors and runs the whole test suite.
# Environment: BUILD_DIR (default build), SONARSYNTH_SANITIZE=ON for an ASan+UBSan build,
# SONARSYNTH_TEST_CMAKE_ARGS (more CMake arguments, e.g. -DSONARSYNTH_BUILD_BENCH=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
build_dir=${BUILD_DIR:-build}
sanitize=${SONARSYNTH_SANITIZE:-OFF}
build_type=Release
[[ "$sanitize" == ON ]] && build_type=RelWithDebInfo
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" -DSONARSYNTH_WERROR=ON \
  -DSONARSYNTH_SANITIZE="$sanitize" ${SONARSYNTH_TEST_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" --parallel 2
# The independent MCAP reader of mcap_tests (npm packages into the build directory; the test
# is skipped without them).
if command -v npm >/dev/null; then
  tests/mcap_reader/install.sh "$build_dir"
else
  echo "test.sh: npm not found: mcap_tests' independent reader will be skipped" >&2
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build_dir" --output-on-failure --parallel 2
