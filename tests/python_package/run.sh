#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Python package as a user installs it (docs/python.md, Installing); run by .ci/run:
#   tests/python_package/run.sh <prefix of a `cmake --install`> <scratch directory>
# 1. a copy of the checkout's files (git ls-files: no build directories), a new virtual
#    environment with --system-site-packages, `pip install --no-index --no-build-isolation` of the
#    copy (no network; CMake builds the extension afresh), then smoke.py in that environment from
#    outside the source tree;
# 2. smoke.py with /usr/bin/python3 and PYTHONPATH = the site directory of the `cmake --install`.
set -euo pipefail
prefix=$(realpath "$1")
out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
python=${SONARSYNTH_PYTHON:-/usr/bin/python3}
rm -rf "$out"
mkdir -p "$out/src"
out=$(realpath "$out")

git -C "$root" ls-files -z --cached --others --exclude-standard |
  (cd "$root" && xargs -0 sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh) |
  (cd "$root" && tar --null -T - -cf -) | tar -xf - -C "$out/src"

(cd "$out/src" && find . | sort) >"$out/files-before"
"$python" -m venv --system-site-packages "$out/venv"
# setup.py's temporary build directory under $out, beside src/: with ccache (setup.py), the
# paths relative to $out are the same from run to run, so a rerun compiles from the cache.
mkdir -p "$out/tmp"
start=$(date +%s)
(cd "$out" && TMPDIR="$out/tmp" venv/bin/python -m pip install --no-index --no-build-isolation --no-cache-dir \
  --quiet ./src) || { echo "python_package: pip install failed" >&2; exit 1; }
echo "pip install: $(( $(date +%s) - start )) s (CMake build of the extension included)"
(cd "$out/src" && find . | sort) >"$out/files-after"
if ! diff "$out/files-before" "$out/files-after" >&2; then
  echo "python_package: pip install wrote into the source tree (above)" >&2
  exit 1
fi
site=$("$out/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')
cd "$out"
venv/bin/python -c "import sonarsynth"
venv/bin/python "$root/tests/python_package/smoke.py" --source "$out/src" --site "$site" --pip

echo "cmake --install tree:"
site=$prefix/$("$python" -c 'import sys; print("lib/python%d.%d/site-packages" % sys.version_info[:2])')
PYTHONPATH=$site "$python" "$root/tests/python_package/smoke.py" --source "$root" --site "$site"
