#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Byte comparison of two builds' outputs: `simulate` of every sample scene, `dataset` of every
# sample spec, and `convert`/`mosaic`/`waterfall`/`info --json` of the real file when present.
# Prints one line per output file whose sha256 differs (or that one build lacks) and a summary.
# Files that record the program itself (effective.yaml's version line, dataset manifests'
# timings) are compared with those lines removed.
# Usage: scripts/compare_outputs.sh OLD_CLI NEW_CLI [work dir]
set -euo pipefail
old=$(readlink -f "$1"); new=$(readlink -f "$2")
work=${3:-$(mktemp -d)}
cd "$(dirname "$0")/.."
real=$(ls ../shared/data/xtf/*.xtf 2>/dev/null | head -1 || true)
run_both() {  # run_both NAME FILE ARGS...: -o NAME[/FILE] appended (FILE "" = a dir)
  # Both builds write to the same path (work/run/NAME), since some products record their own
  # path and command line; the results are then moved to work/old and work/new.
  local name=$1 file=$2; shift 2
  for side in old new; do
    local cli=$old out="$work/run/$name"; [ $side = new ] && cli=$new
    rm -rf "$work/run" "$work/$side/$name"; mkdir -p "$work/run" "$work/$side"
    if [ -n "$file" ]; then mkdir -p "$out"; out="$out/$file"; fi
    "$cli" "$@" -o "$out" >"$work/$side/$name.log" 2>&1 || echo "$side $name: exit $?"
    mv "$work/run/$name" "$work/$side/$name"
  done
}
for scene in samples/*.yaml; do
  run_both "simulate-$(basename "$scene" .yaml)" "" simulate "$scene" --threads 2
done
for spec in samples/datasets/*.yaml; do
  run_both "dataset-$(basename "$spec" .yaml)" "" dataset "$spec" --items 0:3
done
if [ -n "$real" ]; then
  run_both convert-real real.jsf convert "$real"
  run_both mosaic-real mosaic.tif mosaic "$real"
  run_both waterfall-real waterfall.png waterfall "$real"
  run_both convert-real-bag real.bag convert "$real"
  run_both convert-real-mcap real.mcap convert "$real"
  for side in old new; do
    cli=$old; [ $side = new ] && cli=$new
    "$cli" info --json "$real" >"$work/$side/info-real.json" 2>&1 || echo "$side info: exit $?"
    rm -rf "$work/run" && mkdir -p "$work/run" && cp "$work/$side/convert-real/real.jsf" "$work/run/"
    "$cli" convert "$work/run/real.jsf" -o "$work/run/back.xtf" >>"$work/$side/convert-real.log" 2>&1 ||
      echo "$side convert back: exit $?"
    mv "$work/run/back.xtf" "$work/$side/convert-real/"
    # info names the file: both builds read it at the same path.
    cp "$work/$side/convert-real-bag/real.bag" "$work/run/"
    "$cli" info --json "$work/run/real.bag" >"$work/$side/info-real-bag.json" 2>&1 ||
      echo "$side info bag: exit $?"
  done
fi
normalise() {  # drops lines that name the program or a wall time
  case "$1" in
    *.yaml | *.json | *.jsonl | *.txt | *.csv) grep -vE 'version|sonarsynth [0-9]|seconds|elapsed|_s":|created' "$1" | sha256sum | cut -d' ' -f1 ;;
    *) sha256sum "$1" | cut -d' ' -f1 ;;
  esac
}
# GeoTIFFs whose bytes differ: same pixels (every band and overview) and metadata? Builds before
# the truth rasters' writes were serialised wrote their blocks in an order that depended on GDAL's
# shared block cache (docs/labels.md), so an old build's truth raster may differ in layout only.
same_pixels() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
import numpy as np
from osgeo import gdal
a, b = gdal.Open(sys.argv[1]), gdal.Open(sys.argv[2])
def bands(d):
    for i in range(1, d.RasterCount + 1):
        band = d.GetRasterBand(i)
        yield band
        for o in range(band.GetOverviewCount()):
            yield band.GetOverview(o)
ok = (a.RasterCount == b.RasterCount and a.GetGeoTransform() == b.GetGeoTransform()
      and a.GetMetadata() == b.GetMetadata()
      and all(np.array_equal(x.ReadAsArray(), y.ReadAsArray(), equal_nan=True)
              for x, y in zip(bands(a), bands(b))))
sys.exit(0 if ok else 1)
PY
}
same=0; layout=0; differ=0
while IFS= read -r rel; do
  a="$work/old/$rel"; b="$work/new/$rel"
  if [ ! -f "$a" ] || [ ! -f "$b" ]; then echo "only in one: $rel"; differ=$((differ + 1)); continue; fi
  if [ "$(normalise "$a")" = "$(normalise "$b")" ]; then
    same=$((same + 1))
  elif [[ $rel == *.tif ]] && same_pixels "$a" "$b"; then
    echo "same pixels and metadata, other byte layout: $rel"; layout=$((layout + 1))
  else
    echo "differs: $rel"; differ=$((differ + 1))
  fi
done < <( (cd "$work/old" && find . -type f ! -name '*.log'; cd "$work/new" && find . -type f ! -name '*.log') | sort -u)
echo "compare_outputs: $same files byte-identical, $layout GeoTIFFs with the same pixels and metadata in another byte layout, $differ differ ($work)"
[ $differ -eq 0 ]
