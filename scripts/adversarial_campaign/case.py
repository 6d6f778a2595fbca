"""Case model, shared constants and the `simulate` command line used by most cases."""

import re

CLASSES = ["ok", "clean_error", "crash", "hang", "silent_wrong", "data_lost", "unclassified"]
# When a case shows several problems the most severe one names it.
SEVERITY = ["data_lost", "crash", "hang", "silent_wrong", "unclassified", "clean_error", "ok"]
CATEGORIES = ["cli", "yaml", "raster", "xtf", "interrupt", "fs"]
CATEGORY_WEIGHT = {"cli": 0.25, "yaml": 0.36, "raster": 0.10, "xtf": 0.21, "interrupt": 0.04,
                   "fs": 0.04}
SANITIZER_MARKERS = ["AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer",
                     "ThreadSanitizer", "runtime error:", "terminate called", "Segmentation fault",
                     "stack smashing", "double free", "corrupted size", "Assertion `"]
TEMP_RE = re.compile(r"^\..*\.(part|old)-\d+")
MAX_DEPTH_M = 12000.0


class Case:
    """One adversarial input.

    argv: list of strings; "{CLI}" is replaced by the binary; paths are relative to the case's
    working directory (sandbox/a/b/work).  expect: valid | invalid | either.
    needles: strings of which at least one should appear in a clean error message.
    outputs: paths the command may create (checked for plausibility on success).
    setup(h, work): prepares the sandbox beyond the standard content.
    mutable: relative paths (to the sandbox root) the case may legitimately change.
    """

    def __init__(self, category, desc, argv, expect, needles=(), outputs=(), setup=None,
                 mutable=(), kind="run", extra=None, allow_dark=False):
        self.category, self.desc, self.argv, self.expect = category, desc, argv, expect
        self.needles, self.outputs, self.setup = list(needles), list(outputs), setup
        self.mutable, self.kind, self.extra, self.allow_dark = list(mutable), kind, extra or {}, allow_dark


SIM_FAST = ["--no-mosaic", "--no-waterfall", "--no-truth", "-q", "--threads", "1"]


def sim(*extra, scene="scene.yaml", out="out", fast=True):
    return ["{CLI}", "simulate", scene, "-o", out] + list(extra) + (SIM_FAST if fast else ["-q"])

