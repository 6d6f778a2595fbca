# SPDX-License-Identifier: MIT
# run_simulation writes what the bindings render; read_xtf returns it with its navigation.
import subprocess

import numpy as np
import pytest

import sonarsynth


def test_run_simulation_xtf_equals_render(scene_path, tmp_path):
    out_dir = tmp_path / "out"
    calls = []
    result = sonarsynth.run_simulation(scene_path, str(out_dir), mosaic=False, waterfalls=False,
                                       progress=lambda done, total: calls.append((done, total)))
    sim = sonarsynth.Simulation.from_file(scene_path)
    poses = sim.survey_poses()
    assert result["total_pings"] == len(poses)
    assert result["line_names"] == ["a", "b"]
    assert calls and calls[-1][0] == calls[-1][1] == len(poses)
    rendered = sim.render_poses(poses)
    first = 0
    for name in result["line_names"]:
        xtf = sonarsynth.read_xtf(str(out_dir / f"{name}.xtf"))
        n = xtf["port"].shape[0]
        assert not xtf["anomalies"]
        sl = slice(first, first + n)
        # u16 samples: the rendered floats are whole numbers in [0, 65535], stored exactly.
        assert xtf["port"].tobytes() == rendered["samples"][sl, 0].tobytes()
        assert xtf["starboard"].tobytes() == rendered["samples"][sl, 1].tobytes()
        # Navigation: times rounded to the XTF's 1/100 s, positions back in the local frame.
        assert np.array_equal(xtf["time_utc_us"], (poses["time_utc_us"][sl] + 5000) // 10000 * 10000)
        assert xtf["nav_valid"].all()
        for i in range(n):
            x, y = sim.local_from_geodetic(xtf["sensor_lat_deg"][i], xtf["sensor_lon_deg"][i])
            assert abs(x - poses["sensor_x_m"][first + i]) < 0.01
            assert abs(y - poses["sensor_y_m"][first + i]) < 0.01
        assert np.allclose(xtf["roll_rad"], poses["roll_rad"][sl], atol=1e-3)
        first += n
    assert first == len(poses)


def test_cli_simulate_writes_the_same_xtf(scene_path, cli, tmp_path):
    a, b = tmp_path / "py", tmp_path / "cli"
    sonarsynth.run_simulation(scene_path, str(a), mosaic=False, waterfalls=False, truth=False)
    subprocess.run([cli, "simulate", scene_path, "-o", str(b), "--no-mosaic", "--no-waterfall",
                    "--no-truth"], check=True, capture_output=True)
    for name in ["a", "b"]:
        x, y = sonarsynth.read_xtf(str(a / f"{name}.xtf")), sonarsynth.read_xtf(str(b / f"{name}.xtf"))
        for k in ["port", "starboard", "time_utc_us", "sensor_lat_deg", "sensor_lon_deg"]:
            assert x[k].tobytes() == y[k].tobytes(), k


def test_run_simulation_records_its_product_options(scene_path, cli, tmp_path):
    # The product options are not scene settings: effective.yaml names them as `simulate`
    # options, for a Python run as for a CLI run, and giving them again gives the same files.
    a, b = tmp_path / "py", tmp_path / "cli"
    sonarsynth.run_simulation(scene_path, str(a), waterfalls=False, truth=False,
                              mosaic_pixel_m=0.5)
    header = [line for line in (a / "effective.yaml").read_text().splitlines()
              if line.startswith("# product options:")]
    assert header == ["# product options: --no-waterfall --no-truth --res 0.5"]
    flags = header[0].split(":", 1)[1].split()
    subprocess.run([cli, "simulate", str(a / "effective.yaml"), "-o", str(b)] + flags,
                   check=True, capture_output=True)
    for name in ["a.xtf", "b.xtf", "mosaic.tif"]:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    assert not (b / "a_waterfall.png").exists()
    # The gain-normalised mosaic of a run without truth (no label band in its spool) is the
    # mosaic of the run with truth.
    c = tmp_path / "with_truth"
    subprocess.run([cli, "simulate", scene_path, "-o", str(c), "--no-waterfall", "--res", "0.5"],
                   check=True, capture_output=True)
    assert (c / "truth_mosaic.tif").exists()
    assert (a / "mosaic.tif").read_bytes() == (c / "mosaic.tif").read_bytes()


def test_run_simulation_errors(scene_path, tmp_path):
    with pytest.raises(ValueError, match="--range"):
        sonarsynth.run_simulation(scene_path, str(tmp_path / "o"), range_m=-1.0)
    assert not (tmp_path / "o").exists()
    with pytest.raises(sonarsynth.FormatError):
        sonarsynth.read_xtf(str(tmp_path / "missing.xtf"))
    with pytest.raises(OSError):
        sonarsynth.read_xtf(str(tmp_path / "missing.xtf"))


def test_read_jsf_matches_the_xtf_of_the_same_run(scene_path, tmp_path):
    # output.jsf: the same run writes <line>.jsf beside <line>.xtf (docs/jsf.md).
    jsf_scene = tmp_path / "jsf_scene.yaml"
    jsf_scene.write_text(open(scene_path).read() + "output: {jsf: true}\n")
    out_dir = tmp_path / "out"
    sonarsynth.run_simulation(str(jsf_scene), str(out_dir), mosaic=False, waterfalls=False,
                              truth=False)
    for name in ["a", "b"]:
        x = sonarsynth.read_xtf(str(out_dir / f"{name}.xtf"))
        j = sonarsynth.read_jsf(str(out_dir / f"{name}.jsf"))
        either = sonarsynth.read_sonar(str(out_dir / f"{name}.jsf"))
        assert (x["format"], j["format"], either["format"]) == ("xtf", "jsf", "jsf")
        assert not j["anomalies"]
        assert j["port"].shape == x["port"].shape and j["port"].shape[0] > 0
        # Samples: bit-exact (u16 in both files).
        assert j["port"].tobytes() == x["port"].tobytes()
        assert j["starboard"].tobytes() == x["starboard"].tobytes()
        assert either["starboard"].tobytes() == j["starboard"].tobytes()
        assert j["nav_valid"].all() and j["time_valid"].all()
        # Navigation within JSF's resolution (docs/jsf.md §4): positions in 1/600,000 degree,
        # against XTF's doubles; times in milliseconds against XTF's 1/100 s.
        assert np.abs(j["sensor_lat_deg"] - x["sensor_lat_deg"]).max() <= 0.5 / 600000 + 1e-12
        assert np.abs(j["sensor_lon_deg"] - x["sensor_lon_deg"]).max() <= 0.5 / 600000 + 1e-12
        assert np.abs(j["time_utc_us"] - x["time_utc_us"]).max() <= 5000
    # Each reader refuses the other's format with FormatError; read_sonar takes both.
    with pytest.raises(sonarsynth.FormatError, match="not an XTF"):
        sonarsynth.read_xtf(str(out_dir / "a.jsf"))
    with pytest.raises(sonarsynth.FormatError, match="not a JSF"):
        sonarsynth.read_jsf(str(out_dir / "a.xtf"))
    assert sonarsynth.read_sonar(str(out_dir / "a.xtf"))["format"] == "xtf"


def test_formats_lists_the_library_format_list():
    formats = sonarsynth.formats()
    assert [f["name"] for f in formats] == ["xtf", "jsf", "rosbag", "mcap"]
    by_name = {f["name"]: f for f in formats}
    assert by_name["xtf"]["extensions"] == [".xtf"] and by_name["jsf"]["extensions"] == [".jsf"]
    assert all(f["simulate"] for f in formats)
    assert all(f["read"] for f in formats)
    # ROS 2 bags: written by simulate and convert, read back (docs/robotics.md).
    assert by_name["mcap"]["extensions"] == [".mcap"]
    assert set(by_name["mcap"]["conversions"]) == {("xtf", "mcap"), ("mcap", "xtf"), ("mcap", "jsf")}
    assert set(by_name["jsf"]["conversions"]) == {("xtf", "jsf"), ("jsf", "xtf")}
    assert set(by_name["rosbag"]["conversions"]) == {("xtf", "rosbag"), ("rosbag", "xtf"),
                                                     ("rosbag", "jsf")}


def test_info_is_what_the_cli_prints(scene_path, cli, tmp_path):
    # output.formats: the run writes both formats; info of each equals `sonarsynth info`'s.
    scene = tmp_path / "formats_scene.yaml"
    scene.write_text(open(scene_path).read() + "output: {formats: [xtf, jsf]}\n")
    out_dir = tmp_path / "out"
    sonarsynth.run_simulation(str(scene), str(out_dir), mosaic=False, waterfalls=False,
                              truth=False)
    for name, display in [("a.xtf", "XTF"), ("a.jsf", "JSF")]:
        path = str(out_dir / name)
        info = sonarsynth.info(path, max_anomalies=5)
        as_json = subprocess.run([cli, "info", path, "--json"], check=True, capture_output=True,
                                 text=True).stdout
        as_text = subprocess.run([cli, "info", path, "--max-anomalies", "5"], check=True,
                                 capture_output=True, text=True).stdout
        assert info["json"] + "\n" == as_json
        assert info["text"] == as_text
        assert info["summary"]["format"] == display
        assert info["summary"]["pings"] == sonarsynth.read_sonar(path)["port"].shape[0]
    with pytest.raises(sonarsynth.FormatError):
        sonarsynth.info(str(tmp_path / "missing.xtf"))
