# SPDX-License-Identifier: MIT
"""Benchmark of the dataset generator (docs/dataset.md, docs/benchmarks.md); not a test.

    PYTHONPATH=build/python /usr/bin/python3 python/bench_dataset.py samples/datasets/small.yaml \
        /tmp/bench-dataset [--serial-items 40] [--cluster-items 16] [--repeat 5] [--processes]

1. Serial: the first --serial-items items of the spec, one after the other with all cores per
   item (what `sonarsynth dataset` does): wall and CPU seconds per item, and the time of the
   spec's whole count extrapolated from them (items are drawn from the same distributions).
2. Dask: the first --cluster-items items on sonarsynth_dask.local_cluster with 1 worker, then
   with 2 (one thread each, one rendering thread per item; threads of this process, or worker
   processes with --processes), alternately --repeat times: each run's time and load average,
   the medians and the ratio of the medians (2 workers against 1).
Every run writes into a fresh directory under OUT, removed afterwards.
"""
import argparse
import os
import resource
import shutil
import statistics
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


def cluster_run(spec, out, workers, processes):
    from dask.distributed import Client
    cluster = sonarsynth_dask.local_cluster(workers, processes)
    client = Client(cluster)
    client.wait_for_workers(workers)
    # Warm-up: one item per worker (process start, module import), not timed.
    warm = subset(spec, workers)
    sonarsynth_dask.generate(warm, out + "-warm", client=client, progress=False)
    t0 = time.monotonic()
    r = sonarsynth_dask.generate(spec, out, client=client, progress=False, keep_items=True)
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
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--processes", action="store_true", help="worker processes (with nannies)")
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
        kind = "worker processes" if a.processes else "worker threads"
        times = {1: [], 2: []}
        for rep in range(a.repeat):
            for w in (1, 2):
                t = cluster_run(spec, os.path.join(a.out, "w%d" % w), w, a.processes)
                times[w].append(t)
                print("run %d, %d %s: %d items in %.1f s (%.3f items/s), load average %.2f" %
                      (rep + 1, w, kind, spec.count, t, spec.count / t, os.getloadavg()[0]),
                      flush=True)
        m1, m2 = statistics.median(times[1]), statistics.median(times[2])
        ratios = [t1 / t2 for t1, t2 in zip(times[1], times[2])]
        print("LocalCluster (%s), %d items, %d alternating runs: median %.1f s with 1 worker, "
              "%.1f s with 2: %.2fx (run by run %.2f-%.2fx)" %
              (kind, spec.count, a.repeat, m1, m2, m1 / m2, min(ratios), max(ratios)))
        print("  load average after: %.2f %.2f %.2f" % os.getloadavg())


if __name__ == "__main__":
    main()
