# SPDX-License-Identifier: MIT
# sonarsynth.mosaic is `sonarsynth mosaic` from the same library call: the same rasters.
import subprocess

import numpy as np
import pytest

import sonarsynth

gdal = pytest.importorskip("osgeo.gdal")


@pytest.fixture
def xtf_files(scene_path, tmp_path):
    out = tmp_path / "run"
    sonarsynth.run_simulation(scene_path, str(out), mosaic=False, waterfalls=False, truth=False)
    return [str(out / "a.xtf"), str(out / "b.xtf")]


def raster(path):
    ds = gdal.Open(str(path))
    bands = [ds.GetRasterBand(i + 1).ReadAsArray() for i in range(ds.RasterCount)]
    return ds.GetGeoTransform(), ds.GetProjection(), np.stack(bands)


def same_raster(a, b):
    (ga, pa, xa), (gb, pb, xb) = raster(a), raster(b)
    assert ga == gb and pa == pb
    assert xa.dtype == xb.dtype and xa.tobytes() == xb.tobytes()


@pytest.mark.parametrize("options,flags", [
    ({}, []),
    ({"pixel_size_m": 0.5, "rule": "max", "count": True, "format": "GTiff", "grey": True},
     ["--res", "0.5", "--rule", "max", "--count", "--of", "GTiff", "--grey"]),
])
def test_mosaic_equals_the_cli(xtf_files, cli, tmp_path, options, flags):
    py_out, cli_out = tmp_path / "py.tif", tmp_path / "cli.tif"
    r = sonarsynth.mosaic(xtf_files, py_out, **options)
    done = subprocess.run([cli, "mosaic", *xtf_files, "-o", str(cli_out), *flags], check=True,
                          capture_output=True, text=True)
    assert r["files"] == [str(py_out), str(tmp_path / "py_rgb.tif")]
    same_raster(py_out, cli_out)
    same_raster(tmp_path / "py_rgb.tif", tmp_path / "cli_rgb.tif")
    # The summary is the CLI's line, paths aside.
    expected = done.stdout.replace(str(cli_out), str(py_out))
    assert expected.replace("cli_rgb.tif", "py_rgb.tif") == r["text"] + "\n"
    assert r["pings_gridded"] == r["pings"] > 0
    ds = gdal.Open(str(py_out))
    assert (ds.RasterXSize, ds.RasterYSize) == (r["cols"], r["rows"])
    assert ds.RasterCount == (2 if options.get("count") else 1)


def test_mosaic_refuses_to_write_over_its_input(xtf_files):
    with pytest.raises(ValueError, match="output .* is the input"):
        sonarsynth.mosaic(xtf_files, xtf_files[0], overwrite=True)
    with pytest.raises(ValueError, match="rgb_path .* is the same file as output"):
        sonarsynth.mosaic(xtf_files, "m.tif", rgb_path="m.tif")
    with pytest.raises(ValueError, match="rule = 'median'"):
        sonarsynth.mosaic(xtf_files, "m.tif", rule="median")
