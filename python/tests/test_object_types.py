# SPDX-License-Identifier: MIT
# The object vocabulary (docs/scene-format.md "objects"): object_types() is the table scene
# files, dataset specs and add_object read; each of its types is accepted by all three, and a
# bad parameter gets the same "Violated constraint" text from each, the table's.
import os
import pathlib

import pytest
import yaml

import sonarsynth

SAMPLES = pathlib.Path(os.environ.get("SONARSYNTH_SAMPLES",
                                      pathlib.Path(__file__).parents[2] / "samples")).resolve()

BASE = """\
name: vocabulary
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [80, 80], cell_m: 1, depth_m: 15}
survey:
  speed_m_s: 3.0
  altitude_m: 5
  lines: [{name: a, waypoints: [{east_m: -6, north_m: 20}, {east_m: 6, north_m: 20}]}]
"""


def with_object(entry):
    return BASE.replace("survey:", "objects:\n  - " + entry + "\nsurvey:")


def spec(type_name, keys):
    return f"""\
name: vocabulary
seed: 3
count: 2
location: {{lat_deg: 43.0, lon_deg: 5.0}}
seabed: {{depth_m: 12, cell_m: 0.5}}
objects:
  count: 1
  across_track_m: [2, 6]
  types:
    {type_name}: {{{keys}}}
survey: {{line_length_m: 6, altitude_m: 4, speed_m_s: 3}}
sonar: {{preset: seascan-hds-600, range_m: 10, samples: 200}}
"""


TYPES = sonarsynth.object_types()


def test_the_table_names_the_types_and_their_bounds():
    assert [t["name"] for t in TYPES] == ["pipe", "cylinder", "box", "rock", "wreck", "moored",
                                          "mesh"]
    for t in TYPES:
        assert t["shape"] in ("cylinder", "box", "ellipsoid", "mesh")
        for p in t["params"]:
            assert p["key"] in t["keys"] or t["name"] == "wreck", (t["name"], p["key"])
            assert p["lo"] < p["hi"]
            assert p["constraint"].startswith(p["key"] + (" > " if p["lo_open"] else " >= "))


@pytest.mark.parametrize("t", TYPES, ids=[t["name"] for t in TYPES])
def test_every_type_is_accepted_by_the_file_and_add_object(t, monkeypatch):
    from_file = sonarsynth.Simulation.from_yaml(with_object(t["example"]),
                                                name="scene.yaml", base_dir=str(SAMPLES))
    monkeypatch.chdir(SAMPLES)  # add_object's relative files: from the current directory
    built = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    built.add_object(yaml.safe_load(t["example"]))
    assert built.object_count == from_file.object_count > 0


@pytest.mark.parametrize("t", [t for t in TYPES if t["dataset_spec_keys"]],
                         ids=[t["name"] for t in TYPES if t["dataset_spec_keys"]])
def test_every_dataset_type_is_accepted_by_a_spec(t):
    keys = ", ".join(f"{k['key']}: {k['default']}" for k in t["dataset_spec_keys"])
    if t["name"] == "mesh":
        keys = "models: mine, " + keys
    s = sonarsynth.DatasetSpec.from_yaml(spec(t["name"], keys))
    assert s.count == 2


CASES = [("rock", "diameter_m", "-1"), ("rock", "diameter_m", "2000"),
         ("pipe", "length_m", "0"), ("moored", "height_m", "20000")]


@pytest.mark.parametrize("type_name,key,value", CASES)
def test_a_bad_parameter_gets_the_same_message_from_every_front_end(type_name, key, value):
    t = next(t for t in TYPES if t["name"] == type_name)
    constraint = next(p["constraint"] for p in t["params"] if p["key"] == key)
    entry = yaml.safe_load(t["example"])
    entry[key] = yaml.safe_load(value)
    flow = yaml.safe_dump(entry, default_flow_style=True, width=1000).strip()
    with pytest.raises(ValueError) as in_file:
        sonarsynth.Simulation.from_yaml(with_object(flow), name="scene.yaml")
    assert str(in_file.value) == (f"scene.yaml: objects[0].{key} = '{value}'. "
                                  f"Violated constraint: {constraint}")
    sim = sonarsynth.Simulation.from_yaml(BASE, name="scene.yaml")
    with pytest.raises(ValueError) as in_call:
        sim.add_object(entry)
    assert str(in_call.value) == (f"scene.yaml: add_object.{key} = '{value}'. "
                                  f"Violated constraint: {constraint}")
    with pytest.raises(ValueError) as in_spec:
        sonarsynth.DatasetSpec.from_yaml(spec(type_name, f"{key}: {value}"))
    assert str(in_spec.value) == (f"spec.yaml: objects.types.{type_name}.{key} = '{value}'. "
                                  f"Violated constraint: {constraint}")
