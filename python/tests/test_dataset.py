# SPDX-License-Identifier: MIT
# The dataset generator from Python and on Dask (docs/dataset.md): the same bytes as the CLI and
# as a serial run, failures reported with their index and seed, retried by Dask.
import hashlib
import json
import os
import threading
import pathlib
import pickle
import subprocess
import sys
import uuid

import pytest

import sonarsynth

distributed = pytest.importorskip("distributed")
import sonarsynth_dask  # noqa: E402  (after the skip: it needs Dask)

from conftest import tiny_dataset  # noqa: E402

TINY = tiny_dataset()


def digests(root):
    """sha256 of every file under root/items, by path relative to root."""
    root = pathlib.Path(root)
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted((root / "items").rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def spec():
    return sonarsynth.DatasetSpec.from_yaml(TINY, "tiny.yaml")


@pytest.fixture(scope="module")
def client():
    from dask.distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_spec_errors_name_the_field_and_value():
    with pytest.raises(ValueError, match=r"tiny\.yaml: sonar\.preset.*'klein'"):
        sonarsynth.DatasetSpec.from_yaml(TINY.replace("seascan-hds-600", "klein"), "tiny.yaml")
    with pytest.raises(ValueError, match=r"objects\.count.*lo <= hi"):
        sonarsynth.DatasetSpec.from_yaml(TINY.replace("count: [1, 3]", "count: [3, 1]"),
                                         "tiny.yaml")


def test_spec_pickles_by_its_text(spec):
    back = pickle.loads(pickle.dumps(spec))
    assert back.text == spec.text and back.file == spec.file
    assert [back.item_scene(i) for i in range(4)] == [spec.item_scene(i) for i in range(4)]
    assert len({spec.item_seed(i) for i in range(4)}) == 4


def test_python_run_equals_the_cli(spec, tmp_path, cli):
    r = sonarsynth.run_dataset(spec, str(tmp_path / "py"), threads=1)
    assert r["done"] == 4 and r["failed"] == 0
    spec_file = tmp_path / "tiny.yaml"
    spec_file.write_text(TINY)
    subprocess.run([cli, "dataset", str(spec_file), "-o", str(tmp_path / "cli"), "-q"],
                   check=True)
    py, cl = digests(tmp_path / "py"), digests(tmp_path / "cli")
    # scene, XTF, waterfall, truth, truth class and instance labels, effective.yaml, item.json,
    # marker, and the truth vectors (targets, tracks, coverage GeoJSON)
    assert len(py) == 4 * 12
    assert py == cl
    assert ((tmp_path / "py" / "manifest.jsonl").read_bytes() ==
            (tmp_path / "cli" / "manifest.jsonl").read_bytes())


def test_local_cluster_equals_serial_run(spec, tmp_path, client):
    serial = sonarsynth.run_dataset(spec, str(tmp_path / "serial"), threads=1)
    assert serial["done"] == 4
    assert len(client.scheduler_info()["workers"]) == 2
    pids = tmp_path / "pids"
    pids.mkdir()

    def note_pid(index, seed, where=str(pids)):
        open(os.path.join(where, "%d-%d" % (os.getpid(), index)), "w").close()

    seen = []
    r = sonarsynth_dask.generate(spec, tmp_path / "dask", client=client, before_item=note_pid,
                                 progress=lambda done, total, item: seen.append((done, total,
                                                                                 item["index"])))
    assert r["done"] == 4 and r["failed"] == 0
    assert sorted(i for _, _, i in seen) == [0, 1, 2, 3]
    assert [(d, t) for d, t, _ in seen] == [(1, 4), (2, 4), (3, 4), (4, 4)]
    # Two worker processes, neither of them this one, rendered the items.
    workers = {name.split("-")[0] for name in os.listdir(pids)}
    assert len(workers) == 2 and str(os.getpid()) not in workers
    assert digests(tmp_path / "dask") == digests(tmp_path / "serial")
    assert ((tmp_path / "dask" / "manifest.jsonl").read_bytes() ==
            (tmp_path / "serial" / "manifest.jsonl").read_bytes())
    # A rerun finds every item done.
    again = sonarsynth_dask.generate(spec, tmp_path / "dask", client=client, progress=False)
    assert again["skipped"] == 4 and again["done"] == 0


def test_default_local_cluster_of_threads_equals_serial_run(spec, tmp_path):
    # generate() without a client: two one-thread workers in this process, two items at once in
    # one process (no GIL in the C++ code); the same bytes as one item after the other.
    serial = sonarsynth.run_dataset(spec, str(tmp_path / "serial"), threads=1)
    assert serial["done"] == 4
    notes = tmp_path / "notes"
    notes.mkdir()

    def note_thread(index, seed, where=str(notes)):
        name = "%d-%d-%d" % (os.getpid(), threading.get_ident(), index)
        open(os.path.join(where, name), "w").close()

    r = sonarsynth_dask.generate(spec, tmp_path / "dask", n_workers=2, before_item=note_thread,
                                 progress=False)
    assert r["done"] == 4 and r["failed"] == 0
    # This process's two worker threads rendered the items.
    assert {name.split("-")[0] for name in os.listdir(notes)} == {str(os.getpid())}
    assert len({name.split("-")[1] for name in os.listdir(notes)}) == 2
    assert digests(tmp_path / "dask") == digests(tmp_path / "serial")
    assert ((tmp_path / "dask" / "manifest.jsonl").read_bytes() ==
            (tmp_path / "serial" / "manifest.jsonl").read_bytes())


def test_failed_item_is_reported_with_index_and_seed_after_retries(spec, tmp_path, client):
    attempts = tmp_path / "attempts"
    attempts.mkdir()

    def fail_item_1(index, seed, where=str(attempts)):
        if index == 1:
            open(os.path.join(where, uuid.uuid4().hex), "w").close()
            raise RuntimeError("injected failure")

    seen = []
    r = sonarsynth_dask.generate(spec, tmp_path / "d", client=client, retries=1,
                                 before_item=fail_item_1,
                                 progress=lambda done, total, item: seen.append(item))
    assert r["failed"] == 1 and r["done"] == 3
    assert r["failures"] == [{"index": 1, "seed": spec.item_seed(1),
                              "error": "RuntimeError: injected failure"}]
    assert len(os.listdir(attempts)) == 2  # the first attempt and one retry
    reported = [it for it in seen if it["status"] == "failed"]
    assert [(it["index"], it["seed"]) for it in reported] == [(1, spec.item_seed(1))]
    lines = [json.loads(l) for l in (tmp_path / "d" / "manifest.jsonl").read_text().splitlines()]
    assert [l["status"] for l in lines] == ["done", "failed", "done", "done"]
    assert lines[1]["seed"] == spec.item_seed(1) and "injected" in lines[1]["error"]
    summary = json.loads((tmp_path / "d" / "summary.json").read_text())
    assert summary["failed"] == 1 and summary["failures"][0]["index"] == 1
    # The failure is transient the second time: the rerun renders item 1 and clears the record.
    r2 = sonarsynth_dask.generate(spec, tmp_path / "d", client=client, progress=False)
    assert r2["done"] == 1 and r2["skipped"] == 3 and r2["failed"] == 0
    assert not (tmp_path / "d" / "failed" / "000001.json").exists()


def test_a_transient_failure_is_retried(spec, tmp_path, client):
    marker = tmp_path / "failed-once"

    def fail_first_attempt(index, seed, marker=str(marker)):
        if index == 2 and not os.path.exists(marker):
            open(marker, "w").close()
            raise OSError("transient")

    r = sonarsynth_dask.generate(spec, tmp_path / "d", client=client, retries=2,
                                 before_item=fail_first_attempt, progress=False)
    assert marker.exists()
    assert r["done"] == 4 and r["failed"] == 0


def test_item_slice_split_and_repair(tmp_path):
    text = TINY + "run: {split: {train: 0.5, val: 0.25, test: 0.25}}\n"
    spec = sonarsynth.DatasetSpec.from_yaml(text, "tiny.yaml")
    out = tmp_path / "d"
    r = sonarsynth.run_dataset(spec, out, threads=1, items=(1, 3))
    assert [i["index"] for i in r["items"]] == [1, 2] and r["done"] == 2
    assert [i["split"] for i in r["items"]] == [spec.item_split(1), spec.item_split(2)]
    manifest = [json.loads(line) for line in (out / "manifest.jsonl").read_text().splitlines()]
    assert [m["status"] for m in manifest] == ["pending", "done", "done", "pending"]
    assert all(m["seed_text"] == str(m["seed"]) for m in manifest)
    # A deleted file is found on the next run and the item rendered again, identical.
    before = digests(out)
    os.remove(out / "items" / "000002" / "L1.xtf")
    r = sonarsynth.run_dataset(spec, out, threads=1, items=(1, 3))
    assert r["repaired"] == 1 and "L1.xtf is missing" in r["items"][1]["repaired"]
    assert digests(out) == before


def manifest_lines(out):
    return [json.loads(line) for line in (out / "manifest.jsonl").read_text().splitlines()]


def test_a_failure_recorded_from_python_reads_like_the_clis(spec, tmp_path, cli):
    spec_file = tmp_path / "tiny.yaml"
    spec_file.write_text(TINY)
    # A: the CLI fails item 1 for real (a file where its directory goes) and records it.
    a = tmp_path / "a"
    (a / "items").mkdir(parents=True)
    (a / "items" / "000001").write_text("in the way")
    assert subprocess.run([cli, "dataset", str(spec_file), "-o", str(a), "-q", "--threads", "1"],
                          stderr=subprocess.DEVNULL).returncode == 1
    cli_record = (a / "failed" / "000001.json").read_text()
    error = json.loads(cli_record)["error"]
    assert "cannot move the item into place" in error
    # B: the other items by the CLI, item 1's failure recorded from Python with the same error.
    b = tmp_path / "b"
    for items in ("0:1", "2:4"):
        subprocess.run([cli, "dataset", str(spec_file), "-o", str(b), "-q", "--threads", "1",
                        "--items", items], check=True)
    sonarsynth.record_dataset_failure(spec, b, 1, error)
    assert (b / "failed" / "000001.json").read_text() == cli_record
    sonarsynth.write_dataset_manifest(spec, b)
    for name in ("manifest.jsonl", "summary.json"):
        assert (b / name).read_bytes() == (a / name).read_bytes(), name
    line = manifest_lines(b)[1]
    assert line == {"error": error, "index": 1, "seed": spec.item_seed(1),
                    "seed_text": str(spec.item_seed(1)), "status": "failed"}
    # The CLI resumes B as it resumes A: item 1 rendered, its failure record gone.
    (a / "items" / "000001").unlink()
    for d in (a, b):
        subprocess.run([cli, "dataset", str(spec_file), "-o", str(d), "-q", "--threads", "1"],
                       check=True)
        assert not (d / "failed" / "000001.json").exists()
        assert [m["status"] for m in manifest_lines(d)] == ["done"] * 4
    assert digests(a) == digests(b)
    with pytest.raises(ValueError, match=r"failed item 4\. Violated constraint: index < count"):
        sonarsynth.record_dataset_failure(spec, b, 4, "x")


# A run in a process of its own, so that a hang fails the test (timeout) instead of hanging it.
STOP_IN_A_TASK = """\
import json, os, sys, uuid
import sonarsynth, sonarsynth_dask
kind, out, attempts, processes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "1"

def stop_item_1(index, seed, kind=kind, where=attempts):
    if index == 1:
        open(os.path.join(where, uuid.uuid4().hex), "w").close()
        if kind == "SystemExit":
            sys.exit(3)
        raise KeyboardInterrupt

if __name__ == "__main__":
    spec = sonarsynth.DatasetSpec.from_yaml(sys.stdin.read(), "tiny.yaml")
    r = sonarsynth_dask.generate(spec, out, retries=1, before_item=stop_item_1, progress=False,
                                 processes=processes, dashboard=False)
    print(json.dumps(r))
"""


@pytest.mark.parametrize("kind, processes", [("SystemExit", False), ("KeyboardInterrupt", False),
                                             ("KeyboardInterrupt", True)])
def test_system_exit_or_keyboard_interrupt_in_a_task_is_a_failure(spec, tmp_path, cli, kind,
                                                                  processes):
    script = tmp_path / "run.py"
    script.write_text(STOP_IN_A_TASK)
    attempts = tmp_path / "attempts"
    attempts.mkdir()
    out = tmp_path / "d"
    # (Before: generate() never returned with worker threads; worker processes died, and the
    # items they ran with them, as KilledWorker.)
    p = subprocess.run([sys.executable, str(script), kind, str(out), str(attempts),
                        "1" if processes else "0"], input=TINY, capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    error = "SystemExit: 3" if kind == "SystemExit" else "KeyboardInterrupt"
    assert r["done"] == 3 and r["failed"] == 1
    assert r["failures"] == [{"index": 1, "seed": spec.item_seed(1), "error": error}]
    assert len(os.listdir(attempts)) == 2  # the first attempt and one retry
    line = manifest_lines(out)[1]
    assert line == {"error": error, "index": 1, "seed": spec.item_seed(1),
                    "seed_text": str(spec.item_seed(1)), "status": "failed"}
    # The CLI resumes it like any failure of its own.
    spec_file = tmp_path / "tiny.yaml"
    spec_file.write_text(TINY)
    subprocess.run([cli, "dataset", str(spec_file), "-o", str(out), "-q", "--threads", "1"],
                   check=True)
    assert not (out / "failed" / "000001.json").exists()
    assert [m["status"] for m in manifest_lines(out)] == ["done"] * 4


CTRL_C_IN_THE_CLIENT = """\
import os, signal, socket, sys, time
import sonarsynth, sonarsynth_dask
signal.signal(signal.SIGINT, signal.default_int_handler)  # also when started in the background
out, calls = sys.argv[1], sys.argv[2]

def slow_item(spec, out_dir, index, threads, where=calls):
    open(os.path.join(where, str(index)), "w").close()
    time.sleep(0.2)
    return {"index": index, "seed": spec.item_seed(index), "status": "done"}

spec = sonarsynth.DatasetSpec.from_yaml(sys.stdin.read(), "tiny.yaml")
try:
    sonarsynth_dask.generate(spec, out, item_fn=slow_item, n_workers=2)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
print("not interrupted", flush=True)
"""


def test_ctrl_c_in_the_client_stops_generate_and_closes_its_cluster(tmp_path):
    import re
    import signal
    import socket
    import time
    script = tmp_path / "run.py"
    script.write_text(CTRL_C_IN_THE_CLIENT)
    calls = tmp_path / "calls"
    calls.mkdir()
    p = subprocess.Popen([sys.executable, str(script), str(tmp_path / "d"), str(calls)],
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    try:
        p.stdin.write(TINY.replace("count: 4", "count: 1000"))
        p.stdin.close()
        port = None
        for line in p.stderr:  # the dashboard's link, then one line per item
            m = re.search(r"dashboard at http://[^:]+:(\d+)/", line)
            if m:
                port = int(m.group(1))
            if line.startswith("[2/1000]"):
                break
        assert port is not None
        t0 = time.monotonic()
        p.send_signal(signal.SIGINT)
        p.stderr.read()
        assert p.wait(timeout=30) == 130
        assert time.monotonic() - t0 < 15
        assert p.stdout.read() == "interrupted\n"
    finally:
        p.kill()
        p.wait()
    assert len(os.listdir(calls)) < 100  # 0.2 s items on 2 workers: stopped early
    # The cluster it owned is closed: its dashboard's port is no longer served.
    with socket.socket() as s:
        assert s.connect_ex(("127.0.0.1", port)) != 0


# The window test's probe, read and filled on the worker threads of this process (the item
# function is pickled by reference to this module, so it finds the same dict).
WINDOW_PROBE = {"scheduler": None, "max_tasks": 0, "calls": 0, "lock": threading.Lock()}


def count_tasks_item(spec, out_dir, index, threads):
    probe = WINDOW_PROBE
    with probe["lock"]:
        probe["max_tasks"] = max(probe["max_tasks"], len(probe["scheduler"].tasks))
        probe["calls"] += 1
    return {"index": index, "seed": spec.item_seed(index), "status": "done"}


def test_submission_is_bounded_by_the_window(tmp_path):
    # 2,000 trivial items, a window of 8: generate holds at most 8 futures, and the scheduler,
    # counted from inside the items, holds at most those and the one or two collected a moment
    # before, whose release Dask sends asynchronously (measured: 8 or 9 in ten runs). Before:
    # all 2,000 at once.
    from dask.distributed import Client
    spec = sonarsynth.DatasetSpec.from_yaml(TINY.replace("count: 4", "count: 2000"), "tiny.yaml")
    cluster = sonarsynth_dask.local_cluster(2, dashboard=False)
    client = Client(cluster)
    WINDOW_PROBE.update(scheduler=cluster.scheduler, max_tasks=0, calls=0)
    try:
        r = sonarsynth_dask.generate(spec, tmp_path / "d", client=client, window=8,
                                     item_fn=count_tasks_item, progress=False)
    finally:
        WINDOW_PROBE["scheduler"] = None
        client.close()
        cluster.close()
    assert r["done"] == 2000 and r["failed"] == 0 and "items" not in r
    assert WINDOW_PROBE["calls"] == 2000
    assert 2 < WINDOW_PROBE["max_tasks"] <= 8 + 2, WINDOW_PROBE["max_tasks"]


def test_keep_items_and_the_dashboard_of_the_local_cluster(spec, tmp_path):
    import urllib.error
    import urllib.request
    r = sonarsynth_dask.generate(spec, tmp_path / "d", n_workers=1, keep_items=True,
                                 progress=False)
    assert [it["index"] for it in r["items"]] == [0, 1, 2, 3] and r["done"] == 4
    assert r["dashboard"].startswith("http://")
    # Two clusters side by side (tests in parallel): each its own free port, each served.
    a, b = sonarsynth_dask.local_cluster(1), sonarsynth_dask.local_cluster(1)
    try:
        links = [sonarsynth_dask.dashboard_link(c) for c in (a, b)]
        assert links[0] != links[1]
        for link in links:
            with urllib.request.urlopen(link, timeout=10) as page:
                assert page.status == 200
                body = page.read().decode()
            # The pages Dask serves without bokeh (Debian has none), or bokeh's dashboard.
            assert "Workers" in body or "Dask" in body
            assert "Dask needs bokeh" not in body
    finally:
        a.close()
        b.close()
    off = sonarsynth_dask.local_cluster(1, dashboard=False)
    try:
        assert sonarsynth_dask.dashboard_link(off) == ""
        # (Dask's HTTP server still runs: on the loopback interface, with no page.)
        port = off.scheduler.http_server.port
        with pytest.raises(urllib.error.HTTPError, match="404"):
            urllib.request.urlopen("http://127.0.0.1:%d/info/main/workers.html" % port,
                                   timeout=10)
    finally:
        off.close()
    r = sonarsynth_dask.generate(spec, tmp_path / "d", n_workers=1, dashboard=False,
                                 progress=False)
    assert r["dashboard"] == "" and r["skipped"] == 4
