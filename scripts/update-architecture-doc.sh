#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Rewrites docs/architecture.md's components table from what the build declares (configure first:
# the table is written by cmake into the build directory). Usage: scripts/update-architecture-doc.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake -S . -B "$build" >/dev/null
cmake -DDOC=docs/architecture.md -DTABLE="$build/architecture-components.md" -DNAME=components \
  -DUPDATE=ON -P cmake/CheckGeneratedDoc.cmake
