"""Cases of the `interrupt` and `fs` categories: signals during `simulate`, and awkward
file-system situations (symlinks, read-only parents, stale temporaries, forged markers)."""

import os
import random
import signal

from .case import Case, sim


def gen_interrupt(h, rng):
    cases = []
    r2 = random.Random(rng.random())
    for i in range(24):
        sig = [signal.SIGINT, signal.SIGTERM, signal.SIGKILL][i % 3]
        delay = round(r2.uniform(0.05, 12.0), 2)  # the slow scene takes ~5-10 s
        full = i % 2 == 0
        cases.append(Case("interrupt", "%s after %.2f s%s" % (sig.name, delay, " (full products)" if full else ""),
                          ["{CLI}", "simulate", "slow.yaml", "-o", "out", "-q", "--threads", "1"]
                          + ([] if full else ["--no-mosaic", "--no-truth"]),
                          "either", kind="interrupt", extra={"signal": int(sig), "delay": delay},
                          setup=lambda h, w: h.write_slow(w), outputs=["out"]))
    return cases


def gen_fs(h, rng):
    cases = []
    C = lambda *a, **k: cases.append(Case("fs", *a, **k))
    root_can_write = h.root_ignores_chmod
    if not root_can_write:
        def ro(h, w):
            os.mkdir(os.path.join(w, "ro"))
            os.chmod(os.path.join(w, "ro"), 0o555)
        C("simulate into a read-only parent", sim(out="ro/out"), "invalid", setup=ro, needles=["ro"])
        C("waterfall into a read-only parent", ["{CLI}", "waterfall", "in.xtf", "-o", "ro/w.png", "-q"],
          "invalid", setup=ro, needles=["ro"])
        C("bathy into a read-only parent", ["{CLI}", "bathy", "-o", "ro/g.tif", "--lat", "43", "--lon",
                                            "5", "--size", "10x10", "--cell", "1", "-q"], "invalid",
          setup=ro, needles=["ro"])
    C("simulate: output parent missing", sim(out="missing/deeper/out"), "either",
      needles=["missing"], outputs=["missing/deeper/out"])
    C("simulate: output parent is a file", sim(out="notes.txt/out"), "invalid", needles=["notes.txt"])
    C("simulate: output name 300 chars", sim(out="o" * 300), "invalid", needles=["ooo"])
    C("simulate: output path with a newline", sim(out="a\nb"), "either", needles=["a"],
      outputs=["a\nb"])
    C("simulate: output through a symlink to a foreign dir", sim("--overwrite", out="link"),
      "invalid", setup=lambda h, w: os.symlink("data", os.path.join(w, "link")), needles=["link"])
    C("simulate: output a dangling symlink", sim(out="dangling"), "invalid",
      setup=lambda h, w: os.symlink("nowhere", os.path.join(w, "dangling")), needles=["dangling"])
    C("simulate: scene through a symlink", sim(scene="sl.yaml"), "valid",
      setup=lambda h, w: os.symlink("scene.yaml", os.path.join(w, "sl.yaml")), outputs=["out"])
    C("simulate: a stale temporary of a dead process exists", sim(), "valid",
      setup=lambda h, w: h.fake_stale(w), outputs=["out"], mutable=["a/b/work/.out.part-999999"])
    C("simulate: foreign dir with a fake marker --overwrite", sim("--overwrite", out="data"),
      "invalid", setup=lambda h, w: open(os.path.join(w, "data", ".sonarsynth-output"), "w").write("x"),
      needles=["data"])
    def product_named(h, w):
        os.mkdir(os.path.join(w, "mine"))
        for name in ("L1.xtf", "effective.yaml"):
            open(os.path.join(w, "mine", name), "w").write("a user's copy")
    C("simulate: user dir of product-named files, no marker --overwrite", sim("--overwrite", out="mine"),
      "invalid", setup=product_named, needles=["mine", ".sonarsynth-output"])
    C("waterfall: output parent missing", ["{CLI}", "waterfall", "in.xtf", "-o", "nodir/w.png", "-q"],
      "invalid", needles=["nodir"])
    C("info: unreadable input (chmod 000)" if not root_can_write else "info: input is a FIFO-less special file /dev/null",
      ["{CLI}", "info", "in.xtf" if not root_can_write else "/dev/null"], "invalid" if root_can_write else "invalid",
      setup=(lambda h, w: os.chmod(os.path.join(w, "in.xtf"), 0)) if not root_can_write else None,
      needles=["in.xtf", "/dev/null"])
    return cases
