#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# A zoomed waterfall of a real file's near-nadir samples with the first-return picks of
# bench/bottom_track_real drawn on it (docs/conversion.md, "The real Iver2 file"): green the
# tracker, red the change-point reference, blue the realism detector. Each ping is 6 rows, each
# sample 6 columns; a pick is a tick two rows high in the ping's rows (blue, red, green from
# the top).
#
#   BT_DEBUG=1 build/bench/bottom_track_real FILE.xtf > picks.txt
#   PYTHONPATH=build/python /usr/bin/python3 bench/plots/first_return_picks.py FILE.xtf \
#       picks.txt starboard FIRST_PING END_PING FIRST_SAMPLE END_SAMPLE OUT.png
import sys

import numpy as np
from osgeo import gdal

import sonarsynth

SCALE = 6
MARKS = (("ref0", (40, 120, 255), 0), ("ref1", (255, 40, 40), 2), ("track", (40, 230, 40), 4))


def main(argv):
    if len(argv) != 9:
        sys.exit(__doc__ or "usage: first_return_picks.py FILE PICKS SIDE K0 K1 S0 S1 OUT.png")
    path, picks_path, side_name = argv[1], argv[2], argv[3]
    k0, k1, s0, s1 = map(int, argv[4:8])
    side = {"port": 0, "starboard": 1}[side_name]
    picks = {}
    with open(picks_path) as f:
        for line in f:
            if not line.startswith("dbg "):
                continue
            _, ref, s, k, track, value = line.split()
            if int(s) != side:
                continue
            p = picks.setdefault(int(k), {})
            p["track"] = float(track)
            p["ref" + ref] = float(value)
    samples = sonarsynth.read_xtf(path)[side_name][k0:k1, s0:s1].astype(np.float64)
    db = 20 * np.log10(np.maximum(np.abs(samples), 1.0))
    lo, hi = np.percentile(db, 1), np.percentile(db, 99.5)
    grey = np.clip((db - lo) / (hi - lo), 0, 1) * 255
    rgb = np.repeat(np.repeat(np.repeat(grey[:, :, None], 3, 2), SCALE, 0), SCALE, 1)
    for k in range(k0, k1):
        for key, colour, row in MARKS:
            v = picks.get(k, {}).get(key)
            if v is None or not np.isfinite(v):
                continue
            c = int(np.floor(v)) - s0  # picks are in samples (range / sample spacing)
            if 0 <= c < s1 - s0:
                top = (k - k0) * SCALE + row
                rgb[top:top + 2, c * SCALE:(c + 1) * SCALE, :] = colour
    img = rgb.astype(np.uint8)
    ds = gdal.GetDriverByName("MEM").Create("", img.shape[1], img.shape[0], 3, gdal.GDT_Byte)
    for b in range(3):
        ds.GetRasterBand(b + 1).WriteArray(img[:, :, b])
    gdal.GetDriverByName("PNG").CreateCopy(argv[8], ds)


if __name__ == "__main__":
    main(sys.argv)
