# SPDX-License-Identifier: MIT
# Rendering through the bindings equals the C++ rendering bit for bit.
import numpy as np
import pytest

import sonarsynth
from conftest import read_reference, run_reference

FIELDS = ["samples", "truth_class", "object_id", "grazing_rad", "ground_x_m", "ground_y_m"]


def test_batch_equals_cpp_bit_for_bit(scene_path, reference_helper, tmp_path):
    sim = sonarsynth.Simulation.from_file(scene_path)
    poses = sim.survey_poses()
    out = sim.render_poses(poses, threads=2)
    ref_path = tmp_path / "ref.bin"
    run_reference(reference_helper, scene_path, ref_path)
    ref = read_reference(ref_path, len(poses), sim.samples_per_side)
    for f in FIELDS:
        assert out[f].shape == (len(poses), 2, sim.samples_per_side)
        assert out[f].tobytes() == np.ascontiguousarray(ref[f]).tobytes(), f
    # The scene's objects are seen: every id appears in the truth.
    assert {3, 7, 9} <= set(np.unique(out["object_id"]).tolist())


def test_single_ping_and_threads_agree(scene_path):
    sim = sonarsynth.Simulation.from_file(scene_path)
    poses = sim.survey_poses()[5:25]
    one = sim.render_poses(poses, threads=1)
    two = sim.render_poses(poses, threads=2)
    for f in FIELDS:
        assert one[f].tobytes() == two[f].tobytes(), f
    p = poses[3]
    # render_ping through sensor_pose takes the altitude from the seabed and the position
    # projected on the heading for the along-track lattice; compare it with the same made pose.
    made = sim.make_poses(p["sensor_x_m"], p["sensor_y_m"], p["sensor_z_m"], p["heading_rad"],
                          p["pitch_rad"], p["roll_rad"], first_noise_key=int(p["ping_index"]))
    batch = sim.render_poses(made, threads=1)
    ping = sim.render_ping(float(p["sensor_x_m"]), float(p["sensor_y_m"]),
                           float(p["sensor_z_m"]), float(p["heading_rad"]),
                           float(p["pitch_rad"]), float(p["roll_rad"]),
                           noise_key=int(p["ping_index"]))
    for side_index, side in enumerate(["port", "starboard"]):
        for f in FIELDS:
            assert ping[side][f].tobytes() == batch[f][0, side_index].tobytes(), (side, f)
    # The single ping's arrays view the renderer's buffers: not writable copies of numpy's.
    assert not ping["port"]["samples"].flags["OWNDATA"]


def test_flat_seabed_built_in_code_truth_is_analytic():
    depth_m, altitude_m = 20.0, 8.0
    heights = np.full((101, 101), -depth_m, dtype=np.float32)
    sim = sonarsynth.Simulation.from_heights(heights, x0_m=-50, y0_m=50, dx_m=1, dy_m=-1,
                                             lat_deg=43.0, lon_deg=5.0)
    sim.set({"sonar": {"range_m": 30, "samples": 600}, "seed": 3})
    # A box 10 m to starboard of a sensor heading north: starboard = +x.
    sim.add_object("box", id=4, position={"east_m": 10.0, "north_m": 0.0}, size_m=[2, 2, 1])
    ping = sim.render_ping(0.0, 0.0, -depth_m + altitude_m, 0.0, noise_key=1)
    for side in ["port", "starboard"]:
        s = ping[side]
        assert s["samples"].shape == (600,)
        slant_m = (np.arange(600) + 0.5) * 30.0 / 600
        cls = s["truth_class"]
        # Before the seabed (slant < altitude, one sample of margin): water column; no seabed
        # return at all there.
        early = slant_m < altitude_m - 0.1
        assert np.all(cls[early] == sonarsynth.SAMPLE_CLASSES.index("water_column"))
        assert np.all(s["object_id"][early] == -1)
        # Seabed returns lie on the plane z = -depth at ground range sqrt(slant^2 - alt^2).
        seabed = cls == sonarsynth.SAMPLE_CLASSES.index("seabed")
        assert seabed.sum() > 300
        ground = np.hypot(s["ground_x_m"][seabed], s["ground_y_m"][seabed])
        expect = np.sqrt(slant_m[seabed] ** 2 - altitude_m ** 2)
        assert np.max(np.abs(ground - expect)) < 0.2
    assert 4 in ping["starboard"]["object_id"]
    assert 4 not in ping["port"]["object_id"]


def test_builder_errors_are_value_errors():
    sim = sonarsynth.Simulation.from_heights(np.zeros((10, 10), np.float32), lat_deg=0.5,
                                             lon_deg=3.0, name="built")
    with pytest.raises(ValueError, match="built: add_object.type = 'cone'. Violated constraint: "
                                         "one of pipe, cylinder, box, rock, wreck, moored, mesh"):
        sim.add_object("cone", id=1, position={"east_m": 0, "north_m": 0}, size_m=[1, 1, 1])
    with pytest.raises(ValueError, match="survey.lines"):
        sim.survey_poses()


def test_out_arrays_are_refilled_in_place(scene_path):
    sim = sonarsynth.Simulation.from_file(scene_path)
    poses = sim.survey_poses()
    first = sim.render_poses(poses[:8], threads=1)
    second = sim.render_poses(poses[8:16], threads=1)
    expected = {f: second[f].copy() for f in FIELDS}
    again = sim.render_poses(poses[8:16], threads=2, out=first)
    for f in FIELDS:
        assert again[f] is first[f]
        assert first[f].tobytes() == expected[f].tobytes(), f
    with pytest.raises(ValueError, match="out\\['samples'\\] must be"):
        sim.render_poses(poses[:4], out=first)
    first["samples"].flags.writeable = False
    with pytest.raises(ValueError, match="out\\['samples'\\] must be"):
        sim.render_poses(poses[8:16], out=first)
