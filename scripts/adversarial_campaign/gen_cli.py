"""Cases of the `cli` category: bad flags, output targets, arguments."""

from .case import Case, sim
from .expectations import BAD_NUMBERS, flag_expect


def gen_cli(h, rng):
    cases = []
    C = lambda *a, **k: cases.append(Case("cli", *a, **k))
    # simulate: numeric flags
    for flag in ("--seed", "--range", "--samples", "--threads", "--res"):
        for label, v in BAD_NUMBERS:
            fast = flag != "--res"
            extra = [] if fast else ["--no-waterfall", "--no-truth"]
            C("simulate %s %s" % (flag, label), sim(flag, v, *extra, fast=fast) if fast else
              ["{CLI}", "simulate", "scene.yaml", "-o", "out", flag, v, "-q", "--threads", "1"] + extra,
              flag_expect(flag, v), needles=[flag.lstrip("-"), v, "range", "samples"])
    for flag, vals in (("--quality", ["fast", "default", "high", "bogus", "", "FAST"]),
                       ("--of", ["COG", "GTiff", "PNG", "bogus", ""]),
                       ("--co", ["COMPRESS=DEFLATE", "BOGUS=1", "noequals", "COMPRESS=BOGUS", "="])):
        for v in vals:
            valid = {"fast": "valid", "default": "valid", "high": "either", "COG": "valid",
                     "GTiff": "valid", "COMPRESS=DEFLATE": "valid", "BOGUS=1": "either",
                     "COMPRESS=BOGUS": "either", "FAST": "either"}.get(v, "invalid")
            fast = flag == "--quality"
            argv = (sim(flag, v) if fast else
                    ["{CLI}", "simulate", "scene.yaml", "-o", "out", flag, v, "--no-waterfall",
                     "--no-truth", "-q", "--threads", "1"])
            C("simulate %s %r" % (flag, v), argv, valid, needles=[flag.lstrip("-"), v or "''"])
    # simulate: output targets
    targets = [(".", "cwd (the scene's directory)"), ("..", "the parent"), ("../..", "grandparent"),
               ("/", "the root directory"), ("{ROOT}", "the sandbox root (absolute)"),
               ("{WORK}", "the scene's directory (absolute)"), ("data", "a foreign directory"),
               ("notes.txt", "an existing user file"), ("", "empty path"),
               ("data/", "foreign dir with slash"), (".hidden_dir", "hidden foreign dir"),
               ("scene.yaml", "the scene file itself"), ("out/../out", "dotted path, new")]
    for t, what in targets:
        for ow in (False, True):
            if t == "/" and ow:
                continue  # never hand / --overwrite to a possibly broken build running as root
            extra = ["--overwrite"] if ow else []
            expect = "valid" if t == "out/../out" else "invalid"
            C("simulate -o %s%s" % (what, " --overwrite" if ow else ""),
              sim(*extra, out=t), expect, needles=[t.rstrip("/") or "output", "exist", "refus", "output"],
              outputs=[t] if expect == "valid" else [])
    C("simulate --overwrite onto an earlier sonarsynth output", sim("--overwrite", out="prev"),
      "valid", setup=lambda h, w: h.copy_prev_output(w), mutable=["a/b/work/prev"], outputs=["prev"])
    C("simulate onto an earlier output without --overwrite", sim(out="prev"), "invalid",
      setup=lambda h, w: h.copy_prev_output(w), needles=["prev", "exist"])
    C("simulate with full products (baseline)", ["{CLI}", "simulate", "scene.yaml", "-o", "out",
                                                 "-q", "--threads", "1"], "valid", outputs=["out"])
    C("simulate baseline fast", sim(), "valid", outputs=["out"])
    C("simulate missing scene", sim(scene="nothere.yaml"), "invalid", needles=["nothere.yaml"])
    C("simulate scene is a directory", sim(scene="data"), "invalid", needles=["data"])
    C("simulate no -o", ["{CLI}", "simulate", "scene.yaml"], "invalid", needles=["output", "-o"])
    C("simulate two scenes", ["{CLI}", "simulate", "scene.yaml", "scene.yaml", "-o", "out"],
      "invalid", needles=["scene", "positional", "option"])
    C("simulate unknown flag", sim("--bogus-flag"), "invalid", needles=["bogus-flag"])
    C("unknown command", ["{CLI}", "simulat"], "invalid", needles=["simulat"])
    C("no command", ["{CLI}"], "invalid", needles=["usage"])
    C("simulate scene from /dev/null", sim(scene="/dev/null"), "invalid", needles=["/dev/null"])
    C("simulate scene from /dev/zero (endless)", sim(scene="/dev/zero"), "invalid",
      needles=["/dev/zero"])
    # info
    for label, v in BAD_NUMBERS:
        C("info --max-anomalies %s" % label, ["{CLI}", "info", "in.xtf", "--max-anomalies", v],
          flag_expect("--max-anomalies", v), needles=["max-anomalies", v])
    for inp, what in (("nothere.xtf", "missing"), ("data", "a directory"), ("empty.xtf", "empty"),
                      ("scene.yaml", "a YAML file"), ("/dev/null", "/dev/null"),
                      ("/dev/zero", "/dev/zero")):
        for js in (False, True):
            C("info on %s%s" % (what, " --json" if js else ""),
              ["{CLI}", "info", inp] + (["--json"] if js else []), "invalid",
              needles=[inp, "xtf", "XTF"])
    C("info no input", ["{CLI}", "info"], "invalid", needles=["input", "xtf", "FILE"])
    C("info baseline", ["{CLI}", "info", "in.xtf"], "valid")
    C("info --json baseline", ["{CLI}", "info", "in.xtf", "--json"], "valid")
    # waterfall
    for label, v in BAD_NUMBERS:
        C("waterfall --lo-db %s" % label,
          ["{CLI}", "waterfall", "in.xtf", "-o", "w.png", "--lo-db", v, "--hi-db", "40", "-q"],
          "invalid" if label in ("nan", "inf", "text", "empty", "trailing", "1e9", "1e308",
                                 "2^64+1", "hex") else "either",
          needles=["lo-db", v, "hi-db"], outputs=["w.png"])
    for argv, expect, desc, needles, mut in (
            (["-o", "in.xtf", "--overwrite"], "invalid", "output = input --overwrite", ["in.xtf"], []),
            (["-o", "in.xtf"], "invalid", "output = input", ["in.xtf"], []),
            (["-o", "notes.txt"], "invalid", "output an existing user file", ["notes.txt"], []),
            (["-o", "notes.txt", "--overwrite"], "either", "output a user file --overwrite",
             ["notes.txt"], ["a/b/work/notes.txt"]),
            (["-o", "w.bmp"], "invalid", "unsupported extension", ["w.bmp", "bmp"], []),
            (["-o", "noext"], "invalid", "no extension", ["noext"], []),
            (["-o", "data"], "invalid", "output is a directory", ["data"], []),
            (["-o", "data/"], "invalid", "output is a directory with slash", ["data"], []),
            (["-o", "missing/w.png"], "invalid", "output parent missing", ["missing"], []),
            (["-o", "notes.txt/w.png"], "invalid", "output parent is a file", ["notes.txt"], []),
            (["-o", "w.png", "--lo-db", "10"], "invalid", "--lo-db without --hi-db", ["hi-db", "lo-db"], []),
            (["-o", "w.png", "--lo-db", "40", "--hi-db", "10"], "invalid", "--lo-db > --hi-db",
             ["hi-db", "lo-db"], []),
            (["-o", "w.png", "--lo-db", "10", "--hi-db", "10"], "invalid", "--lo-db = --hi-db",
             ["hi-db", "lo-db"], []),
            (["-o", "w.png"], "valid", "baseline png", [], []),
            (["-o", "w.tif", "--grey", "--slant-correct"], "valid", "baseline tif", [], []),
            (["-o", "/"], "invalid", "output /", ["/"], []),
            (["-o", ""], "invalid", "output empty", ["output"], []),
            (["-o", "x" * 300 + ".png"], "invalid", "output name too long", ["xxxx"], [])):
        out = argv[1]
        C("waterfall " + desc, ["{CLI}", "waterfall", "in.xtf"] + argv + ["-q"], expect,
          needles=needles, outputs=[out] if expect != "invalid" else [], mutable=mut)
    # mosaic
    for label, v in BAD_NUMBERS:
        C("mosaic --res %s" % label, ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--res", v,
                                      "--no-rgb", "-q"],
          flag_expect("--res", v), needles=["res", v], outputs=["m.tif"])
        C("mosaic --taper %s" % label, ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--taper", v,
                                        "--no-rgb", "-q"],
          flag_expect("--taper", v), needles=["taper", v], outputs=["m.tif"])
    for argv, expect, desc, needles in (
            (["in.xtf", "-o", "m.tif", "--rule", "bogus"], "invalid", "--rule bogus", ["rule", "bogus"]),
            (["in.xtf", "-o", "m.tif", "--rule", "max"], "valid", "--rule max", []),
            (["in.xtf", "-o", "m.tif", "--rule", "nearest", "--count"], "valid", "--rule nearest --count", []),
            (["in.xtf", "-o", "m.tif", "--of", "bogus"], "invalid", "--of bogus", ["of", "bogus"]),
            (["in.xtf", "-o", "m.tif", "--co", "noequals"], "invalid", "--co noequals", ["co", "noequals"]),
            (["in.xtf", "-o", "in.xtf", "--overwrite"], "invalid", "-o = input --overwrite", ["in.xtf"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "in.xtf", "--overwrite"], "invalid",
             "--rgb = input --overwrite", ["in.xtf"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "m.tif"], "invalid", "--rgb = -o", ["m.tif", "rgb"]),
            (["in.xtf", "-o", "notes.txt"], "invalid", "-o an existing user file", ["notes.txt"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "nothere.tif"], "invalid",
             "--bathymetry missing", ["nothere.tif"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "notes.txt"], "invalid",
             "--bathymetry a text file", ["notes.txt"]),
            (["in.xtf", "-o", "m.tif", "--bathymetry", "bathy.tif"], "valid", "--bathymetry baseline", []),
            (["-o", "m.tif"], "invalid", "no inputs", ["input", "xtf", "FILES"]),
            (["in.xtf", "in.xtf", "-o", "m.tif"], "either", "same input twice", ["in.xtf"]),
            (["in.xtf", "scene.yaml", "-o", "m.tif"], "invalid", "a YAML file as input", ["scene.yaml"]),
            (["in.xtf", "empty.xtf", "-o", "m.tif"], "invalid", "an empty file as input", ["empty.xtf"]),
            (["in.xtf", "-o", "data"], "invalid", "-o a directory", ["data"]),
            (["in.xtf", "-o", "m.tif"], "valid", "baseline", []),
            (["in.xtf", "-o", "m.tif", "--depth-positive", "--bathymetry", "bathy.tif"], "invalid",
             "--depth-positive on an elevation grid (seabed above the fish)", ["bathy.tif", "depth"]),
            (["in.xtf", "-o", "m.tif", "--rgb", "m_rgb.bmp"], "invalid", "--rgb unsupported extension",
             ["bmp", "rgb"])):
        outs = [a for i, a in enumerate(argv) if i > 0 and argv[i - 1] == "-o"]
        C("mosaic " + desc, ["{CLI}", "mosaic"] + argv + ["-q"], expect, needles=needles,
          outputs=outs if expect != "invalid" else [])
    # bathy
    base = {"--lat": "43", "--lon": "5", "--size": "60x40", "--cell": "0.5"}

    def bathy_argv(over=None, drop=None, extra=()):
        d = dict(base)
        d.update(over or {})
        argv = ["{CLI}", "bathy", "-o", "g.tif", "-q"] + ([] if "--threads" in extra else ["--threads", "1"])
        for k, v in d.items():
            if k != drop:
                argv += [k, v]
        return argv + list(extra)

    for flag in ("--lat", "--lon", "--cell", "--depth"):
        for label, v in BAD_NUMBERS + [("91", "91"), ("-181", "-181"), ("1e4", "1e4")]:
            C("bathy %s %s" % (flag, label), bathy_argv({flag: v}), flag_expect(flag, v),
              needles=[flag.lstrip("-"), v], outputs=["g.tif"])
    for v, expect in (("0x0", "invalid"), ("-1x5", "invalid"), ("1e9x1e9", "invalid"),
                      ("10x", "invalid"), ("x10", "invalid"), ("10x10x10", "invalid"),
                      ("abc", "invalid"), ("nanxnan", "invalid"), ("infx10", "invalid"),
                      ("0.1x0.1", "either"), ("10X10", "either"), ("1e5x1e5", "invalid"),
                      ("60x40", "valid"), (" 60x40", "either")):
        C("bathy --size %r" % v, bathy_argv({"--size": v}), expect, needles=["size", v],
          outputs=["g.tif"])
    for flag, vals in (("--slope", [("90", "invalid"), ("-1", "either"), ("nan", "invalid"),
                                     ("5,1e308", "either"), ("5,", "invalid"), ("5,,", "invalid"),
                                     ("5", "valid")]),
                       ("--ripples", [("0,1", "invalid"), ("1,0.1,0,1", "invalid"),
                                      ("1,0.1,0,0.5", "valid"), ("1e-9,1", "invalid"),
                                      ("nan,1", "invalid"), ("1", "invalid")]),
                       ("--fbm", [("1,20,1000", "either"), ("1,20,6,2", "either"),
                                  ("-1", "invalid"), ("1,0", "invalid"), ("nan", "invalid"),
                                  ("0.2,10,4,0.5", "valid")]),
                       ("--seamount", [("0,0,5,0", "invalid"), ("0,0,5,-3", "invalid"),
                                       ("0,0,1e9,5", "invalid"), ("0,0,5", "invalid"),
                                       ("0,0,-5,3", "valid"), ("1e308,0,5,3", "either")]),
                       ("--scarp", [("0,0,45,2,0", "invalid"), ("0,0,45", "invalid"),
                                    ("0,0,45,2,3", "valid"), ("0,0,45,1e9", "invalid")]),
                       ("--threads", [("-1", "invalid"), ("0", "valid"), ("99999", "invalid"),
                                      ("abc", "invalid")]),
                       ("--seed", [("-1", "either"), ("abc", "invalid"), ("1e308", "invalid"),
                                   ("7", "valid")]),
                       ("--co", [("COMPRESS=DEFLATE", "valid"), ("bogus", "invalid"),
                                 ("BLOCKXSIZE=7", "either")])):
        for v, expect in vals:
            C("bathy %s %s" % (flag, v), bathy_argv(extra=[flag, v]), expect,
              needles=[flag.lstrip("-"), v], outputs=["g.tif"])
    for drop in ("--lat", "--lon", "--size", "--cell"):
        C("bathy without %s" % drop, bathy_argv(drop=drop), "invalid", needles=[drop.lstrip("-")])
    C("bathy -o over a user file", ["{CLI}", "bathy", "-o", "notes.txt", "--lat", "43", "--lon",
                                    "5", "--size", "10x10", "--cell", "1", "-q"], "invalid",
      needles=["notes.txt"])
    C("bathy -o a directory", ["{CLI}", "bathy", "-o", "data", "--lat", "43", "--lon", "5",
                               "--size", "10x10", "--cell", "1", "-q", "--overwrite"], "invalid",
      needles=["data"])
    C("bathy -o the scene --overwrite", ["{CLI}", "bathy", "-o", "scene.yaml", "--lat", "43",
                                         "--lon", "5", "--size", "10x10", "--cell", "1", "-q",
                                         "--overwrite"], "either", needles=["scene.yaml"],
      mutable=["a/b/work/scene.yaml"])
    return cases
