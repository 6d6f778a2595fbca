# SPDX-License-Identifier: MIT
# Inputs checked as the CLI checks them (docs/python.md "Pose checks", "Objects"): bad poses and
# pose arrays raise naming the argument, the value and the allowed range, and render nothing;
# add_object takes the scene file's object vocabulary and builds what the file builds.
import math

import numpy as np
import pytest

import sonarsynth
from conftest import SCENE

FIELDS = ["samples", "truth_class", "object_id", "grazing_rad", "ground_x_m", "ground_y_m"]
SEABED = sonarsynth.SAMPLE_CLASSES.index("seabed")


def sentinel_out(sim, n):
    """A render_poses result for n poses whose arrays hold a sentinel: a refused call must leave
    them untouched (nothing rendered into them)."""
    out = sim.render_poses(sim.survey_poses()[:n], threads=1)
    for a in out.values():
        a.fill(7)
    return out


def untouched(out):
    return all(np.all(a == 7) for a in out.values())


@pytest.fixture
def sim(scene_path):
    return sonarsynth.Simulation.from_file(scene_path)


@pytest.mark.parametrize("field,value,constraint", [
    ("sensor_x_m", math.nan, "a finite number"),
    ("sensor_y_m", math.inf, "a finite number"),
    ("sensor_z_m", -math.inf, "a finite number"),
    ("heading_rad", math.nan, "a finite number"),
    ("heading_rad", math.inf, "a finite number"),
    ("pitch_rad", math.nan, "\\|pitch_rad\\| <= 1.553343034 rad \\(89 deg"),
    ("pitch_rad", -1.56, "\\|pitch_rad\\| <= 1.553343034 rad \\(89 deg"),
    ("roll_rad", math.inf, "\\|roll_rad\\| <= 1.553343034 rad \\(89 deg"),
    ("roll_rad", 3.0, "\\|roll_rad\\| <= 1.553343034 rad \\(89 deg"),
    ("altitude_m", math.inf, "a finite number, or NaN"),
    ("speed_m_s", -1.0, "speed_m_s >= 0"),
])
def test_bad_pose_fields_are_named_and_nothing_renders(sim, field, value, constraint):
    poses = sim.survey_poses()[:6]
    poses[4][field] = value
    out = sentinel_out(sim, 6)
    text = "%.10g" % value  # nan, inf, -1.56, 3
    with pytest.raises(ValueError, match=f"render_poses: poses\\[4\\]: {field} = {text}. "
                                         f"Violated constraint: {constraint}"):
        sim.render_poses(poses, threads=2, out=out)
    assert untouched(out)


def test_pose_under_the_seabed_is_refused(sim):
    poses = sim.survey_poses()[:6]
    p = poses[2]
    seabed_z = float(p["sensor_z_m"] - p["altitude_m"])  # the survey's altitude over the seabed
    poses[2]["sensor_z_m"] = seabed_z - 1000.0
    out = sentinel_out(sim, 6)
    with pytest.raises(ValueError, match="render_poses: poses\\[2\\]: sensor_z_m = -10.*Violated "
                                         "constraint: sensor_z_m > -1[0-9.]* m, the seabed height"):
        sim.render_poses(poses, out=out)
    assert untouched(out)
    x, y = float(p["sensor_x_m"]), float(p["sensor_y_m"])
    with pytest.raises(ValueError, match="render_ping: z_m = .*Violated constraint: z_m > "):
        sim.render_ping(x, y, seabed_z - 1000.0, noise_key=1)
    # Just under the seabed is under it too; just above it is a legal pose.
    with pytest.raises(ValueError, match="altitude -0.01 m"):
        sim.render_ping(x, y, seabed_z - 0.01, noise_key=1)
    sim.render_ping(x, y, seabed_z + 0.01, noise_key=1)
    with pytest.raises(ValueError, match="make_poses: pose 1: z_m = "):
        sim.make_poses([x, x], y, [seabed_z + 1.0, seabed_z - 1.0])


def test_pose_above_the_sea_surface_is_refused(sim):
    p = sim.survey_poses()[0]
    with pytest.raises(ValueError, match="render_ping: z_m = 5. Violated constraint: z_m <= 0"):
        sim.render_ping(float(p["sensor_x_m"]), float(p["sensor_y_m"]), 5.0, noise_key=1)


def test_render_ping_names_its_arguments(sim):
    with pytest.raises(ValueError, match="render_ping: heading_rad = nan. Violated constraint: "
                                         "a finite number"):
        sim.render_ping(0.0, 0.0, -5.0, math.nan, noise_key=1)
    with pytest.raises(ValueError, match="render_ping: x_m = inf"):
        sim.render_ping(math.inf, 0.0, -5.0, noise_key=1)
    with pytest.raises(ValueError, match="render_ping: roll_rad = 2"):
        sim.render_ping(0.0, 0.0, -5.0, roll_rad=2.0, noise_key=1)


def test_pose_off_the_grid_renders_without_seabed(sim):
    # As a survey's pings beyond the grid: no seabed to check against, and none in the echo.
    (x0, y0, x1, y1) = sim.bounds_m
    poses = sim.make_poses(x1 + 500.0, y0, -5.0, 0.0)
    out = sim.render_poses(poses)
    assert not np.any(out["truth_class"] == SEABED)


def test_render_poses_wants_a_pose_array(sim):
    with pytest.raises(TypeError, match="render_poses: poses must be a 1-D numpy structured "
                                        "array of sonarsynth.POSE_DTYPE .*; got list"):
        sim.render_poses([1, 2, 3])
    with pytest.raises(TypeError, match="POSE_DTYPE .*; got an array of dtype int64 "
                                        "\\(no fields\\)"):
        sim.render_poses(np.array([1, 2, 3], dtype=np.int64))
    poses = sim.survey_poses()[:4]
    with pytest.raises(ValueError, match="POSE_DTYPE .*; got an array of shape \\(2, 2\\)"):
        sim.render_poses(poses.reshape(2, 2))
    partial = np.zeros(3, dtype=[("sensor_x_m", "f8"), ("sensor_y_m", "f8")])
    with pytest.raises(ValueError, match="without the fields line, ping_in_line, ping_index, "
                                         "time_utc_us, sensor_z_m,"):
        sim.render_poses(partial)


def test_pose_array_with_other_field_order_is_taken_by_name(sim):
    poses = sim.survey_poses()[3:7]
    names = list(reversed(sonarsynth.POSE_DTYPE.names))
    other = np.zeros(len(poses), dtype=[(n, sonarsynth.POSE_DTYPE[n]) for n in names]
                     + [("extra", "f4")])
    for n in names:
        other[n] = poses[n]
    a = sim.render_poses(poses, threads=1)
    b = sim.render_poses(other, threads=1)
    # A strided view (every other pose) is taken too.
    c = sim.render_poses(sim.survey_poses()[3:11:2], threads=1)
    d = sim.render_poses(np.ascontiguousarray(sim.survey_poses()[3:11:2]), threads=1)
    for f in FIELDS:
        assert a[f].tobytes() == b[f].tobytes(), f
        assert c[f].tobytes() == d[f].tobytes(), f


def test_make_poses_lengths_are_named(sim):
    with pytest.raises(ValueError, match="make_poses: y_m has 2 values, x_m has 3. Violated "
                                         "constraint: arrays of one length"):
        sim.make_poses([0.0, 1.0, 2.0], [0.0, 1.0], -5.0)
    with pytest.raises(ValueError, match="make_poses: roll_rad has 4 values, x_m has 3"):
        sim.make_poses([0.0, 1.0, 2.0], 0.0, -5.0, roll_rad=np.zeros(4))
    with pytest.raises(ValueError, match="make_poses: pose 1: x_m = nan"):
        sim.make_poses([0.0, math.nan], 0.0, -5.0)
    assert len(sim.make_poses([0.0, 1.0, 2.0], 0.0, -5.0)) == 3  # scalars broadcast


# One entry of each type of the scene file's `objects` list, each seen from the survey lines of
# conftest.SCENE (y = 0 and 3 of the grid centre, range 20 m).
OBJECTS = [
    {"type": "pipe", "id": 5, "position": {"east_m": 1, "north_m": -7}, "heading_deg": 80,
     "length_m": 8, "diameter_m": 0.5},
    {"type": "pipe", "id": 5, "start": {"east_m": -6, "north_m": 9},
     "end": {"east_m": 5, "north_m": 11}, "diameter_m": 0.4, "clearance_m": 0.3},
    {"type": "cylinder", "id": 5, "position": {"east_m": 0, "north_m": 8}, "length_m": 3,
     "diameter_m": 0.8, "material": "concrete"},
    {"type": "box", "id": 5, "position": {"east_m": 0.5, "north_m": -6}, "heading_deg": 25,
     "size_m": [2.2, 1.1, 0.9], "embed": 0.2},
    {"type": "rock", "id": 5, "position": {"east_m": -1, "north_m": 8}, "diameter_m": 1.4},
    {"type": "rock", "id": 5, "position": {"east_m": 2, "north_m": -7},
     "size_m": [1.5, 1.0, 0.7]},
    {"type": "wreck", "id": 5, "position": {"east_m": 0, "north_m": -9}, "heading_deg": 100,
     "parts": [{"offset_m": [0, 0], "size_m": [6, 2, 1.5]},
               {"offset_m": [-1, 0], "size_m": [2, 1.5, 1.0], "lift_m": 1.5}]},
    {"type": "moored", "id": 5, "position": {"east_m": 0, "north_m": 8}, "shape": "sphere",
     "diameter_m": 1.0, "height_m": 3},
    {"type": "moored", "id": 5, "position": {"east_m": 0, "north_m": -8}, "shape": "cylinder",
     "heading_deg": 40, "length_m": 2, "diameter_m": 0.6, "height_m": 2.5},
]

BASE = SCENE[:SCENE.index("objects:")] + SCENE[SCENE.index("survey:"):]


def flow(v):
    """A value in YAML flow style (as a scene file would hold it)."""
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k}: {flow(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(flow(x) for x in v) + "]"
    return str(v)


def with_objects(entries):
    return BASE.replace("survey:", "objects:\n" + "".join(f"  - {flow(e)}\n" for e in entries)
                        + "survey:")


def render(sim):
    poses = sim.survey_poses()[::6]
    return sim.render_poses(poses, threads=2)


@pytest.mark.parametrize("entry", OBJECTS, ids=[
    f"{e['type']}-{i}" for i, e in enumerate(OBJECTS)])
def test_add_object_renders_as_the_scene_file(entry):
    from_file = sonarsynth.Simulation.from_yaml(with_objects([entry]), name="scene.yaml")
    built = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    assert built.object_count == 0
    kwargs = {k: v for k, v in entry.items() if k != "type"}
    built.add_object(entry["type"], **kwargs)
    assert built.object_count == from_file.object_count > 0
    a, b = render(from_file), render(built)
    assert np.any(a["object_id"] == 5)  # the object is seen: the comparison is not vacuous
    for f in FIELDS:
        assert a[f].tobytes() == b[f].tobytes(), f
    # The dict form is the same entry.
    again = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    again.add_object(dict(entry))
    assert render(again)["samples"].tobytes() == a["samples"].tobytes()


def test_add_object_automatic_ids_and_material_index_follow_the_file():
    entries = [{"type": "box", "id": 4, "position": {"east_m": 0.5, "north_m": -6},
                "size_m": [2, 1, 1]},
               {"type": "rock", "position": {"east_m": -1, "north_m": 8}, "diameter_m": 1.4,
                "material": "gravel"}]
    from_file = sonarsynth.Simulation.from_yaml(with_objects(entries), name="scene.yaml")
    built = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    built.add_object("box", id=4, position={"east_m": 0.5, "north_m": -6},
                     size_m=np.array([2.0, 1.0, 1.0]))
    # A material index (material_index) stands for its name; the id is the file's automatic 5.
    built.add_object("rock", position={"east_m": -1, "north_m": 8}, diameter_m=1.4,
                     material=built.material_index("gravel"))
    a, b = render(from_file), render(built)
    assert {4, 5} <= set(np.unique(a["object_id"]).tolist())
    for f in FIELDS:
        assert a[f].tobytes() == b[f].tobytes(), f
    with pytest.raises(ValueError, match="scene.yaml: add_object.id = '4'. Violated constraint: "
                                         "ids are unique within a scene"):
        built.add_object("box", id=4, position={"east_m": 0, "north_m": 0}, size_m=[1, 1, 1])
    with pytest.raises(ValueError, match="add_object.material = 99. Violated constraint: a "
                                         "material name, or an index >= 0 and < "):
        built.add_object("box", position={"east_m": 0, "north_m": 0}, size_m=[1, 1, 1],
                         material=99)
    assert built.object_count == from_file.object_count  # refused calls added nothing


@pytest.mark.parametrize("entry", [
    {"type": "box", "position": {"east_m": 0, "north_m": 0}, "size_m": [0, 1, 1]},
    {"type": "box", "position": {"east_m": 0, "north_m": 0}, "size_m": [1, 1]},
    {"type": "pipe", "position": {"east_m": 0, "north_m": 0}, "length_m": 5, "diameter_m": -1},
    {"type": "rock", "position": {"east_m": 0, "north_m": 0}, "diameter_m": 1, "radius_m": 1},
    {"type": "moored", "position": {"east_m": 0, "north_m": 0}, "diameter_m": 1, "height_m": 0.2},
    {"type": "wreck", "position": {"east_m": 0, "north_m": 0}, "parts": []},
    {"type": "box", "position": {"east_m": 900, "north_m": 0}, "size_m": [1, 1, 1]},
    {"type": "box", "position": {"east_m": 0, "north_m": 0}, "size_m": [1, 1, 1],
     "material": "kelp"},
    {"type": "cone", "position": {"east_m": 0, "north_m": 0}},
], ids=["size0", "size2", "diameter", "key", "moored", "wreck", "offgrid", "material", "type"])
def test_add_object_messages_are_the_scene_files(entry):
    with pytest.raises(ValueError) as in_file:
        sonarsynth.Simulation.from_yaml(with_objects([entry]), name="scene.yaml")
    built = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    with pytest.raises(ValueError) as in_code:
        built.add_object(**entry)
    assert built.object_count == 0
    # The same message, the entry's place named as the call: objects[0] -> add_object.
    expected = str(in_file.value).replace("objects[0]", "add_object")
    assert str(in_code.value) == expected
    assert "add_object" in expected or "scene.yaml" in expected


def test_positional_form_is_refused_with_a_pointer():
    sim = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    with pytest.raises(TypeError, match="add_object takes the object's type and the scene "
                                        "file's keys by name"):
        sim.add_object("box", 4, 10.0, 0.0, (1.0, 1.0, 0.5))


CUBE_OBJ = """\
v -1 -0.5 0
v 1 -0.5 0
v -1 0.5 0
v 1 0.5 0
v -1 -0.5 1
v 1 -0.5 1
v -1 0.5 1
v 1 0.5 1
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
"""

LAYER = """\
{"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"type": "box", "id": 5, "size_m": "2,1,1", "heading_deg": 15},
  "geometry": {"type": "Point", "coordinates": [5.0, 43.00007]}}]}
"""


@pytest.mark.parametrize("kind", ["mesh", "layer"])
def test_add_object_from_files_renders_as_the_scene_file(tmp_path, kind):
    # The file paths are absolute: the file resolves them against its directory, add_object
    # against the current one.
    if kind == "mesh":
        path = tmp_path / "cube.obj"
        path.write_text(CUBE_OBJ)
        entry = {"type": "mesh", "id": 5, "file": str(path), "position": {"east_m": 0.5,
                                                                          "north_m": -6},
                 "heading_deg": 20, "scale": [1.5, 1, 1]}
    else:
        path = tmp_path / "targets.geojson"
        path.write_text(LAYER)
        entry = {"file": str(path)}
    try:
        from_file = sonarsynth.Simulation.from_yaml(with_objects([entry]), name="scene.yaml")
    except ValueError as e:
        if "assimp" in str(e):
            pytest.skip("this build reads no mesh files")
        raise
    built = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    built.add_object(**{**entry, "file": path})  # an os.PathLike is taken as its path
    assert built.object_count == from_file.object_count == 1
    a, b = render(from_file), render(built)
    assert np.any(a["object_id"] == 5)
    for f in FIELDS:
        assert a[f].tobytes() == b[f].tobytes(), f
