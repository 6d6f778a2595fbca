"""The base scene (tiny and fast: ~600 pings of 128 samples), the slow scene of the interrupt
cases, a YAML emitter for mutants and helpers to walk and edit the scene tree."""

import json

class Raw:
    """YAML text inserted verbatim (a mutated value)."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return "Raw(%r)" % self.text[:40]


def base_scene(bathy_file=None):
    if bathy_file:
        bathy = {"file": bathy_file, "depth_positive_down": False, "band": 1}
    else:
        bathy = {"generate": {
            "centre": {"lat_deg": 43.0, "lon_deg": 5.0},
            "size_m": [80, 80], "cell_m": 0.5, "depth_m": 20, "seed": 5,
            "components": [
                {"type": "plane", "slope_deg": 1.0, "downslope_azimuth_deg": 100},
                {"type": "seamount", "east_m": 5, "north_m": 10, "height_m": 1.5, "radius_m": 4},
            ]}}
    return {
        "name": "adv",
        "seed": 3,
        "bathymetry": bathy,
        "materials": [{"name": "shell", "lambert_mu_db": -17, "reflectivity": 0.7,
                       "texture_shape": 4}],
        "seabed": {"material": "sand"},
        "objects": [
            {"type": "pipe", "id": 1, "start": {"east_m": -15, "north_m": 8},
             "end": {"east_m": 15, "north_m": 8}, "diameter_m": 0.5, "clearance_m": 0,
             "material": "steel"},
            {"type": "box", "position": {"east_m": 0, "north_m": -8}, "heading_deg": 35,
             "size_m": [3, 1.5, 1.2], "material": "steel"},
            {"type": "rock", "position": {"east_m": 8, "north_m": -5}, "diameter_m": 1.2},
        ],
        "survey": {
            "start_time": "2026-03-01T10:00:00Z",
            "speed_m_s": 3.0,
            "altitude_m": 6,
            "layback_m": 0,
            "lever_arm_m": [0, 0, 0],
            "disturbance": {"roll_deg": 0.5, "pitch_deg": 0.3, "yaw_deg": 0.3, "heave_m": 0.05,
                            "period_s": 7},
            "lines": [{"name": "L1", "waypoints": [{"east_m": -25, "north_m": 0},
                                                    {"east_m": 25, "north_m": 0}]}],
        },
        "sonar": {
            "frequency_khz": 600, "range_m": 18, "samples": 128, "sound_speed_m_s": 1500,
            "tilt_deg": 20, "vertical_beam": {"shape": "gaussian", "width_deg": 50},
            "horizontal_beam_deg": 0.5, "pulse": {"type": "cw", "length_us": 50},
            "ping_period_s": 0,
        },
        "render": {
            "backscatter": "paper", "shadows": True, "spreading": True, "beam_pattern": True,
            "absorption": True,
            "water": {"temperature_c": 10, "salinity_psu": 35, "ph": 8, "depth_m": 20},
            "calibration_k": 1.0,
            "quality": {"grid_subdivisions": 1, "object_segments": 16, "gauss_points": 2,
                        "along_track_planes": "auto", "along_track_tolerance_db": 1.0},
        },
        "noise": {"model": "speckle", "uniform_half_width": 0.3, "snr_db": 20, "texture": True,
                  "freeze_cell_m": 0, "along_track_correlation": True},
        # The sensor stage and the new output keys at their defaults (docs/scene-format.md): the
        # XTF is the same as without them.
        "sensor": {"noise_floor_dbfs": -50, "volume_reverberation_db": -29, "shadow_fill_db": -36,
                   "first_return_reflection_db": -6, "first_return_rms_slope": 0.15,
                   "side_lobe_db": -16, "ring_down_m": 0.15},
        "output": {"tvg": "spherical", "gain_db": "auto", "sample_format": "u16", "truth": True,
                   "quantity": "amplitude", "detector": "max", "detector_sub_samples": 3,
                   "seabed_median_dbfs": -11, "normalise": "none", "display": "db"},
    }


def yaml_scalar(v):
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if v is None:
        return "~"
    raise TypeError(v)


def is_scalar_list(v):
    return isinstance(v, list) and all(not isinstance(x, (dict, list)) for x in v)


def emit_yaml(node, indent=0):
    pad = "  " * indent
    out = []
    if isinstance(node, dict):
        for k, v in node.items():
            key = k.text if isinstance(k, Raw) else k
            if isinstance(v, dict) and v:
                out.append("%s%s:" % (pad, key))
                out.append(emit_yaml(v, indent + 1))
            elif isinstance(v, list) and v and not is_scalar_list(v):
                out.append("%s%s:" % (pad, key))
                out.append(emit_yaml(v, indent + 1))
            elif isinstance(v, list):
                out.append("%s%s: [%s]" % (pad, key, ", ".join(yaml_scalar(x) for x in v)))
            elif isinstance(v, dict):
                out.append("%s%s: {}" % (pad, key))
            else:
                out.append("%s%s: %s" % (pad, key, yaml_scalar(v)))
    elif isinstance(node, list):
        for item in node:
            if isinstance(item, dict) and item:
                body = emit_yaml(item, indent + 1).split("\n")
                out.append("%s- %s" % (pad, body[0].lstrip()))
                out.extend(body[1:])
            elif isinstance(item, list) and not is_scalar_list(item):
                out.append("%s-" % pad)
                out.append(emit_yaml(item, indent + 1))
            elif isinstance(item, list):
                out.append("%s- [%s]" % (pad, ", ".join(yaml_scalar(x) for x in item)))
            else:
                out.append("%s- %s" % (pad, yaml_scalar(item)))
    return "\n".join(x for x in out if x != "")


def scene_text(scene):
    return emit_yaml(scene) + "\n"


def leaves(node, path=()):
    """Every scalar leaf (lists of scalars yield one leaf per element)."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from leaves(v, path + (i,))
    else:
        yield path, node


def containers(node, path=()):
    if isinstance(node, dict):
        yield path, node
        for k, v in node.items():
            yield from containers(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from containers(v, path + (i,))


def get_path(node, path):
    for p in path:
        node = node[p]
    return node


def set_path(node, path, value):
    get_path(node, path[:-1])[path[-1]] = value


def path_str(path):
    s = ""
    for p in path:
        s += "[%d]" % p if isinstance(p, int) else ("." if s else "") + str(p)
    return s


SLOW_SCENE = """name: slow
seed: 3
bathymetry:
  generate: {centre: {lat_deg: 43.0, lon_deg: 5.0}, size_m: [300, 120], cell_m: 0.5, depth_m: 20}
survey:
  start_time: "2026-03-01T10:00:00Z"
  speed_m_s: 1.0
  altitude_m: 8
  lines:
    - {name: L1, waypoints: [{east_m: -120, north_m: 0}, {east_m: 120, north_m: 0}]}
    - {name: L2, waypoints: [{east_m: 120, north_m: 10}, {east_m: -120, north_m: 10}]}
sonar: {frequency_khz: 600, range_m: 40, samples: 1024}
"""
