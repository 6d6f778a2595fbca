# SPDX-License-Identifier: MIT
# ROS 1 bags (docs/rosbag.md) read by an independent reader: Debian's python3-rosbag, which
# decodes every message with the definition embedded in the bag (genpy), and the ROS 1 message
# packages python3-sensor-msgs / -tf2-msgs / -std-msgs. Every ping's samples and time are
# compared with the XTF of the same run read through the project's reader.
import json
import math
import subprocess

import numpy as np
import pytest

try:
    import rosbag
    from sensor_msgs.msg import Imu, NavSatFix
    from tf2_msgs.msg import TFMessage
except ImportError as e:  # pragma: no cover - depends on the machine
    pytest.skip(f"python3-rosbag and the ROS 1 message packages are not installed ({e}); "
                "scripts/install-deps.sh --dev installs them", allow_module_level=True)

import sonarsynth

PORT, STBD = "/sonarsynth/sidescan/port", "/sonarsynth/sidescan/starboard"
TYPES = {PORT: "marine_acoustic_msgs/RawSonarImage", STBD: "marine_acoustic_msgs/RawSonarImage",
         "/sonarsynth/fix": "sensor_msgs/NavSatFix", "/sonarsynth/imu": "sensor_msgs/Imu",
         "/tf_static": "tf2_msgs/TFMessage"}
# The ROS 1 (catkin) generated code of marine_acoustic_msgs 2.0 states this MD5 (gennodejs,
# roslisp); the package is not in Debian.
RAW_SONAR_IMAGE_MD5 = "84d7210aa67320a9262e0908f3e466c5"


def simulate(scene_path, cli, tmp_path, formats="[xtf, rosbag]", extra=""):
    scene = tmp_path / "bag_scene.yaml"
    scene.write_text(open(scene_path).read() + f"output: {{formats: {formats}{extra}}}\n")
    out = tmp_path / "out"
    subprocess.run([cli, "simulate", str(scene), "-o", str(out), "--no-mosaic",
                    "--no-waterfall", "--no-truth"], check=True, capture_output=True)
    return out


def read_bag(path):
    with rosbag.Bag(str(path)) as bag:
        info = bag.get_type_and_topic_info()
        conns = {c.topic: c for c in bag._get_connections()}
        msgs = {}
        for topic, msg, t in bag.read_messages():
            msgs.setdefault(topic, []).append((msg, t))
    return info, conns, msgs


def check_bag_against_xtf(bag_path, x, sample_dtype, time_tol_us):
    info, conns, msgs = read_bag(bag_path)
    pings = x["port"].shape[0]
    assert pings > 0
    # Topics, types, MD5 sums and definitions: those of the installed message packages; the
    # reader's classes generated from the embedded definitions have the stated MD5 sums.
    assert set(info.topics) == set(TYPES)
    for topic, type_ in TYPES.items():
        assert info.topics[topic].msg_type == type_ and conns[topic].datatype == type_
        assert type(msgs[topic][0][0])._md5sum == conns[topic].md5sum
        assert info.topics[topic].message_count == len(msgs[topic])
        assert info.topics[topic].message_count == (1 if topic == "/tf_static" else pings)
    for cls in (NavSatFix, Imu, TFMessage):
        assert info.msg_types[cls._type] == cls._md5sum
        topic = next(t for t, ty in TYPES.items() if ty == cls._type)
        assert conns[topic].msg_def == cls._full_text
    assert info.msg_types["marine_acoustic_msgs/RawSonarImage"] == RAW_SONAR_IMAGE_MD5
    # Every ping: time, samples, position, heading.
    for k in range(pings):
        for topic, side in ((PORT, "port"), (STBD, "starboard")):
            msg, t = msgs[topic][k]
            assert msg.header.stamp == t and msg.header.seq == x["ping_number"][k]
            assert msg.header.frame_id == ("sidescan_port" if side == "port" else
                                           "sidescan_starboard")
            assert abs(t.to_nsec() // 1000 - int(x["time_utc_us"][k])) <= time_tol_us
            n = int(x[f"{side}_sample_count"][k])
            assert msg.samples_per_beam == n and msg.image.beam_count == 1
            samples = np.frombuffer(msg.image.data, dtype=sample_dtype)
            assert np.array_equal(samples, x[side][k, :n].astype(sample_dtype))
            assert msg.sample_rate == pytest.approx(n * msg.ping_info.sound_speed /
                                                    (2 * x["slant_range_m"][k]), rel=1e-6)
        fix, t = msgs["/sonarsynth/fix"][k]
        assert fix.header.stamp == t == msgs[PORT][k][1] and fix.status.status == 0
        assert fix.latitude == pytest.approx(x["sensor_lat_deg"][k], abs=1e-9)
        assert fix.longitude == pytest.approx(x["sensor_lon_deg"][k], abs=1e-9)
        assert math.isnan(fix.altitude)
        q = msgs["/sonarsynth/imu"][k][0].orientation
        yaw_enu = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        heading = math.remainder(math.pi / 2 - yaw_enu - x["heading_rad"][k], 2 * math.pi)
        assert abs(heading) < 1e-5
    tf = msgs["/tf_static"][0][0]
    assert sorted(tr.child_frame_id for tr in tf.transforms) == ["sidescan_port",
                                                                 "sidescan_starboard"]
    assert all(tr.header.frame_id == "base_link" for tr in tf.transforms)
    return msgs


def test_simulate_bag_equals_the_xtf_of_the_run(scene_path, cli, tmp_path):
    out = simulate(scene_path, cli, tmp_path)
    for name in ["a", "b"]:
        x = sonarsynth.read_xtf(str(out / f"{name}.xtf"))
        # XTF stores times to 1/100 s (rounded), the bag to the nanosecond.
        msgs = check_bag_against_xtf(out / f"{name}.bag", x, "<u2", 5000)
        assert msgs[PORT][0][0].image.dtype == 2  # DTYPE_UINT16
        assert msgs[PORT][0][0].ping_info.frequency == 600e3


def test_f32_samples_and_convert_from_xtf(scene_path, cli, tmp_path):
    out = simulate(scene_path, cli, tmp_path, extra=", sample_format: f32")
    x = sonarsynth.read_xtf(str(out / "a.xtf"))
    msgs = check_bag_against_xtf(out / "a.bag", x, "<f4", 5000)
    assert msgs[PORT][0][0].image.dtype == 8  # DTYPE_FLOAT32
    # convert XTF -> bag: the same samples, the XTF's times exactly.
    converted = tmp_path / "a_converted.bag"
    subprocess.run([cli, "convert", str(out / "a.xtf"), "-o", str(converted)], check=True,
                   capture_output=True)
    check_bag_against_xtf(converted, x, "<f4", 0)


def test_random_access_across_chunks(scene_path, cli, tmp_path):
    # 3000 samples per side: the line's bag spans several 768 KiB chunks. Reads from a start
    # time (through the chunk infos and index data records) give exactly the messages from that
    # time on, as the whole read does.
    scene = tmp_path / "bag_scene.yaml"
    scene.write_text(open(scene_path).read() + "output: {formats: [rosbag]}\n")
    out = tmp_path / "out"
    subprocess.run([cli, "simulate", str(scene), "-o", str(out), "--samples", "3000",
                    "--no-mosaic", "--no-waterfall", "--no-truth"], check=True,
                   capture_output=True)
    with rosbag.Bag(str(out / "a.bag")) as bag:
        assert bag.get_compression_info().compression == "none"
        assert len(bag._chunks) >= 3
        every = [(topic, t, msg.header.seq) for topic, msg, t in bag.read_messages(topics=[PORT])]
        for k in (0, 1, len(every) // 2, len(every) - 1):
            start = every[k][1]
            part = [(topic, t, msg.header.seq)
                    for topic, msg, t in bag.read_messages(topics=[PORT], start_time=start)]
            assert part == [e for e in every if e[1] >= start]


# Reading bags (docs/rosbag.md, "Reading bags").

# The bag of a run read as its XTF: test_bag_read.py (for both bag formats, without python3-rosbag).


def test_a_bag_written_by_python_rosbag_reads_and_converts(scene_path, cli, tmp_path):
    # Messages built by genpy from the RawSonarImage definition a sonarsynth bag embeds, on
    # topics and frames of another robot, written by rosbag.Bag: found by type, not by topic.
    import genpy
    import genpy.dynamic
    import rospy
    from sensor_msgs.msg import NavSatStatus

    out = simulate(scene_path, cli, tmp_path, formats="[rosbag]")
    with rosbag.Bag(str(out / "a.bag")) as bag:
        definition = next(c.msg_def for c in bag._get_connections() if c.topic == PORT)
    Raw = genpy.dynamic.generate_dynamic("marine_acoustic_msgs/RawSonarImage",
                                         definition)["marine_acoustic_msgs/RawSonarImage"]
    assert Raw._md5sum == RAW_SONAR_IMAGE_MD5
    rng = np.random.default_rng(7)
    n_pings, n = 6, 250
    samples = rng.integers(0, 32768, size=(n_pings, 2, n), dtype=np.uint16)
    t0 = rospy.Time(1700000000, 120000000)
    path = tmp_path / "robot.bag"
    with rosbag.Bag(str(path), "w") as bag:
        for k in range(n_pings):
            t = t0 + rospy.Duration(0, 250000000 * k)
            fix = NavSatFix()
            fix.header.stamp, fix.header.frame_id = t, "gps"
            fix.status.status, fix.status.service = NavSatStatus.STATUS_FIX, 1
            fix.latitude, fix.longitude, fix.altitude = 47.25 + 1e-5 * k, -122.5, float("nan")
            bag.write("/robot/gps/fix", fix, t)
            imu = Imu()
            imu.header.stamp, imu.header.frame_id = t, "imu_link"
            yaw = math.pi / 2 - math.radians(30 + k)  # heading 30 + k degrees, ENU
            imu.orientation.z, imu.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
            bag.write("/robot/imu/data", imu, t)
            for side, frame in ((0, "sss_port"), (1, "sss_stbd")):
                m = Raw()
                m.header.seq, m.header.stamp, m.header.frame_id = 100 + k, t, frame
                m.ping_info.frequency, m.ping_info.sound_speed = 900e3, 1480.0
                m.sample_rate = n * 1480.0 / (2 * 30.0)  # 30 m slant range
                m.samples_per_beam, m.image.dtype, m.image.beam_count = n, 2, 1
                m.tx_delays, m.tx_angles, m.rx_angles = [0.0], [0.0], [0.0]
                m.image.data = samples[k, side].astype("<u2").tobytes()
                bag.write("/robot/sss/raw", m, t)
    info = json.loads(subprocess.run([cli, "info", str(path), "--json"], check=True,
                                     capture_output=True, text=True).stdout)
    assert info["format"] == "ROS 1 bag" and info["pings"] == n_pings
    assert info["pings_with_valid_navigation"] == n_pings and info["anomaly_count"] == 0
    read_as = {c["topic"]: c["read_as"] for c in info["connections"]}
    assert read_as == {"/robot/gps/fix": "navigation", "/robot/imu/data": "attitude",
                       "/robot/sss/raw": "side-scan images"}
    xtf = tmp_path / "robot.xtf"
    subprocess.run([cli, "convert", str(path), "-o", str(xtf)], check=True, capture_output=True)
    x = sonarsynth.read_xtf(str(xtf))
    assert np.array_equal(x["port"], samples[:, 0].astype(x["port"].dtype))
    assert np.array_equal(x["starboard"], samples[:, 1].astype(x["starboard"].dtype))
    assert list(x["ping_number"]) == [100 + k for k in range(n_pings)]
    assert list(x["time_utc_us"]) == [1700000000120000 + 250000 * k for k in range(n_pings)]
    assert np.allclose(x["sensor_lat_deg"], 47.25 + 1e-5 * np.arange(n_pings), atol=1e-9)
    assert np.allclose(np.degrees(x["heading_rad"]), 30 + np.arange(n_pings), atol=1e-4)
    assert np.allclose(x["slant_range_m"], 30.0, rtol=1e-6)
