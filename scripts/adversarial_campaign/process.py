"""Running the binary (limits, timeout, process group), snapshots of a sandbox, small text
helpers."""

import hashlib
import os
import resource
import signal
import subprocess
import time


def snapshot(root):
    snap = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for d in dirnames:
            p = os.path.join(dirpath, d)
            snap[os.path.relpath(p, root)] = "<link>" if os.path.islink(p) else "<dir>"
        for f in filenames:
            p = os.path.join(dirpath, f)
            rel = os.path.relpath(p, root)
            try:
                if os.path.islink(p):
                    snap[rel] = "<link:%s>" % os.readlink(p)
                else:
                    h = hashlib.sha256()
                    with open(p, "rb") as fh:
                        for chunk in iter(lambda: fh.read(1 << 20), b""):
                            h.update(chunk)
                    snap[rel] = h.hexdigest()
            except OSError as e:
                snap[rel] = "<unreadable %s>" % e.errno
    return snap


class RunResult:
    def __init__(self, argv, rc, stdout, stderr, seconds, timed_out, signalled=None):
        self.argv, self.rc, self.stdout, self.stderr = argv, rc, stdout, stderr
        self.seconds, self.timed_out, self.signalled = seconds, timed_out, signalled


def limits(mem_mb):
    def f():
        os.setpgid(0, 0)
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if mem_mb:
            b = mem_mb * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (b, b))
        os.nice(10)
    return f


def kill_group(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except OSError:
        pass


def run(argv, cwd, timeout, mem_mb, stdin_data=None):
    t0 = time.monotonic()
    p = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, preexec_fn=limits(mem_mb))
    try:
        out, err = p.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        kill_group(p)
        out, err = p.communicate()
        timed_out = True
    return RunResult(argv, p.returncode, out, err, time.monotonic() - t0, timed_out)


def text(b, n=600):
    s = b.decode("utf-8", "replace") if isinstance(b, bytes) else b
    return s if len(s) <= n else s[:n] + "...[%d chars]" % len(s)


def shlex_quote(s):
    import shlex
    s = s if len(s) < 200 else s[:60] + "...(%d chars)" % len(s)
    return shlex.quote(s)


def make_removable(root):
    for dirpath, dirnames, _ in os.walk(root):
        for d in dirnames:
            p = os.path.join(dirpath, d)
            try:
                if not os.path.islink(p):
                    os.chmod(p, 0o755)
            except OSError:
                pass
