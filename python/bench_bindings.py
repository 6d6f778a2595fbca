#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Rendering through the Python bindings against the same loop in C++ (docs/python.md).

Both render the first PINGS survey poses of SCENE on one thread, REPEATS times, with a Simulator
built as run_simulation builds it; the C++ side is python_render_reference's `bench` mode, the
Python side Simulation.render_poses (threads=1), which also copies each ping into the batch's
numpy arrays. Prints the median pings/s of each and their ratio. The repeats alternate between
the two so that a change of the machine's load hits both.

  PYTHONPATH=build/python /usr/bin/python3 python/bench_bindings.py \
      --helper build/python/python_render_reference --scene samples/rough_seabed.yaml
"""
import argparse
import re
import statistics
import subprocess
import time

import sonarsynth


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--helper", required=True, help="build/python/python_render_reference")
    ap.add_argument("--scene", required=True, help="scene file")
    ap.add_argument("--pings", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=7)
    a = ap.parse_args()

    sim = sonarsynth.Simulation.from_file(a.scene)
    poses = sim.survey_poses()[: a.pings]
    sim.render_poses(poses[:2], threads=1)  # builds the Simulator (pilot pings) outside the timing
    cpp, py = [], []
    for r in range(a.repeats):
        out = subprocess.run([a.helper, "bench", a.scene, str(len(poses)), "1"], check=True,
                             capture_output=True, text=True).stdout
        cpp.append(float(re.search(r"median: ([0-9.]+)", out).group(1)))
        t0 = time.perf_counter()
        sim.render_poses(poses, threads=1)
        py.append(len(poses) / (time.perf_counter() - t0))
        print(f"repeat {r}: C++ {cpp[-1]:.2f} pings/s, Python {py[-1]:.2f} pings/s", flush=True)
    c, p = statistics.median(cpp), statistics.median(py)
    print(f"scene {a.scene}, {len(poses)} pings x {sim.samples_per_side} samples a side, "
          f"{a.repeats} repeats")
    print(f"median C++    {c:.2f} pings/s")
    print(f"median Python {p:.2f} pings/s  ({100.0 * (p / c - 1.0):+.1f} %)")


if __name__ == "__main__":
    main()
