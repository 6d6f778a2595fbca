"""The harness: base products, sandboxes, running one case (also under a signal) and naming its
class."""

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from .case import SANITIZER_MARKERS, SEVERITY, SIM_FAST, TEMP_RE, Case, sim
from .oracles import check_xtf
from .process import RunResult, kill_group, limits, run, shlex_quote, snapshot, text
from .scene import SLOW_SCENE, base_scene, scene_text
from .verdicts import Verdicts


class Harness(Verdicts):
    def __init__(self, args):
        self.cli = os.path.abspath(args.cli)
        self.timeout = args.timeout
        self.seed = args.seed
        self.verbose = args.verbose
        self.root = tempfile.mkdtemp(prefix="sonarsynth-adv-", dir=args.tmp)
        self.cache = os.path.join(self.root, "cache")
        os.mkdir(self.cache)
        with open(self.cli, "rb") as f:
            blob = f.read()
        asan = b"__asan_init" in blob
        self.cli_sha256 = hashlib.sha256(blob).hexdigest()
        self.mem_mb = 0 if asan else args.mem_mb
        self.root_ignores_chmod = self._probe_chmod()

    def _probe_chmod(self):
        d = os.path.join(self.cache, "ro-probe")
        os.mkdir(d)
        os.chmod(d, 0o555)
        try:
            open(os.path.join(d, "x"), "w").close()
            ok = True
        except OSError:
            ok = False
        os.chmod(d, 0o755)
        shutil.rmtree(d)
        return ok

    def prepare(self):
        """The base products every case starts from: a scene, its XTF, a bathymetry GeoTIFF."""
        with open(os.path.join(self.cache, "scene.yaml"), "w") as f:
            f.write(scene_text(base_scene()))
        r = run([self.cli, "simulate", "scene.yaml", "-o", "prev", "-q", "--threads", "1"],
                self.cache, 300, self.mem_mb)
        if r.rc != 0:
            sys.exit("base scene failed (rc %s): %s" % (r.rc, text(r.stderr)))
        self.base_xtf = os.path.join(self.cache, "prev", "L1.xtf")
        with open(self.base_xtf, "rb") as f:
            self.base_xtf_bytes = f.read()
        problems = check_xtf(self, self.base_xtf, self.cache)
        if problems:
            print("warning: the base XTF itself looks implausible: %s" % problems, file=sys.stderr)
        self.base_tif = os.path.join(self.cache, "bathy.tif")
        r = run([self.cli, "bathy", "-o", self.base_tif, "--lat", "43", "--lon", "5", "--size",
                 "80x80", "--cell", "0.5", "--slope", "1,100", "-q", "--threads", "1"],
                self.cache, 300, self.mem_mb)
        if r.rc != 0:
            sys.exit("base bathy failed (rc %s): %s" % (r.rc, text(r.stderr)))
        self.base_origin = (662979.070081245, 4762795.641689336)
        if shutil.which("gdalinfo"):
            g = subprocess.run(["gdalinfo", "-json", self.base_tif], stdout=subprocess.PIPE)
            try:
                gt = json.loads(g.stdout)["geoTransform"]
                self.base_origin = (gt[0], gt[3])
            except (ValueError, KeyError):
                pass

    # sandbox helpers used by case setups
    def copy_prev_output(self, work):
        shutil.copytree(os.path.join(self.cache, "prev"), os.path.join(work, "prev"), symlinks=True)

    def write_slow(self, work):
        with open(os.path.join(work, "slow.yaml"), "w") as f:
            f.write(SLOW_SCENE)

    def fake_stale(self, work):
        os.mkdir(os.path.join(work, ".out.part-999999"))
        with open(os.path.join(work, ".out.part-999999", ".sonarsynth-output"), "w") as f:
            f.write("stale")

    def make_sandbox(self, idx):
        box = os.path.join(self.root, "cases", "c%05d" % idx)
        work = os.path.join(box, "a", "b", "work")
        os.makedirs(work)
        with open(os.path.join(box, "top-level-user-file.txt"), "w") as f:
            f.write("user data next to the sandbox root\n")
        with open(os.path.join(work, "scene.yaml"), "w") as f:
            f.write(scene_text(base_scene()))
        with open(os.path.join(work, "notes.txt"), "w") as f:
            f.write("precious notes\n")
        with open(os.path.join(work, ".hidden"), "w") as f:
            f.write("hidden precious\n")
        os.makedirs(os.path.join(work, "data", "sub"))
        with open(os.path.join(work, "data", "sub", "data.bin"), "wb") as f:
            f.write(bytes(range(256)) * 4)
        os.makedirs(os.path.join(work, ".hidden_dir"))
        with open(os.path.join(work, ".hidden_dir", "h.txt"), "w") as f:
            f.write("hidden dir content\n")
        shutil.copy(self.base_xtf, os.path.join(work, "in.xtf"))
        shutil.copy(self.base_tif, os.path.join(work, "bathy.tif"))
        open(os.path.join(work, "empty.xtf"), "w").close()
        return box, work

    # ---- one case ----
    def run_case(self, idx, case):
        box, work = self.make_sandbox(idx)
        if case.setup:
            case.setup(self, work)
        before = snapshot(box)
        argv = [a.replace("{CLI}", self.cli).replace("{ROOT}", box).replace("{WORK}", work)
                for a in case.argv]
        issues = []   # (class, reason)
        rec = {"id": idx, "category": case.category, "description": case.desc,
               "command": " ".join(shlex_quote(a) for a in argv), "expect": case.expect}
        if case.kind == "interrupt":
            r, post = self.run_interrupt(case, argv, work, box, before, issues)
        else:
            r = run(argv, work, self.timeout, self.mem_mb)
            post = None
        rec.update({"exit": r.rc, "seconds": round(r.seconds, 3), "timed_out": r.timed_out,
                    "stderr_head": text(r.stderr, 400)})
        after = snapshot(box)
        litter = self.check_files(case, box, work, before, after, r, issues,
                                  interrupted=case.kind == "interrupt")
        if case.kind != "interrupt":
            self.classify_exit(case, r, work, issues, rec)
        elif post:
            issues.extend(post)
        cls = None
        for sev in SEVERITY:
            if any(c == sev for c, _ in issues):
                cls = sev
                break
        if cls is None:  # only litter, or nothing at all: never silently "ok"
            issues.append(("unclassified", "no rule decided this case"))
            cls = "unclassified"
        rec["class"] = cls
        rec["reasons"] = [reason for c, reason in issues if c == cls] + \
                         [("(%s) " % c) + reason for c, reason in issues if c != cls]
        rec["litter"] = litter
        rec["generic_message"] = any(c == "clean_error" and "generic" in reason for c, reason in issues)
        return rec, box

    def run_interrupt(self, case, argv, work, box, before, issues):
        sig, delay = case.extra["signal"], case.extra["delay"]
        t0 = time.monotonic()
        p = subprocess.Popen(argv, cwd=work, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, preexec_fn=limits(self.mem_mb))
        try:
            out, err = p.communicate(timeout=delay)
            finished_first = True
        except subprocess.TimeoutExpired:
            finished_first = False
            os.kill(p.pid, sig)
            try:
                out, err = p.communicate(timeout=self.timeout)
            except subprocess.TimeoutExpired:
                kill_group(p)
                out, err = p.communicate()
                r = RunResult(argv, p.returncode, out, err, time.monotonic() - t0, True)
                issues.append(("hang", "no exit %s s after %s" % (self.timeout, signal.Signals(sig).name)))
                return r, []
        r = RunResult(argv, p.returncode, out, err, time.monotonic() - t0, False)
        post = []
        e = err.decode("utf-8", "replace")
        if any(m in e for m in SANITIZER_MARKERS) or r.rc == 3:
            post.append(("crash", "exit %s after %s: %s" % (r.rc, signal.Signals(sig).name, text(e, 200))))
        elif r.rc < 0 and -r.rc != sig:
            post.append(("crash", "died of %s after %s" % (signal.Signals(-r.rc).name, signal.Signals(sig).name)))
        elif r.rc not in (0, 128 + sig, -sig, 1):
            post.append(("crash", "exit %s after %s" % (r.rc, signal.Signals(sig).name)))
        outdir = os.path.join(work, "out")
        if os.path.exists(outdir):
            names = os.listdir(outdir)
            missing = [n for n in ("effective.yaml", "L1.xtf", "L2.xtf") if n not in names]
            if missing:
                post.append(("data_lost", "interrupted run left an incomplete visible %s (missing %s)"
                             % ("out", ", ".join(missing))))
            elif r.rc != 0:
                post.append(("ok", "completed before the signal took effect (exit %s)" % r.rc))
        if r.rc == 0:
            post += [("silent_wrong", p_) for p_ in self.check_outputs(case, ["out"], work)]
        if sig == signal.SIGKILL:
            # the next run to the same -o must succeed and clean up
            rerun = [self.cli, "simulate", "scene.yaml", "-o", "out", "--overwrite"] + SIM_FAST
            r2 = run(rerun, work, self.timeout, self.mem_mb)
            if r2.timed_out:
                post.append(("hang", "rerun after SIGKILL did not finish"))
            elif r2.rc != 0:
                post.append(("crash" if r2.rc == 3 or r2.rc < 0 else "unclassified",
                             "rerun after SIGKILL failed (exit %s): %s" % (r2.rc, text(r2.stderr, 200))))
            else:
                left = [n for n in os.listdir(work) if TEMP_RE.match(n)]
                if left:
                    post.append(("litter", "rerun after SIGKILL left temporaries: %s" % left[:3]))
                post += [("silent_wrong", "rerun: " + p_) for p_ in
                         self.check_outputs(Case("interrupt", "", sim(), "valid"), ["out"], work)]
        if not any(c in ("crash", "hang", "data_lost", "silent_wrong", "unclassified") for c, _ in post):
            post.append(("ok", "%s %s: exit %s, output absent or complete"
                         % ("finished before" if finished_first else "interrupted by",
                            signal.Signals(sig).name, r.rc)))
        return r, post
