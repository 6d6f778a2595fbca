"""Plausibility checks of what a successful run produced (XTF decoding, `info --json`, rasters)
and of error messages (needle_variants)."""

import json
import math
import os
import shutil
import struct
import subprocess
from array import array

from .case import MAX_DEPTH_M
from .process import run, text


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
                elif bps == 1:
                    vals = raw
                    zeros += vals.count(0)
                    sat += vals.count(255)
                elif bps == 2:
                    a = array("H")
                    a.frombytes(raw[: len(raw) // 2 * 2])
                    vals = a
                    zeros += a.count(0)
                    # sonarsynth clamps u16 samples to 0..32767 (docs/xtf.md); other writers
                    # may use the whole 0..65535
                    sat += sum(1 for v in a if v >= 32767)
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
