"""Cases of the `yaml` category for the scene keys of the sensor stage and the new output, noise
and sonar keys (docs/scene-format.md, docs/physics.md §1.10, docs/sonar-presets.md): `off`,
the bounds of each key, the other enum values, the presets and how they combine with explicit
keys.  The leaf mutations of these keys come from gen_yaml (they are in the base scene); this
module adds what those cannot express."""

import copy
import os

from .case import Case, sim
from .scene import Raw, base_scene, scene_text

# docs/sonar-presets.md; the first two are chirp presets, the others CW.
PRESETS = ["edgetech-4200-300", "edgetech-4200-600", "seascan-hds-600", "klein-3900-445",
           "klein-3900-900"]
# sensor keys that take `off` (formats/config/option_table.cpp: sensor_level)
OFF_KEYS = ["noise_floor_dbfs", "volume_reverberation_db", "shadow_fill_db",
            "first_return_reflection_db", "ring_down_m"]
# docs/scene-format.md says every sensor key takes `off`; these two are parameters of the first
# return (switched off by first_return_reflection_db: off), so refusing `off` is fine as well.
OFF_EITHER_KEYS = ["first_return_rms_slope", "side_lobe_db"]
FULL = ["-q", "--threads", "1"]   # every product: waterfalls and mosaic_rgb use output.display


def gen_keys(scene0=None):
    scene0 = scene0 or base_scene()
    cases = []

    def C(desc, edit, expect, needles=(), argv=None, allow_dark=False):
        s = copy.deepcopy(scene0)
        edit(s)
        body = scene_text(s)

        def setup(h, w, body=body):
            with open(os.path.join(w, "scene.yaml"), "w") as f:
                f.write(body)
        cases.append(Case("yaml", "key: " + desc, argv or sim(), expect, needles=needles,
                          outputs=["out"], setup=setup, allow_dark=allow_dark))

    def put(section, key, value):
        def edit(s):
            s[section][key] = value
        return edit

    def several(*edits):
        def edit(s):
            for e in edits:
                e(s)
        return edit

    # ---- sensor ----
    for k in OFF_KEYS:
        C("sensor.%s = off" % k, put("sensor", k, Raw("off")), "valid", needles=[k, "off"])
    for k in OFF_EITHER_KEYS:
        C("sensor.%s = off" % k, put("sensor", k, Raw("off")), "either", needles=[k, "off"])
    C("every sensor effect off", several(*[put("sensor", k, Raw("off")) for k in OFF_KEYS]),
      "valid")
    C("sensor: {} (the defaults)", lambda s: s.__setitem__("sensor", {}), "valid")
    C("sensor: null", lambda s: s.__setitem__("sensor", None), "either", needles=["sensor"])
    C("sensor: off (the section, not a key)", lambda s: s.__setitem__("sensor", Raw("off")),
      "invalid", needles=["sensor", "off"])
    C("sensor: []", lambda s: s.__setitem__("sensor", []), "invalid", needles=["sensor"])
    C("sensor keys under output", several(lambda s: s.pop("sensor"),
                                          put("output", "noise_floor_dbfs", -62)),
      "invalid", needles=["noise_floor_dbfs"])
    bounds = [
        ("noise_floor_dbfs", [(-300, "either"), (-300.5, "invalid"), (0, "either"),
                              (0.5, "invalid"), (-120, "valid")]),
        ("volume_reverberation_db", [(100, "either"), (100.5, "invalid"), (-300, "either"),
                                     (-300.5, "invalid"), (-10, "valid")]),
        ("shadow_fill_db", [(100, "either"), (100.5, "invalid"), (-300, "either"),
                            (-300.5, "invalid"), (-10, "valid")]),
        ("first_return_reflection_db", [(0, "valid"), (0.5, "invalid"), (-300, "either"),
                                        (-300.5, "invalid")]),
        ("first_return_rms_slope", [(1, "valid"), (1.001, "invalid"), (0, "invalid"),
                                    (1e-6, "either"), (-0.15, "invalid")]),
        ("side_lobe_db", [(0, "either"), (0.5, "invalid"), (-300, "either"),
                          (-300.5, "invalid"), (-60, "valid")]),
        # the range is 18 m: 17.9 leaves one sample, 18 and beyond leave none
        ("ring_down_m", [(0, "valid"), (-0.1, "invalid"), (2, "valid"), (17.9, "either"),
                         (18, "either"), (20, "either"), (1e4, "either"), (10000.5, "invalid")]),
    ]
    for k, vals in bounds:
        for v, expect in vals:
            C("sensor.%s = %r" % (k, v), put("sensor", k, v), expect, needles=[k, repr(v)])
    C("first return off, its slope and side lobes still given",
      put("sensor", "first_return_reflection_db", Raw("off")), "valid")
    C("sensor.noise_floor_dbfs = '-62' (a quoted number)", put("sensor", "noise_floor_dbfs", "-62"),
      "either", needles=["noise_floor_dbfs"])
    C("sensor.ring_down_m = OFF (upper case)", put("sensor", "ring_down_m", Raw("OFF")), "either",
      needles=["ring_down_m", "OFF"])

    # ---- output ----
    enum_cases = [
        ("quantity", "intensity", "valid"), ("quantity", "Intensity", "either"),
        ("quantity", "power", "invalid"), ("quantity", "", "invalid"),
        ("detector", "mean", "valid"), ("detector", "median", "invalid"),
        ("detector", "MAX", "either"),
        ("normalise", "per_ping_max", "valid"), ("normalise", "per-ping-max", "invalid"),
        ("normalise", "bogus", "invalid"),
        ("display", "linear", "valid"), ("display", "log", "invalid"),
    ]
    for k, v, expect in enum_cases:
        C("output.%s = %r" % (k, v), put("output", k, v), expect, needles=[k, v or "''"])
    for v, expect in ((1, "valid"), (16, "valid"), (0, "invalid"), (17, "invalid"),
                      (2.5, "invalid"), (16.5, "invalid"), ("3", "either")):
        C("output.detector_sub_samples = %r" % (v,), put("output", "detector_sub_samples", v),
          expect, needles=["detector_sub_samples", str(v)])
    for v, expect in ((-0.001, "either"), (0, "invalid"), (0.5, "invalid"), (-3, "valid"),
                      (-40, "valid"), (-200, "either"), (-200.5, "invalid")):
        C("output.seabed_median_dbfs = %r" % v, put("output", "seabed_median_dbfs", v), expect,
          needles=["seabed_median_dbfs", repr(v)])
    for fmt in ("u8", "f32"):
        C("output.quantity = intensity, sample_format %s" % fmt,
          several(put("output", "quantity", "intensity"), put("output", "sample_format", fmt)),
          "valid")
        C("output.seabed_median_dbfs = -3, sample_format %s" % fmt,
          several(put("output", "seabed_median_dbfs", -3), put("output", "sample_format", fmt)),
          "valid")
    C("output.detector = mean, detector_sub_samples 1",
      several(put("output", "detector", "mean"), put("output", "detector_sub_samples", 1)), "valid")
    C("output.detector = max, detector_sub_samples 16 (quantity intensity)",
      several(put("output", "detector_sub_samples", 16), put("output", "quantity", "intensity")),
      "valid")
    C("output.normalise = per_ping_max with gain_db 60 (the gain cancels)",
      several(put("output", "normalise", "per_ping_max"), put("output", "gain_db", 60)), "valid")
    C("output.normalize (American spelling)",
      several(lambda s: s["output"].pop("normalise"), put("output", "normalize", "none")),
      "invalid", needles=["normalize"])
    for disp in ("db", "linear"):
        C("output.display = %s, every product" % disp, put("output", "display", disp), "valid",
          argv=["{CLI}", "simulate", "scene.yaml", "-o", "out"] + FULL)
    C("the paper's display: normalise per_ping_max, display linear, noise paper, every product",
      several(put("output", "normalise", "per_ping_max"), put("output", "display", "linear"),
              put("noise", "model", "paper")), "valid",
      argv=["{CLI}", "simulate", "scene.yaml", "-o", "out"] + FULL)
    C("intensity, mean of 16 looks, linear display, every product",
      several(put("output", "quantity", "intensity"), put("output", "detector", "mean"),
              put("output", "detector_sub_samples", 16), put("output", "display", "linear")),
      "valid", argv=["{CLI}", "simulate", "scene.yaml", "-o", "out"] + FULL)

    # ---- noise ----
    for v, expect in ((False, "valid"), (Raw("yes"), "either"), (Raw("on"), "either"),
                      (1, "either"), ("maybe", "invalid")):
        C("noise.along_track_correlation = %s" % (v.text if isinstance(v, Raw) else repr(v)),
          put("noise", "along_track_correlation", v), expect, needles=["along_track_correlation"])
    C("noise.along_track_correlation = false, freeze_cell_m 0.5",
      several(put("noise", "along_track_correlation", False), put("noise", "freeze_cell_m", 0.5)),
      "valid")
    C("noise.along_track_correlation = true, freeze_cell_m 0.5 (unused)",
      put("noise", "freeze_cell_m", 0.5), "either", needles=["freeze_cell_m"])

    def variance(v, model="paper"):
        def edit(s):
            del s["noise"]["uniform_half_width"]
            s["noise"]["uniform_variance"] = v
            s["noise"]["model"] = model
        return edit
    for v, expect in ((0.01, "valid"), (0, "valid"), (1 / 3, "valid"), (0.34, "invalid"),
                      (-0.01, "invalid"), (Raw(".nan"), "invalid"), (Raw("1e9"), "invalid"),
                      ("text", "invalid"), (None, "either")):
        label = v.text if isinstance(v, Raw) else repr(v)
        C("noise.uniform_variance = %s (paper noise)" % label, variance(v), expect,
          needles=["uniform_variance", label])
    C("noise.uniform_variance = 0.01 with the speckle model (unused)",
      variance(0.01, "speckle"), "either", needles=["uniform_variance"])
    C("noise.uniform_variance and uniform_half_width both given",
      several(put("noise", "model", "paper"), put("noise", "uniform_variance", 0.01)), "invalid",
      needles=["uniform_variance", "uniform_half_width"])

    # ---- sonar.preset ----
    def preset_only(name, **extra):
        def edit(s):
            s["sonar"] = {"preset": name}
            s["sonar"].update(extra)
        return edit
    for name in PRESETS:
        C("sonar.preset = %s beside every explicit key" % name, put("sonar", "preset", name),
          "valid")
        C("sonar.preset = %s alone" % name, preset_only(name), "valid")
    for v, expect in (("bogus", "invalid"), ("Klein-3900-445", "either"), ("", "invalid"),
                      ("klein", "invalid"), (3, "invalid"), ([], "invalid"), ({}, "invalid"),
                      (None, "either")):
        C("sonar.preset = %r" % (v,), put("sonar", "preset", v), expect,
          needles=["preset", str(v) if v not in ("", [], {}) else "preset"])
    C("sonar.preset under render", put("render", "preset", "klein-3900-445"), "invalid",
      needles=["preset"])
    C("sonar.preset at the top level", lambda s: s.__setitem__("preset", "klein-3900-445"),
      "invalid", needles=["preset"])
    # docs/sonar-presets.md: a pulse block of another type needs that type's key
    C("chirp preset, pulse {type: cw} without length_us",
      preset_only("edgetech-4200-600", pulse={"type": "cw"}), "invalid",
      needles=["length_us", "pulse"])
    C("CW preset, pulse {type: chirp} without bandwidth_khz",
      preset_only("klein-3900-445", pulse={"type": "chirp"}), "invalid",
      needles=["bandwidth_khz", "pulse"])
    C("chirp preset, pulse {type: cw, length_us: 50}",
      preset_only("edgetech-4200-600", pulse={"type": "cw", "length_us": 50}), "valid")
    C("preset, vertical_beam {width_deg: 30} (keeps the shape)",
      preset_only("klein-3900-445", vertical_beam={"width_deg": 30}), "valid")
    C("preset, vertical_beam {shape: sinc} (that shape's defaults)",
      preset_only("klein-3900-445", vertical_beam={"shape": "sinc"}), "valid")
    C("preset, vertical_beam {shape: table} without its tables",
      preset_only("klein-3900-445", vertical_beam={"shape": "table"}), "invalid",
      needles=["off_axis_deg", "gain_db", "table"])
    C("preset, range_m 0", preset_only("klein-3900-900", range_m=0), "invalid",
      needles=["range_m", "0"])
    C("preset with --range 30 --samples 256", preset_only("edgetech-4200-300"), "valid",
      argv=sim("--range", "30", "--samples", "256"))
    C("preset with --samples 9000", preset_only("edgetech-4200-300"), "invalid",
      argv=sim("--samples", "9000"), needles=["samples", "9000"])
    return cases
