"""Which mutated values are known to be invalid: scene leaves (NUMERIC_RULES) and numeric
command-line flags (flag_expect)."""

import math
import re

from .case import MAX_DEPTH_M

# --------------------------------------------------------------------------------------------
# Which mutated leaf values are known to be invalid.  A rule maps the key name (and sometimes its
# parent) to a predicate over the numeric value: True = valid, False = invalid, None = either.
# Non-numeric replacements of numeric keys are invalid; keys without a rule give "either".
# --------------------------------------------------------------------------------------------

def rng_(lo=None, hi=None, lo_open=False, hi_open=False, integer=False):
    def f(x):
        if integer and x != int(x):
            return False
        if lo is not None and (x < lo or (lo_open and x == lo)):
            return False
        if hi is not None and (x > hi or (hi_open and x == hi)):
            return False
        return True
    return f


def either(_x):
    return None


GRID_HALF = 40.0
NUMERIC_RULES = {
    # key: predicate (parent-specific keys are written "parent.key")
    "seed": lambda x: None if x == int(x) else False,
    "lat_deg": lambda x: (True if x != 0 else None) if -90 <= x <= 90 else False,  # 0 = "no fix" in XTF
    "lon_deg": lambda x: (True if x != 0 else None) if -180 <= x <= 180 else False,
    "size_m": lambda x: None if 1 <= x <= 5000 else False,       # grid extent (bathymetry)
    "cell_m": lambda x: None if 0.01 <= x <= 10 else False,
    "generate.depth_m": lambda x: None if 7 <= x <= 1000 else False,  # fish altitude is 6 m
    "slope_deg": lambda x: None if 0 <= x < 30 else (False if x >= 90 else None),
    "downslope_azimuth_deg": lambda x: None if abs(x) <= 1e6 else None,
    "height_m": lambda x: None if abs(x) < 10 else False,
    "radius_m": lambda x: None if x > 0 else False,
    "speed_m_s": lambda x: (None if x < 0.1 else True) if 0 < x <= 20 else False,
    "altitude_m": lambda x: True if 0.5 <= x <= 12 else (None if 0 < x < 0.5 else False),
    "layback_m": lambda x: None if abs(x) < 100 else False,
    "lever_arm_m": lambda x: None if abs(x) < 100 else False,
    "roll_deg": lambda x: None if abs(x) < 45 else False,
    "pitch_deg": lambda x: None if abs(x) < 45 else False,
    "yaw_deg": lambda x: None if abs(x) < 45 else False,
    "heave_m": lambda x: None if abs(x) < 2 else False,
    "period_s": lambda x: True if 1 <= x <= 100 else (None if 0 < x else False),
    "waypoints.east_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "waypoints.north_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "frequency_khz": lambda x: True if 50 <= x <= 2000 else (None if 0 < x <= 1e4 else False),
    "range_m": lambda x: True if 10 <= x <= 300 else (None if 6 < x < 10 else False),
    "samples": lambda x: True if 16 <= x <= 8192 and x == int(x) else (
        None if 1 <= x < 16 and x == int(x) else False),
    "sound_speed_m_s": lambda x: True if 1400 <= x <= 1600 else (None if 1000 <= x <= 2000 else False),
    "tilt_deg": lambda x: True if 0 <= x <= 45 else (None if -90 <= x <= 90 else False),
    "width_deg": lambda x: True if 5 <= x <= 120 else (None if 0 < x <= 180 else False),
    "horizontal_beam_deg": lambda x: True if 0.1 <= x <= 5 else (None if 0 < x <= 180 else False),
    "length_us": lambda x: True if 10 <= x <= 1000 else (None if 0 < x <= 20000 else False),
    "ping_period_s": lambda x: True if x == 0 or 0.03 <= x <= 1 else (
        False if x < 0 or 0 < x < 0.024 or x > 3600 else None),  # two-way travel 18 m: 0.024 s
    "lambert_mu_db": lambda x: None if -100 <= x <= 0 else False,
    "reflectivity": lambda x: True if 0 < x <= 1 else (None if x == 0 else False),
    "texture_shape": lambda x: None if 0 <= x <= 1e6 else False,
    "id": lambda x: True if x >= 1 and x == int(x) and x < 1e6 else (None if x >= 1 else False),
    "objects.east_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "objects.north_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "position.east_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "position.north_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "start.east_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "start.north_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "end.east_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "end.north_m": lambda x: True if abs(x) <= 20 else (None if abs(x) < GRID_HALF else False),
    "generate.east_m": lambda x: None,
    "generate.north_m": lambda x: None,
    "heading_deg": lambda x: True if abs(x) <= 360 else None,
    "diameter_m": lambda x: True if 0.05 <= x <= 5 else (None if 0 < x < 50 else False),
    "clearance_m": lambda x: True if 0 <= x <= 2 else (None if -5 < x < 10 else False),
    "objects.size_m": lambda x: True if 0.1 <= x <= 10 else (None if 0 < x < 50 else False),
    "temperature_c": lambda x: True if -2 <= x <= 35 else (None if -5 <= x <= 50 else False),
    "salinity_psu": lambda x: True if 0 <= x <= 42 else (None if 0 <= x <= 100 else False),
    "ph": lambda x: True if 6 <= x <= 9 else (None if 0 <= x <= 14 else False),
    "water.depth_m": lambda x: True if 1 <= x <= 11000 else (None if x > 0 and x <= 12000 else False),
    "calibration_k": lambda x: True if 1e-3 <= x <= 1e3 else (None if x > 0 else False),
    "grid_subdivisions": rng_(1, 64, integer=True),
    "object_segments": rng_(2, 256, integer=True),
    "gauss_points": rng_(1, 5, integer=True),
    "along_track_tolerance_db": lambda x: True if 0.01 <= x <= 20 else (None if x > 0 else False),
    "uniform_half_width": lambda x: True if 0 <= x < 1 else (None if x == 1 else False),
    "snr_db": lambda x: True if -20 <= x <= 100 else (None if abs(x) <= 1000 else False),
    "freeze_cell_m": lambda x: True if 0 <= x <= 2 else (None if x > 0 and x < 100 else False),
    # Below ~36 dB under the automatic gain the seabed rounds to 0 and sonarsynth refuses the gain.
    "gain_db": lambda x: True if 40 <= x <= 120 else (None if -150 <= x < 150 else False),
    "band": lambda x: True if x == 1 else False,
    # sensor stage (docs/physics.md §1.10); the bounds of formats/config/option_table.cpp are "either"
    "noise_floor_dbfs": lambda x: True if -120 <= x <= -20 else (None if -300 <= x <= 0 else False),
    "volume_reverberation_db": lambda x: True if -80 <= x <= -10 else (
        None if -300 <= x <= 100 else False),
    "shadow_fill_db": lambda x: True if -80 <= x <= -10 else (None if -300 <= x <= 100 else False),
    "first_return_reflection_db": lambda x: True if -40 <= x <= 0 else (
        None if -300 <= x <= 0 else False),
    "first_return_rms_slope": lambda x: True if 0.01 <= x <= 1 else (None if 0 < x <= 1 else False),
    "side_lobe_db": lambda x: True if -60 <= x <= -3 else (None if -300 <= x <= 0 else False),
    "ring_down_m": lambda x: True if 0 <= x <= 2 else (None if 0 <= x <= 1e4 else False),
    "detector_sub_samples": rng_(1, 16, integer=True),
    "seabed_median_dbfs": lambda x: True if -40 <= x <= -1 else (None if -200 <= x < 0 else False),
    "uniform_variance": lambda x: True if 0 <= x <= 1 / 3 else False,
}
ENUMS = {"type", "shape", "backscatter", "model", "tvg", "sample_format", "material",
         "along_track_planes", "gain_db", "quantity", "detector", "normalise", "display", "preset"}
BOOLS = {"shadows", "spreading", "beam_pattern", "absorption", "texture", "truth",
         "depth_positive_down", "along_track_correlation"}


def rule_for(path):
    key = path[-1] if not isinstance(path[-1], int) else path[-2]
    parents = [p for p in path[:-1] if not isinstance(p, int)]
    if isinstance(path[-1], int):
        parents = parents[:-1]
    for parent in reversed(parents):
        r = NUMERIC_RULES.get("%s.%s" % (parent, key))
        if r is not None:
            return key, r
    return key, NUMERIC_RULES.get(key)


# The replacement values: (label, raw YAML, numeric value or None)
LONG = "x" * 5000
REPLACEMENTS = [
    ("-1", "-1", -1.0), ("0", "0", 0.0), ("huge", "1e9", 1e9), ("tiny", "1e-9", 1e-9),
    ("1e308", "1e308", 1e308), ("nan", ".nan", None), ("inf", ".inf", None),
    ("-inf", "-.inf", None), ("text", "hello", None), ("null", "~", None), ("list", "[]", None),
    ("map", "{}", None), ("longstr", LONG, None),
    ("int-overflow", "18446744073709551617", 18446744073709551617.0),  # a valid YAML number
]


def expectation_for_leaf(path, original, label, raw, num):
    key, rule = rule_for(path)
    if key in ("name",) or key == "start_time":
        if label in ("list", "map"):
            return "invalid"
        if key == "start_time":
            return "invalid" if label != "null" else "either"
        if label == "longstr" and path == ("survey", "lines", 0, "name"):
            return "invalid"  # a 5000-character file name cannot be created
        return "either"
    if isinstance(original, bool) or key in BOOLS:
        return "either" if label in ("null",) else ("invalid" if label not in ("0",) else "either")
    if isinstance(original, str) and key in ENUMS and key != "gain_db":
        return "invalid" if label != "null" else "either"
    if label == "null":
        return "either"   # may mean "the default"
    if num is None:
        return "invalid"  # nan, inf, text, [], {}, long string, integer overflow for a number
    if rule is None:
        return "either"
    verdict = rule(num)
    return {True: "valid", False: "invalid", None: "either"}[verdict]


BAD_NUMBERS = [("-1", "-1"), ("0", "0"), ("1e9", "1e9"), ("nan", "nan"), ("inf", "inf"),
               ("text", "abc"), ("1e308", "1e308"), ("empty", ""), ("2^64+1", "18446744073709551617"),
               ("tiny", "1e-9"), ("hex", "0x10"), ("trailing", "5abc")]


def flag_expect(flag, value):
    """Expectation for a numeric flag value (table of valid ranges)."""
    try:
        x = float(value)
    except ValueError:
        return "invalid"
    if not math.isfinite(x):
        return "invalid"
    if value.startswith("0x"):
        return "either"
    table = {
        "--seed": lambda x: "valid" if x >= 0 and x == int(x) and x < 2 ** 63 else "either",
        "--range": lambda x: "valid" if 10 <= x <= 300 else ("invalid" if x <= 6 or x > 1e5 else "either"),
        "--samples": lambda x: "valid" if 16 <= x <= 8192 and x == int(x) else (
            "invalid" if x < 1 or x > 8192 or x != int(x) else "either"),
        "--threads": lambda x: "valid" if 1 <= x <= 1024 and x == int(x) else (
            "either" if x == 0 else "invalid"),
        "--res": lambda x: "valid" if 0.05 <= x <= 10 else ("invalid" if x <= 0 or x < 1e-3 else "either"),
        "--max-anomalies": lambda x: "valid" if 0 <= x <= 1e6 and x == int(x) else "either",
        "--taper": lambda x: "valid" if 0 <= x <= 0.5 else "invalid",
        "--lo-db": lambda x: "either",
        "--lat": lambda x: "valid" if -80 <= x <= 80 else ("invalid" if abs(x) > 90 else "either"),
        "--lon": lambda x: "valid" if -180 <= x <= 180 else "invalid",
        "--cell": lambda x: "valid" if 0.05 <= x <= 10 else ("invalid" if x <= 0 or x < 1e-3 or x > 1e4 else "either"),
        "--depth": lambda x: "valid" if 1 <= x <= 11000 else ("invalid" if x <= 0 or x > MAX_DEPTH_M else "either"),
    }
    if value.strip() != value or value.endswith("abc"):
        return "invalid"
    if flag in ("--seed", "--samples", "--threads", "--max-anomalies") and re.search(r"[.eE]", value):
        return "either" if x == int(x) and x >= 0 else "invalid"   # 1e9: an integer in float spelling
    return table.get(flag, lambda x: "either")(x)
