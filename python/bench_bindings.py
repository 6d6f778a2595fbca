#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Rendering through the Python bindings against the same loop in C++ (docs/python.md).

Both render the first PINGS survey poses of SCENE on one thread, REPEATS times, with a Simulator
built as run_simulation builds it; the C++ side is python_render_reference's `bench` mode, the
Python side Simulation.render_poses (threads=1), which also copies each ping into the batch's
numpy arrays: refilling a previous result in place (out=) and into freshly allocated arrays
(whose first-touch page faults cost the most). Prints the median pings/s of each, by wall time and by the
rendering thread's CPU time (the figure that a shared machine's load disturbs least), and their
ratio. The repeats alternate between
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
    # Builds the Simulator (pilot pings) outside the timing; `batch` is refilled in place below (out=).
    batch = sim.render_poses(poses, threads=1)
    cpp, py, cpp_cpu, py_cpu, fresh, fresh_cpu = [], [], [], [], [], []
    for r in range(a.repeats):
        out = subprocess.run([a.helper, "bench", a.scene, str(len(poses)), "1"], check=True,
                             capture_output=True, text=True).stdout
        m = re.search(r"median: ([0-9.]+) pings/s wall, ([0-9.]+) pings/s cpu", out)
        cpp.append(float(m.group(1)))
        cpp_cpu.append(float(m.group(2)))
        # threads=1 renders on the calling thread: thread_time() is its CPU time.
        for wall, cpu, kw in [(py, py_cpu, {"out": batch}), (fresh, fresh_cpu, {})]:
            t0, c0 = time.perf_counter(), time.thread_time()
            sim.render_poses(poses, threads=1, **kw)
            cpu.append(len(poses) / (time.thread_time() - c0))
            wall.append(len(poses) / (time.perf_counter() - t0))
        print(f"repeat {r}: C++ {cpp[-1]:.2f} wall / {cpp_cpu[-1]:.2f} cpu pings/s, "
              f"Python out= {py[-1]:.2f} / {py_cpu[-1]:.2f}, "
              f"fresh arrays {fresh[-1]:.2f} / {fresh_cpu[-1]:.2f}", flush=True)
    print(f"scene {a.scene}, {len(poses)} pings x {sim.samples_per_side} samples a side, "
          f"{a.repeats} repeats")
    for what, c, p, f in [("wall", cpp, py, fresh), ("cpu", cpp_cpu, py_cpu, fresh_cpu)]:
        c, p, f = statistics.median(c), statistics.median(p), statistics.median(f)
        print(f"median ({what:4}) C++ {c:.2f} pings/s, Python out= {p:.2f} pings/s "
              f"({100.0 * (p / c - 1.0):+.1f} %), Python fresh arrays {f:.2f} pings/s "
              f"({100.0 * (f / c - 1.0):+.1f} %)")


if __name__ == "__main__":
    main()
