#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The size rules of the house (docs/architecture.md, "Size rules"): no
# source file over 600 lines, no function over 120 lines. Lists every offender and exits 1 if
# there is one. Function extents come from Universal Ctags (Debian: universal-ctags).
# Usage: scripts/code_size.sh [max file lines] [max function lines]
set -euo pipefail
cd "$(dirname "$0")/.."
max_file=${1:-600}
max_function=${2:-120}
command -v ctags >/dev/null || { echo "code_size: ctags (universal-ctags) not found" >&2; exit 2; }
files=$(git ls-files '*.cpp' '*.hpp')
long_files=$(echo "$files" | xargs wc -l | awk -v m="$max_file" '$2 != "total" && $1 > m {print $1 " lines: " $2}')
long_functions=$(echo "$files" | xargs ctags --c++-kinds=fp --fields=+ne -o - 2>/dev/null |
  awk -F'\t' -v m="$max_function" '{
    line = 0; end = 0
    for (i = 4; i <= NF; i++) {
      if ($i ~ /^line:/) { split($i, a, ":"); line = a[2] }
      if ($i ~ /^end:/) { split($i, b, ":"); end = b[2] }
    }
    if (end > 0 && end - line + 1 > m) print end - line + 1 " lines: " $2 ":" line " " $1
  }' | sort -rn)
status=0
if [ -n "$long_files" ]; then echo "files over $max_file lines:"; echo "$long_files"; status=1; fi
if [ -n "$long_functions" ]; then echo "functions over $max_function lines:"; echo "$long_functions"; status=1; fi
[ $status -eq 0 ] && echo "code_size: no file over $max_file lines, no function over $max_function lines"
exit $status
