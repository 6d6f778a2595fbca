#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Instructions per stage of the per-ping pipeline, by callgrind, on the vector kernels' AVX2 and
# scalar paths (valgrind cannot run AVX-512 code).
#
#   bench/profile_stages.sh PING_BENCHMARK [PATH ...] [-- ping_benchmark arguments]
#
# PATH: avx2 and/or scalar (default both), set through SONARSYNTH_SIMD. The default workload is
# one thread, one run of a 20 m line of the standard workload (ping_benchmark's defaults
# otherwise). Prints, per path, the instructions per ping of the stages (inclusive counts of the
# stage functions; a stage absent from a build prints -) and per sample (2 x 4096 samples).
set -euo pipefail
[[ $# -ge 1 ]] || { sed -n 3,11p "$0"; exit 2; }
bin=$1
shift
paths=()
while [[ $# -gt 0 && $1 != "--" ]]; do paths+=("$1"); shift; done
[[ $# -gt 0 && $1 == "--" ]] && shift
args=("$@")
[[ ${#paths[@]} -gt 0 ]] || paths=(avx2 scalar)
[[ ${#args[@]} -gt 0 ]] || args=(--runs 1 --threads 1 --length-m 20)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for p in "${paths[@]}"; do
  # Only what runs inside render_sides is counted (not the scene, the pilot or the sinks).
  SONARSYNTH_SIMD=$p valgrind --tool=callgrind --callgrind-out-file="$tmp/$p.out" \
    --toggle-collect='sonarsynth::Simulator::render_sides*' \
    "$bin" "${args[@]}" > "$tmp/$p.txt" 2> "$tmp/$p.err"
  callgrind_annotate --inclusive=yes --threshold=100 "$tmp/$p.out" > "$tmp/$p.incl" 2>/dev/null
  pings=$(sed -n 's/^scene .*, \([0-9]*\) pings of.*/\1/p' "$tmp/$p.txt")
  /usr/bin/python3 - "$tmp/$p.incl" "$p" "$pings" <<'PY'
import re, sys
path, name, pings = sys.argv[1], sys.argv[2], int(sys.argv[3])
samples = 2 * 4096
stages = [  # (stage, a function whose inclusive count is the stage)
    ("whole ping (render_sides)", r"Simulator::render_sides\("),
    ("render + profile (render_planes)", r"Simulator::render_planes\("),
    ("mean terms (add_sensor_mean_terms)", r"add_sensor_mean_terms\("),
    ("detector, texture, lattice (detect_speckle)", r"detect_speckle\("),
    ("quantise", r"Simulator::quantise\("),
]
counts = {}
for line in open(path):
    m = re.match(r"\s*([\d,]+) (?:\([^)]*\))?\s*(\S+?):(.*)", line)
    if not m:
        continue
    n, fn = int(m.group(1).replace(",", "")), m.group(3)
    for stage, pat in stages:
        if re.search(pat, fn) and stage not in counts:
            counts[stage] = n
print(f"\n{name} path ({pings} pings):")
print("| stage | instructions/ping | /sample |")
print("|---|---:|---:|")
for stage, _ in stages:
    if stage in counts:
        c = counts[stage] / pings
        print(f"| {stage} | {c / 1e6:.2f} M | {c / samples:.0f} |")
    else:
        print(f"| {stage} | - | - |")
PY
done
