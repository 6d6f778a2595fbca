# SPDX-License-Identifier: MIT
# Inputs as a user gives them (docs/python.md): paths as pathlib.Path, the local frame against an
# independent projection, bad arguments refused with the argument, its value and the allowed
# range (the scene file's rules and messages), and files with pings of different lengths read
# without padding.
import os
import pathlib
import re
import struct
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sonarsynth

DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data"
SAMPLES = pathlib.Path(os.environ.get("SONARSYNTH_SAMPLES",
                                      pathlib.Path(__file__).resolve().parents[2] / "samples"))


def write_geotiff(path, heights, epsg=32631, x0=640000.0, y0=4762000.0, cell=1.0, nodata=None):
    """A north-up GeoTIFF of `heights` (rows, cols) through GDAL, for scene files."""
    gdal = pytest.importorskip("osgeo.gdal")
    osr = pytest.importorskip("osgeo.osr")
    rows, cols = heights.shape
    ds = gdal.GetDriverByName("GTiff").Create(str(path), cols, rows, 1, gdal.GDT_Float32)
    ds.SetGeoTransform([x0, cell, 0.0, y0, 0.0, -cell])
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(epsg)
    ds.SetProjection(srs.ExportToWkt())
    band = ds.GetRasterBand(1)
    if nodata is not None:
        band.SetNoDataValue(nodata)
    band.WriteArray(heights)
    ds = None


def utm(epsg):
    """(lat, lon) degrees -> (easting, northing) in `epsg` by GDAL/PROJ (independent of the
    library's GeographicLib)."""
    osr = pytest.importorskip("osgeo.osr")
    wgs84, target = osr.SpatialReference(), osr.SpatialReference()
    wgs84.ImportFromEPSG(4326)
    target.ImportFromEPSG(epsg)
    for s in (wgs84, target):
        s.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    t = osr.CoordinateTransformation(wgs84, target)
    return lambda lat, lon: t.TransformPoint(lon, lat)[:2]


def flat(depth_m=-20.0, n=101):
    return np.full((n, n), depth_m, np.float32)


# --- paths -------------------------------------------------------------------------------------

def test_every_path_argument_takes_a_pathlib_path(scene_path, tmp_path):
    scene = pathlib.Path(scene_path)
    jsf_scene = tmp_path / "jsf_scene.yaml"
    jsf_scene.write_text(scene.read_text() + "output: {jsf: true}\n")
    out = tmp_path / "out"
    r = sonarsynth.run_simulation(jsf_scene, out, mosaic=False, waterfalls=False, truth=False)
    assert (out / "a.xtf").is_file() and r["total_pings"] > 0
    x = sonarsynth.read_xtf(out / "a.xtf")
    j = sonarsynth.read_jsf(out / "a.jsf")
    either = sonarsynth.read_sonar(out / "a.jsf")
    assert x["port"].shape[0] > 0
    assert x["port"].tobytes() == j["port"].tobytes() == either["port"].tobytes()
    # The same arrays as with a str.
    assert sonarsynth.read_xtf(str(out / "a.xtf"))["port"].tobytes() == x["port"].tobytes()
    a = sonarsynth.Simulation.from_file(scene)
    b = sonarsynth.Simulation.from_file(str(scene))
    assert np.array_equal(a.survey_poses(), b.survey_poses())
    with pytest.raises(sonarsynth.FormatError):
        sonarsynth.read_xtf(tmp_path / "missing.xtf")


def test_from_yaml_base_dir_takes_a_path(tmp_path):
    grid_dir = tmp_path / "grids"
    grid_dir.mkdir()
    write_geotiff(grid_dir / "seabed.tif", flat(-15.0, 60))
    text = ("bathymetry: {file: seabed.tif}\nsurvey: {lines: [{name: a, waypoints: "
            "[{east_m: -10, north_m: 0}, {east_m: 10, north_m: 0}]}]}\n")
    sim = sonarsynth.Simulation.from_yaml(text, name="mine.yaml", base_dir=grid_dir)
    assert sim.epsg == 32631 and len(sim.survey_poses()) > 0
    # Relative to base_dir, not to the working directory: elsewhere the file is not found.
    with pytest.raises(sonarsynth.FormatError):
        sonarsynth.Simulation.from_yaml(text, name="mine.yaml", base_dir=tmp_path)


def test_dataset_functions_take_paths(tmp_path):
    spec_file = tmp_path / "tiny.yaml"
    spec_file.write_text(textwrap.dedent("""\
        name: tiny
        seed: 5
        count: 1
        location: {lat_deg: 43.0, lon_deg: 5.0}
        seabed: {depth_m: 12, cell_m: 0.5}
        objects: {count: 1, types: {rock: {diameter_m: 1}}}
        survey: {line_length_m: 3, altitude_m: 4, speed_m_s: 3}
        sonar: {preset: seascan-hds-600, range_m: 8, samples: 100}
        """))
    spec = sonarsynth.DatasetSpec.from_file(spec_file)
    assert spec.count == 1
    d = tmp_path / "ds"
    sonarsynth.prepare_dataset_dir(spec, d)
    item = sonarsynth.run_dataset_item(spec, d, 0, threads=1)
    assert item["status"] == "done"
    sonarsynth.write_dataset_manifest(spec, d)
    assert (d / "manifest.jsonl").is_file()
    assert sonarsynth.run_dataset(spec, d, threads=1)["skipped"] == 1


# --- the local frame ---------------------------------------------------------------------------

def test_scene_frame_matches_an_independent_projection():
    sim = sonarsynth.Simulation.from_file(SAMPLES / "rough_seabed.yaml")
    f = sim.scene_frame
    assert (f.epsg, f.zone, f.northp) == (32632, 32, True)
    forward = utm(f.epsg)
    # The origin: the generator's centre projected, rounded to whole kilometres.
    e, n = forward(57.05, 11.20)
    assert (f.origin_easting_m, f.origin_northing_m) == (round(e / 1000) * 1000,
                                                         round(n / 1000) * 1000)
    lat = np.array([57.0, 57.05, 57.1, 56.9, 57.049])
    lon = np.array([11.0, 11.20, 11.4, 11.3, 11.201])
    x, y = f.local_from_geodetic(lat, lon)
    for i in range(len(lat)):
        e, n = forward(lat[i], lon[i])
        assert abs(x[i] - (e - f.origin_easting_m)) < 1e-3
        assert abs(y[i] - (n - f.origin_northing_m)) < 1e-3
    # Round trip, and the origin's own coordinates.
    la, lo = f.geodetic_from_local(x, y)
    assert np.abs(la - lat).max() < 1e-10 and np.abs(lo - lon).max() < 1e-10
    assert np.allclose(f.local_from_geodetic(f.origin_lat_deg, f.origin_lon_deg), (0, 0),
                       atol=1e-6)
    # Scalars give floats, arrays their (broadcast) shape, NaN gives NaN.
    assert all(isinstance(v, float) for v in f.local_from_geodetic(57.05, 11.2))
    assert f.local_from_geodetic(lat.reshape(5, 1), lon[:3])[0].shape == (5, 3)
    assert np.isnan(f.geodetic_from_local(np.nan, 0.0)).all()
    # sim.local_from_geodetic is the same implementation.
    assert sim.local_from_geodetic(lat, lon)[0].tobytes() == x.tobytes()
    with pytest.raises(ValueError, match=r"element 1: lat_deg = 95"):
        f.local_from_geodetic([57.0, 95.0], [11.0, 11.0])


def test_survey_poses_map_back_to_the_scene_files_coordinates():
    sim = sonarsynth.Simulation.from_file(SAMPLES / "rough_seabed.yaml")
    f = sim.scene_frame
    bx0, by0, bx1, by1 = sim.bounds_m
    assert f.grid_centre_m == ((bx0 + bx1) / 2, (by0 + by1) / 2)
    # The grid is centred on the generator's centre: up to rounding to its 0.2 m cells.
    assert np.allclose(f.grid_centre_m, f.local_from_geodetic(57.05, 11.20), atol=0.1)
    poses = sim.survey_poses()
    # The scene file's lines: L1 (-70, -5) -> (70, -5), L2 (70, 25) -> (-70, 25), east_m/north_m.
    for line, (e0, e1, north) in enumerate([(-70, 70, -5), (70, -70, 25)]):
        p = poses[poses["line"] == line]
        east, n = f.scene_from_local(p["reference_x_m"], p["reference_y_m"])
        assert np.abs(n - north).max() < 1e-9
        assert abs(east[0] - e0) < 1e-9
        step = np.abs(np.diff(east))
        assert abs(east[-1] - e0) <= 140 and abs(east[-1] - e1) < step.max() + 1e-9
        # One ping every speed x ping period along the line (survey.speed_m_s: 1.5).
        assert np.allclose(step, 1.5 * np.diff(p["time_utc_us"]) / 1e6, atol=1e-6)
        x, y = f.local_from_scene(east, n)
        assert np.allclose(x, p["reference_x_m"], atol=1e-9)
        assert np.allclose(y, p["reference_y_m"], atol=1e-9)
    # A line given in scene coordinates through local_from_scene runs over the grid.
    sim.add_line("mine", np.column_stack(f.local_from_scene([-60, 60], [0, 0])))
    mine = sim.survey_poses()
    mine = mine[mine["line"] == 2]
    assert (mine["sensor_x_m"] > bx0).all() and (mine["sensor_x_m"] < bx1).all()
    assert (mine["altitude_m"] > 0).all()


def test_from_heights_frame_is_the_zone_of_lat_lon_with_a_kilometre_origin():
    sim = sonarsynth.Simulation.from_heights(flat(), x0_m=-50, y0_m=50, dx_m=1, dy_m=-1,
                                             lat_deg=-33.9, lon_deg=18.4)
    f = sim.scene_frame
    assert f.epsg == 32734 and not f.northp
    e, n = utm(f.epsg)(-33.9, 18.4)
    assert (f.origin_easting_m, f.origin_northing_m) == (round(e / 1000) * 1000,
                                                         round(n / 1000) * 1000)
    assert f.grid_centre_m == (0.0, 0.0)
    x, y = f.local_from_geodetic(-33.9, 18.4)
    assert abs(x - (e - f.origin_easting_m)) < 1e-3 and abs(y - (n - f.origin_northing_m)) < 1e-3


# --- from_heights ------------------------------------------------------------------------------

def heights_error(heights, **kw):
    args = dict(x0_m=0.0, y0_m=0.0, dx_m=1.0, dy_m=-1.0, lat_deg=43.0, lon_deg=5.0)
    args.update(kw)
    with pytest.raises(ValueError) as e:
        sonarsynth.Simulation.from_heights(heights, name="code", **args)
    return str(e.value)


def test_from_heights_refuses_what_a_scene_file_refuses(tmp_path):
    nan = np.full((20, 20), np.nan, np.float32)
    assert "heights_m: every node is nodata" in heights_error(nan)
    assert "every node is nodata" in heights_error(np.full((20, 20), np.inf, np.float32))
    board = np.where((np.indices((20, 20)).sum(0) % 2) == 0, -20.0, np.nan).astype(np.float32)
    assert "no 2 x 2 block of valid nodes" in heights_error(board)
    # 50 m above sea level: the message of a scene file with the same grid.
    up = flat(50.0, 20)
    msg = heights_error(up)
    rule = ("the seabed is above sea level everywhere (heights 50 .. 50 m). Violated "
            "constraint: bathymetry heights < 0 somewhere")
    assert msg.startswith("code: from_heights: heights_m: ") and rule in msg
    write_geotiff(tmp_path / "up.tif", up)
    with pytest.raises(ValueError, match=re.escape(rule)):
        sonarsynth.Simulation.from_yaml("bathymetry: {file: up.tif}\n", base_dir=tmp_path)
    write_geotiff(tmp_path / "none.tif", np.full((20, 20), -9999.0, np.float32), nodata=-9999.0)
    with pytest.raises(sonarsynth.FormatError, match="every node is nodata"):
        sonarsynth.Simulation.from_yaml("bathymetry: {file: none.tif}\n", base_dir=tmp_path)
    # A coast (part of the grid above sea level) is a seabed, as in a scene file.
    coast = flat(-20.0, 20)
    coast[:5] = 3.0
    sonarsynth.Simulation.from_heights(coast, lat_deg=43.0, lon_deg=5.0)


def test_from_heights_names_the_bad_argument():
    h = flat(-20.0, 20)
    msg = heights_error(h, lon_deg=np.inf)
    assert "lon_deg = inf" in msg and "lat" not in msg.replace("Violated", "")
    assert "lat_deg = 95" in heights_error(h, lat_deg=95.0)
    assert "lat_deg = nan" in heights_error(h, lat_deg=np.nan)
    for key in ("x0_m", "y0_m"):
        for bad in (np.nan, np.inf):
            assert f"{key} = {'nan' if np.isnan(bad) else 'inf'}" in heights_error(h, **{key: bad})
    for bad in (0.0, -1.0, np.nan, np.inf):
        assert "dx_m = " in heights_error(h, dx_m=bad)
    for bad in (0.0, np.nan, -np.inf):
        assert "dy_m = " in heights_error(h, dy_m=bad)
    assert "heights_m has 1 dimensions" in heights_error(np.zeros(10, np.float32) - 5)
    assert "at least 2 x 2 nodes" in heights_error(np.full((1, 10), -5.0, np.float32))


# --- add_line ----------------------------------------------------------------------------------

def line_error(sim, waypoints):
    with pytest.raises(ValueError) as e:
        sim.add_line("l", waypoints)
    return str(e.value)


def test_add_line_names_the_bad_waypoint():
    sim = sonarsynth.Simulation.from_heights(flat(), x0_m=-50, y0_m=50, dx_m=1, dy_m=-1,
                                             lat_deg=43.0, lon_deg=5.0, name="code")
    for bad, text in ((np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf")):
        msg = line_error(sim, [[0, 0], [bad, 5], [10, 0]])
        assert "code: survey line 'l' waypoint 1 = (" + text in msg, msg
        assert "finite" in msg and "repeats" not in msg
    assert "(0, 10000000) m is 10000000 m from the bathymetry grid's centre" in line_error(sim, [[0, 0], [0, 1e7]])
    assert "repeats waypoint 1" in line_error(sim, [[0, 0], [0, 0]])
    assert ">= 2 waypoints" in line_error(sim, [[0, 0]])
    assert "has shape (3)" in line_error(sim, [1, 2, 3])
    assert "has shape (2, 3)" in line_error(sim, [[1, 2, 3], [4, 5, 6]])
    # Nothing was added: the survey has no line yet.
    with pytest.raises(ValueError, match="none"):
        sim.survey_poses()
    sim.add_line("ok", [[-20, 0], [20, 0]])
    assert len(sim.survey_poses()) > 0


# --- pings of different lengths ----------------------------------------------------------------

LONG = 1_048_575  # the largest JSF ping: a 20-bit sample count


def pattern(n):
    """n little-endian u16 samples of a known pattern."""
    return np.arange(n, dtype=np.uint32).astype(np.uint16) * np.uint16(7) + np.uint16(1)


def craft_jsf(path, pings, long_samples, short_samples=16):
    """A JSF file (docs/jsf.md) built from the messages of tiny-from-xtf.jsf: `pings` pings of
    `short_samples` per side, ping pings // 2 with `long_samples` on port."""
    d = (DATA / "jsf" / "tiny-from-xtf.jsf").read_bytes()
    msgs, off = [], 0
    while off + 16 <= len(d):
        size = struct.unpack_from("<I", d, off + 12)[0]
        msgs.append(d[off:off + 16 + size])
        off += 16 + size
    is80 = [struct.unpack_from("<H", m, 4)[0] == 80 for m in msgs]
    out = bytearray(b"".join(m for m, s in zip(msgs, is80) if not s))
    side = {m[8]: m[:16 + 240] for m, s in zip(msgs, is80) if s}
    for p in range(pings):
        for ch in (0, 1):
            n = long_samples if (p == pings // 2 and ch == 0) else short_samples
            m = bytearray(side[ch])
            struct.pack_into("<I", m, 12, 240 + 2 * n)
            struct.pack_into("<I", m, 16 + 8, p)
            msb1 = struct.unpack_from("<H", m, 16 + 16)[0] & ~0x0F00
            struct.pack_into("<H", m, 16 + 16, msb1 | ((n >> 16) & 0xF) << 8)
            struct.pack_into("<H", m, 16 + 114, n & 0xFFFF)
            out += m + pattern(n).tobytes()
    path.write_bytes(out)
    return len(out)


def craft_xtf(path, pings, long_samples, short_samples=16):
    """An XTF file (docs/xtf.md) built from golden-tiny.xtf's headers and first ping: `pings`
    pings of `short_samples` per side, ping pings // 2 with `long_samples` on port."""
    d = (DATA / "xtf" / "golden-tiny.xtf").read_bytes()
    off, head, ping = 1024, [d[:1024]], None
    while off + 14 <= len(d):
        n = struct.unpack_from("<I", d, off + 10)[0]
        if d[off + 2] != 0:
            head.append(d[off:off + n])
        elif ping is None:
            ping = d[off:off + n]
        off += n
    ns = struct.unpack_from("<I", ping, 256 + 42)[0]
    chans = [ping[256:256 + 64], ping[256 + 64 + 2 * ns:256 + 128 + 2 * ns]]
    out = bytearray(b"".join(head))
    for p in range(pings):
        body = bytearray()
        for ch in (0, 1):
            n = long_samples if (p == pings // 2 and ch == 0) else short_samples
            c = bytearray(chans[ch])
            struct.pack_into("<I", c, 42, n)
            # Port is stored far -> near (docs/xtf.md): the reader reverses it.
            body += c + (pattern(n)[::-1] if ch == 0 else pattern(n)).tobytes()
        total = 256 + len(body)
        total += -total % 64
        h = bytearray(ping[:256])
        struct.pack_into("<I", h, 10, total)
        out += h + body + bytes(total - 256 - len(body))
    path.write_bytes(out)
    return len(out)


@pytest.mark.parametrize("craft,reader", [(craft_jsf, sonarsynth.read_jsf),
                                          (craft_xtf, sonarsynth.read_xtf)])
def test_pings_of_different_lengths_are_not_padded(tmp_path, craft, reader):
    path = tmp_path / "long.bin"
    craft(path, 9, 1000, short_samples=16)
    for r in (reader(path), sonarsynth.read_sonar(path)):
        assert not r["anomalies"]
        port, stbd = r["port"], r["starboard"]
        lengths = [16] * 9
        lengths[4] = 1000
        assert isinstance(port, list) and [len(a) for a in port] == lengths
        assert r["port_sample_count"].tolist() == lengths
        for a, n in zip(port, lengths):
            assert a.dtype == np.float32 and np.array_equal(a, pattern(n).astype(np.float32))
        # Starboard: every ping 16 samples, the (pings, samples) array as before.
        assert isinstance(stbd, np.ndarray) and stbd.shape == (9, 16)
        assert r["starboard_sample_count"].tolist() == [16] * 9
        assert np.array_equal(stbd, np.tile(pattern(16).astype(np.float32), (9, 1)))
        assert len(r["time_utc_us"]) == 9
    # No ping at all: (0, 0) arrays.
    craft(path, 0, 10)
    empty = reader(path)
    assert empty["port"].shape == (0, 0) and empty["port_sample_count"].shape == (0,)


@pytest.mark.parametrize("craft", [craft_jsf, craft_xtf])
def test_one_long_ping_costs_its_samples_not_all_pings_times_it(tmp_path, craft):
    # A 2 MB file: 465 pings, one of them with 1,048,575 samples on port. Padded to the longest
    # that was 465 x 1,048,575 x 4 bytes = 1.95 GB for port (3.9 GB peak); it must stay within a
    # small multiple of the file's size.
    path = tmp_path / "long.bin"
    size = craft(path, 465, LONG)
    assert 2_000_000 < size < 2_500_000
    probe = textwrap.dedent(f"""\
        import resource, sonarsynth
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        r = sonarsynth.read_sonar({str(path)!r})
        after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        assert sorted(len(a) for a in r["port"])[-2:] == [16, {LONG}]
        print((after - before) * 1024)
        """)
    grown = int(subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True,
                               text=True, env=dict(os.environ)).stdout)
    assert grown < 10 * size, f"peak RSS grew by {grown} bytes reading a {size}-byte file"
