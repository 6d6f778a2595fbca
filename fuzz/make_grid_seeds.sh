#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Seeds for grid_reader_fuzz: small rasters made from the test BAG with gdal_translate (UTM and
# geographic GeoTIFFs, a user-defined transverse Mercator over an identified geographic CRS, float
# and compressed integer, ASCII and Surfer grids), one file each.
set -euo pipefail
out=${1:?usage: fuzz/make_grid_seeds.sh OUT_DIR}
bag="$(dirname "$0")/../tests/data/bathymetry/tiny_sr.bag"
mkdir -p "$out"
t() { gdal_translate -q -b 1 "$@" 2>/dev/null; }
t -of GTiff -ot Float32 -outsize 16 16 "$bag" "$out/utm.tif"
t -of GTiff -ot Float32 -outsize 12 10 -a_srs EPSG:4326 -a_ullr -68.83 48.45 -68.82 48.44 \
  "$bag" "$out/geographic.tif"
tm='PROJCS["local TM",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
tm+='PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]],'
tm+='PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],'
tm+='PARAMETER["central_meridian",-69],PARAMETER["scale_factor",1],PARAMETER["false_easting",0],'
tm+='PARAMETER["false_northing",0],UNIT["metre",1]]'
t -of GTiff -ot Float32 -outsize 10 10 -a_srs "$tm" -a_ullr 60000 5370000 60100 5369900 \
  "$bag" "$out/local_tm.tif"
t -of GTiff -ot Int16 -outsize 8 8 -co COMPRESS=DEFLATE "$bag" "$out/deflate.tif"
t -of AAIGrid -outsize 8 8 "$bag" "$out/grid.asc"
t -of GSBG -outsize 8 8 "$bag" "$out/grid.grd"
rm -f "$out"/*.aux.xml "$out"/*.prj
