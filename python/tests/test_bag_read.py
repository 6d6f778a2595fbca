# SPDX-License-Identifier: MIT
# Bags read back (docs/rosbag.md and docs/robotics.md, "Reading bags"): the ROS 1 bag and the
# MCAP file of a run read as the XTF of the same run through read_sonar, and `info`, `waterfall`
# and `mosaic` of the MCAP file equal those of the XTF (the bag carries no altitude: both mosaics
# use the tracked bottom).
import json
import subprocess

import numpy as np
import pytest

import sonarsynth


def simulate(scene_path, cli, tmp_path):
    scene = tmp_path / "mcap_scene.yaml"
    scene.write_text(open(scene_path).read() + "output: {formats: [xtf, rosbag, mcap]}\n")
    out = tmp_path / "out"
    subprocess.run([cli, "simulate", str(scene), "-o", str(out), "--no-mosaic",
                    "--no-waterfall", "--no-truth"], check=True, capture_output=True)
    return out


@pytest.mark.parametrize("fmt,ext", [("rosbag", "bag"), ("mcap", "mcap")])
def test_sonarsynth_reads_its_bags_as_the_xtf_of_the_run(scene_path, cli, tmp_path, fmt, ext):
    out = simulate(scene_path, cli, tmp_path)
    for name in ["a", "b"]:
        x = sonarsynth.read_xtf(str(out / f"{name}.xtf"))
        b = sonarsynth.read_sonar(str(out / f"{name}.{ext}"))
        assert b["format"] == fmt and not b["anomalies"]
        assert np.array_equal(b["port"], x["port"]) and np.array_equal(b["starboard"], x["starboard"])
        # Each line's pings are numbered from 0 (the MCAP's Message sequence; the ROS 1 header seq).
        assert np.array_equal(b["ping_number"], x["ping_number"])
        # XTF stores times to 1/100 s (rounded), the bag to the nanosecond.
        assert np.abs(b["time_utc_us"] - x["time_utc_us"]).max() <= 5000
        assert np.abs(b["sensor_lat_deg"] - x["sensor_lat_deg"]).max() <= 1e-9
        assert np.abs(b["sensor_lon_deg"] - x["sensor_lon_deg"]).max() <= 1e-9
        heading = np.remainder(b["heading_rad"] - x["heading_rad"] + np.pi, 2 * np.pi) - np.pi
        assert np.abs(heading).max() < 1e-5  # the XTF's float degrees
        assert np.abs(b["pitch_rad"] - x["pitch_rad"]).max() < 1e-5
        assert np.abs(b["roll_rad"] - x["roll_rad"]).max() < 1e-5


def test_info_waterfall_and_mosaic_of_a_bag_equal_the_xtf_ones(scene_path, cli, tmp_path):
    gdal = pytest.importorskip("osgeo.gdal")
    out = simulate(scene_path, cli, tmp_path)
    info = {}
    for ext in ["xtf", "mcap"]:
        f = str(out / f"a.{ext}")
        info[ext] = json.loads(subprocess.run([cli, "info", f, "--json"], check=True,
                                              capture_output=True, text=True).stdout)
        subprocess.run([cli, "waterfall", f, "-o", str(tmp_path / f"{ext}.png")], check=True,
                       capture_output=True)
        subprocess.run([cli, "mosaic", f, "-o", str(tmp_path / f"{ext}.tif"), "--altitude-source",
                        "track"], check=True, capture_output=True)
    x, b = info["xtf"], info["mcap"]
    assert b["format"] == "MCAP" and b["indexed"] and b["anomaly_count"] == 0
    assert b["pings"] == x["pings"] and b["pings_with_valid_navigation"] == x["pings_with_valid_navigation"]
    assert b["time"]["first"] == x["time"]["first"] and b["time"]["last"] == x["time"]["last"]
    assert b["samples"] == x["channels"][0]["samples"]
    assert b["slant_range_m"] == pytest.approx(x["channels"][0]["slant_range_m"], rel=1e-6)
    for bkey, xkey in [("longitude", "x"), ("latitude", "y")]:
        for end in ["min", "max"]:
            assert b["navigation"][bkey][end] == pytest.approx(x["navigation"][xkey][end], abs=1e-9)
    for key in ["heading_deg", "pitch_deg", "roll_deg"]:
        for end in ["min", "max"]:
            assert b["ping_attitude"][key][end] == pytest.approx(x["ping_attitude"][key][end], abs=1e-4)
    assert (tmp_path / "mcap.png").read_bytes() == (tmp_path / "xtf.png").read_bytes()
    a, m = gdal.Open(str(tmp_path / "xtf.tif")), gdal.Open(str(tmp_path / "mcap.tif"))
    assert a.GetGeoTransform() == m.GetGeoTransform() and a.GetProjection() == m.GetProjection()
    assert np.array_equal(a.ReadAsArray(), m.ReadAsArray(), equal_nan=True)
