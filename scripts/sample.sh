#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs what is missing, builds (Release) and runs the main job: `sonarsynth simulate` on the
# founding paper's pipe scene (samples/paper_pipes.yaml), results in out/paper_pipes/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel 2
mkdir -p out
./build/tools/sonarsynth simulate samples/paper_pipes.yaml -o out/paper_pipes --overwrite "$@"
