"""Cases of the `yaml` category: mutated scene files."""

import copy
import os
import random

from .case import Case, sim
from .expectations import REPLACEMENTS, expectation_for_leaf
from .gen_keys import gen_keys
from .scene import (Raw, base_scene, containers, get_path, leaves, path_str, scene_text,
                    set_path, yaml_scalar)


def gen_yaml(h, rng):
    cases = []
    scene0 = base_scene()

    def C(desc, scene_or_text, expect, needles=(), setup_extra=None, timeout_kind=None,
          allow_dark=False):
        body = scene_or_text if isinstance(scene_or_text, (str, bytes)) else scene_text(scene_or_text)

        def setup(h, w, body=body):
            mode = "wb" if isinstance(body, bytes) else "w"
            with open(os.path.join(w, "scene.yaml"), mode) as f:
                f.write(body)
            if setup_extra:
                setup_extra(h, w)
        cases.append(Case("yaml", desc, sim(), expect, needles=needles, outputs=["out"],
                          setup=setup, allow_dark=allow_dark))

    for path, orig in leaves(scene0):
        for label, raw, num in REPLACEMENTS:
            if raw == yaml_scalar(orig):
                continue
            s = copy.deepcopy(scene0)
            set_path(s, path, Raw(raw))
            key = [p for p in path if not isinstance(p, int)][-1]
            C("%s = %s" % (path_str(path), label), s,
              expectation_for_leaf(path, orig, label, raw, num),
              needles=[key, raw[:40]], allow_dark=key in ("calibration_k",))
    # Physically invalid combinations named in the brief
    phys = [
        (("survey", "speed_m_s"), -2.0, "negative speed"),
        (("survey", "altitude_m"), 30, "altitude above the water (depth 20)"),
        (("survey", "altitude_m"), 19.9, "altitude 19.9 m: the fish at the surface, beyond tilt"),
        (("sonar", "range_m"), 4, "range < altitude"),
        (("sonar", "samples"), 8193, "samples 8193 > 8192"),
        (("sonar", "samples"), 100000, "samples 100000"),
        (("output", "gain_db"), 200, "gain_db 200"),
        (("sonar", "ping_period_s"), 0.001, "ping period below the two-way travel time"),
        (("survey", "lines", 0, "waypoints", 1, "east_m"), 500, "line leaves the grid"),
        (("survey", "lines", 0, "waypoints", 0, "east_m"), -500, "line starts off the grid"),
        (("survey", "start_time"), "2026-13-01T10:00:00Z", "month 13"),
        (("survey", "start_time"), "yesterday", "start_time text"),
        (("survey", "start_time"), "1899-01-01T00:00:00Z", "start_time before 1900"),
        (("survey", "start_time"), "99999-01-01T00:00:00Z", "start_time year 99999"),
        (("objects", 0, "end", "east_m"), 900, "pipe end beyond the grid"),
        (("objects", 2, "position", "east_m"), 900, "rock beyond the grid"),
        (("objects", 0, "id"), 2, "duplicate object id? (box gets 2 automatically)"),
        (("sonar", "frequency_khz"), 1e6, "frequency 1 GHz"),
        (("sonar", "sound_speed_m_s"), 1e-3, "sound speed 1 mm/s"),
        (("bathymetry", "generate", "size_m", 0), 1e7, "a 10000 km grid"),
        (("bathymetry", "generate", "cell_m"), 1e-4, "0.1 mm cells (6.4e11 cells)"),
        (("bathymetry", "generate", "centre", "lat_deg"), 89.99999, "grid centre at the pole"),
        (("bathymetry", "generate", "depth_m"), 20000, "20 km deep"),
        (("survey", "lines", 0, "waypoints", 1, "east_m"), -25, "zero-length line"),
        (("materials", 0, "name"), "sand", "redefining sand (allowed: override)"),
        (("seabed", "material"), "unobtanium", "unknown material"),
        (("seabed", "material"), "steel", "object material as seabed"),
        (("objects", 1, "size_m"), [3, 1.5], "box size with two values"),
        (("survey", "lever_arm_m"), [0, 0], "lever arm with two values"),
        (("sonar", "vertical_beam"), {"shape": "table", "off_axis_deg": [-40, 0, 40],
                                      "gain_db": [0, 0]}, "beam table lengths differ"),
        (("sonar", "vertical_beam"), {"shape": "table", "off_axis_deg": [0, -40, 40],
                                      "gain_db": [0, 0, 0]}, "beam table not sorted"),
        (("sonar", "vertical_beam"), {"shape": "sinc", "height_over_wavelength": 0},
         "sinc height 0"),
        (("sonar", "pulse"), {"type": "chirp", "bandwidth_khz": 0}, "chirp bandwidth 0"),
        (("sonar", "pulse"), {"type": "chirp", "bandwidth_khz": 1e6}, "chirp bandwidth 1 GHz"),
        (("survey", "lines", 0, "waypoints"), [{"east_m": 0, "north_m": 0}], "one waypoint"),
        (("survey", "lines", 0, "waypoints"), [], "no waypoints"),
        (("survey", "lines"), [], "no lines"),
        (("survey", "lines", 0, "name"), "../escape", "line name with ../"),
        (("survey", "lines", 0, "name"), "/etc/passwd", "line name absolute path"),
        (("survey", "lines", 0, "name"), "", "empty line name"),
        (("survey", "lines", 0, "name"), "effective", "line name colliding with a product"),
        (("survey", "lines", 0, "name"), "a/b", "line name with a slash"),
    ]
    # A line partly off the grid is a warning with the fraction, its off-grid pings flagged
    # (altitude 0, counted by `info`): accepted either way.
    valid_phys = {"line leaves the grid", "line starts off the grid",
                  "redefining sand (allowed: override)", "altitude 19.9 m: the fish at the surface, beyond tilt",
                  "grid centre at the pole", "line name colliding with a product",
                  "duplicate object id? (box gets 2 automatically)"}
    for path, value, desc in phys:
        s = copy.deepcopy(scene0)
        set_path(s, path, value)
        C("physical: " + desc, s, "either" if desc in valid_phys else "invalid",
          needles=[str(path[-1]), str(value)[:30]])
    # two lines with the same name
    s = copy.deepcopy(scene0)
    s["survey"]["lines"].append(copy.deepcopy(s["survey"]["lines"][0]))
    C("two lines with the same name", s, "invalid", needles=["L1", "name"])
    # deleted keys
    for path, node in list(containers(scene0)):
        if not isinstance(node, dict):
            continue
        for k in node:
            s = copy.deepcopy(scene0)
            del get_path(s, path)[k]
            p = path + (k,)
            # a vertical_beam or pulse block without its shape or type keeps the current one
            # (docs/sonar-presets.md), so deleting those keys is not required to fail
            required = p in (("bathymetry",), ("survey",), ("survey", "lines"),
                             ("bathymetry", "generate"), ("bathymetry", "generate", "centre"),
                             ("bathymetry", "generate", "size_m"), ("bathymetry", "generate", "cell_m"),
                             ("survey", "lines", 0, "waypoints")) or k in ("lat_deg", "lon_deg") or (
                k == "type" and p != ("sonar", "pulse", "type")) or (
                k in ("east_m", "north_m") and "components" not in p)
            C("delete %s" % path_str(p), s, "invalid" if required else "either",
              needles=[str(k)])
    # unknown keys at every mapping level
    for path, node in list(containers(scene0)):
        if isinstance(node, dict):
            s = copy.deepcopy(scene0)
            get_path(s, path)["bogus_key"] = 1
            C("unknown key under %s" % (path_str(path) or "top"), s, "invalid",
              needles=["bogus_key"])
            s = copy.deepcopy(scene0)
            get_path(s, path)["derived" if not path else "Speed_M_S"] = 1
            if path:
                C("miscased key under %s" % path_str(path), s, "invalid", needles=["Speed_M_S"])
    base_text = scene_text(scene0)
    # duplicate keys
    for key in ("speed_m_s", "range_m", "samples", "name", "survey", "depth_m"):
        lines = base_text.split("\n")
        for i, line in enumerate(lines):
            if line.strip().startswith(key + ":"):
                lines.insert(i + 1, line.split(":")[0] + ": " + ("0.5" if key != "survey" else "{}"))
                break
        C("duplicate key %s" % key, "\n".join(lines), "invalid", needles=[key, "duplicate"])
    # complex keys, tags, anchors, bombs
    C("complex key ? [a, b] : 1", base_text + "? [a, b]\n: 1\n", "invalid", needles=["a", "key"])
    C("complex mapping key", base_text + "? {x: 1}\n: 2\n", "invalid", needles=["x", "key"])
    C("tagged value !!binary", base_text.replace("seed: 3", "seed: !!binary aGVsbG8="), "invalid",
      needles=["seed"])
    C("custom tag", base_text.replace("speed_m_s: 3.0", "speed_m_s: !foo 3.0"), "either",
      needles=["speed_m_s"])
    C("valid anchors and aliases", base_text.replace(
        "centre:\n", "centre: &c\n").replace("name: \"adv\"", "name: \"adv\"\nx_anchor_use: *c")
      if False else base_text.replace("lever_arm_m: [0, 0, 0]", "lever_arm_m: &z [0, 0, 0]"),
      "valid")
    C("alias to an undefined anchor", base_text.replace("seed: 3", "seed: *nothere"), "invalid",
      needles=["nothere", "alias", "anchor"])
    C("alias cycle-ish (anchor used inside itself)", base_text.replace(
        "seabed:\n  material: \"sand\"", "seabed: &s\n  material: \"sand\"\n  self: *s"), "invalid",
      needles=["self", "s"])

    def bomb(levels, width, where):
        out = ["a0: &a0 [\"lol\"]"]
        for i in range(1, levels):
            out.append("a%d: &a%d [%s]" % (i, i, ", ".join(["*a%d" % (i - 1)] * width)))
        return out
    for levels, width in ((4, 10), (6, 10), (7, 10)):
        b = bomb(levels, width, None)
        top = "x_bomb:\n" + "\n".join("  " + x for x in b) + "\n"
        C("alias bomb %d^%d under an unknown key" % (width, levels - 1), base_text + top,
          "invalid", needles=["x_bomb"])
        C("alias bomb %d^%d as the name" % (width, levels - 1),
          "\n".join("#" + x for x in []) + "defs:\n" + "\n".join("  " + x for x in b) + "\n"
          + base_text.replace("name: \"adv\"", "name: *a%d" % (levels - 1)), "invalid",
          needles=["name", "defs"])
    # lines multiplied through aliases: 10^3 identical lines
    t = base_text.replace("  lines:\n    - name: \"L1\"", "  lines: &l1\n    - name: \"L1\"")
    C("1000 aliased copies of the line list as waypoints", t + "x_more: [" + ", ".join(["*l1"] * 1000)
      + "]\n", "invalid", needles=["x_more"])
    # encodings and bytes
    C("non-UTF-8 byte in a comment", base_text.encode() + b"# caf\xe9\n", "valid")
    C("non-UTF-8 byte in the name", base_text.encode().replace(b'name: "adv"', b"name: adv\xff\xfe"),
      "either", needles=["name"])
    C("non-UTF-8 byte in a line name", base_text.encode().replace(b'name: "L1"', b"name: L\xff1"),
      "either", needles=["name", "L"])
    C("UTF-8 BOM", b"\xef\xbb\xbf" + base_text.encode(), "either")
    C("UTF-16 file", base_text.encode("utf-16"), "either", needles=["scene.yaml"])
    C("NUL byte inside", base_text.encode().replace(b"seed: 3", b"seed: 3\x00"), "invalid",
      needles=["seed", "scene.yaml"])
    C("CRLF line endings", base_text.replace("\n", "\r\n"), "valid")
    C("tab indentation", base_text.replace("  speed_m_s", "\tspeed_m_s"), "invalid",
      needles=["scene.yaml", "line", "tab"])
    C("empty file", "", "invalid", needles=["scene.yaml", "empty", "bathymetry"])
    C("only a comment", "# nothing\n", "invalid", needles=["scene.yaml", "bathymetry"])
    C("a scalar document", "42\n", "invalid", needles=["scene.yaml", "map"])
    C("a list document", "- 1\n- 2\n", "invalid", needles=["scene.yaml", "map"])
    C("two documents", base_text + "---\nname: second\n", "invalid", needles=["document", "scene.yaml"])
    C("truncated in the middle", base_text[: len(base_text) // 2], "invalid", needles=["scene.yaml"])
    C("unterminated quote", base_text.replace('name: "adv"', 'name: "adv'), "invalid",
      needles=["scene.yaml", "line"])
    C("unbalanced flow", base_text.replace("lever_arm_m: [0, 0, 0]", "lever_arm_m: [0, 0, 0"),
      "invalid", needles=["scene.yaml", "line"])
    C("nesting depth 1000", base_text + "x_deep: " + "[" * 1000 + "]" * 1000 + "\n", "invalid",
      needles=["x_deep", "scene.yaml", "depth"])
    C("nesting depth 100000", base_text + "x_deep: " + "[" * 100000 + "]" * 100000 + "\n",
      "invalid", needles=["x_deep", "scene.yaml", "depth"])
    C("nesting depth 100000 maps", base_text + "x_deep: " + "{a: " * 100000 + "1" + "}" * 100000 + "\n",
      "invalid", needles=["x_deep", "scene.yaml", "depth"])
    r2 = random.Random(rng.random())
    for i in range(6):
        C("binary garbage %d" % i, bytes(r2.getrandbits(8) for _ in range(2000)), "invalid",
          needles=["scene.yaml"])
    for i in range(6):
        bt = bytearray(base_text.encode())
        for _ in range(r2.randint(1, 8)):
            bt[r2.randrange(len(bt))] = r2.getrandbits(8)
        C("random byte flips %d" % i, bytes(bt), "either", needles=["scene.yaml"])
    C("10 MB name", base_text.replace('name: "adv"', 'name: "' + "n" * (10 << 20) + '"'), "either",
      needles=["name"])
    C("100000 objects", base_text + "", "valid") if False else None
    many = copy.deepcopy(scene0)
    many["objects"] = [{"type": "rock", "position": {"east_m": (i % 40) - 20, "north_m": (i // 40) % 40 - 20},
                        "diameter_m": 0.3} for i in range(2000)]
    C("2000 rocks", many, "either")
    cases += gen_keys(scene0)
    return cases
