#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Two builds of bench/ping_benchmark measured alternately in one run (the machine's speed drifts
# by +-25 % over minutes: only ratios of medians measured this way are worth reading).
#
#   bench/ab_ping.sh OLD_BINARY NEW_BINARY [ROUNDS] [-- ping_benchmark arguments]
#
# Each round runs OLD then NEW with `--runs 5` (or the arguments after --). Prints, per thread
# count, every round's pings/s, the medians and NEW/OLD, then the median CPU per ping of each
# stage. SONARSYNTH_SIMD in the environment caps both builds' vector kernels (a build without
# them ignores it).
set -euo pipefail
[[ $# -ge 2 ]] || { sed -n 3,11p "$0"; exit 2; }
old=$1 new=$2
shift 2
rounds=3
if [[ $# -gt 0 && $1 != "--" ]]; then rounds=$1; shift; fi
[[ $# -gt 0 && $1 == "--" ]] && shift
args=("$@")
[[ ${#args[@]} -gt 0 ]] || args=(--runs 5)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for ((r = 1; r <= rounds; ++r)); do
  for which in old new; do
    bin=$old
    [[ $which == new ]] && bin=$new
    "$bin" "${args[@]}" > "$tmp/$which.$r.txt"
    grep '^threads' "$tmp/$which.$r.txt" | sed "s/^/$which round $r: /" >&2
  done
done
/usr/bin/python3 - "$tmp" "$rounds" <<'PY'
import re, statistics, sys
tmp, rounds = sys.argv[1], int(sys.argv[2])
line = re.compile(r"threads (\d+):\s+(\d+) pings/s.*profile\s+([\d.]+) us, render\s+([\d.]+) us, "
                  r"noise\+tvg\s+([\d.]+) us \| checksum (\S+)")
data = {}
for which in ("old", "new"):
    for r in range(1, rounds + 1):
        for m in line.finditer(open(f"{tmp}/{which}.{r}.txt").read()):
            t = int(m.group(1))
            d = data.setdefault((which, t), {"pps": [], "profile": [], "render": [], "noise": [], "sum": set()})
            d["pps"].append(int(m.group(2)))
            d["profile"].append(float(m.group(3)))
            d["render"].append(float(m.group(4)))
            d["noise"].append(float(m.group(5)))
            d["sum"].add(m.group(6))
threads = sorted({t for _, t in data})
print("| threads | old pings/s | new pings/s | new/old (medians) |")
print("|---:|---|---|---:|")
for t in threads:
    o, n = data[("old", t)], data[("new", t)]
    mo, mn = statistics.median(o["pps"]), statistics.median(n["pps"])
    print(f"| {t} | {' / '.join(map(str, o['pps']))} | {' / '.join(map(str, n['pps']))} | {mn / mo:.2f} |")
print()
print("| threads | stage | old us/ping | new us/ping | new/old |")
print("|---:|---|---:|---:|---:|")
for t in threads:
    for stage in ("profile", "render", "noise"):
        mo = statistics.median(data[("old", t)][stage])
        mn = statistics.median(data[("new", t)][stage])
        name = "noise+tvg" if stage == "noise" else stage
        print(f"| {t} | {name} | {mo:.1f} | {mn:.1f} | {mn / mo:.2f} |")
for which in ("old", "new"):
    sums = set().union(*(data[(which, t)]["sum"] for t in threads))
    print(f"\n{which} checksums: {', '.join(sorted(sums))}")
PY
