"""Classification of a finished run: exit code and stderr, produced outputs, and the files of the
sandbox before and after."""

import math
import os
import re
import signal

from .case import SANITIZER_MARKERS, TEMP_RE
from .oracles import check_raster, check_xtf, needle_variants, strict_json
from .process import run


class Verdicts:
    """Methods of Harness that judge one run (they use self.cli, self.timeout, self.mem_mb)."""

    def classify_exit(self, case, r, work, issues, rec):
        err = r.stderr.decode("utf-8", "replace")
        san = [m for m in SANITIZER_MARKERS if m in err]
        if r.timed_out:
            issues.append(("hang", "no exit after %s s" % self.timeout))
            return
        if san:
            issues.append(("crash", "sanitizer/abort output: %s" % ", ".join(san)))
        if r.rc < 0:
            issues.append(("crash", "killed by signal %s" % signal.Signals(-r.rc).name))
            return
        if r.rc == 3:
            issues.append(("crash", "exit 3 (internal error)"))
            return
        if r.rc not in (0, 1, 2):
            issues.append(("crash", "unexpected exit code %d" % r.rc))
            return
        if r.rc in (1, 2):
            if case.expect == "valid":
                issues.append(("unclassified", "a valid input was rejected (exit %d)" % r.rc))
                return
            if not err.strip():
                issues.append(("clean_error", "generic: empty stderr"))
                return
            low = err.lower().replace("-", "_")
            hit = [n for n in needle_variants(case.needles) if n.lower().replace("-", "_") in low]
            if hit:
                issues.append(("clean_error", "names %r" % hit[0]))
            else:
                issues.append(("clean_error", "generic: names none of %r" % case.needles[:4]))
            return
        # exit 0
        if case.expect == "invalid":
            issues.append(("silent_wrong", "exit 0 for an input known to be invalid"))
        problems = self.check_outputs(case, argv_outputs(case), work)
        for p in problems:
            issues.append(("silent_wrong", p))
        if case.expect != "invalid" and not problems:
            issues.append(("ok", "exit 0, output plausible"))
        if case.argv[1:2] == ["info"] and "--json" in case.argv:
            try:
                strict_json(r.stdout.decode("utf-8", "replace"))
            except ValueError as e:
                issues.append(("silent_wrong", "info --json printed invalid JSON: %s" % e))

    def check_outputs(self, case, outputs, work):
        problems = []
        for out in outputs:
            p = os.path.join(work, out)
            if case.argv[1] == "simulate":
                if not os.path.isdir(p):
                    problems.append("exit 0 but output directory %r missing" % out)
                    continue
                names = os.listdir(p)
                if "effective.yaml" not in names:
                    problems.append("effective.yaml missing in %s" % out)
                xtfs = [n for n in names if n.endswith(".xtf")]
                if not xtfs:
                    problems.append("no .xtf in %s" % out)
                want = self.expected_lines(case, work)
                for line in want:
                    if line + ".xtf" not in names:
                        problems.append("line %r has no .xtf" % line)
                want_alt = self.requested_altitude(work, case)
                for x in xtfs[:3]:
                    problems += check_xtf(self, os.path.join(p, x), work, case.allow_dark, want_alt)
                if "--no-mosaic" not in case.argv and "mosaic.tif" in names:
                    problems += check_raster(os.path.join(p, "mosaic.tif"))
            elif case.argv[1] == "convert":
                # exit 0 means at least one ping was written (docs/conversion.md, "Drops and
                # repairs"); a slant range of kilometres is a corrupted sample interval.
                r = run([self.cli, "info", p, "--json"], work, self.timeout, self.mem_mb)
                try:
                    info = strict_json(r.stdout.decode("utf-8", "replace")) if r.rc == 0 else {}
                except ValueError:
                    info = {}
                if not info.get("pings"):
                    problems.append("exit 0 but %r holds no ping (info rc %s)" % (out, r.rc))
            elif case.argv[1] in ("waterfall", "mosaic", "bathy"):
                if not os.path.isfile(p):
                    problems.append("exit 0 but %r missing" % out)
                elif os.path.getsize(p) == 0:
                    problems.append("%r is empty" % out)
                elif out.endswith((".tif", ".png")):
                    problems += check_raster(p)
        return problems

    def requested_altitude(self, work, case):
        """survey.altitude_m of the scene when the run follows the terrain, else None."""
        scene = case.argv[2] if len(case.argv) > 2 else "scene.yaml"
        try:
            with open(os.path.join(work, scene), encoding="utf-8") as f:
                t = f.read()
        except (OSError, UnicodeDecodeError):
            return None
        m = re.findall(r"^  altitude_m: ([-+0-9.eE]+)\s*$", t, re.M)
        if len(m) != 1 or re.search(r"^  depth_m:", t, re.M):
            return None
        try:
            v = float(m[0])
        except ValueError:
            return None
        return v if math.isfinite(v) and v > 0 else None

    def expected_lines(self, case, work):
        try:
            with open(os.path.join(work, "scene.yaml"), encoding="utf-8") as f:
                t = f.read()
        except (OSError, UnicodeDecodeError):
            return []
        # survey lines are the only "- name:" items at four spaces (materials are at two)
        return re.findall(r'^    - name: "([A-Za-z0-9_]+)"\s*$', t, re.M)[:5]

    def check_files(self, case, box, work, before, after, r, issues, interrupted=False):
        """Pre-existing files changed or lost, visible leftovers of failed runs, temporaries."""
        mutable = case.mutable
        for rel, digest in before.items():
            if any(rel == m or rel.startswith(m + "/") for m in mutable):
                continue
            if rel not in after:
                issues.append(("data_lost", "user file removed: %s" % rel))
            elif after[rel] != digest:
                issues.append(("data_lost", "user file changed: %s" % rel))
        new = [rel for rel in after if rel not in before]
        litter = sorted(rel for rel in new if TEMP_RE.match(os.path.basename(rel)))
        ended_by_itself = not r.timed_out and not (interrupted and case.extra.get("signal") == signal.SIGKILL)
        if litter and ended_by_itself:
            issues.append(("litter", "temporaries left: %s" % ", ".join(litter[:4])))
        visible_top = sorted(set(rel.split("/")[0] if not rel.startswith("a/b/work/") else
                                 "a/b/work/" + rel[len("a/b/work/"):].split("/")[0] for rel in new))
        visible_top = [v for v in visible_top if not TEMP_RE.match(os.path.basename(v))]
        if ended_by_itself and r.rc not in (0, None) and not interrupted and visible_top:
            issues.append(("data_lost", "failed run (exit %s) left visible output: %s"
                           % (r.rc, ", ".join(visible_top[:4]))))
        return litter if ended_by_itself else []


def argv_outputs(case):
    return case.outputs
