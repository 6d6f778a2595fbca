"""Cases of the `xtf` category: mutants of the base XTF read by info, waterfall and mosaic."""

import os
import random
import struct

from .case import Case


def gen_xtf(h, rng):
    cases = []
    r2 = random.Random(rng.random())
    data = h.base_xtf_bytes
    size = len(data)
    # packet offsets of the base file
    offs, off = [], 1024
    while off + 14 <= size:
        offs.append(off)
        off += struct.unpack_from("<I", data, off + 10)[0]
    sonar = [o for o in offs if data[o + 2] == 0]

    def put(b, pos, fmt, val):
        struct.pack_into(fmt, b, pos, val)
        return b

    mutants = []  # (desc, function(bytearray) -> bytearray)
    for cut in sorted(set([0, 1, 13, 255, 256, 1023, 1024, 1024 + 13, 1024 + 255,
                           sonar[1] + 3, size - 1] + [r2.randrange(0, size) for _ in range(8)])):
        mutants.append(("truncated at %d of %d" % (cut, size), lambda b, cut=cut: b[:cut]))
    for i in range(16):
        n = r2.choice([1, 2, 8, 64, 512])
        lo = 0 if i < 4 else 1024
        flips = [(r2.randrange(lo, size if i >= 4 else 1024), r2.getrandbits(8)) for _ in range(n)]

        def mut(b, flips=flips):
            for pos, val in flips:
                b[pos] = val
            return b
        mutants.append(("%d random byte flips%s" % (n, " in the file header" if i < 4 else ""), mut))
    p = sonar[len(sonar) // 2]
    fh_fields = [("NumberOfSonarChannels", 166, "<H", [0, 7, 255, 65535]),
                 ("NumberOfBathymetryChannels", 168, "<H", [65535]),
                 ("NavUnits", 164, "<H", [0, 7, 65535]),
                 ("chan0.BytesPerSample", 256 + 6, "<H", [0, 1, 3, 8, 65535]),
                 ("chan0.SampleFormat", 256 + 74, "<B", [1, 2, 5, 8, 99]),
                 ("chan0.TypeOfChannel", 256, "<B", [3, 200]),
                 ("FileFormat", 0, "<B", [0, 255])]
    for name, pos, fmt, vals in fh_fields:
        for v in vals:
            mutants.append(("file header %s = %d" % (name, v), lambda b, pos=pos, fmt=fmt, v=v: put(b, pos, fmt, v)))
    pk_fields = [("NumChansToFollow", 4, "<H", [0, 1, 3, 255, 65535]),
                 ("NumBytesThisRecord", 10, "<I", [0, 13, 14, 64, 255, 0x7FFFFFFF, 0xFFFFFFFF]),
                 ("MagicNumber", 0, "<H", [0, 0xCEFA]),
                 ("HeaderType", 2, "<B", [1, 3, 42, 255]),
                 ("ping.Year", 14, "<H", [0, 65535]), ("ping.Month", 16, "<B", [0, 13, 255]),
                 ("ping.Hour", 18, "<B", [25]),
                 ("ping.SoundVelocity", 30, "<f", [0.0, -1.0, float("nan"), float("inf"), 1e30]),
                 ("ping.SensorXcoordinate", 128, "<d", [float("nan"), 1e300, -999.0]),
                 ("ping.SensorYcoordinate", 120, "<d", [float("nan"), 91.0]),
                 ("ping.SensorDepth", 164, "<f", [float("nan"), -1e9, 1e9]),
                 ("ping.SensorPrimaryAltitude", 168, "<f", [float("nan"), 0.0, -5.0, 1e9]),
                 ("ping.SensorHeading", 184, "<f", [float("nan"), 1e9]),
                 ("chan.SlantRange", 256 + 4, "<f", [0.0, -1.0, float("nan"), float("inf"), 1e30]),
                 ("chan.NumSamples", 256 + 42, "<I", [0, 1, 129, 8193, 65535, 0x7FFFFFFF, 0xFFFFFFFF]),
                 ("chan.ChannelNumber", 256, "<H", [1, 2, 5, 65535])]
    for name, pos, fmt, vals in pk_fields:
        for v in vals:
            for where, pk in (("middle ping", p), ("first ping", sonar[0])):
                if where == "first ping" and not name.startswith(("Num", "chan.Num")):
                    continue
                mutants.append(("%s %s = %r" % (where, name, v),
                                lambda b, pos=pos + pk, fmt=fmt, v=v: put(b, pos, fmt, v)))
    # every ping's NumSamples raised (reads beyond records)
    def all_ns(b, v=200):
        for o in sonar:
            struct.pack_into("<I", b, o + 256 + 42, v)
        return b
    mutants.append(("every ping chan0 NumSamples = 200 (> record)", all_ns))
    mutants.append(("garbage appended (1 MB random)", lambda b: b + bytes(r2.getrandbits(8) for _ in range(4096)) * 256))
    mutants.append(("file header only", lambda b: b[:1024]))
    mutants.append(("packets duplicated (time goes back)", lambda b: b + b[1024:]))
    mutants.append(("all zeros of the same size", lambda b: bytearray(len(b))))
    mutants.append(("a ping packet spliced into the file header", lambda b: b[p:p + 512] + b[512:]))

    commands = [("info", ["{CLI}", "info", "in.xtf"], []),
                ("info --json", ["{CLI}", "info", "in.xtf", "--json"], []),
                ("waterfall", ["{CLI}", "waterfall", "in.xtf", "-o", "w.png", "-q"], ["w.png"]),
                ("mosaic", ["{CLI}", "mosaic", "in.xtf", "-o", "m.tif", "--no-rgb", "-q"], ["m.tif"]),
                ("convert", ["{CLI}", "convert", "in.xtf", "-o", "c.jsf", "-q"], ["c.jsf"])]
    for desc, mut in mutants:
        body = bytes(mut(bytearray(data)))

        def setup(h, w, body=body):
            with open(os.path.join(w, "in.xtf"), "wb") as f:
                f.write(body)
        for cname, argv, outs in commands:
            cases.append(Case("xtf", "%s: %s" % (cname, desc), argv, "either",
                              needles=["in.xtf", "xtf", "XTF"], outputs=outs, setup=setup,
                              kind="xtf"))
    return cases
