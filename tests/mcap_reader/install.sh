#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the independent MCAP reader's npm packages (package-lock.json, exact versions) into
# BUILD_DIR/mcap_reader/node_modules, where the mcap_tests look for them; never into the source
# tree and never while the library builds. Usage: tests/mcap_reader/install.sh BUILD_DIR
set -euo pipefail
build_dir=${1:?usage: tests/mcap_reader/install.sh BUILD_DIR}
here="$(cd "$(dirname "$0")" && pwd)"
command -v npm >/dev/null || { echo "mcap_reader: npm not found (apt-get install npm)" >&2; exit 1; }
mkdir -p "$build_dir/mcap_reader"
cp "$here/package.json" "$here/package-lock.json" "$build_dir/mcap_reader/"
cd "$build_dir/mcap_reader"
npm ci --no-audit --no-fund --loglevel=error
echo "mcap_reader: installed into $build_dir/mcap_reader/node_modules"
