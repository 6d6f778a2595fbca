# SPDX-License-Identifier: MIT
"""Scale-out of the sonarsynth dataset generator on Dask (docs/dataset.md).

Every item of a dataset spec is one Dask task: ``sonarsynth.run_dataset_item`` on a worker,
which renders the item into the shared dataset directory atomically. An item is a pure function
of (spec, seed, index), so it is byte-identical whichever worker renders it, in whatever order.
A task that fails is retried by Dask (``retries``); an item that still fails is reported with its
index and seed, recorded in ``failed/<index>.json`` (``sonarsynth.record_dataset_failure``, the
generator's own record) and in the manifest, never dropped. At most ``window`` tasks are in the
cluster at once, so the client's memory does not grow with the number of items.

    from dask.distributed import Client
    import sonarsynth, sonarsynth_dask
    spec = sonarsynth.DatasetSpec.from_file("samples/datasets/small.yaml")
    result = sonarsynth_dask.generate(spec, "small-dataset", client=Client("tcp://host:8786"))
"""
import importlib.util
import os
import sys
import threading
import time
import uuid

import sonarsynth

__all__ = ["ItemFailed", "dashboard_link", "generate", "local_cluster", "run_item"]


class ItemFailed(Exception):
    """A task of an item ended with a BaseException that is not an Exception (SystemExit,
    KeyboardInterrupt raised inside the task): raised in its place, so that Dask retries and
    reports the item like any other failure. ``error`` is the original's "Type: message"."""

    def __init__(self, error):
        super().__init__(error)
        self.error = error


def _error_text(e):
    text = str(e)
    return "%s: %s" % (type(e).__name__, text) if text else type(e).__name__


def _mark_recorded(e):
    """Tells the client that failed/<index>.json holds this failure already."""
    try:
        e.sonarsynth_recorded = True
    except AttributeError:  # an exception type without a __dict__: the client records it
        pass


def run_item(spec, out_dir, index, threads=1, before_item=None, item_fn=None):
    """One item on a worker: ``before_item(index, seed)`` (if given; a test hook) then
    ``sonarsynth.run_dataset_item`` (or ``item_fn(spec, out_dir, index, threads)``, a stand-in
    for tests and benchmarks). Returns the item's result dict; raises if the item fails, after
    recording the failure in failed/<index>.json (run_dataset_item records its own).

    A SystemExit or KeyboardInterrupt raised inside the task (never a user's Ctrl-C: Dask runs
    tasks on threads of its own, and signals reach only the main thread) is recorded and raised
    as ItemFailed, an ordinary exception: Dask would otherwise let it through and stop the
    worker's event loop (with worker threads, the whole cluster), and generate() would never
    return. Called on the main thread (directly, not by Dask), it lets them through unchanged.
    """
    try:
        if before_item is not None:
            before_item(index, spec.item_seed(index))
        if item_fn is not None:
            return item_fn(spec, out_dir, index, threads)
        try:
            return sonarsynth.run_dataset_item(spec, out_dir, index, threads)
        except Exception as e:
            _mark_recorded(e)  # run_dataset_item wrote failed/<index>.json itself
            raise
    except BaseException as e:
        if getattr(e, "sonarsynth_recorded", False):
            raise
        if (not isinstance(e, Exception) and
                threading.current_thread() is threading.main_thread()):
            raise
        error = _error_text(e)
        recorded = False
        try:
            sonarsynth.record_dataset_failure(spec, out_dir, index, error)
            recorded = True
        except Exception:  # the client records it when the item has failed for good
            pass
        if isinstance(e, Exception):
            if recorded:
                _mark_recorded(e)
            raise
        failed = ItemFailed(error)
        if recorded:
            _mark_recorded(failed)
        raise failed from e


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

# Dask's debugging logs (task transitions, read by `story()`; results sent), bounded but long:
# 100,000 entries on the scheduler and on each worker (hard-coded there in Dask 2022.12), several
# per item, so the memory of a run grew with its items up to some 10^5 items (docs/dataset.md,
# Dask). A LocalCluster of ours keeps the last LOG_LENGTH entries of each.
LOG_LENGTH = 5000
LOG_CONFIG = {"distributed.scheduler.transition-log-length": LOG_LENGTH}


def _shorten_worker_log(dask_worker):
    """A worker's logs of transitions (WorkerState.log in Dask 2022.12) and of results sent
    (Worker.transfer_outgoing_log: one entry per item whose result the client fetched) cut to
    LOG_LENGTH entries."""
    from collections import deque
    for owner, name in ((getattr(dask_worker, "state", None), "log"),
                        (dask_worker, "transfer_outgoing_log"),
                        (dask_worker, "transfer_incoming_log")):
        log = getattr(owner, name, None)
        if isinstance(log, deque) and (log.maxlen is None or log.maxlen > LOG_LENGTH):
            setattr(owner, name, deque(log, maxlen=LOG_LENGTH))


def local_cluster(n_workers, processes=False, dashboard=True):
    """A LocalCluster of ``n_workers`` single-threaded workers with WORKER_CONFIG.

    processes=False (default): the workers are threads of this process, next to the scheduler,
    with no nanny and no worker process (an item runs in C++ without the GIL, so two items run
    on two cores). One event loop instead of one per process: 0.03 s of CPU per item besides the
    item against 0.09 s with worker processes (docs/dataset.md, Benchmarks). A crash of the C++
    code (not an exception: those are retried) ends the whole run, which is resumable.
    processes=True: one worker process per worker, each under a nanny (the config is handed on).
    Dask's transition logs are cut to their last LOG_LENGTH entries (memory, see LOG_LENGTH).
    dashboard: True (default) serves Dask's dashboard on a free port (":0", every interface, as
    Dask's own default ":8787" does; a free port so that clusters side by side never clash);
    False: none (no page served); a string: that address (e.g. "localhost:8787"). Its link:
    ``dashboard_link(cluster)``.
    """
    import dask
    from dask.distributed import LocalCluster
    config = dict(WORKER_CONFIG, **LOG_CONFIG)
    on = dashboard is not False and dashboard is not None
    if on:
        options = {"dashboard_address": ":0" if dashboard is True else str(dashboard)}
    else:
        # The scheduler of Dask 2022.12 runs its HTTP server whatever dashboard_address says
        # (None: port 8787, or any other when that one is taken, on the host's address): here it
        # listens on a free port of the loopback interface and serves no page.
        config["distributed.scheduler.http.routes"] = []
        options = {"dashboard_address": "127.0.0.1:0", "scheduler_kwargs": {"dashboard": False}}
    with dask.config.set(config):
        cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=processes,
                               **options)
    cluster.sonarsynth_dashboard = on
    if processes:
        from dask.distributed import Client
        with Client(cluster) as client:
            client.run(_shorten_worker_log)
    else:
        for worker in cluster.workers.values():
            _shorten_worker_log(worker)
    return cluster


def dashboard_link(cluster):
    """The link of the dashboard of a cluster of this Python (local_cluster), "" without one.

    Dask's interactive pages (/status) need bokeh, which Debian does not package; without it
    they only say so, and the link is to the pages Dask serves without bokeh: the workers, their
    tasks, call stacks and logs (/info/main/workers.html; JSON counts at /json/counts.json)."""
    if not getattr(cluster, "sonarsynth_dashboard", True):
        return ""
    link = getattr(cluster, "dashboard_link", "") or ""
    if link.endswith("/status") and importlib.util.find_spec("bokeh") is None:
        link = link[:-len("status")] + "info/main/workers.html"
    return link


def generate(spec, out_dir, client=None, n_workers=2, indices=None, shard=(0, 1),
             threads_per_item=1, retries=2, progress=True, before_item=None, processes=False,
             window=None, keep_items=False, dashboard=True, item_fn=None):
    """Renders the items of ``spec`` (a sonarsynth.DatasetSpec or a spec file's path) into ``out_dir`` as Dask tasks.

    client: a dask.distributed.Client (any cluster; ``out_dir`` must be a path every worker can
        write, e.g. a shared file system); None starts ``local_cluster(n_workers, processes,
        dashboard)`` (by default ``n_workers`` one-thread workers in this process, and a
        dashboard whose link is printed with the progress and returned), closed at the end.
    indices: the items to run (default: all of this shard); shard=(K, N): the items i with
        i % N == K, as ``sonarsynth dataset --shard K/N``.
    threads_per_item: rendering threads per item (1 suits one worker process per core); the
        files do not depend on it.
    retries: how many times Dask re-runs a failed item before reporting it.
    progress: True prints one line per finished item to stderr; a callable gets
        (done, total, item) with item a dict (index, seed, status, error, ...); False: silent.
    before_item: a callable (index, seed) run on the worker before each item (test hook).
    window: the most item tasks in the cluster at once (submitted, not yet collected); the next
        item is submitted as one finishes. None: 4 x the worker threads of the cluster at the
        start, at least 8. The client's memory then does not grow with the number of items.
    keep_items: True also returns every item's result dict ("items"; memory grows with the
        number of items); by default only counts and failures (the records are in the dataset
        directory: manifest.jsonl, items/<index>/item.json).
    item_fn: for tests and benchmarks only: a callable (spec, out_dir, index, threads) run on the
        worker in place of sonarsynth.run_dataset_item, returning an item dict (index, seed,
        status "done" or "skipped").

    A SystemExit or KeyboardInterrupt raised inside a task is a failure of its item (retried,
    recorded, listed in "failures" as "SystemExit: ..."), not an end of the run; a Ctrl-C of the
    calling process (KeyboardInterrupt in the client) stops generate at once: the items not yet
    started are cancelled, an owned cluster is closed (after the items running in it finish:
    C++ cannot be interrupted), and the KeyboardInterrupt goes on up. The run is resumable.

    Returns {"done", "skipped", "failed", "repaired", "failures": [{"index", "seed", "error"}]
    in index order, "seconds": wall time, "dashboard": the dashboard's link ("" without one),
    and with keep_items "items": [item dicts in index order]}. The manifest and summary are
    rewritten at the end.
    """
    from dask.distributed import Client, as_completed

    t0 = time.monotonic()
    if isinstance(spec, (str, os.PathLike)):
        spec = sonarsynth.DatasetSpec.from_file(os.fspath(spec))
    out_dir = os.path.abspath(os.fspath(out_dir))
    sonarsynth.prepare_dataset_dir(spec, out_dir)
    k, n = shard
    if indices is None:
        indices = range(k, spec.count, n)  # lazy: 10^7 items take no memory
    elif not hasattr(indices, "__len__"):
        indices = list(indices)
    total = len(indices)
    report = _print_progress if progress is True else (progress or None)

    own = None
    if client is None:
        cluster = local_cluster(n_workers, processes, dashboard)
        own = (cluster, Client(cluster))
        client = own[1]
        link = dashboard_link(cluster)
        if link and progress is True:
            print("sonarsynth_dask: dashboard at %s" % link, file=sys.stderr, flush=True)
    else:
        try:
            link = client.dashboard_link or ""
        except (KeyError, AttributeError):  # a scheduler without a dashboard
            link = ""
    if window is None:
        window = max(8, 4 * sum(client.nthreads().values()))
    if window < 1:
        raise ValueError("window = %r. Violated constraint: window >= 1" % (window,))

    counts = {"done": 0, "skipped": 0, "failed": 0, "repaired": 0}
    failures = []
    kept = [] if keep_items else None
    in_flight = {}  # future -> index: at most `window`
    try:
        # Keys unique to this call: Dask hands out a finished result again for a key it still
        # holds, and an item's result depends on the state of out_dir.
        run_token = uuid.uuid4().hex
        todo = iter(indices)
        finished = as_completed(loop=client.loop)

        def submit_next():
            i = next(todo, None)
            if i is None:
                return
            f = client.submit(run_item, spec, out_dir, i, threads_per_item, before_item, item_fn,
                              key="sonarsynth-item-%06d-%s" % (i, run_token), pure=False,
                              retries=retries)
            in_flight[f] = i
            finished.add(f)

        for _ in range(window):
            submit_next()
        done = 0
        for f in finished:
            i = in_flight.pop(f)
            item = _collect(f, spec, out_dir, i)
            del f  # the last reference: Dask forgets the task
            submit_next()
            counts[item["status"]] += 1
            if item.get("repaired"):
                counts["repaired"] += 1
            if item["status"] == "failed":
                failures.append({"index": i, "seed": item["seed"], "error": item["error"]})
            if kept is not None:
                kept.append(item)
            done += 1
            if report:
                report(done, total, item)
    except BaseException:
        # A Ctrl-C (or an error of ours): the items not yet started are dropped from a cluster
        # that goes on; an owned one is closed below.
        if own is None and in_flight:
            try:
                client.cancel(list(in_flight))
            except Exception:
                pass
        raise
    finally:
        in_flight.clear()
        if own is not None:
            own[1].close()
            own[0].close()
    sonarsynth.write_dataset_manifest(spec, out_dir)
    failures.sort(key=lambda f: f["index"])
    result = dict(counts)
    result.update(failures=failures, seconds=time.monotonic() - t0, dashboard=link)
    if kept is not None:
        result["items"] = sorted(kept, key=lambda it: it["index"])
    return result


def _collect(f, spec, out_dir, i):
    """The item dict of a finished task; a failed one is recorded in failed/<index>.json unless
    its worker recorded it (a worker lost, a task cancelled: nothing on the worker did)."""
    if f.status == "finished":
        return f.result()
    if f.status == "cancelled":
        e = None
        error = "CancelledError: the task was cancelled"
    else:
        e = f.exception()
        error = e.error if isinstance(e, ItemFailed) else _error_text(e)
    record = os.path.join(out_dir, "failed", "%06d.json" % i)
    if not getattr(e, "sonarsynth_recorded", False) or not os.path.exists(record):
        sonarsynth.record_dataset_failure(spec, out_dir, i, error)
    return {"index": i, "seed": spec.item_seed(i), "status": "failed", "error": error,
            "files": [], "objects": {}, "pings": 0, "seconds": 0.0}
