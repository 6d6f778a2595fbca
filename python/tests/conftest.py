# SPDX-License-Identifier: MIT
# Shared fixtures of the Python module's tests (docs/python.md). ctest sets PYTHONPATH to the
# built module and SONARSYNTH_CLI / SONARSYNTH_PY_HELPER to the C++ programs they compare with.
import os
import pathlib
import subprocess

import numpy as np
import pytest

import sonarsynth

SCENE = """\
name: py-test
seed: 11
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [80, 80], cell_m: 0.5, depth_m: 12,
             components: [{type: fbm, rms_m: 0.05, wavelength_m: 6, octaves: 3}]}
objects:
  - {type: box, id: 3, position: {east_m: 0, north_m: -6}, heading_deg: 10, size_m: [2, 1, 0.8]}
  - {type: rock, id: 7, position: {east_m: 2, north_m: 7}, diameter_m: 1.2}
  - {type: pipe, id: 9, start: {east_m: -10, north_m: 12}, end: {east_m: 10, north_m: 14}, diameter_m: 0.4}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 3.0
  altitude_m: 5
  disturbance: {roll_deg: 0.5, pitch_deg: 0.3, yaw_deg: 0.3, heave_m: 0.05, period_s: 5}
  lines:
    - {name: a, waypoints: [{east_m: -6, north_m: 0}, {east_m: 6, north_m: 0}]}
    - {name: b, waypoints: [{east_m: 6, north_m: 3}, {east_m: -6, north_m: 3}]}
sonar: {frequency_khz: 600, range_m: 20, samples: 300}
"""


def tiny_dataset(name="tiny", line_length_m=6, run=""):
    """The dataset spec of tiny_dataset.yaml (its comment lines left out) named `name`, with a
    `line_length_m` line and `run` (a "run:" section) appended."""
    lines = (pathlib.Path(__file__).parent / "tiny_dataset.yaml").read_text().splitlines(True)
    text = "".join(line for line in lines if not line.startswith("#"))
    text = text.replace("name: tiny\n", f"name: {name}\n", 1)
    return text.replace("line_length_m: 6,", f"line_length_m: {line_length_m},", 1) + run


def helper(name):
    path = os.environ.get(name)
    if not path:
        pytest.skip(f"{name} not set (run the tests through ctest)")
    return path


@pytest.fixture
def scene_path(tmp_path):
    p = tmp_path / "scene.yaml"
    p.write_text(SCENE)
    return str(p)


@pytest.fixture
def reference_helper():
    return helper("SONARSYNTH_PY_HELPER")


@pytest.fixture
def cli():
    return helper("SONARSYNTH_CLI")


def read_reference(path, pings, samples):
    """The C++ helper's dump: per ping, port then starboard, each samples / class / id /
    grazing / ground x / ground y (python/render_reference.cpp)."""
    side = np.dtype([("samples", "<f4", samples), ("truth_class", "u1", samples),
                     ("object_id", "<i4", samples), ("grazing_rad", "<f4", samples),
                     ("ground_x_m", "<f8", samples), ("ground_y_m", "<f8", samples)])
    data = np.fromfile(path, dtype=side)
    assert data.size == 2 * pings
    return data.reshape(pings, 2)


def run_reference(helper_path, scene, out):
    subprocess.run([helper_path, "dump", scene, str(out)], check=True)
