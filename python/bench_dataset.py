# SPDX-License-Identifier: MIT
"""Benchmark of the dataset generator (docs/dataset.md, docs/benchmarks.md); not a test.

    PYTHONPATH=build/python /usr/bin/python3 python/bench_dataset.py samples/datasets/small.yaml \
        /tmp/bench-dataset [--serial-items 40] [--cluster-items 16]

1. Serial: the first --serial-items items of the spec, one after the other with all cores per
   item (what `sonarsynth dataset` does): wall and CPU seconds per item, and the time of the
   spec's whole count extrapolated from them (items are drawn from the same distributions).
2. Dask: the first --cluster-items items on a LocalCluster of 1 worker process, then of 2 (one
   thread each, one rendering thread per item): items/s and the ratio.
Every run writes into a fresh directory under OUT, removed afterwards.
"""
import argparse
import os
import resource
import shutil
import time

import sonarsynth
import sonarsynth_dask


def subset(spec, n):
    """The same spec with count n: items depend on (seed, index) only, so these are the spec's
    first n items."""
    text = spec.text
    lines = [("count: %d" % n) if l.startswith("count:") else l for l in text.splitlines()]
    return sonarsynth.DatasetSpec.from_yaml("\n".join(lines) + "\n", spec.file)


def cpu_s():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def cluster_run(spec, out, workers):
    from dask.distributed import Client
    cluster = sonarsynth_dask.local_cluster(workers)
    client = Client(cluster)
    client.wait_for_workers(workers)
    # Warm-up: one item per worker (process start, module import), not timed.
    warm = subset(spec, workers)
    sonarsynth_dask.generate(warm, out + "-warm", client=client, progress=False)
    t0 = time.monotonic()
    r = sonarsynth_dask.generate(spec, out, client=client, progress=False)
    dt = time.monotonic() - t0
    client.close()
    cluster.close()
    assert r["done"] == spec.count, r["failures"]
    shutil.rmtree(out + "-warm")
    shutil.rmtree(out)
    return dt


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("spec")
    ap.add_argument("out")
    ap.add_argument("--serial-items", type=int, default=40)
    ap.add_argument("--cluster-items", type=int, default=16)
    a = ap.parse_args()
    full = sonarsynth.DatasetSpec.from_file(a.spec)
    os.makedirs(a.out, exist_ok=True)
    print("cores: %d, load average before: %.2f %.2f %.2f" % ((os.cpu_count(),) +
                                                             os.getloadavg()))

    if a.serial_items > 0:
        spec = subset(full, a.serial_items)
        out = os.path.join(a.out, "serial")
        c0, t0 = cpu_s(), time.monotonic()
        r = sonarsynth.run_dataset(spec, out)
        wall, cpu = time.monotonic() - t0, cpu_s() - c0
        assert r["failed"] == 0
        pings = sum(it["pings"] for it in r["items"])
        size = sum(os.path.getsize(os.path.join(dp, f)) for dp, _, fs in os.walk(out) for f in fs)
        shutil.rmtree(out)
        n = a.serial_items
        print("serial, all cores per item: %d items (%d pings, %.0f MB) in %.1f s wall, %.1f s CPU:"
              " %.2f s wall and %.2f s CPU per item" % (n, pings, size / 1e6, wall, cpu, wall / n,
                                                        cpu / n))
        print("  extrapolated to %d items: %.0f s wall (%.1f min), %.0f MB" %
              (full.count, wall / n * full.count, wall / n * full.count / 60,
               size / n * full.count / 1e6))
        print("  load average after: %.2f %.2f %.2f" % os.getloadavg())

    if a.cluster_items > 0:
        spec = subset(full, a.cluster_items)
        t1 = cluster_run(spec, os.path.join(a.out, "w1"), 1)
        print("LocalCluster, 1 worker:  %d items in %.1f s (%.3f items/s)" %
              (spec.count, t1, spec.count / t1))
        t2 = cluster_run(spec, os.path.join(a.out, "w2"), 2)
        print("LocalCluster, 2 workers: %d items in %.1f s (%.3f items/s), %.2fx one worker" %
              (spec.count, t2, spec.count / t2, t1 / t2))
        print("  load average after: %.2f %.2f %.2f" % os.getloadavg())


if __name__ == "__main__":
    main()
