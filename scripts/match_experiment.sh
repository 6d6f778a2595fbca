#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The founding paper's validation on our images (docs/feature-matching.md): simulate
# samples/paper_loop.yaml with each noise model and several seeds, mosaic the start and the
# loop-closure passes separately, match their common area with `sonarsynth match` (every
# detector, with and without each pre-filter) and write the markdown tables of the doc.
# Usage: scripts/match_experiment.sh [--build DIR] [--out DIR] [--seeds "1 2 3 4 5"]
# Needs a build with OpenCV (libopencv-dev) and python3. Takes about 2 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
out=build/match-experiment
seeds="1 2 3 4 5"
while (($#)); do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--out DIR] [--seeds \"1 2 3\"]" >&2; exit 2 ;;
  esac
done
cli=$build/tools/sonarsynth
[[ -x $cli ]] || { echo "match_experiment: no $cli (build first)" >&2; exit 1; }
command -v python3 >/dev/null || { echo "match_experiment: needs python3" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out"

for noise in none paper speckle; do
  # The sample with its noise model replaced (relative paths: none in this scene).
  sed "s/^  model: speckle$/  model: $noise/" samples/paper_loop.yaml >"$out/paper_loop_$noise.yaml"
  grep -q "model: $noise" "$out/paper_loop_$noise.yaml"
  for seed in $seeds; do
    run=$out/$noise-$seed
    "$cli" simulate "$out/paper_loop_$noise.yaml" -o "$run" --seed "$seed" -q --no-mosaic \
      --no-waterfall --no-truth
    "$cli" mosaic "$run/start.xtf" -o "$run/start.tif" --no-rgb -q
    "$cli" mosaic "$run/closure.xtf" -o "$run/closure.tif" --no-rgb -q
    "$cli" match "$run/start.tif" "$run/closure.tif" --overlap \
      --prefilter none,median,bilateral --json "$run/match.json" -q
    echo "match_experiment: $noise seed $seed done"
  done
done
# The inlier image of the first speckle run, for the doc.
first=$(echo "$seeds" | awk '{print $1}')
"$cli" match "$out/speckle-$first/start.tif" "$out/speckle-$first/closure.tif" --overlap \
  --detectors akaze --json "$out/example.json" --image "$out/inliers_speckle_akaze.png" -q

python3 - "$out" $seeds <<'PY'
import json, statistics, sys
out, seeds = sys.argv[1], sys.argv[2:]
dets = ["sift", "brisk", "orb", "akaze"]
paper = {"sift": 8, "brisk": 7, "orb": 4, "akaze": 11}
rows = {}
for noise in ["none", "paper", "speckle"]:
    for seed in seeds:
        with open(f"{out}/{noise}-{seed}/match.json") as f:
            for r in json.load(f)["results"]:
                rows.setdefault((noise, r["prefilter"], r["detector"]), []).append(r)
def cell(rs, key):
    v = [r[key] for r in rs if r[key] is not None]
    if not v: return "-"
    m = statistics.mean(v)
    return f"{m:.1f} ({min(v)}-{max(v)})" if key != "transform_rms_m" else f"{statistics.median(v):.2f}"
lines = []
lines.append("Inliers after RANSAC, mean (min-max) over seeds " + ", ".join(seeds) + ":\n")
lines.append("| noise | pre-filter | " + " | ".join(d.upper() if d != "akaze" else "A-KAZE" for d in dets) + " |")
lines.append("|---|---|" + "---|" * len(dets))
lines.append("| *paper, Table 2* | *none* | " + " | ".join(f"*{paper[d]}*" for d in dets) + " |")
for noise in ["none", "paper", "speckle"]:
    for pf in ["none", "median", "bilateral"]:
        lines.append(f"| {noise} | {pf} | " + " | ".join(cell(rows[(noise, pf, d)], "inliers") for d in dets) + " |")
lines.append("\nCorrect inliers (keypoint pair within 1 m of the truth), mean (min-max), and in brackets the\n"
             "median RMS error of the estimated transform at the inliers, metres:\n")
lines.append("| noise | pre-filter | " + " | ".join(d.upper() if d != "akaze" else "A-KAZE" for d in dets) + " |")
lines.append("|---|---|" + "---|" * len(dets))
for noise in ["none", "paper", "speckle"]:
    for pf in ["none", "median", "bilateral"]:
        cells = []
        for d in dets:
            rs = rows[(noise, pf, d)]
            cells.append(cell(rs, "correct_inliers") + " [" + cell(rs, "transform_rms_m") + " m]")
        lines.append(f"| {noise} | {pf} | " + " | ".join(cells) + " |")
lines.append("\nKeypoints in the start patch / matches after the ratio test, mean over seeds:\n")
lines.append("| noise | pre-filter | " + " | ".join(d.upper() if d != "akaze" else "A-KAZE" for d in dets) + " |")
lines.append("|---|---|" + "---|" * len(dets))
for noise in ["none", "paper", "speckle"]:
    for pf in ["none", "median", "bilateral"]:
        lines.append(f"| {noise} | {pf} | " + " | ".join(
            f"{statistics.mean(r['keypoints_a'] for r in rows[(noise, pf, d)]):.0f} / "
            f"{statistics.mean(r['matches'] for r in rows[(noise, pf, d)]):.0f}" for d in dets) + " |")
text = "\n".join(lines) + "\n"
with open(f"{out}/tables.md", "w") as f:
    f.write(text)
print(text)
PY
echo "match_experiment: tables in $out/tables.md"
