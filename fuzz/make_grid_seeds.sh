#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Seeds for grid_reader_fuzz: small rasters made from the test BAG with gdal_translate (UTM and
# geographic GeoTIFFs, float and compressed integer, ASCII and Surfer grids), one file each.
set -euo pipefail
out=${1:?usage: fuzz/make_grid_seeds.sh OUT_DIR}
bag="$(dirname "$0")/../tests/data/bathymetry/tiny_sr.bag"
mkdir -p "$out"
t() { gdal_translate -q -b 1 "$@" 2>/dev/null; }
t -of GTiff -ot Float32 -outsize 16 16 "$bag" "$out/utm.tif"
t -of GTiff -ot Float32 -outsize 12 10 -a_srs EPSG:4326 -a_ullr -68.83 48.45 -68.82 48.44 \
  "$bag" "$out/geographic.tif"
t -of GTiff -ot Int16 -outsize 8 8 -co COMPRESS=DEFLATE "$bag" "$out/deflate.tif"
t -of AAIGrid -outsize 8 8 "$bag" "$out/grid.asc"
t -of GSBG -outsize 8 8 "$bag" "$out/grid.grd"
rm -f "$out"/*.aux.xml "$out"/*.prj
