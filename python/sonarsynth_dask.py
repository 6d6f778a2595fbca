# SPDX-License-Identifier: MIT
"""Scale-out of the sonarsynth dataset generator on Dask (docs/dataset.md).

Every item of a dataset spec is one Dask task: ``sonarsynth.run_dataset_item`` on a worker,
which renders the item into the shared dataset directory atomically. An item is a pure function
of (spec, seed, index), so it is byte-identical whichever worker renders it, in whatever order.
A task that fails is retried by Dask (``retries``); an item that still fails is reported with its
index and seed, recorded in ``failed/<index>.json`` and in the manifest, never dropped.

    from dask.distributed import Client
    import sonarsynth, sonarsynth_dask
    spec = sonarsynth.DatasetSpec.from_file("samples/datasets/small.yaml")
    result = sonarsynth_dask.generate(spec, "small-dataset", client=Client("tcp://host:8786"))
"""
import json
import os
import sys
import time
import uuid

import sonarsynth

__all__ = ["generate", "run_item"]


def run_item(spec, out_dir, index, threads=1, before_item=None):
    """One item on a worker: ``before_item(index, seed)`` (if given; a test hook) then
    ``sonarsynth.run_dataset_item``. Returns its result dict; raises if the item fails."""
    if before_item is not None:
        before_item(index, spec.item_seed(index))
    return sonarsynth.run_dataset_item(spec, out_dir, index, threads)


def _record_failure(out_dir, spec, index, error):
    """failed/<index>.json in the generator's own format (the manifest reads it), unless the
    generator wrote one already."""
    path = os.path.join(out_dir, "failed", "%06d.json" % index)
    if os.path.exists(path):
        return
    record = {"error": error, "index": index, "seed": spec.item_seed(index), "status": "failed"}
    tmp = path + ".tmp-%d" % os.getpid()
    with open(tmp, "w") as f:
        f.write(json.dumps(record, sort_keys=True, separators=(",", ":")) + "\n")
    os.replace(tmp, path)


def _print_progress(done, total, item):
    state = item["status"]
    extra = "" if state != "failed" else ": " + item["error"]
    print("[%d/%d] item %d (seed %d) %s%s" % (done, total, item["index"], item["seed"], state,
                                              extra), file=sys.stderr, flush=True)


# What a LocalCluster of ours leaves out or slows down: periodic work of Dask that costs CPU the
# items then lack once every core renders an item (measured in docs/dataset.md, Benchmarks: with
# Dask's defaults, 0.24-0.35 s of CPU per item besides the items' own 1.2-1.3 s, on two workers):
# - the workers' statistical profiler samples Python stacks every 10 ms; the items' time is spent
#   in C++, where the samples see nothing;
# - the event-loop tick monitor (every 20 ms, only warns of a blocked loop), the system monitor
#   (every 0.5 s, feeds the dashboard) and the memory monitor (every 0.1 s; items take a few
#   hundred MiB at most) run every second or less often;
# - work stealing (every 0.1 s) is off: every task is one item of about the same length, queued on
#   the scheduler until a worker is free.
WORKER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.scheduler.work-stealing": False,
}


def local_cluster(n_workers, processes=False):
    """A LocalCluster of ``n_workers`` single-threaded workers with WORKER_CONFIG.

    processes=False (default): the workers are threads of this process, next to the scheduler,
    with no nanny and no worker process (an item runs in C++ without the GIL, so two items run
    on two cores). One event loop instead of one per process: 0.03 s of CPU per item besides the
    item against 0.09 s with worker processes (docs/dataset.md, Benchmarks). A crash of the C++
    code (not an exception: those are retried) ends the whole run, which is resumable.
    processes=True: one worker process per worker, each under a nanny (the config is handed on).
    """
    import dask
    from dask.distributed import LocalCluster
    with dask.config.set(WORKER_CONFIG):
        return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=processes,
                            dashboard_address=None)


def generate(spec, out_dir, client=None, n_workers=2, indices=None, shard=(0, 1),
             threads_per_item=1, retries=2, progress=True, before_item=None, processes=False):
    """Renders the items of ``spec`` (a sonarsynth.DatasetSpec or a spec file's path) into ``out_dir`` as Dask tasks.

    client: a dask.distributed.Client (any cluster; ``out_dir`` must be a path every worker can
        write, e.g. a shared file system); None starts ``local_cluster(n_workers, processes)``
        (by default ``n_workers`` one-thread workers in this process), closed at the end.
    indices: the items to run (default: all of this shard); shard=(K, N): the items i with
        i % N == K, as ``sonarsynth dataset --shard K/N``.
    threads_per_item: rendering threads per item (1 suits one worker process per core); the
        files do not depend on it.
    retries: how many times Dask re-runs a failed item before reporting it.
    progress: True prints one line per finished item to stderr; a callable gets
        (done, total, item) with item a dict (index, seed, status, error, ...); False: silent.
    before_item: a callable (index, seed) run on the worker before each item (test hook).

    Returns {"items": [item dicts in index order], "done", "skipped", "failed",
    "failures": [{"index", "seed", "error"}], "seconds": wall time}. The manifest and summary
    are rewritten at the end.
    """
    from dask.distributed import Client, as_completed

    t0 = time.monotonic()
    if isinstance(spec, (str, os.PathLike)):
        spec = sonarsynth.DatasetSpec.from_file(os.fspath(spec))
    out_dir = os.path.abspath(str(out_dir))
    sonarsynth.prepare_dataset_dir(spec, out_dir)
    k, n = shard
    if indices is None:
        indices = range(k, spec.count, n)
    indices = list(indices)
    report = _print_progress if progress is True else (progress or None)

    own = None
    if client is None:
        cluster = local_cluster(n_workers, processes)
        own = (cluster, Client(cluster))
        client = own[1]
    try:
        # Keys unique to this call: Dask hands out a finished result again for a key it still
        # holds, and an item's result depends on the state of out_dir.
        run_token = uuid.uuid4().hex
        futures = {}
        for i in indices:
            f = client.submit(run_item, spec, out_dir, i, threads_per_item, before_item,
                              key="sonarsynth-item-%06d-%s" % (i, run_token), pure=False,
                              retries=retries)
            futures[f] = i
        items = {}
        for f in as_completed(list(futures)):
            i = futures[f]
            if f.status == "finished":
                item = f.result()
            else:
                error = "%s: %s" % (type(f.exception()).__name__, f.exception())
                item = {"index": i, "seed": spec.item_seed(i), "status": "failed",
                        "error": error, "files": [], "objects": {}, "pings": 0, "seconds": 0.0}
                _record_failure(out_dir, spec, i, error)
            items[i] = item
            if report:
                report(len(items), len(indices), item)
    finally:
        if own is not None:
            own[1].close()
            own[0].close()
    sonarsynth.write_dataset_manifest(spec, out_dir)
    ordered = [items[i] for i in sorted(items)]
    failures = [{"index": it["index"], "seed": it["seed"], "error": it["error"]}
                for it in ordered if it["status"] == "failed"]
    return {
        "items": ordered,
        "done": sum(it["status"] == "done" for it in ordered),
        "skipped": sum(it["status"] == "skipped" for it in ordered),
        "failed": len(failures),
        "failures": failures,
        "seconds": time.monotonic() - t0,
    }
