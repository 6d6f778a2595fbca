#!/bin/sh
# SPDX-License-Identifier: MIT
# Markdown table of the realism figures (docs/realism.md) of a real and a simulated XTF file:
#   bench/realism_table.sh REAL.xtf SIM.xtf
# Runs $BUILD_DIR/bench/realism --json on both (BUILD_DIR defaults to build); figures are the
# pooled ones (both sides) unless the row says otherwise.
set -eu
if [ $# -ne 2 ]; then
  echo "usage: $0 REAL.xtf SIM.xtf (env BUILD_DIR, default build)" >&2
  exit 1
fi
bin="${BUILD_DIR:-build}/bench/realism"
if [ ! -x "$bin" ]; then
  echo "$0: $bin not found (build the realism target, or set BUILD_DIR)" >&2
  exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" "$1" --json >"$tmp/real.json"
"$bin" "$2" --json >"$tmp/sim.json"
python3 - "$tmp/real.json" "$tmp/sim.json" <<'PY'
import json
import sys

real, sim = (json.load(open(p)) for p in sys.argv[1:3])


def fig(j, key, side="pooled"):
    f = j.get("figures", {}).get(key)
    return None if f is None else f.get(side)


def fmt(v, digits):
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    return f"{v:.{digits}f}"


def cell(j, keys, digits, sep=" / "):
    return sep.join(fmt(fig(j, k), digits) for k in keys)


rows = []


def row(label, keys, digits=2, sep=" / "):
    rows.append((label, cell(real, keys, digits, sep), cell(sim, keys, digits, sep)))


def top(label, keys, digits=2):
    cells = []
    for j in (real, sim):
        cells.append(" / ".join(fmt(j.get(k), digits) for k in keys))
    rows.append((label, *cells))


top("file", ["file"])
top("pings measured / samples per side / slant range (m)",
    ["pings_measured", "samples_per_side", "slant_range_m"], 0)
row("1 seabed std/mean, median tile", ["tile_contrast"], 3)
row("1 seabed std of 10 log10, median tile (dB)", ["tile_db_std"], 2)
row("2 water column - near seabed (dB)", ["water_minus_near_db"], 1)
row("3 shadow - lit seabed, p50 (dB)", ["shadow_minus_lit_db_p50"], 1)
row("3 shadow - water column (dB)", ["shadow_minus_water_db"], 1)
row("7 across-track lag-1, near / mid / far (median tile)",
    ["across_lag1_near", "across_lag1_mid", "across_lag1_far"], 2)
row("7 across-track spectrum quarters / mean (all rows)",
    [f"across_spectrum_q{q}" for q in range(1, 5)], 2, " ")
row("7 across-track spectrum quarters / mean (median tile)",
    [f"across_spectrum_tile_q{q}" for q in range(1, 5)], 2, " ")


def along(j):
    cells = []
    for band in j.get("lag1_along_track_median_tile", []):
        v = band.get("pooled")
        if v is not None:
            cells.append(f"{band['band_m'][0]:.1f}-{band['band_m'][1]:.1f}: {v:.2f}")
    return ", ".join(cells) if cells else "-"


rows.append(("8 along-track lag-1 per range band (median tile)", along(real), along(sim)))
row("9 shadow std/mean: all shadow / median region / lit seabed",
    ["shadow_cv", "shadow_region_cv_p50", "lit_cv"], 2)
row("9 shadow std/mean, regions p25 / p75", ["shadow_region_cv_p25", "shadow_region_cv_p75"], 2)


def edge(j):
    w = fig(j, "shadow_edge_width_m")
    n = fig(j, "shadow_edge_transitions")
    inw = fig(j, "shadow_edge_in_15_25m")
    if w is None:
        return "-"
    where = "15-25 m" if inw == 1 else "all ranges"
    return f"{w:.2f} ({int(n)} edges, {where})"


rows.append(("10 shadow -> lit edge, 10-90 % width (m)", edge(real), edge(sim)))
row("11 water std/mean, 64-ping blocks (median)", ["water_block_cv_p50"], 2)
row("11 water std/mean, single ping p25 / p50 / p75",
    ["water_ping_cv_p25", "water_ping_cv_p50", "water_ping_cv_p75"], 2)
row("11 water skewness, pooled / block median", ["water_skewness", "water_block_skewness_p50"], 2)
row("11 water lowest value (counts)", ["water_min"], 0)
row("11 water level, last - first third (dB)", ["water_trend_db"], 1)
offsets = ["000", "003", "006", "009", "020", "050", "090"]
row("12 level at r0 + 0 / .03 / .06 / .09 / .2 / .5 / .9 m - near seabed (dB)",
    [f"first_profile_r0_{o}cm_db" for o in offsets], 1, " ")
row("12 the same from the header altitude (dB)",
    [f"first_profile_altitude_{o}cm_db" for o in offsets], 1, " ")


def monotone(j):
    m = fig(j, "first_profile_monotone")
    d = fig(j, "first_profile_max_drop_db")
    if m is None:
        return "-"
    return f"{'yes' if m == 1 else 'no'} (largest drop {d:.1f} dB)"


rows.append(("12 profile monotone within 1 dB to +0.5 m", monotone(real), monotone(sim)))
row("13 far [0.9, 0.97) R - near [1.4, 1.6) r0 (dB)", ["far_minus_near_db"], 1)
row("13 altitude / R (median)", ["altitude_over_range"], 3)
row("14 samples at full scale in [r0, r0 + 2 m) (%)", ["first_2m_clipped_pct"], 1)
row("15 level of all samples, p1 / p50 / p99 (dB)",
    ["level_p01_db", "level_p50_db", "level_p99_db"], 1)
top("16 header altitude min / median / max (m)",
    ["altitude_min_m", "altitude_median_m", "altitude_max_m"], 2)

print("| measure | real | simulated |")
print("|---|---:|---:|")
for label, a, b in rows:
    print(f"| {label} | {a} | {b} |")
PY
