# SPDX-License-Identifier: MIT
"""Memory of sonarsynth_dask.generate() against the number of items (docs/dataset.md); not a test.

    PYTHONPATH=build/python /usr/bin/python3 python/bench_dask_memory.py OUT \
        [--items 1000 10000 100000] [--window W] [--workers 2] [--module DIR]

Each count runs in a fresh process (so that its peak is its own): generate() over that many
trivial items (an item function that renders nothing and returns the item's record, through
``item_fn``, or, for a sonarsynth_dask without it, in place of sonarsynth.run_dataset_item) on
the default local_cluster, whose scheduler and worker threads live in the same process as the
client. The process's resident memory is sampled every 0.1 s; printed per count: the wall time,
items/s, the resident memory before generate(), its largest sample until the last item was
collected, VmHWM (the peak of the process, the manifest written at the end included) and the
growth of the peak over the baseline. --module DIR imports sonarsynth_dask from DIR (e.g. an
older version, for comparison). Every run writes into a fresh directory under OUT, removed
afterwards.
"""
import argparse
import inspect
import json
import os
import shutil
import subprocess
import sys
import threading
import time

SPEC = """\
name: trivial
seed: 7
count: {count}
location: {{lat_deg: 43.0, lon_deg: 5.0}}
seabed: {{depth_m: 12}}
survey: {{line_length_m: 6, altitude_m: 4, speed_m_s: 3}}
sonar: {{preset: seascan-hds-600, range_m: 10, samples: 200}}
"""


def status_kib(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    raise RuntimeError(field + " not in /proc/self/status")


def trivial_item(spec, out_dir, index, threads):
    """An item that renders nothing: the record a skipped item would return, without files."""
    return {"index": index, "seed": spec.item_seed(index), "status": "done", "split": "",
            "repaired": "", "error": "", "files": [], "objects": {}, "pings": 0, "seconds": 0.0}


def child(count, out, window, workers):
    import sonarsynth
    import sonarsynth_dask
    spec = sonarsynth.DatasetSpec.from_yaml(SPEC.format(count=count), "trivial.yaml")
    kwargs = {"n_workers": workers, "progress": False}
    if window:
        kwargs["window"] = window
    if "item_fn" in inspect.signature(sonarsynth_dask.generate).parameters:
        kwargs["item_fn"] = trivial_item
        kwargs["dashboard"] = False
    else:  # an older sonarsynth_dask: its run_item calls sonarsynth.run_dataset_item
        sonarsynth.run_dataset_item = trivial_item
    samples = []
    stop = threading.Event()

    def sample():
        while not stop.wait(0.1):
            samples.append((time.monotonic(), status_kib("VmRSS")))

    last = [0.0]

    def progress(done, total, item):
        if done == total:
            last[0] = time.monotonic()

    kwargs["progress"] = progress
    base = status_kib("VmRSS")
    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    t0 = time.monotonic()
    r = sonarsynth_dask.generate(spec, out, **kwargs)
    seconds = time.monotonic() - t0
    stop.set()
    sampler.join()
    assert r["done"] == count and r["failed"] == 0, r["failures"][:3]
    loop_peak = max([base] + [kib for t, kib in samples if t <= last[0]])
    print(json.dumps({"items": count, "seconds": seconds, "items_per_s": count / seconds,
                      "base_kib": base, "loop_peak_kib": loop_peak,
                      "hwm_kib": status_kib("VmHWM")}))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--items", type=int, nargs="+", default=[1000, 10000, 100000])
    ap.add_argument("--window", type=int, default=0, help="0: generate()'s default")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--module", default="", help="import sonarsynth_dask from this directory")
    ap.add_argument("--child", type=int, default=0, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.module:
        sys.path.insert(0, a.module)
    if a.child:
        child(a.child, a.out, a.window, a.workers)
        return
    env = dict(os.environ)
    print("%9s %9s %9s %10s %12s %10s %10s" % ("items", "seconds", "items/s", "base MiB",
                                                "loop peak", "VmHWM", "growth"))
    for n in a.items:
        out = os.path.join(a.out, "items-%d" % n)
        shutil.rmtree(out, ignore_errors=True)
        cmd = [sys.executable, os.path.abspath(__file__), out, "--child", str(n), "--window",
               str(a.window), "--workers", str(a.workers)]
        if a.module:
            cmd += ["--module", a.module]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True)
        shutil.rmtree(out, ignore_errors=True)
        if p.returncode != 0:
            sys.exit(p.stderr[-4000:])
        r = json.loads(p.stdout.strip().splitlines()[-1])
        mib = lambda kib: kib / 1024.0  # noqa: E731
        print("%9d %9.1f %9.0f %10.1f %12.1f %10.1f %10.1f" % (
            n, r["seconds"], r["items_per_s"], mib(r["base_kib"]), mib(r["loop_peak_kib"]),
            mib(r["hwm_kib"]), mib(r["hwm_kib"] - r["base_kib"])), flush=True)


if __name__ == "__main__":
    main()
