# SPDX-License-Identifier: MIT
# Configuration through the single option table: the names, units and messages of a scene file.
import pytest

import sonarsynth
from conftest import SCENE


def test_every_option_listed_once():
    paths = [o["path"] for o in sonarsynth.options()]
    assert len(paths) == len(set(paths))
    for p in ["seed", "sonar.range_m", "sonar.samples", "sonar.tilt_deg", "noise.model",
              "render.quality.grid_subdivisions", "survey.speed_m_s"]:
        assert p in paths


def test_set_get_round_trip(scene_path):
    sim = sonarsynth.Simulation.from_file(scene_path)
    assert sim.get("sonar.range_m") == 20.0
    assert sim.get("sonar.samples") == 300
    sim.set("sonar.range_m", 35)
    sim.set({"sonar": {"samples": 128, "tilt_deg": 12.5}, "seed": 99})
    sim.set({"sonar.frequency_khz": 450.0})
    assert sim.get("sonar.range_m") == 35.0
    assert sim.get("sonar.samples") == 128
    assert sim.get("sonar.tilt_deg") == 12.5
    assert sim.get("sonar.frequency_khz") == 450.0
    assert sim.get("seed") == 99
    assert sim.settings()["sonar.samples"] == 128
    out = sim.render_poses(sim.survey_poses()[:2])
    assert out["samples"].shape == (2, 2, 128)


def test_set_equals_the_same_values_in_the_file(tmp_path):
    """Settings made with set() render exactly as the same values written in the file."""
    edited = SCENE.replace("range_m: 20, samples: 300", "range_m: 25, samples: 200, tilt_deg: 15")
    p1, p2 = tmp_path / "a.yaml", tmp_path / "b.yaml"
    p1.write_text(SCENE)
    p2.write_text(edited + "noise: {model: paper, uniform_variance: 0.02}\n")
    a = sonarsynth.Simulation.from_file(str(p1))
    a.set({"sonar.range_m": 25, "sonar.samples": 200, "sonar.tilt_deg": 15,
           "noise": {"model": "paper", "uniform_variance": 0.02}})
    b = sonarsynth.Simulation.from_file(str(p2))
    assert a.settings() == b.settings()
    ra = a.render_poses(a.survey_poses()[:10])
    rb = b.render_poses(b.survey_poses()[:10])
    assert ra["samples"].tobytes() == rb["samples"].tobytes()


BAD = [
    ("sonar", "range_m", "-5"),
    ("sonar", "samples", "0"),
    ("sonar", "samples", "2.5"),
    ("sonar", "tilt_deg", "200"),
    ("sonar", "preset", "nope"),
    ("noise", "model", "bogus"),
    ("render", "absorption", "maybe"),
    ("survey", "speed_m_s", "0"),
    ("", "seed", "-1"),
]


def scene_with(section, key, value):
    """SCENE with `key: value` added to `section` (a new top-level section if absent)."""
    if section == "":
        return SCENE.replace("seed: 11", f"seed: {value}")
    if section == "sonar":
        sonar = "sonar: {frequency_khz: 600, range_m: 20, samples: 300}"
        items = dict(kv.split(": ") for kv in sonar[len("sonar: {"):-1].split(", "))
        items[key] = value
        return SCENE.replace(sonar, "sonar: {" + ", ".join(f"{k}: {v}" for k, v in items.items()) + "}")
    if section == "survey":
        return SCENE.replace("  speed_m_s: 3.0\n", f"  {key}: {value}\n")
    return SCENE + f"{section}: {{{key}: {value}}}\n"


@pytest.mark.parametrize("section,key,value", BAD)
def test_validation_messages_equal_the_scene_files(tmp_path, scene_path, section, key, value):
    bad = tmp_path / "bad.yaml"
    bad.write_text(scene_with(section, key, value))
    with pytest.raises(ValueError) as from_file:
        sonarsynth.Simulation.from_file(str(bad))
    sim = sonarsynth.Simulation.from_yaml(SCENE, name=str(bad), base_dir=str(tmp_path))
    path = f"{section}.{key}" if section else key
    # The value as Python gives it: a number when the file holds one.
    try:
        py_value = int(value)
    except ValueError:
        try:
            py_value = float(value)
        except ValueError:
            py_value = value
    with pytest.raises(ValueError) as from_set:
        sim.set(path, py_value)
    assert str(from_set.value) == str(from_file.value)
    assert str(from_file.value).startswith(str(bad) + ": ")


def test_unknown_option(scene_path):
    sim = sonarsynth.Simulation.from_file(scene_path)
    with pytest.raises(ValueError, match="rnage_m: unknown key"):
        sim.set("sonar.rnage_m", 3)
    with pytest.raises(ValueError, match="not an option"):
        sim.get("sonar.rnage_m")


# Constraints between keys: set() takes each value alone (others may follow), the Simulation
# refuses the combination before it renders, with the scene file's constraint.
@pytest.mark.parametrize("section,key,value", [("sonar", "ping_period_s", "0.001"),
                                               ("sensor", "ring_down_m", "9"),
                                               ("sonar", "samples", "9000")])
def test_constraints_between_keys_are_the_scene_files(tmp_path, section, key, value):
    bad = tmp_path / "bad.yaml"
    bad.write_text(scene_with(section, key, value))
    with pytest.raises(ValueError) as from_file:
        sonarsynth.Simulation.from_file(str(bad))
    sim = sonarsynth.Simulation.from_yaml(SCENE, name=str(bad), base_dir=str(tmp_path))
    sim.set(f"{section}.{key}", float(value) if "." in value else int(value))
    with pytest.raises(ValueError) as from_render:
        sim.gain_db
    assert str(from_render.value).startswith(f"{bad}: {section}.{key} = ")
    constraint = str(from_file.value).split("Violated constraint: ")[1]
    assert str(from_render.value).split("Violated constraint: ")[1] == constraint
    # Repaired, it renders.
    repair = {"ping_period_s": ("sonar.ping_period_s", 0.1), "ring_down_m": ("sonar.range_m", 95),
              "samples": ("output.allow_more_than_8192_samples", True)}[key]
    sim.set(*repair)
    assert sim.gain_db == sim.gain_db
