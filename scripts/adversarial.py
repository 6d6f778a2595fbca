#!/usr/bin/python3
"""Adversarial campaign against the sonarsynth CLI (docs/adversarial-testing.md).

    /usr/bin/python3 scripts/adversarial.py --cli build/tools/sonarsynth \
        [--cases N] [--seed S] [--timeout SEC] [--out report.json] [--keep-failures DIR]

Every case runs in a fresh sandbox (a valid base scene, a base XTF and raster, and "user files",
hidden ones included) that is snapshotted before and compared after the run.  Each case gets
exactly one class:

  ok            valid input, exit 0, plausible output
  clean_error   exit 1/2 with a message on stderr (flagged `generic` when it names nothing the
                case knows about: the key, flag, value or file)
  crash         exit 3 ("internal error"), a signal, an unexpected exit code, sanitizer output
  hang          ran past the timeout
  silent_wrong  exit 0 for an input known to be invalid, or exit 0 with implausible output
  data_lost     a user file (or the scene) changed or vanished, or a visible output was left
                behind by a failed run, or an interrupted run left an incomplete directory
  unclassified  anything the rules above do not decide (the reason is recorded)

`litter` (hidden .part-/.old- temporaries left by a run that ended by itself or by
SIGINT/SIGTERM) is counted in its own column, independently of the class.

Standard library only.  Deterministic for a given --seed (except for the timing of
interrupts).
"""

import argparse
import copy
import hashlib
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
from array import array

CLASSES = ["ok", "clean_error", "crash", "hang", "silent_wrong", "data_lost", "unclassified"]
# When a case shows several problems the most severe one names it.
SEVERITY = ["data_lost", "crash", "hang", "silent_wrong", "unclassified", "clean_error", "ok"]
CATEGORIES = ["cli", "yaml", "raster", "xtf", "interrupt", "fs"]
CATEGORY_WEIGHT = {"cli": 0.25, "yaml": 0.36, "raster": 0.10, "xtf": 0.21, "interrupt": 0.04,
                   "fs": 0.04}
SANITIZER_MARKERS = ["AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer",
                     "ThreadSanitizer", "runtime error:", "terminate called", "Segmentation fault",
                     "stack smashing", "double free", "corrupted size", "Assertion `"]
TEMP_RE = re.compile(r"^\..*\.(part|old)-\d+")
MAX_DEPTH_M = 12000.0


# --------------------------------------------------------------------------------------------
# The base scene (tiny and fast: ~600 pings of 128 samples) and a YAML emitter for mutants.
# --------------------------------------------------------------------------------------------

class Raw:
    """YAML text inserted verbatim (a mutated value)."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return "Raw(%r)" % self.text[:40]


def base_scene(bathy_file=None):
    if bathy_file:
        bathy = {"file": bathy_file, "depth_positive_down": False, "band": 1}
    else:
        bathy = {"generate": {
            "centre": {"lat_deg": 43.0, "lon_deg": 5.0},
            "size_m": [80, 80], "cell_m": 0.5, "depth_m": 20, "seed": 5,
            "components": [
                {"type": "plane", "slope_deg": 1.0, "downslope_azimuth_deg": 100},
                {"type": "seamount", "east_m": 5, "north_m": 10, "height_m": 1.5, "radius_m": 4},
            ]}}
    return {
        "name": "adv",
        "seed": 3,
        "bathymetry": bathy,
        "materials": [{"name": "shell", "lambert_mu_db": -17, "reflectivity": 0.7,
                       "texture_shape": 4}],
        "seabed": {"material": "sand"},
        "objects": [
            {"type": "pipe", "id": 1, "start": {"east_m": -15, "north_m": 8},
             "end": {"east_m": 15, "north_m": 8}, "diameter_m": 0.5, "clearance_m": 0,
             "material": "steel"},
            {"type": "box", "position": {"east_m": 0, "north_m": -8}, "heading_deg": 35,
             "size_m": [3, 1.5, 1.2], "material": "steel"},
            {"type": "rock", "position": {"east_m": 8, "north_m": -5}, "diameter_m": 1.2},
        ],
        "survey": {
            "start_time": "2026-03-01T10:00:00Z",
            "speed_m_s": 3.0,
            "altitude_m": 6,
            "layback_m": 0,
            "lever_arm_m": [0, 0, 0],
            "disturbance": {"roll_deg": 0.5, "pitch_deg": 0.3, "yaw_deg": 0.3, "heave_m": 0.05,
                            "period_s": 7},
            "lines": [{"name": "L1", "waypoints": [{"east_m": -25, "north_m": 0},
                                                    {"east_m": 25, "north_m": 0}]}],
        },
        "sonar": {
            "frequency_khz": 600, "range_m": 18, "samples": 128, "sound_speed_m_s": 1500,
            "tilt_deg": 20, "vertical_beam": {"shape": "gaussian", "width_deg": 50},
            "horizontal_beam_deg": 0.5, "pulse": {"type": "cw", "length_us": 50},
            "ping_period_s": 0,
        },
        "render": {
            "backscatter": "paper", "shadows": True, "spreading": True, "beam_pattern": True,
            "absorption": True,
            "water": {"temperature_c": 10, "salinity_psu": 35, "ph": 8, "depth_m": 20},
            "calibration_k": 1.0,
            "quality": {"grid_subdivisions": 1, "object_segments": 16, "gauss_points": 2,
                        "along_track_planes": "auto", "along_track_tolerance_db": 1.0},
        },
        "noise": {"model": "speckle", "uniform_half_width": 0.3, "snr_db": 20, "texture": True,
                  "freeze_cell_m": 0},
        "output": {"tvg": "spherical", "gain_db": "auto", "sample_format": "u16", "truth": True},
    }


def yaml_scalar(v):
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if v is None:
        return "~"
    raise TypeError(v)


def is_scalar_list(v):
    return isinstance(v, list) and all(not isinstance(x, (dict, list)) for x in v)


def emit_yaml(node, indent=0):
    pad = "  " * indent
    out = []
    if isinstance(node, dict):
        for k, v in node.items():
            key = k.text if isinstance(k, Raw) else k
            if isinstance(v, dict) and v:
                out.append("%s%s:" % (pad, key))
                out.append(emit_yaml(v, indent + 1))
            elif isinstance(v, list) and v and not is_scalar_list(v):
                out.append("%s%s:" % (pad, key))
                out.append(emit_yaml(v, indent + 1))
            elif isinstance(v, list):
                out.append("%s%s: [%s]" % (pad, key, ", ".join(yaml_scalar(x) for x in v)))
            elif isinstance(v, dict):
                out.append("%s%s: {}" % (pad, key))
            else:
                out.append("%s%s: %s" % (pad, key, yaml_scalar(v)))
    elif isinstance(node, list):
        for item in node:
            if isinstance(item, dict) and item:
                body = emit_yaml(item, indent + 1).split("\n")
                out.append("%s- %s" % (pad, body[0].lstrip()))
                out.extend(body[1:])
            elif isinstance(item, list) and not is_scalar_list(item):
                out.append("%s-" % pad)
                out.append(emit_yaml(item, indent + 1))
            elif isinstance(item, list):
                out.append("%s- [%s]" % (pad, ", ".join(yaml_scalar(x) for x in item)))
            else:
                out.append("%s- %s" % (pad, yaml_scalar(item)))
    return "\n".join(x for x in out if x != "")


def scene_text(scene):
    return emit_yaml(scene) + "\n"


def leaves(node, path=()):
    """Every scalar leaf (lists of scalars yield one leaf per element)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from leaves(v, path + (i,))
    else:
        yield path, node


def containers(node, path=()):
    if isinstance(node, dict):
        yield path, node
        for k, v in node.items():
            yield from containers(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from containers(v, path + (i,))


def get_path(node, path):
    for p in path:
        node = node[p]
    return node


def set_path(node, path, value):
    get_path(node, path[:-1])[path[-1]] = value


def path_str(path):
    s = ""
    for p in path:
        s += "[%d]" % p if isinstance(p, int) else ("." if s else "") + str(p)
    return s


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
}
ENUMS = {"type", "shape", "backscatter", "model", "tvg", "sample_format", "material",
         "along_track_planes", "gain_db"}
BOOLS = {"shadows", "spreading", "beam_pattern", "absorption", "texture", "truth",
         "depth_positive_down"}


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


# --------------------------------------------------------------------------------------------
# Snapshot, run, plausibility checks, classification
# --------------------------------------------------------------------------------------------

def snapshot(root):
    snap = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for d in dirnames:
            p = os.path.join(dirpath, d)
            snap[os.path.relpath(p, root)] = "<link>" if os.path.islink(p) else "<dir>"
        for f in filenames:
            p = os.path.join(dirpath, f)
            rel = os.path.relpath(p, root)
            try:
                if os.path.islink(p):
                    snap[rel] = "<link:%s>" % os.readlink(p)
                else:
                    h = hashlib.sha256()
                    with open(p, "rb") as fh:
                        for chunk in iter(lambda: fh.read(1 << 20), b""):
                            h.update(chunk)
                    snap[rel] = h.hexdigest()
            except OSError as e:
                snap[rel] = "<unreadable %s>" % e.errno
    return snap


class RunResult:
    def __init__(self, argv, rc, stdout, stderr, seconds, timed_out, signalled=None):
        self.argv, self.rc, self.stdout, self.stderr = argv, rc, stdout, stderr
        self.seconds, self.timed_out, self.signalled = seconds, timed_out, signalled


def limits(mem_mb):
    def f():
        os.setpgid(0, 0)
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if mem_mb:
            b = mem_mb * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (b, b))
        os.nice(10)
    return f


def kill_group(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except OSError:
        pass


def run(argv, cwd, timeout, mem_mb, stdin_data=None):
    t0 = time.monotonic()
    p = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, preexec_fn=limits(mem_mb))
    try:
        out, err = p.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        kill_group(p)
        out, err = p.communicate()
        timed_out = True
    return RunResult(argv, p.returncode, out, err, time.monotonic() - t0, timed_out)


def text(b, n=600):
    s = b.decode("utf-8", "replace") if isinstance(b, bytes) else b
    return s if len(s) <= n else s[:n] + "...[%d chars]" % len(s)


# ---- XTF decoding (just what the plausibility checks need) ----

def xtf_sample_stats(path, max_bytes=64 << 20):
    """Zero / saturated / non-finite fractions of every sonar sample in our own XTF files."""
    with open(path, "rb") as fh:
        data = fh.read(max_bytes)
    if len(data) < 1024:
        return {"error": "shorter than the file header"}
    counts = struct.unpack_from("<HHHBBHB", data, 166)
    total = counts[0] + counts[1] + counts[3] + counts[4] + counts[5] + counts[6]
    header = 1024 + (1024 * ((total - 6 + 7) // 8) if total > 6 else 0)
    chans = []
    for i in range(min(total, 6)):
        base = 256 + 128 * i
        bps = struct.unpack_from("<H", data, base + 6)[0]
        fmt = data[base + 74]
        chans.append((bps, fmt))
    off, pings = header, 0
    n = zeros = sat = nonfinite = 0
    while off + 14 <= len(data):
        magic, htype, _sub, nchan = struct.unpack_from("<HBBH", data, off)
        size = struct.unpack_from("<I", data, off + 10)[0]
        if magic != 0xFACE or size < 14:
            return {"error": "bad packet at offset %d" % off}
        if htype == 0:
            pings += 1
            pos = off + 256
            for _ in range(nchan):
                chno = struct.unpack_from("<H", data, pos)[0]
                ns = struct.unpack_from("<I", data, pos + 42)[0]
                bps, fmt = chans[chno] if chno < len(chans) else (2, 3)
                raw = data[pos + 64: pos + 64 + ns * bps]
                if fmt == 5 or (fmt == 0 and bps == 4 and False):
                    a = array("f")
                    a.frombytes(raw[: len(raw) // 4 * 4])
                    vals = list(a)
                    nonfinite += sum(1 for v in vals if not math.isfinite(v))
                    zeros += sum(1 for v in vals if v == 0)
                    full = None
                elif bps == 1:
                    vals = raw
                    zeros += vals.count(0)
                    sat += vals.count(255)
                elif bps == 2:
                    a = array("H")
                    a.frombytes(raw[: len(raw) // 2 * 2])
                    vals = a
                    zeros += a.count(0)
                    sat += a.count(65535)
                else:
                    a = array("I")
                    a.frombytes(raw[: len(raw) // 4 * 4])
                    vals = a
                    zeros += a.count(0)
                    sat += a.count(0xFFFFFFFF)
                n += len(vals)
                pos += 64 + ns * bps
        off += size
    if n == 0:
        return {"pings": pings, "samples": 0}
    return {"pings": pings, "samples": n, "zero_frac": zeros / n, "saturated_frac": sat / n,
            "nonfinite": nonfinite}


def finite_tree(node, path=""):
    """Paths of non-finite numbers in a parsed JSON tree (json.loads accepts NaN/Infinity)."""
    bad = []
    if isinstance(node, dict):
        for k, v in node.items():
            bad += finite_tree(v, path + "." + str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            bad += finite_tree(v, "%s[%d]" % (path, i))
    elif isinstance(node, float) and not math.isfinite(node):
        bad.append(path)
    return bad


def strict_json(s):
    def reject(c):
        raise ValueError("non-standard JSON constant " + c)
    return json.loads(s, parse_constant=reject)


def flagged_no_seabed(info):
    """True if `info --json` counts pings flagged as having no seabed (altitude 0)."""
    for v in (info.get("pings_without_altitude"),
              (info.get("ping_attitude") or {}).get("pings_without_altitude"),
              (info.get("anomaly_counts") or {}).get("pings_without_altitude")):
        if isinstance(v, int) and v > 0:
            return True
    return False


def check_xtf(h, xtf, cwd, allow_dark=False, want_altitude=None):
    """Problems (strings) with an XTF file that a run reported as written successfully."""
    problems = []
    r = run([h.cli, "info", xtf, "--json"], cwd, h.timeout, h.mem_mb)
    if r.timed_out or r.rc != 0:
        return ["`info --json` on the produced %s failed (rc %s): %s"
                % (os.path.basename(xtf), r.rc, text(r.stderr, 200))]
    try:
        info = strict_json(r.stdout.decode("utf-8", "replace"))
    except ValueError as e:
        return ["`info --json` printed invalid JSON for %s: %s" % (os.path.basename(xtf), e)]
    pings = info.get("pings", 0)
    if not pings:
        problems.append("no pings")
    if info.get("pings_with_valid_navigation", 0) != pings:
        problems.append("pings without valid navigation: %s of %s"
                        % (pings - info.get("pings_with_valid_navigation", 0), pings))
    nav = info.get("navigation") or {}
    for axis, lim in (("x", 180.0), ("y", 90.0)):
        ax = nav.get(axis) or {}
        for k in ("min", "max"):
            v = ax.get(k)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or abs(v) > lim:
                problems.append("navigation %s.%s = %r" % (axis, k, v))
    att = info.get("ping_attitude") or {}
    ranges = [c.get("slant_range_m", {}).get("max") for c in info.get("channels", [])]
    max_range = max([x for x in ranges if isinstance(x, (int, float))] or [float("nan")])
    alt = att.get("altitude_m") or {}
    amin, amax = alt.get("min"), alt.get("max")
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in (amin, amax)):
        problems.append("altitude not finite: %r..%r" % (amin, amax))
    elif (amin < 0 or (amin == 0 and not flagged_no_seabed(info))) or not (amax <= max_range):
        # Altitude 0 is sonarsynth's flag for "no seabed under the sensor"; it is fine only when
        # `info` counts those pings as anomalies (pings_without_altitude).
        problems.append("altitude %g..%g outside (0, range %g]" % (amin, amax, max_range))
    elif want_altitude and ((abs(amin - want_altitude) > max(1.0, 0.25 * want_altitude) and
                             not (amin == 0 and flagged_no_seabed(info))) or
                            abs(amax - want_altitude) > max(1.0, 0.25 * want_altitude)):
        problems.append("altitude %g..%g m, the scene asks for %g m (terrain following)"
                        % (amin, amax, want_altitude))
    dep = att.get("depth_m") or {}
    for k in ("min", "max"):
        v = dep.get(k)
        if not isinstance(v, (int, float)) or not math.isfinite(v) or abs(v) > MAX_DEPTH_M:
            problems.append("depth.%s = %r" % (k, v))
        elif v < -0.5:
            problems.append("depth.%s = %g: the fish is above the sea surface" % (k, v))
    if not (isinstance(max_range, (int, float)) and math.isfinite(max_range) and max_range > 0):
        problems.append("slant range %r" % max_range)
    for c in info.get("channels", []):
        s = c.get("samples", {})
        if not s.get("min") or s.get("max", 0) > 65536:
            problems.append("channel %s samples %r" % (c.get("ChannelNumber"), s))
    bad = finite_tree(info)
    if bad:
        problems.append("non-finite values in info: " + ", ".join(bad[:5]))
    st = xtf_sample_stats(xtf)
    if "error" in st:
        problems.append("cannot decode own XTF: " + st["error"])
    elif st.get("samples", 0) == 0:
        problems.append("no samples")
    else:
        if st["nonfinite"]:
            problems.append("%d non-finite samples" % st["nonfinite"])
        if st["zero_frac"] > 0.999 and not allow_dark:
            problems.append("all samples zero (%.4f)" % st["zero_frac"])
        if st["saturated_frac"] > 0.9:
            problems.append("%.0f%% of samples saturated" % (100 * st["saturated_frac"]))
    return problems


def check_raster(path):
    if not shutil.which("gdalinfo"):
        return [] if os.path.getsize(path) > 0 else ["empty raster"]
    r = subprocess.run(["gdalinfo", "-json", "-stats", path], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, timeout=120)
    if r.returncode != 0:
        return ["gdalinfo cannot read %s: %s" % (os.path.basename(path), text(r.stderr, 200))]
    try:
        info = json.loads(r.stdout.decode("utf-8", "replace"))
    except ValueError:
        return []
    w, hgt = info.get("size", [0, 0])
    if w <= 0 or hgt <= 0:
        return ["raster of size %r" % info.get("size")]
    return []


# --------------------------------------------------------------------------------------------
# Cases
# --------------------------------------------------------------------------------------------

class Case:
    """One adversarial input.

    argv: list of strings; "{CLI}" is replaced by the binary; paths are relative to the case's
    working directory (sandbox/a/b/work).  expect: valid | invalid | either.
    needles: strings of which at least one should appear in a clean error message.
    outputs: paths the command may create (checked for plausibility on success).
    setup(h, work): prepares the sandbox beyond the standard content.
    mutable: relative paths (to the sandbox root) the case may legitimately change.
    """

    def __init__(self, category, desc, argv, expect, needles=(), outputs=(), setup=None,
                 mutable=(), kind="run", extra=None, allow_dark=False):
        self.category, self.desc, self.argv, self.expect = category, desc, argv, expect
        self.needles, self.outputs, self.setup = list(needles), list(outputs), setup
        self.mutable, self.kind, self.extra, self.allow_dark = list(mutable), kind, extra or {}, allow_dark


SIM_FAST = ["--no-mosaic", "--no-waterfall", "--no-truth", "-q", "--threads", "1"]


def sim(*extra, scene="scene.yaml", out="out", fast=True):
    return ["{CLI}", "simulate", scene, "-o", out] + list(extra) + (SIM_FAST if fast else ["-q"])


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


def gen_cli(h, rng):
    cases = []
    C = lambda *a, **k: cases.append(Case("cli", *a, **k))
    # simulate: numeric flags
    for flag in ("--seed", "--range", "--samples", "--threads", "--res"):
        for label, v in BAD_NUMBERS:
            fast = flag != "--res"
            extra = [] if fast else ["--no-waterfall", "--no-truth"]
            C("simulate %s %s" % (flag, label), sim(flag, v, *extra, fast=fast) if fast else
              ["{CLI}", "simulate", "scene.yaml", "-o", "out", flag, v, "-q", "--threads", "1"] + extra,
              flag_expect(flag, v), needles=[flag.lstrip("-"), v, "range", "samples"])
    for flag, vals in (("--quality", ["fast", "default", "high", "bogus", "", "FAST"]),
                       ("--of", ["COG", "GTiff", "PNG", "bogus", ""]),
                       ("--co", ["COMPRESS=DEFLATE", "BOGUS=1", "noequals", "COMPRESS=BOGUS", "="])):
        for v in vals:
            valid = {"fast": "valid", "default": "valid", "high": "either", "COG": "valid",
                     "GTiff": "valid", "COMPRESS=DEFLATE": "valid", "BOGUS=1": "either",
                     "COMPRESS=BOGUS": "either", "FAST": "either"}.get(v, "invalid")
            fast = flag == "--quality"
            argv = (sim(flag, v) if fast else
                    ["{CLI}", "simulate", "scene.yaml", "-o", "out", flag, v, "--no-waterfall",
                     "--no-truth", "-q", "--threads", "1"])
            C("simulate %s %r" % (flag, v), argv, valid, needles=[flag.lstrip("-"), v or "''"])
    # simulate: output targets
    targets = [(".", "cwd (the scene's directory)"), ("..", "the parent"), ("../..", "grandparent"),
               ("/", "the root directory"), ("{ROOT}", "the sandbox root (absolute)"),
               ("{WORK}", "the scene's directory (absolute)"), ("data", "a foreign directory"),
               ("notes.txt", "an existing user file"), ("", "empty path"),
               ("data/", "foreign dir with slash"), (".hidden_dir", "hidden foreign dir"),
               ("scene.yaml", "the scene file itself"), ("out/../out", "dotted path, new")]
    for t, what in targets:
        for ow in (False, True):
            if t == "/" and ow:
                continue  # never hand / --overwrite to a possibly broken build running as root
            extra = ["--overwrite"] if ow else []
            expect = "valid" if t == "out/../out" else "invalid"
            C("simulate -o %s%s" % (what, " --overwrite" if ow else ""),
              sim(*extra, out=t), expect, needles=[t.rstrip("/") or "output", "exist", "refus", "output"],
              outputs=[t] if expect == "valid" else [])
    C("simulate --overwrite onto an earlier sonarsynth output", sim("--overwrite", out="prev"),
      "valid", setup=lambda h, w: h.copy_prev_output(w), mutable=["a/b/work/prev"], outputs=["prev"])
    C("simulate onto an earlier output without --overwrite", sim(out="prev"), "invalid",
      setup=lambda h, w: h.copy_prev_output(w), needles=["prev", "exist"])
    C("simulate with full products (baseline)", ["{CLI}", "simulate", "scene.yaml", "-o", "out",
                                                 "-q", "--threads", "1"], "valid", outputs=["out"])
    C("simulate baseline fast", sim(), "valid", outputs=["out"])
    C("simulate missing scene", sim(scene="nothere.yaml"), "invalid", needles=["nothere.yaml"])
    C("simulate scene is a directory", sim(scene="data"), "invalid", needles=["data"])
    C("simulate no -o", ["{CLI}", "simulate", "scene.yaml"], "invalid", needles=["output", "-o"])
    C("simulate two scenes", ["{CLI}", "simulate", "scene.yaml", "scene.yaml", "-o", "out"],
      "invalid", needles=["scene", "positional", "option"])
    C("simulate unknown flag", sim("--bogus-flag"), "invalid", needles=["bogus-flag"])
    C("unknown command", ["{CLI}", "simulat"], "invalid", needles=["simulat"])
    C("no command", ["{CLI}"], "invalid", needles=["usage"])
    C("simulate scene from /dev/null", sim(scene="/dev/null"), "invalid", needles=["/dev/null"])
    C("simulate scene from /dev/zero (endless)", sim(scene="/dev/zero"), "invalid",
      needles=["/dev/zero"])
    # info
    for label, v in BAD_NUMBERS:
        C("info --max-anomalies %s" % label, ["{CLI}", "info", "in.xtf", "--max-anomalies", v],
          flag_expect("--max-anomalies", v), needles=["max-anomalies", v])
    for inp, what in (("nothere.xtf", "missing"), ("data", "a directory"), ("empty.xtf", "empty"),
                      ("scene.yaml", "a YAML file"), ("/dev/null", "/dev/null"),
                      ("/dev/zero", "/dev/zero")):
        for js in (False, True):
            C("info on %s%s" % (what, " --json" if js else ""),
              ["{CLI}", "info", inp] + (["--json"] if js else []), "invalid",
              needles=[inp, "xtf", "XTF"])
    C("info no input", ["{CLI}", "info"], "invalid", needles=["input", "xtf", "FILE"])
    C("info baseline", ["{CLI}", "info", "in.xtf"], "valid")
    C("info --json baseline", ["{CLI}", "info", "in.xtf", "--json"], "valid")
    # waterfall
    for label, v in BAD_NUMBERS:
        C("waterfall --lo-db %s" % label,
          ["{CLI}", "waterfall", "in.xtf", "-o", "w.png", "--lo-db", v, "--hi-db", "40", "-q"],
          "invalid" if label in ("nan", "inf", "text", "empty", "trailing", "1e9", "1e308",
                                 "2^64+1", "hex") else "either",
          needles=["lo-db", v, "hi-db"], outputs=["w.png"])
    for argv, expect, desc, needles, mut in (
            (["-o", "in.xtf", "--overwrite"], "invalid", "output = input --overwrite", ["in.xtf"], []),
            (["-o", "in.xtf"], "invalid", "output = input", ["in.xtf"], []),
            (["-o", "notes.txt"], "invalid", "output an existing user file", ["notes.txt"], []),
            (["-o", "notes.txt", "--overwrite"], "either", "output a user file --overwrite",
             ["notes.txt"], ["a/b/work/notes.txt"]),
            (["-o", "w.bmp"], "invalid", "unsupported extension", ["w.bmp", "bmp"], []),
            (["-o", "noext"], "invalid", "no extension", ["noext"], []),
            (["-o", "data"], "invalid", "output is a directory", ["data"], []),
            (["-o", "data/"], "invalid", "output is a directory with slash", ["data"], []),
            (["-o", "missing/w.png"], "invalid", "output parent missing", ["missing"], []),
            (["-o", "notes.txt/w.png"], "invalid", "output parent is a file", ["notes.txt"], []),
            (["-o", "w.png", "--lo-db", "10"], "invalid", "--lo-db without --hi-db", ["hi-db", "lo-db"], []),
            (["-o", "w.png", "--lo-db", "40", "--hi-db", "10"], "invalid", "--lo-db > --hi-db",
             ["hi-db", "lo-db"], []),
            (["-o", "w.png", "--lo-db", "10", "--hi-db", "10"], "invalid", "--lo-db = --hi-db",
             ["hi-db", "lo-db"], []),
            (["-o", "w.png"], "valid", "baseline png", [], []),
            (["-o", "w.tif", "--grey", "--slant-correct"], "valid", "baseline tif", [], []),
            (["-o", "/"], "invalid", "output /", ["/"], []),
            (["-o", ""], "invalid", "output empty", ["output"], []),
            (["-o", "x" * 300 + ".png"], "invalid", "output name too long", ["xxxx"], [])):
        out = argv[1]
        C("waterfall " + desc, ["{CLI}", "waterfall", "in.xtf"] + argv + ["-q"], expect,
          needles=needles, outputs=[out] if expect != "invalid" else [], mutable=mut)
    # mosaic
    for label, v in BAD_NUMBERS:
        C("mosaic --res %s" % label, ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--res", v,
                                      "--no-rgb", "-q"],
          flag_expect("--res", v), needles=["res", v], outputs=["m.tif"])
        C("mosaic --taper %s" % label, ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--taper", v,
                                        "--no-rgb", "-q"],
          flag_expect("--taper", v), needles=["taper", v], outputs=["m.tif"])
    for argv, expect, desc, needles in (
            (["in.xtf", "-o", "m.tif", "--rule", "bogus"], "invalid", "--rule bogus", ["rule", "bogus"]),
            (["in.xtf", "-o", "m.tif", "--rule", "max"], "valid", "--rule max", []),
            (["in.xtf", "-o", "m.tif", "--rule", "nearest", "--count"], "valid", "--rule nearest --count", []),
            (["in.xtf", "-o", "m.tif", "--of", "bogus"], "invalid", "--of bogus", ["of", "bogus"]),
            (["in.xtf", "-o", "m.tif", "--co", "noequals"], "invalid", "--co noequals", ["co", "noequals"]),
            (["in.xtf", "-o", "in.xtf", "--overwrite"], "invalid", "-o = input --overwrite", ["in.xtf"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "in.xtf", "--overwrite"], "invalid",
             "--rgb = input --overwrite", ["in.xtf"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "m.tif"], "invalid", "--rgb = -o", ["m.tif", "rgb"]),
            (["in.xtf", "-o", "notes.txt"], "invalid", "-o an existing user file", ["notes.txt"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "nothere.tif"], "invalid",
             "--bathymetry missing", ["nothere.tif"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "notes.txt"], "invalid",
             "--bathymetry a text file", ["notes.txt"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "bathy.tif"], "valid", "--bathymetry baseline", []),
            (["-o", "m.tif"], "invalid", "no inputs", ["input", "xtf", "FILES"]),
            (["in.xtf", "in.xtf", "-o", "m.tif"], "either", "same input twice", ["in.xtf"]),
            (["in.xtf", "scene.yaml", "-o", "m.tif"], "invalid", "a YAML file as input", ["scene.yaml"]),
            (["in.xtf", "empty.xtf", "-o", "m.tif"], "invalid", "an empty file as input", ["empty.xtf"]),
            (["in.xtf", "-o", "data"], "invalid", "-o a directory", ["data"]),
            (["in.xtf", "-o", "m.tif"], "valid", "baseline", []),
            (["in.xtf", "-o", "m.tif", "--depth-positive", "--bathymetry", "bathy.tif"], "invalid",
             "--depth-positive on an elevation grid (seabed above the fish)", ["bathy.tif", "depth"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "m_rgb.bmp"], "invalid", "--rgb unsupported extension",
             ["bmp", "rgb"])):
        outs = [a for i, a in enumerate(argv) if i > 0 and argv[i - 1] == "-o"]
        C("mosaic " + desc, ["{CLI}", "mosaic"] + argv + ["-q"], expect, needles=needles,
          outputs=outs if expect != "invalid" else [])
    # bathy
    base = {"--lat": "43", "--lon": "5", "--size": "60x40", "--cell": "0.5"}

    def bathy_argv(over=None, drop=None, extra=()):
        d = dict(base)
        d.update(over or {})
        argv = ["{CLI}", "bathy", "-o", "g.tif", "-q"] + ([] if "--threads" in extra else ["--threads", "1"])
        for k, v in d.items():
            if k != drop:
                argv += [k, v]
        return argv + list(extra)

    for flag in ("--lat", "--lon", "--cell", "--depth"):
        for label, v in BAD_NUMBERS + [("91", "91"), ("-181", "-181"), ("1e4", "1e4")]:
            C("bathy %s %s" % (flag, label), bathy_argv({flag: v}), flag_expect(flag, v),
              needles=[flag.lstrip("-"), v], outputs=["g.tif"])
    for v, expect in (("0x0", "invalid"), ("-1x5", "invalid"), ("1e9x1e9", "invalid"),
                      ("10x", "invalid"), ("x10", "invalid"), ("10x10x10", "invalid"),
                      ("abc", "invalid"), ("nanxnan", "invalid"), ("infx10", "invalid"),
                      ("0.1x0.1", "either"), ("10X10", "either"), ("1e5x1e5", "invalid"),
                      ("60x40", "valid"), (" 60x40", "either")):
        C("bathy --size %r" % v, bathy_argv({"--size": v}), expect, needles=["size", v],
          outputs=["g.tif"])
    for flag, vals in (("--slope", [("90", "invalid"), ("-1", "either"), ("nan", "invalid"),
                                     ("5,1e308", "either"), ("5,", "invalid"), ("5,,", "invalid"),
                                     ("5", "valid")]),
                       ("--ripples", [("0,1", "invalid"), ("1,0.1,0,1", "invalid"),
                                      ("1,0.1,0,0.5", "valid"), ("1e-9,1", "invalid"),
                                      ("nan,1", "invalid"), ("1", "invalid")]),
                       ("--fbm", [("1,20,1000", "either"), ("1,20,6,2", "either"),
                                  ("-1", "invalid"), ("1,0", "invalid"), ("nan", "invalid"),
                                  ("0.2,10,4,0.5", "valid")]),
                       ("--seamount", [("0,0,5,0", "invalid"), ("0,0,5,-3", "invalid"),
                                       ("0,0,1e9,5", "invalid"), ("0,0,5", "invalid"),
                                       ("0,0,-5,3", "valid"), ("1e308,0,5,3", "either")]),
                       ("--scarp", [("0,0,45,2,0", "invalid"), ("0,0,45", "invalid"),
                                    ("0,0,45,2,3", "valid"), ("0,0,45,1e9", "invalid")]),
                       ("--threads", [("-1", "invalid"), ("0", "valid"), ("99999", "invalid"),
                                      ("abc", "invalid")]),
                       ("--seed", [("-1", "either"), ("abc", "invalid"), ("1e308", "invalid"),
                                   ("7", "valid")]),
                       ("--co", [("COMPRESS=DEFLATE", "valid"), ("bogus", "invalid"),
                                 ("BLOCKXSIZE=7", "either")])):
        for v, expect in vals:
            C("bathy %s %s" % (flag, v), bathy_argv(extra=[flag, v]), expect,
              needles=[flag.lstrip("-"), v], outputs=["g.tif"])
    for drop in ("--lat", "--lon", "--size", "--cell"):
        C("bathy without %s" % drop, bathy_argv(drop=drop), "invalid", needles=[drop.lstrip("-")])
    C("bathy -o over a user file", ["{CLI}", "bathy", "-o", "notes.txt", "--lat", "43", "--lon",
                                    "5", "--size", "10x10", "--cell", "1", "-q"], "invalid",
      needles=["notes.txt"])
    C("bathy -o a directory", ["{CLI}", "bathy", "-o", "data", "--lat", "43", "--lon", "5",
                               "--size", "10x10", "--cell", "1", "-q", "--overwrite"], "invalid",
      needles=["data"])
    C("bathy -o the scene --overwrite", ["{CLI}", "bathy", "-o", "scene.yaml", "--lat", "43",
                                         "--lon", "5", "--size", "10x10", "--cell", "1", "-q",
                                         "--overwrite"], "either", needles=["scene.yaml"],
      mutable=["a/b/work/scene.yaml"])
    return cases


def gen_yaml(h, rng):
    cases = []
    scene0 = base_scene()

    def C(desc, scene_or_text, expect, needles=(), setup_extra=None, timeout_kind=None,
          allow_dark=False):
        body = scene_or_text if isinstance(scene_or_text, (str, bytes)) else scene_text(scene_or_text)

        def setup(h, w, body=body):
            mode = "wb" if isinstance(body, bytes) else "w"
            with open(os.path.join(w, "scene.yaml"), mode) as f:
                f.write(body)
            if setup_extra:
                setup_extra(h, w)
        cases.append(Case("yaml", desc, sim(), expect, needles=needles, outputs=["out"],
                          setup=setup, allow_dark=allow_dark))

    for path, orig in leaves(scene0):
        for label, raw, num in REPLACEMENTS:
            if raw == yaml_scalar(orig):
                continue
            s = copy.deepcopy(scene0)
            set_path(s, path, Raw(raw))
            key = [p for p in path if not isinstance(p, int)][-1]
            C("%s = %s" % (path_str(path), label), s,
              expectation_for_leaf(path, orig, label, raw, num),
              needles=[key, raw[:40]], allow_dark=key in ("calibration_k",))
    # Physically invalid combinations named in the brief
    phys = [
        (("survey", "speed_m_s"), -2.0, "negative speed"),
        (("survey", "altitude_m"), 30, "altitude above the water (depth 20)"),
        (("survey", "altitude_m"), 19.9, "altitude 19.9 m: the fish at the surface, beyond tilt"),
        (("sonar", "range_m"), 4, "range < altitude"),
        (("sonar", "samples"), 8193, "samples 8193 > 8192"),
        (("sonar", "samples"), 100000, "samples 100000"),
        (("output", "gain_db"), 200, "gain_db 200"),
        (("sonar", "ping_period_s"), 0.001, "ping period below the two-way travel time"),
        (("survey", "lines", 0, "waypoints", 1, "east_m"), 500, "line leaves the grid"),
        (("survey", "lines", 0, "waypoints", 0, "east_m"), -500, "line starts off the grid"),
        (("survey", "start_time"), "2026-13-01T10:00:00Z", "month 13"),
        (("survey", "start_time"), "yesterday", "start_time text"),
        (("survey", "start_time"), "1899-01-01T00:00:00Z", "start_time before 1900"),
        (("survey", "start_time"), "99999-01-01T00:00:00Z", "start_time year 99999"),
        (("objects", 0, "end", "east_m"), 900, "pipe end beyond the grid"),
        (("objects", 2, "position", "east_m"), 900, "rock beyond the grid"),
        (("objects", 0, "id"), 2, "duplicate object id? (box gets 2 automatically)"),
        (("sonar", "frequency_khz"), 1e6, "frequency 1 GHz"),
        (("sonar", "sound_speed_m_s"), 1e-3, "sound speed 1 mm/s"),
        (("bathymetry", "generate", "size_m", 0), 1e7, "a 10000 km grid"),
        (("bathymetry", "generate", "cell_m"), 1e-4, "0.1 mm cells (6.4e11 cells)"),
        (("bathymetry", "generate", "centre", "lat_deg"), 89.99999, "grid centre at the pole"),
        (("bathymetry", "generate", "depth_m"), 20000, "20 km deep"),
        (("survey", "lines", 0, "waypoints", 1, "east_m"), -25, "zero-length line"),
        (("materials", 0, "name"), "sand", "redefining sand (allowed: override)"),
        (("seabed", "material"), "unobtanium", "unknown material"),
        (("seabed", "material"), "steel", "object material as seabed"),
        (("objects", 1, "size_m"), [3, 1.5], "box size with two values"),
        (("survey", "lever_arm_m"), [0, 0], "lever arm with two values"),
        (("sonar", "vertical_beam"), {"shape": "table", "off_axis_deg": [-40, 0, 40],
                                      "gain_db": [0, 0]}, "beam table lengths differ"),
        (("sonar", "vertical_beam"), {"shape": "table", "off_axis_deg": [0, -40, 40],
                                      "gain_db": [0, 0, 0]}, "beam table not sorted"),
        (("sonar", "vertical_beam"), {"shape": "sinc", "height_over_wavelength": 0},
         "sinc height 0"),
        (("sonar", "pulse"), {"type": "chirp", "bandwidth_khz": 0}, "chirp bandwidth 0"),
        (("sonar", "pulse"), {"type": "chirp", "bandwidth_khz": 1e6}, "chirp bandwidth 1 GHz"),
        (("survey", "lines", 0, "waypoints"), [{"east_m": 0, "north_m": 0}], "one waypoint"),
        (("survey", "lines", 0, "waypoints"), [], "no waypoints"),
        (("survey", "lines"), [], "no lines"),
        (("survey", "lines", 0, "name"), "../escape", "line name with ../"),
        (("survey", "lines", 0, "name"), "/etc/passwd", "line name absolute path"),
        (("survey", "lines", 0, "name"), "", "empty line name"),
        (("survey", "lines", 0, "name"), "effective", "line name colliding with a product"),
        (("survey", "lines", 0, "name"), "a/b", "line name with a slash"),
    ]
    # A line partly off the grid is a warning with the fraction, its off-grid pings flagged
    # (altitude 0, counted by `info`): accepted either way.
    valid_phys = {"line leaves the grid", "line starts off the grid",
                  "redefining sand (allowed: override)", "altitude 19.9 m: the fish at the surface, beyond tilt",
                  "grid centre at the pole", "line name colliding with a product",
                  "duplicate object id? (box gets 2 automatically)"}
    for path, value, desc in phys:
        s = copy.deepcopy(scene0)
        set_path(s, path, value)
        C("physical: " + desc, s, "either" if desc in valid_phys else "invalid",
          needles=[str(path[-1]), str(value)[:30]])
    # two lines with the same name
    s = copy.deepcopy(scene0)
    s["survey"]["lines"].append(copy.deepcopy(s["survey"]["lines"][0]))
    C("two lines with the same name", s, "invalid", needles=["L1", "name"])
    # deleted keys
    for path, node in list(containers(scene0)):
        if not isinstance(node, dict):
            continue
        for k in node:
            s = copy.deepcopy(scene0)
            del get_path(s, path)[k]
            p = path + (k,)
            required = p in (("bathymetry",), ("survey",), ("survey", "lines"),
                             ("bathymetry", "generate"), ("bathymetry", "generate", "centre"),
                             ("bathymetry", "generate", "size_m"), ("bathymetry", "generate", "cell_m"),
                             ("survey", "lines", 0, "waypoints"), ("sonar", "vertical_beam", "shape"),
                             ("sonar", "pulse", "type")) or k in ("type", "lat_deg", "lon_deg") or (
                k in ("east_m", "north_m") and "components" not in p)
            C("delete %s" % path_str(p), s, "invalid" if required else "either",
              needles=[str(k)])
    # unknown keys at every mapping level
    for path, node in list(containers(scene0)):
        if isinstance(node, dict):
            s = copy.deepcopy(scene0)
            get_path(s, path)["bogus_key"] = 1
            C("unknown key under %s" % (path_str(path) or "top"), s, "invalid",
              needles=["bogus_key"])
            s = copy.deepcopy(scene0)
            get_path(s, path)["derived" if not path else "Speed_M_S"] = 1
            if path:
                C("miscased key under %s" % path_str(path), s, "invalid", needles=["Speed_M_S"])
    base_text = scene_text(scene0)
    # duplicate keys
    for key in ("speed_m_s", "range_m", "samples", "name", "survey", "depth_m"):
        lines = base_text.split("\n")
        for i, line in enumerate(lines):
            if line.strip().startswith(key + ":"):
                lines.insert(i + 1, line.split(":")[0] + ": " + ("0.5" if key != "survey" else "{}"))
                break
        C("duplicate key %s" % key, "\n".join(lines), "invalid", needles=[key, "duplicate"])
    # complex keys, tags, anchors, bombs
    C("complex key ? [a, b] : 1", base_text + "? [a, b]\n: 1\n", "invalid", needles=["a", "key"])
    C("complex mapping key", base_text + "? {x: 1}\n: 2\n", "invalid", needles=["x", "key"])
    C("tagged value !!binary", base_text.replace("seed: 3", "seed: !!binary aGVsbG8="), "invalid",
      needles=["seed"])
    C("custom tag", base_text.replace("speed_m_s: 3.0", "speed_m_s: !foo 3.0"), "either",
      needles=["speed_m_s"])
    C("valid anchors and aliases", base_text.replace(
        "centre:\n", "centre: &c\n").replace("name: \"adv\"", "name: \"adv\"\nx_anchor_use: *c")
      if False else base_text.replace("lever_arm_m: [0, 0, 0]", "lever_arm_m: &z [0, 0, 0]"),
      "valid")
    C("alias to an undefined anchor", base_text.replace("seed: 3", "seed: *nothere"), "invalid",
      needles=["nothere", "alias", "anchor"])
    C("alias cycle-ish (anchor used inside itself)", base_text.replace(
        "seabed:\n  material: \"sand\"", "seabed: &s\n  material: \"sand\"\n  self: *s"), "invalid",
      needles=["self", "s"])

    def bomb(levels, width, where):
        out = ["a0: &a0 [\"lol\"]"]
        for i in range(1, levels):
            out.append("a%d: &a%d [%s]" % (i, i, ", ".join(["*a%d" % (i - 1)] * width)))
        return out
    for levels, width in ((4, 10), (6, 10), (7, 10)):
        b = bomb(levels, width, None)
        top = "x_bomb:\n" + "\n".join("  " + x for x in b) + "\n"
        C("alias bomb %d^%d under an unknown key" % (width, levels - 1), base_text + top,
          "invalid", needles=["x_bomb"])
        C("alias bomb %d^%d as the name" % (width, levels - 1),
          "\n".join("#" + x for x in []) + "defs:\n" + "\n".join("  " + x for x in b) + "\n"
          + base_text.replace("name: \"adv\"", "name: *a%d" % (levels - 1)), "invalid",
          needles=["name", "defs"])
    # lines multiplied through aliases: 10^3 identical lines
    t = base_text.replace("  lines:\n    - name: \"L1\"", "  lines: &l1\n    - name: \"L1\"")
    C("1000 aliased copies of the line list as waypoints", t + "x_more: [" + ", ".join(["*l1"] * 1000)
      + "]\n", "invalid", needles=["x_more"])
    # encodings and bytes
    C("non-UTF-8 byte in a comment", base_text.encode() + b"# caf\xe9\n", "valid")
    C("non-UTF-8 byte in the name", base_text.encode().replace(b'name: "adv"', b"name: adv\xff\xfe"),
      "either", needles=["name"])
    C("non-UTF-8 byte in a line name", base_text.encode().replace(b'name: "L1"', b"name: L\xff1"),
      "either", needles=["name", "L"])
    C("UTF-8 BOM", b"\xef\xbb\xbf" + base_text.encode(), "either")
    C("UTF-16 file", base_text.encode("utf-16"), "either", needles=["scene.yaml"])
    C("NUL byte inside", base_text.encode().replace(b"seed: 3", b"seed: 3\x00"), "invalid",
      needles=["seed", "scene.yaml"])
    C("CRLF line endings", base_text.replace("\n", "\r\n"), "valid")
    C("tab indentation", base_text.replace("  speed_m_s", "\tspeed_m_s"), "invalid",
      needles=["scene.yaml", "line", "tab"])
    C("empty file", "", "invalid", needles=["scene.yaml", "empty", "bathymetry"])
    C("only a comment", "# nothing\n", "invalid", needles=["scene.yaml", "bathymetry"])
    C("a scalar document", "42\n", "invalid", needles=["scene.yaml", "map"])
    C("a list document", "- 1\n- 2\n", "invalid", needles=["scene.yaml", "map"])
    C("two documents", base_text + "---\nname: second\n", "invalid", needles=["document", "scene.yaml"])
    C("truncated in the middle", base_text[: len(base_text) // 2], "invalid", needles=["scene.yaml"])
    C("unterminated quote", base_text.replace('name: "adv"', 'name: "adv'), "invalid",
      needles=["scene.yaml", "line"])
    C("unbalanced flow", base_text.replace("lever_arm_m: [0, 0, 0]", "lever_arm_m: [0, 0, 0"),
      "invalid", needles=["scene.yaml", "line"])
    C("nesting depth 1000", base_text + "x_deep: " + "[" * 1000 + "]" * 1000 + "\n", "invalid",
      needles=["x_deep", "scene.yaml", "depth"])
    C("nesting depth 100000", base_text + "x_deep: " + "[" * 100000 + "]" * 100000 + "\n",
      "invalid", needles=["x_deep", "scene.yaml", "depth"])
    C("nesting depth 100000 maps", base_text + "x_deep: " + "{a: " * 100000 + "1" + "}" * 100000 + "\n",
      "invalid", needles=["x_deep", "scene.yaml", "depth"])
    r2 = random.Random(rng.random())
    for i in range(6):
        C("binary garbage %d" % i, bytes(r2.getrandbits(8) for _ in range(2000)), "invalid",
          needles=["scene.yaml"])
    for i in range(6):
        bt = bytearray(base_text.encode())
        for _ in range(r2.randint(1, 8)):
            bt[r2.randrange(len(bt))] = r2.getrandbits(8)
        C("random byte flips %d" % i, bytes(bt), "either", needles=["scene.yaml"])
    C("10 MB name", base_text.replace('name: "adv"', 'name: "' + "n" * (10 << 20) + '"'), "either",
      needles=["name"])
    C("100000 objects", base_text + "", "valid") if False else None
    many = copy.deepcopy(scene0)
    many["objects"] = [{"type": "rock", "position": {"east_m": (i % 40) - 20, "north_m": (i // 40) % 40 - 20},
                        "diameter_m": 0.3} for i in range(2000)]
    C("2000 rocks", many, "either")
    return cases


# ---- rasters ----

def asc_grid(ncols, nrows, cell, xll, yll, values, nodata=None):
    lines = ["ncols %d" % ncols, "nrows %d" % nrows, "xllcorner %r" % xll, "yllcorner %r" % yll,
             "cellsize %r" % cell]
    if nodata is not None:
        lines.append("NODATA_value %s" % nodata)
    for r in range(nrows):
        lines.append(" ".join(values(r, c) for c in range(ncols)))
    return "\n".join(lines) + "\n"


def gen_raster(h, rng):
    cases = []
    r2 = random.Random(rng.random())

    def C(desc, make, expect, needles=("bathy",), scene_over=None, fname="bathy.tif"):
        def setup(h, w):
            make(h, w)
            s = base_scene(bathy_file=fname)
            if scene_over:
                scene_over(s)
            with open(os.path.join(w, "scene.yaml"), "w") as f:
                f.write(scene_text(s))
        cases.append(Case("raster", desc, sim(), expect, needles=list(needles) + [fname],
                          outputs=["out"], setup=setup))

    def from_base(mutator):
        def make(h, w):
            with open(os.path.join(w, "bathy.tif"), "rb") as f:
                b = bytearray(f.read())
            b = mutator(b)
            with open(os.path.join(w, "bathy.tif"), "wb") as f:
                f.write(b)
        return make

    C("raster baseline (sonarsynth bathy)", lambda h, w: None, "valid")
    size = os.path.getsize(h.base_tif)
    for i in range(10):
        cut = r2.randrange(0, size)
        C("raster truncated at %d of %d" % (cut, size), from_base(lambda b, cut=cut: b[:cut]), "invalid")
    for cut in (0, 8, 16, 200):
        C("raster truncated at %d" % cut, from_base(lambda b, cut=cut: b[:cut]), "invalid")
    for i in range(14):
        flips = [(r2.randrange(0, size), r2.getrandbits(8)) for _ in range(r2.choice([1, 4, 32]))]
        if i < 5:   # header region, where the tags live
            flips = [(r2.randrange(0, min(size, 600)), r2.getrandbits(8)) for _ in range(r2.choice([1, 3]))]

        def mut(b, flips=flips):
            for pos, val in flips:
                b[pos] = val
            return b
        C("raster %d byte flips%s" % (len(flips), " in the header" if i < 5 else ""), mut and from_base(mut),
          "either")
    C("raster file missing", lambda h, w: os.remove(os.path.join(w, "bathy.tif")), "invalid")
    C("raster is a directory", lambda h, w: (os.remove(os.path.join(w, "bathy.tif")),
                                             os.mkdir(os.path.join(w, "bathy.tif"))), "invalid")
    C("raster is a text file", lambda h, w: open(os.path.join(w, "bathy.tif"), "w").write("hello\n"),
      "invalid")
    C("raster band 2 of a 1-band file", lambda h, w: None, "invalid",
      scene_over=lambda s: s["bathymetry"].__setitem__("band", 2), needles=["band"])
    C("raster depth_positive_down on elevations (seabed above the fish)", lambda h, w: None,
      "invalid", scene_over=lambda s: s["bathymetry"].__setitem__("depth_positive_down", True),
      needles=["depth", "altitude"])
    C("raster path absolute /dev/zero", lambda h, w: None, "invalid", fname="/dev/zero")
    C("raster path is the scene itself", lambda h, w: None, "invalid", fname="scene.yaml")
    # ASCII grids written here (full control over values, size and CRS); .prj = CRS
    utm31 = ('PROJCS["WGS 84 / UTM zone 31N",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",'
             '6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],'
             'PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],'
             'PARAMETER["central_meridian",3],PARAMETER["scale_factor",0.9996],'
             'PARAMETER["false_easting",500000],PARAMETER["false_northing",0],UNIT["metre",1]]')
    x0, y0 = h.base_origin

    def asc(desc, ncols, nrows, cell, values, expect, prj=True, nodata=None, xll=None, yll=None,
            tif=False, needles=("bathy",)):
        # GDAL's ASCII grid reader refuses "inf"/"nan" tokens; for the GeoTIFF variant they are
        # written as sentinels, converted uncompressed, and the sentinel float32 bytes patched.
        sentinels = {"inf": (12345.0, float("inf")), "nan": (12346.0, float("nan")),
                     "-inf": (12347.0, float("-inf"))}

        def make(h, w):
            os.remove(os.path.join(w, "bathy.tif"))
            name = os.path.join(w, "grid.asc")
            vals = values
            if tif:
                vals = lambda r, c: (lambda v: "%g" % sentinels[v][0] if v in sentinels else v)(values(r, c))
            with open(name, "w") as f:
                f.write(asc_grid(ncols, nrows, cell, x0 if xll is None else xll,
                                 (y0 - nrows * cell) if yll is None else yll, vals, nodata))
            if prj:
                with open(os.path.join(w, "grid.prj"), "w") as f:
                    f.write(utm31)
            if tif and shutil.which("gdal_translate"):
                g = subprocess.run(["gdal_translate", "-q", "-ot", "Float32", "-co", "COMPRESS=NONE",
                                    name, os.path.join(w, "grid.tif")], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE)
                if g.returncode != 0:  # the case cannot be built: unclassified, never "ok"
                    raise RuntimeError("gdal_translate failed: " + text(g.stderr, 200))
                with open(os.path.join(w, "grid.tif"), "rb") as f:
                    blob = f.read()
                for sentinel, value in sentinels.values():
                    blob = blob.replace(struct.pack("<f", sentinel), struct.pack("<f", value))
                with open(os.path.join(w, "grid.tif"), "wb") as f:
                    f.write(blob)
                for ext in ("asc", "prj"):
                    p = os.path.join(w, "grid." + ext)
                    if os.path.exists(p):
                        os.remove(p)
        fname = "grid.tif" if tif and shutil.which("gdal_translate") else "grid.asc"
        C("raster " + desc + (" (GeoTIFF)" if tif else " (ASCII grid)"), make, expect,
          needles=needles, fname=fname)

    flat = lambda r, c: "-20"
    for tif in (False, True):
        asc("flat 160x160 baseline", 160, 160, 0.5, flat, "valid", tif=tif)
        asc("value inf everywhere", 160, 160, 0.5, lambda r, c: "inf", "invalid", tif=tif)
        asc("value nan everywhere", 160, 160, 0.5, lambda r, c: "nan", "invalid", tif=tif)
        asc("value 1e38 everywhere", 160, 160, 0.5, lambda r, c: "1e38", "invalid", tif=tif)
        asc("value -1e38 everywhere", 160, 160, 0.5, lambda r, c: "-1e38", "invalid", tif=tif)
        asc("one nan cell under the line", 160, 160, 0.5,
            lambda r, c: "nan" if (r, c) == (80, 80) else "-20", "either", tif=tif)
        asc("one 1e38 spike under the line", 160, 160, 0.5,
            lambda r, c: "1e38" if (r, c) == (80, 80) else "-20", "either", tif=tif)
        asc("all nodata", 160, 160, 0.5, lambda r, c: "-9999", "invalid", nodata="-9999", tif=tif)
        asc("seabed above the sea surface (+20)", 160, 160, 0.5, lambda r, c: "20", "invalid", tif=tif)
        asc("1x1 grid", 1, 1, 80.0, flat, "either", tif=tif)
        asc("2x2 grid", 2, 2, 40.0, flat, "either", tif=tif)
        asc("1 um cells (line off the grid)", 160, 160, 1e-6, flat, "invalid", tif=tif)
        asc("no CRS", 160, 160, 0.5, flat, "invalid", prj=False, tif=tif, needles=("CRS", "bathy", "grid"))
        asc("another place in the zone (lines are relative to the grid centre)", 160, 160, 0.5, flat,
            "valid", xll=300000.0, yll=4000000.0, tif=tif)
    asc("wrong row count (short file)", 160, 159, 0.5, flat, "invalid")
    asc("text values", 160, 160, 0.5, lambda r, c: "abc" if c == 3 else "-20", "invalid")
    asc("cellsize 0", 160, 160, 0.0, flat, "invalid")
    asc("cellsize -0.5", 160, 160, -0.5, flat, "invalid")
    asc("cellsize nan", 160, 160, float("nan"), flat, "invalid")
    return cases


# ---- XTF mutants ----

def gen_xtf(h, rng):
    cases = []
    r2 = random.Random(rng.random())
    data = h.base_xtf_bytes
    size = len(data)
    # packet offsets of the base file
    offs, off = [], 1024
    while off + 14 <= size:
        offs.append(off)
        off += struct.unpack_from("<I", data, off + 10)[0]
    sonar = [o for o in offs if data[o + 2] == 0]

    def put(b, pos, fmt, val):
        struct.pack_into(fmt, b, pos, val)
        return b

    mutants = []  # (desc, function(bytearray) -> bytearray)
    for cut in sorted(set([0, 1, 13, 255, 256, 1023, 1024, 1024 + 13, 1024 + 255,
                           sonar[1] + 3, size - 1] + [r2.randrange(0, size) for _ in range(8)])):
        mutants.append(("truncated at %d of %d" % (cut, size), lambda b, cut=cut: b[:cut]))
    for i in range(16):
        n = r2.choice([1, 2, 8, 64, 512])
        lo = 0 if i < 4 else 1024
        flips = [(r2.randrange(lo, size if i >= 4 else 1024), r2.getrandbits(8)) for _ in range(n)]

        def mut(b, flips=flips):
            for pos, val in flips:
                b[pos] = val
            return b
        mutants.append(("%d random byte flips%s" % (n, " in the file header" if i < 4 else ""), mut))
    p = sonar[len(sonar) // 2]
    fh_fields = [("NumberOfSonarChannels", 166, "<H", [0, 7, 255, 65535]),
                 ("NumberOfBathymetryChannels", 168, "<H", [65535]),
                 ("NavUnits", 164, "<H", [0, 7, 65535]),
                 ("chan0.BytesPerSample", 256 + 6, "<H", [0, 1, 3, 8, 65535]),
                 ("chan0.SampleFormat", 256 + 74, "<B", [1, 2, 5, 8, 99]),
                 ("chan0.TypeOfChannel", 256, "<B", [3, 200]),
                 ("FileFormat", 0, "<B", [0, 255])]
    for name, pos, fmt, vals in fh_fields:
        for v in vals:
            mutants.append(("file header %s = %d" % (name, v), lambda b, pos=pos, fmt=fmt, v=v: put(b, pos, fmt, v)))
    pk_fields = [("NumChansToFollow", 4, "<H", [0, 1, 3, 255, 65535]),
                 ("NumBytesThisRecord", 10, "<I", [0, 13, 14, 64, 255, 0x7FFFFFFF, 0xFFFFFFFF]),
                 ("MagicNumber", 0, "<H", [0, 0xCEFA]),
                 ("HeaderType", 2, "<B", [1, 3, 42, 255]),
                 ("ping.Year", 14, "<H", [0, 65535]), ("ping.Month", 16, "<B", [0, 13, 255]),
                 ("ping.Hour", 18, "<B", [25]),
                 ("ping.SoundVelocity", 30, "<f", [0.0, -1.0, float("nan"), float("inf"), 1e30]),
                 ("ping.SensorXcoordinate", 128, "<d", [float("nan"), 1e300, -999.0]),
                 ("ping.SensorYcoordinate", 120, "<d", [float("nan"), 91.0]),
                 ("ping.SensorDepth", 164, "<f", [float("nan"), -1e9, 1e9]),
                 ("ping.SensorPrimaryAltitude", 168, "<f", [float("nan"), 0.0, -5.0, 1e9]),
                 ("ping.SensorHeading", 184, "<f", [float("nan"), 1e9]),
                 ("chan.SlantRange", 256 + 4, "<f", [0.0, -1.0, float("nan"), float("inf"), 1e30]),
                 ("chan.NumSamples", 256 + 42, "<I", [0, 1, 129, 8193, 65535, 0x7FFFFFFF, 0xFFFFFFFF]),
                 ("chan.ChannelNumber", 256, "<H", [1, 2, 5, 65535])]
    for name, pos, fmt, vals in pk_fields:
        for v in vals:
            for where, pk in (("middle ping", p), ("first ping", sonar[0])):
                if where == "first ping" and not name.startswith(("Num", "chan.Num")):
                    continue
                mutants.append(("%s %s = %r" % (where, name, v),
                                lambda b, pos=pos + pk, fmt=fmt, v=v: put(b, pos, fmt, v)))
    # every ping's NumSamples raised (reads beyond records)
    def all_ns(b, v=200):
        for o in sonar:
            struct.pack_into("<I", b, o + 256 + 42, v)
        return b
    mutants.append(("every ping chan0 NumSamples = 200 (> record)", all_ns))
    mutants.append(("garbage appended (1 MB random)", lambda b: b + bytes(r2.getrandbits(8) for _ in range(4096)) * 256))
    mutants.append(("file header only", lambda b: b[:1024]))
    mutants.append(("packets duplicated (time goes back)", lambda b: b + b[1024:]))
    mutants.append(("all zeros of the same size", lambda b: bytearray(len(b))))
    mutants.append(("a ping packet spliced into the file header", lambda b: b[p:p + 512] + b[512:]))

    commands = [("info", ["{CLI}", "info", "in.xtf"], []),
                ("info --json", ["{CLI}", "info", "in.xtf", "--json"], []),
                ("waterfall", ["{CLI}", "waterfall", "in.xtf", "-o", "w.png", "-q"], ["w.png"]),
                ("mosaic", ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--no-rgb", "-q"], ["m.tif"])]
    for desc, mut in mutants:
        body = bytes(mut(bytearray(data)))

        def setup(h, w, body=body):
            with open(os.path.join(w, "in.xtf"), "wb") as f:
                f.write(body)
        for cname, argv, outs in commands:
            cases.append(Case("xtf", "%s: %s" % (cname, desc), argv, "either",
                              needles=["in.xtf", "xtf", "XTF"], outputs=outs, setup=setup,
                              kind="xtf"))
    return cases


# ---- interrupts and filesystem ----

def gen_interrupt(h, rng):
    cases = []
    r2 = random.Random(rng.random())
    for i in range(24):
        sig = [signal.SIGINT, signal.SIGTERM, signal.SIGKILL][i % 3]
        delay = round(r2.uniform(0.05, 12.0), 2)  # the slow scene takes ~5-10 s
        full = i % 2 == 0
        cases.append(Case("interrupt", "%s after %.2f s%s" % (sig.name, delay, " (full products)" if full else ""),
                          ["{CLI}", "simulate", "slow.yaml", "-o", "out", "-q", "--threads", "1"]
                          + ([] if full else ["--no-mosaic", "--no-truth"]),
                          "either", kind="interrupt", extra={"signal": int(sig), "delay": delay},
                          setup=lambda h, w: h.write_slow(w), outputs=["out"]))
    return cases


def gen_fs(h, rng):
    cases = []
    C = lambda *a, **k: cases.append(Case("fs", *a, **k))
    root_can_write = h.root_ignores_chmod
    if not root_can_write:
        def ro(h, w):
            os.mkdir(os.path.join(w, "ro"))
            os.chmod(os.path.join(w, "ro"), 0o555)
        C("simulate into a read-only parent", sim(out="ro/out"), "invalid", setup=ro, needles=["ro"])
        C("waterfall into a read-only parent", ["{CLI}", "waterfall", "in.xtf", "-o", "ro/w.png", "-q"],
          "invalid", setup=ro, needles=["ro"])
        C("bathy into a read-only parent", ["{CLI}", "bathy", "-o", "ro/g.tif", "--lat", "43", "--lon",
                                            "5", "--size", "10x10", "--cell", "1", "-q"], "invalid",
          setup=ro, needles=["ro"])
    C("simulate: output parent missing", sim(out="missing/deeper/out"), "either",
      needles=["missing"], outputs=["missing/deeper/out"])
    C("simulate: output parent is a file", sim(out="notes.txt/out"), "invalid", needles=["notes.txt"])
    C("simulate: output name 300 chars", sim(out="o" * 300), "invalid", needles=["ooo"])
    C("simulate: output path with a newline", sim(out="a\nb"), "either", needles=["a"],
      outputs=["a\nb"])
    C("simulate: output through a symlink to a foreign dir", sim("--overwrite", out="link"),
      "invalid", setup=lambda h, w: os.symlink("data", os.path.join(w, "link")), needles=["link"])
    C("simulate: output a dangling symlink", sim(out="dangling"), "invalid",
      setup=lambda h, w: os.symlink("nowhere", os.path.join(w, "dangling")), needles=["dangling"])
    C("simulate: scene through a symlink", sim(scene="sl.yaml"), "valid",
      setup=lambda h, w: os.symlink("scene.yaml", os.path.join(w, "sl.yaml")), outputs=["out"])
    C("simulate: a stale temporary of a dead process exists", sim(), "valid",
      setup=lambda h, w: h.fake_stale(w), outputs=["out"], mutable=["a/b/work/.out.part-999999"])
    C("simulate: foreign dir with a fake marker --overwrite", sim("--overwrite", out="data"),
      "invalid", setup=lambda h, w: open(os.path.join(w, "data", ".sonarsynth-output"), "w").write("x"),
      needles=["data"])
    C("waterfall: output parent missing", ["{CLI}", "waterfall", "in.xtf", "-o", "nodir/w.png", "-q"],
      "invalid", needles=["nodir"])
    C("info: unreadable input (chmod 000)" if not root_can_write else "info: input is a FIFO-less special file /dev/null",
      ["{CLI}", "info", "in.xtf" if not root_can_write else "/dev/null"], "invalid" if root_can_write else "invalid",
      setup=(lambda h, w: os.chmod(os.path.join(w, "in.xtf"), 0)) if not root_can_write else None,
      needles=["in.xtf", "/dev/null"])
    return cases


GENERATORS = {"cli": gen_cli, "yaml": gen_yaml, "raster": gen_raster, "xtf": gen_xtf,
              "interrupt": gen_interrupt, "fs": gen_fs}

SLOW_SCENE = """name: slow
seed: 3
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [300, 120], cell_m: 0.5, depth_m: 20}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 1.0
  altitude_m: 8
  lines:
    - {name: L1, waypoints: [{east_m: -120, north_m: 0}, {east_m: 120, north_m: 0}]}
    - {name: L2, waypoints: [{east_m: 120, north_m: 10}, {east_m: -120, north_m: 10}]}
sonar: {frequency_khz: 600, range_m: 40, samples: 1024}
"""


# --------------------------------------------------------------------------------------------
# The harness
# --------------------------------------------------------------------------------------------

class Harness:
    def __init__(self, args):
        self.cli = os.path.abspath(args.cli)
        self.timeout = args.timeout
        self.seed = args.seed
        self.verbose = args.verbose
        self.root = tempfile.mkdtemp(prefix="sonarsynth-adv-", dir=args.tmp)
        self.cache = os.path.join(self.root, "cache")
        os.mkdir(self.cache)
        with open(self.cli, "rb") as f:
            blob = f.read()
        asan = b"__asan_init" in blob
        self.cli_sha256 = hashlib.sha256(blob).hexdigest()
        self.mem_mb = 0 if asan else args.mem_mb
        self.root_ignores_chmod = self._probe_chmod()

    def _probe_chmod(self):
        d = os.path.join(self.cache, "ro-probe")
        os.mkdir(d)
        os.chmod(d, 0o555)
        try:
            open(os.path.join(d, "x"), "w").close()
            ok = True
        except OSError:
            ok = False
        os.chmod(d, 0o755)
        shutil.rmtree(d)
        return ok

    def prepare(self):
        """The base products every case starts from: a scene, its XTF, a bathymetry GeoTIFF."""
        with open(os.path.join(self.cache, "scene.yaml"), "w") as f:
            f.write(scene_text(base_scene()))
        r = run([self.cli, "simulate", "scene.yaml", "-o", "prev", "-q", "--threads", "1"],
                self.cache, 300, self.mem_mb)
        if r.rc != 0:
            sys.exit("base scene failed (rc %s): %s" % (r.rc, text(r.stderr)))
        self.base_xtf = os.path.join(self.cache, "prev", "L1.xtf")
        with open(self.base_xtf, "rb") as f:
            self.base_xtf_bytes = f.read()
        problems = check_xtf(self, self.base_xtf, self.cache)
        if problems:
            print("warning: the base XTF itself looks implausible: %s" % problems, file=sys.stderr)
        self.base_tif = os.path.join(self.cache, "bathy.tif")
        r = run([self.cli, "bathy", "-o", self.base_tif, "--lat", "43", "--lon", "5", "--size",
                 "80x80", "--cell", "0.5", "--slope", "1,100", "-q", "--threads", "1"],
                self.cache, 300, self.mem_mb)
        if r.rc != 0:
            sys.exit("base bathy failed (rc %s): %s" % (r.rc, text(r.stderr)))
        self.base_origin = (662979.070081245, 4762795.641689336)
        if shutil.which("gdalinfo"):
            g = subprocess.run(["gdalinfo", "-json", self.base_tif], stdout=subprocess.PIPE)
            try:
                gt = json.loads(g.stdout)["geoTransform"]
                self.base_origin = (gt[0], gt[3])
            except (ValueError, KeyError):
                pass

    # sandbox helpers used by case setups
    def copy_prev_output(self, work):
        shutil.copytree(os.path.join(self.cache, "prev"), os.path.join(work, "prev"), symlinks=True)

    def write_slow(self, work):
        with open(os.path.join(work, "slow.yaml"), "w") as f:
            f.write(SLOW_SCENE)

    def fake_stale(self, work):
        os.mkdir(os.path.join(work, ".out.part-999999"))
        with open(os.path.join(work, ".out.part-999999", ".sonarsynth-output"), "w") as f:
            f.write("stale")

    def make_sandbox(self, idx):
        box = os.path.join(self.root, "cases", "c%05d" % idx)
        work = os.path.join(box, "a", "b", "work")
        os.makedirs(work)
        with open(os.path.join(box, "top-level-user-file.txt"), "w") as f:
            f.write("user data next to the sandbox root\n")
        with open(os.path.join(work, "scene.yaml"), "w") as f:
            f.write(scene_text(base_scene()))
        with open(os.path.join(work, "notes.txt"), "w") as f:
            f.write("precious notes\n")
        with open(os.path.join(work, ".hidden"), "w") as f:
            f.write("hidden precious\n")
        os.makedirs(os.path.join(work, "data", "sub"))
        with open(os.path.join(work, "data", "sub", "data.bin"), "wb") as f:
            f.write(bytes(range(256)) * 4)
        os.makedirs(os.path.join(work, ".hidden_dir"))
        with open(os.path.join(work, ".hidden_dir", "h.txt"), "w") as f:
            f.write("hidden dir content\n")
        shutil.copy(self.base_xtf, os.path.join(work, "in.xtf"))
        shutil.copy(self.base_tif, os.path.join(work, "bathy.tif"))
        open(os.path.join(work, "empty.xtf"), "w").close()
        return box, work

    # ---- one case ----
    def run_case(self, idx, case):
        box, work = self.make_sandbox(idx)
        if case.setup:
            case.setup(self, work)
        before = snapshot(box)
        argv = [a.replace("{CLI}", self.cli).replace("{ROOT}", box).replace("{WORK}", work)
                for a in case.argv]
        issues = []   # (class, reason)
        rec = {"id": idx, "category": case.category, "description": case.desc,
               "command": " ".join(shlex_quote(a) for a in argv), "expect": case.expect}
        if case.kind == "interrupt":
            r, post = self.run_interrupt(case, argv, work, box, before, issues)
        else:
            r = run(argv, work, self.timeout, self.mem_mb)
            post = None
        rec.update({"exit": r.rc, "seconds": round(r.seconds, 3), "timed_out": r.timed_out,
                    "stderr_head": text(r.stderr, 400)})
        after = snapshot(box)
        litter = self.check_files(case, box, work, before, after, r, issues,
                                  interrupted=case.kind == "interrupt")
        if case.kind != "interrupt":
            self.classify_exit(case, r, work, issues, rec)
        elif post:
            issues.extend(post)
        cls = None
        for sev in SEVERITY:
            if any(c == sev for c, _ in issues):
                cls = sev
                break
        if cls is None:  # only litter, or nothing at all: never silently "ok"
            issues.append(("unclassified", "no rule decided this case"))
            cls = "unclassified"
        rec["class"] = cls
        rec["reasons"] = [reason for c, reason in issues if c == cls] + \
                         [("(%s) " % c) + reason for c, reason in issues if c != cls]
        rec["litter"] = litter
        rec["generic_message"] = any(c == "clean_error" and "generic" in reason for c, reason in issues)
        return rec, box

    def classify_exit(self, case, r, work, issues, rec):
        err = r.stderr.decode("utf-8", "replace")
        san = [m for m in SANITIZER_MARKERS if m in err]
        if r.timed_out:
            issues.append(("hang", "no exit after %s s" % self.timeout))
            return
        if san:
            issues.append(("crash", "sanitizer/abort output: %s" % ", ".join(san)))
        if r.rc < 0:
            issues.append(("crash", "killed by signal %s" % signal.Signals(-r.rc).name))
            return
        if r.rc == 3:
            issues.append(("crash", "exit 3 (internal error)"))
            return
        if r.rc not in (0, 1, 2):
            issues.append(("crash", "unexpected exit code %d" % r.rc))
            return
        if r.rc in (1, 2):
            if case.expect == "valid":
                issues.append(("unclassified", "a valid input was rejected (exit %d)" % r.rc))
                return
            if not err.strip():
                issues.append(("clean_error", "generic: empty stderr"))
                return
            low = err.lower().replace("-", "_")
            hit = [n for n in needle_variants(case.needles) if n.lower().replace("-", "_") in low]
            if hit:
                issues.append(("clean_error", "names %r" % hit[0]))
            else:
                issues.append(("clean_error", "generic: names none of %r" % case.needles[:4]))
            return
        # exit 0
        if case.expect == "invalid":
            issues.append(("silent_wrong", "exit 0 for an input known to be invalid"))
        problems = self.check_outputs(case, argv_outputs(case), work)
        for p in problems:
            issues.append(("silent_wrong", p))
        if case.expect != "invalid" and not problems:
            issues.append(("ok", "exit 0, output plausible"))
        if case.argv[1:2] == ["info"] and "--json" in case.argv:
            try:
                strict_json(r.stdout.decode("utf-8", "replace"))
            except ValueError as e:
                issues.append(("silent_wrong", "info --json printed invalid JSON: %s" % e))

    def check_outputs(self, case, outputs, work):
        problems = []
        for out in outputs:
            p = os.path.join(work, out)
            if case.argv[1] == "simulate":
                if not os.path.isdir(p):
                    problems.append("exit 0 but output directory %r missing" % out)
                    continue
                names = os.listdir(p)
                if "effective.yaml" not in names:
                    problems.append("effective.yaml missing in %s" % out)
                xtfs = [n for n in names if n.endswith(".xtf")]
                if not xtfs:
                    problems.append("no .xtf in %s" % out)
                want = self.expected_lines(case, work)
                for line in want:
                    if line + ".xtf" not in names:
                        problems.append("line %r has no .xtf" % line)
                want_alt = self.requested_altitude(work, case)
                for x in xtfs[:3]:
                    problems += check_xtf(self, os.path.join(p, x), work, case.allow_dark, want_alt)
                if "--no-mosaic" not in case.argv and "mosaic.tif" in names:
                    problems += check_raster(os.path.join(p, "mosaic.tif"))
            elif case.argv[1] in ("waterfall", "mosaic", "bathy"):
                if not os.path.isfile(p):
                    problems.append("exit 0 but %r missing" % out)
                elif os.path.getsize(p) == 0:
                    problems.append("%r is empty" % out)
                elif out.endswith((".tif", ".png")):
                    problems += check_raster(p)
        return problems

    def requested_altitude(self, work, case):
        """survey.altitude_m of the scene when the run follows the terrain, else None."""
        scene = case.argv[2] if len(case.argv) > 2 else "scene.yaml"
        try:
            with open(os.path.join(work, scene), encoding="utf-8") as f:
                t = f.read()
        except (OSError, UnicodeDecodeError):
            return None
        m = re.findall(r"^  altitude_m: ([-+0-9.eE]+)\s*$", t, re.M)
        if len(m) != 1 or re.search(r"^  depth_m:", t, re.M):
            return None
        try:
            v = float(m[0])
        except ValueError:
            return None
        return v if math.isfinite(v) and v > 0 else None

    def expected_lines(self, case, work):
        try:
            with open(os.path.join(work, "scene.yaml"), encoding="utf-8") as f:
                t = f.read()
        except (OSError, UnicodeDecodeError):
            return []
        # survey lines are the only "- name:" items at four spaces (materials are at two)
        return re.findall(r'^    - name: "([A-Za-z0-9_]+)"\s*$', t, re.M)[:5]

    def check_files(self, case, box, work, before, after, r, issues, interrupted=False):
        """Pre-existing files changed or lost, visible leftovers of failed runs, temporaries."""
        mutable = case.mutable
        for rel, digest in before.items():
            if any(rel == m or rel.startswith(m + "/") for m in mutable):
                continue
            if rel not in after:
                issues.append(("data_lost", "user file removed: %s" % rel))
            elif after[rel] != digest:
                issues.append(("data_lost", "user file changed: %s" % rel))
        new = [rel for rel in after if rel not in before]
        litter = sorted(rel for rel in new if TEMP_RE.match(os.path.basename(rel)))
        ended_by_itself = not r.timed_out and not (interrupted and case.extra.get("signal") == signal.SIGKILL)
        if litter and ended_by_itself:
            issues.append(("litter", "temporaries left: %s" % ", ".join(litter[:4])))
        visible_top = sorted(set(rel.split("/")[0] if not rel.startswith("a/b/work/") else
                                 "a/b/work/" + rel[len("a/b/work/"):].split("/")[0] for rel in new))
        visible_top = [v for v in visible_top if not TEMP_RE.match(os.path.basename(v))]
        if ended_by_itself and r.rc not in (0, None) and not interrupted and visible_top:
            issues.append(("data_lost", "failed run (exit %s) left visible output: %s"
                           % (r.rc, ", ".join(visible_top[:4]))))
        return litter if ended_by_itself else []

    def run_interrupt(self, case, argv, work, box, before, issues):
        sig, delay = case.extra["signal"], case.extra["delay"]
        t0 = time.monotonic()
        p = subprocess.Popen(argv, cwd=work, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, preexec_fn=limits(self.mem_mb))
        try:
            out, err = p.communicate(timeout=delay)
            finished_first = True
        except subprocess.TimeoutExpired:
            finished_first = False
            os.kill(p.pid, sig)
            try:
                out, err = p.communicate(timeout=self.timeout)
            except subprocess.TimeoutExpired:
                kill_group(p)
                out, err = p.communicate()
                r = RunResult(argv, p.returncode, out, err, time.monotonic() - t0, True)
                issues.append(("hang", "no exit %s s after %s" % (self.timeout, signal.Signals(sig).name)))
                return r, []
        r = RunResult(argv, p.returncode, out, err, time.monotonic() - t0, False)
        post = []
        e = err.decode("utf-8", "replace")
        if any(m in e for m in SANITIZER_MARKERS) or r.rc == 3:
            post.append(("crash", "exit %s after %s: %s" % (r.rc, signal.Signals(sig).name, text(e, 200))))
        elif r.rc < 0 and -r.rc != sig:
            post.append(("crash", "died of %s after %s" % (signal.Signals(-r.rc).name, signal.Signals(sig).name)))
        elif r.rc not in (0, 128 + sig, -sig, 1):
            post.append(("crash", "exit %s after %s" % (r.rc, signal.Signals(sig).name)))
        outdir = os.path.join(work, "out")
        if os.path.exists(outdir):
            names = os.listdir(outdir)
            missing = [n for n in ("effective.yaml", "L1.xtf", "L2.xtf") if n not in names]
            if missing:
                post.append(("data_lost", "interrupted run left an incomplete visible %s (missing %s)"
                             % ("out", ", ".join(missing))))
            elif r.rc != 0:
                post.append(("ok", "completed before the signal took effect (exit %s)" % r.rc))
        if r.rc == 0:
            post += [("silent_wrong", p_) for p_ in self.check_outputs(case, ["out"], work)]
        if sig == signal.SIGKILL:
            # the next run to the same -o must succeed and clean up
            rerun = [self.cli, "simulate", "scene.yaml", "-o", "out", "--overwrite"] + SIM_FAST
            r2 = run(rerun, work, self.timeout, self.mem_mb)
            if r2.timed_out:
                post.append(("hang", "rerun after SIGKILL did not finish"))
            elif r2.rc != 0:
                post.append(("crash" if r2.rc == 3 or r2.rc < 0 else "unclassified",
                             "rerun after SIGKILL failed (exit %s): %s" % (r2.rc, text(r2.stderr, 200))))
            else:
                left = [n for n in os.listdir(work) if TEMP_RE.match(n)]
                if left:
                    post.append(("litter", "rerun after SIGKILL left temporaries: %s" % left[:3]))
                post += [("silent_wrong", "rerun: " + p_) for p_ in
                         self.check_outputs(Case("interrupt", "", sim(), "valid"), ["out"], work)]
        if not any(c in ("crash", "hang", "data_lost", "silent_wrong", "unclassified") for c, _ in post):
            post.append(("ok", "%s %s: exit %s, output absent or complete"
                         % ("finished before" if finished_first else "interrupted by",
                            signal.Signals(sig).name, r.rc)))
        return r, post


def needle_variants(needles):
    """The needles plus other spellings of numbers (1e308 -> 1e+308)."""
    out = []
    for n in needles:
        if not n:
            continue
        out.append(n)
        try:
            x = float(n)
            out += ["%g" % x, repr(x)]
        except ValueError:
            pass
    return out


def argv_outputs(case):
    return case.outputs


def shlex_quote(s):
    import shlex
    s = s if len(s) < 200 else s[:60] + "...(%d chars)" % len(s)
    return shlex.quote(s)


def select(cases_by_cat, n, rng):
    """A deterministic sample of n cases, spread over the categories by CATEGORY_WEIGHT."""
    total = sum(len(v) for v in cases_by_cat.values())
    if n >= total:
        return [c for cat in CATEGORIES for c in cases_by_cat[cat]]
    quota = {cat: int(round(n * CATEGORY_WEIGHT[cat])) for cat in CATEGORIES}
    spare = 0
    for cat in CATEGORIES:
        if quota[cat] > len(cases_by_cat[cat]):
            spare += quota[cat] - len(cases_by_cat[cat])
            quota[cat] = len(cases_by_cat[cat])
    while spare > 0:
        grew = False
        for cat in CATEGORIES:
            if spare and quota[cat] < len(cases_by_cat[cat]):
                quota[cat] += 1
                spare -= 1
                grew = True
        if not grew:
            break
    chosen = []
    for cat in CATEGORIES:
        pool = cases_by_cat[cat]
        idx = sorted(rng.sample(range(len(pool)), quota[cat]))
        chosen += [pool[i] for i in idx]
    return chosen


def summary_table(records):
    cols = CLASSES + ["generic_msg", "litter"]
    rows = []
    for cat in CATEGORIES + ["all"]:
        rs = [r for r in records if cat == "all" or r["category"] == cat]
        if not rs:
            continue
        row = {c: sum(1 for r in rs if r["class"] == c) for c in CLASSES}
        row["generic_msg"] = sum(1 for r in rs if r["generic_message"])
        row["litter"] = sum(1 for r in rs if r["litter"])
        rows.append([("**all**" if cat == "all" else cat), len(rs)] + [row[c] for c in cols])
    head = "| category | cases | " + " | ".join(cols) + " |"
    sep = "|" + "---|" * (len(cols) + 2)
    return "\n".join([head, sep] + ["| " + " | ".join(str(x) for x in r) + " |" for r in rows])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", required=True, help="the sonarsynth binary under test")
    ap.add_argument("--cases", type=int, default=400, help="number of cases (default 400)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per run (default 60)")
    ap.add_argument("--out", default="adversarial-report.json")
    ap.add_argument("--keep-failures", metavar="DIR",
                    help="copy the sandbox of every case not ok/clean_error (or with litter) here")
    ap.add_argument("--categories", default=",".join(CATEGORIES),
                    help="comma-separated subset of " + ",".join(CATEGORIES))
    ap.add_argument("--mem-mb", type=int, default=4096,
                    help="address-space limit per run, MiB (0 = none; off for ASan builds)")
    ap.add_argument("--tmp", default=None, help="where the sandboxes go (default $TMPDIR)")
    ap.add_argument("--list", action="store_true", help="list the selected cases and exit")
    ap.add_argument("--keep-sandboxes", action="store_true")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit("not an executable: " + args.cli)
    h = Harness(args)
    t0 = time.time()
    try:
        h.prepare()
        rng = random.Random(args.seed)
        cats = [c for c in args.categories.split(",") if c]
        by_cat = {}
        for cat in CATEGORIES:
            r_cat = random.Random("%d-%s" % (args.seed, cat))
            by_cat[cat] = GENERATORS[cat](h, r_cat) if cat in cats else []
        chosen = select(by_cat, args.cases, rng)
        universe = sum(len(v) for v in by_cat.values())
        print("sonarsynth adversarial campaign: %d of %d generated cases, seed %d, timeout %g s, cli %s"
              % (len(chosen), universe, args.seed, args.timeout, args.cli), file=sys.stderr)
        if args.list:
            for i, c in enumerate(chosen):
                print("%4d %-9s %-7s %s" % (i, c.category, c.expect, c.desc))
            return
        records = []
        for i, case in enumerate(chosen):
            try:
                rec, box = h.run_case(i, case)
            except Exception as e:  # the harness's own failure is recorded, never hidden
                rec = {"id": i, "category": case.category, "description": case.desc,
                       "command": " ".join(case.argv), "expect": case.expect, "exit": None,
                       "class": "unclassified", "reasons": ["harness error: %r" % e],
                       "litter": [], "generic_message": False, "stderr_head": ""}
                box = os.path.join(h.root, "cases", "c%05d" % i)
            records.append(rec)
            bad = rec["class"] not in ("ok", "clean_error") or rec["litter"]
            if args.verbose or bad:
                print("[%4d/%d] %-12s %-9s %s :: %s" % (i + 1, len(chosen), rec["class"], case.category,
                                                      case.desc[:70], "; ".join(rec["reasons"])[:200]),
                      file=sys.stderr)
            if bad and args.keep_failures:
                dst = os.path.join(args.keep_failures, "c%05d-%s" % (i, rec["class"]))
                if os.path.exists(box):
                    shutil.rmtree(dst, ignore_errors=True)
                    shutil.copytree(box, dst, symlinks=True, ignore_dangling_symlinks=True)
                    with open(os.path.join(dst, "case.json"), "w") as f:
                        json.dump(rec, f, indent=1)
            if not args.keep_sandboxes and os.path.exists(box):
                make_removable(box)
                shutil.rmtree(box, ignore_errors=True)
        table = summary_table(records)
        print("\n## sonarsynth adversarial campaign\n")
        print("cli `%s` (sha256 %s), %d cases (of %d generated), seed %d, timeout %g s, %.0f s\n"
              % (args.cli, h.cli_sha256[:12], len(records), universe, args.seed, args.timeout,
                 time.time() - t0))
        print(table)
        report = {"cli": args.cli, "cli_sha256": h.cli_sha256, "seed": args.seed, "cases": len(records), "generated": universe,
                  "timeout": args.timeout, "seconds": round(time.time() - t0, 1),
                  "summary_markdown": table, "records": records}
        with open(args.out, "w") as f:
            json.dump(report, f, indent=1)
        print("\ndetails: %s" % args.out)
    finally:
        if not args.keep_sandboxes:
            make_removable(h.root)
            shutil.rmtree(h.root, ignore_errors=True)


def make_removable(root):
    for dirpath, dirnames, _ in os.walk(root):
        for d in dirnames:
            p = os.path.join(dirpath, d)
            try:
                if not os.path.islink(p):
                    os.chmod(p, 0o755)
            except OSError:
                pass


if __name__ == "__main__":
    main()
