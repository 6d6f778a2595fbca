# SPDX-License-Identifier: MIT
"""Typed use of the module: test_stubs.py type-checks this file with `mypy --strict` against the
package's stubs, and runs it, so the stubs say what the module does (docs/python.md, Type stubs).
"""
from typing import Any, Dict, List, Tuple

import numpy as np
import numpy.typing as npt

import sonarsynth


def use_api(scene_path: str, xtf_path: str, spec_path: str) -> Dict[str, Any]:
    sim = sonarsynth.Simulation.from_file(scene_path, seed=3, range_m=20.0)
    sim.set("sonar.samples", 200)
    sim.set({"sonar": {"tilt_deg": 20}})
    samples: int = sim.samples_per_side
    bounds: Tuple[Any, ...] = sim.bounds_m
    poses: npt.NDArray[np.void] = sim.survey_poses()
    ping = sim.render_ping(float(poses["sensor_x_m"][0]), float(poses["sensor_y_m"][0]),
                           float(poses["sensor_z_m"][0]), heading_rad=0.1, noise_key=7)
    batch = sim.render_poses(poses[:2], threads=1)
    rendered: npt.NDArray[np.float32] = batch["samples"]
    made = sim.make_poses(np.array([0.0]), np.array([0.0]), np.array([-5.0]))
    record = np.zeros(1, dtype=sonarsynth.POSE_DTYPE)
    options: List[Any] = sonarsynth.options()
    xtf = sonarsynth.read_xtf(xtf_path)
    try:
        sonarsynth.read_sonar(xtf_path + ".missing")
        missing_error = ""
    except sonarsynth.FormatError as e:
        missing_error = str(e)
    spec = sonarsynth.DatasetSpec.from_file(spec_path)
    return {"version": sonarsynth.__version__, "samples": samples, "bounds": bounds,
            "ping_shape": ping["port"]["samples"].shape, "batch_shape": rendered.shape,
            "made": len(made), "record": record.dtype == made.dtype, "options": len(options),
            "xtf_pings": xtf["port"].shape[0], "missing_error": missing_error,
            "spec_count": spec.count, "split": spec.item_split(0),
            "classes": len(sonarsynth.SAMPLE_CLASSES), "item_dir": sonarsynth.dataset_item_dir(3)}
