"""Cases of the `raster` category: broken bathymetry GeoTIFFs and hand-written ASCII grids."""

import os
import random
import shutil
import struct
import subprocess

from .case import Case, sim
from .process import text
from .scene import base_scene, scene_text


def asc_grid(ncols, nrows, cell, xll, yll, values, nodata=None, rows_written=None):
    """An ESRI ASCII grid; rows_written < nrows makes a file shorter than its header."""
    lines = ["ncols %d" % ncols, "nrows %d" % nrows, "xllcorner %r" % xll, "yllcorner %r" % yll,
             "cellsize %r" % cell]
    if nodata is not None:
        lines.append("NODATA_value %s" % nodata)
    for r in range(nrows if rows_written is None else rows_written):
        lines.append(" ".join(values(r, c) for c in range(ncols)))
    return "\n".join(lines) + "\n"


def gen_raster(h, rng):
    cases = []
    r2 = random.Random(rng.random())

    def C(desc, make, expect, needles=("bathy",), scene_over=None, fname="bathy.tif"):
        def setup(h, w):
            make(h, w)
            s = base_scene(bathy_file=fname)
            if scene_over:
                scene_over(s)
            with open(os.path.join(w, "scene.yaml"), "w") as f:
                f.write(scene_text(s))
        cases.append(Case("raster", desc, sim(), expect, needles=list(needles) + [fname],
                          outputs=["out"], setup=setup))

    def from_base(mutator):
        def make(h, w):
            with open(os.path.join(w, "bathy.tif"), "rb") as f:
                b = bytearray(f.read())
            b = mutator(b)
            with open(os.path.join(w, "bathy.tif"), "wb") as f:
                f.write(b)
        return make

    C("raster baseline (sonarsynth bathy)", lambda h, w: None, "valid")
    size = os.path.getsize(h.base_tif)
    for i in range(10):
        cut = r2.randrange(0, size)
        C("raster truncated at %d of %d" % (cut, size), from_base(lambda b, cut=cut: b[:cut]), "invalid")
    for cut in (0, 8, 16, 200):
        C("raster truncated at %d" % cut, from_base(lambda b, cut=cut: b[:cut]), "invalid")
    for i in range(14):
        flips = [(r2.randrange(0, size), r2.getrandbits(8)) for _ in range(r2.choice([1, 4, 32]))]
        if i < 5:   # header region, where the tags live
            flips = [(r2.randrange(0, min(size, 600)), r2.getrandbits(8)) for _ in range(r2.choice([1, 3]))]

        def mut(b, flips=flips):
            for pos, val in flips:
                b[pos] = val
            return b
        C("raster %d byte flips%s" % (len(flips), " in the header" if i < 5 else ""), mut and from_base(mut),
          "either")
    C("raster file missing", lambda h, w: os.remove(os.path.join(w, "bathy.tif")), "invalid")
    C("raster is a directory", lambda h, w: (os.remove(os.path.join(w, "bathy.tif")),
                                             os.mkdir(os.path.join(w, "bathy.tif"))), "invalid")
    C("raster is a text file", lambda h, w: open(os.path.join(w, "bathy.tif"), "w").write("hello\n"),
      "invalid")
    C("raster band 2 of a 1-band file", lambda h, w: None, "invalid",
      scene_over=lambda s: s["bathymetry"].__setitem__("band", 2), needles=["band"])
    C("raster depth_positive_down on elevations (seabed above the fish)", lambda h, w: None,
      "invalid", scene_over=lambda s: s["bathymetry"].__setitem__("depth_positive_down", True),
      needles=["depth", "altitude"])
    C("raster path absolute /dev/zero", lambda h, w: None, "invalid", fname="/dev/zero")
    C("raster path is the scene itself", lambda h, w: None, "invalid", fname="scene.yaml")
    # ASCII grids written here (full control over values, size and CRS); .prj = CRS
    utm31 = ('PROJCS["WGS 84 / UTM zone 31N",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",'
             '6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],'
             'PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],'
             'PARAMETER["central_meridian",3],PARAMETER["scale_factor",0.9996],'
             'PARAMETER["false_easting",500000],PARAMETER["false_northing",0],UNIT["metre",1]]')
    x0, y0 = h.base_origin

    def asc(desc, ncols, nrows, cell, values, expect, prj=True, nodata=None, xll=None, yll=None,
            tif=False, needles=("bathy",), rows_written=None):
        # GDAL's ASCII grid reader refuses "inf"/"nan" tokens; for the GeoTIFF variant they are
        # written as sentinels, converted uncompressed, and the sentinel float32 bytes patched.
        sentinels = {"inf": (12345.0, float("inf")), "nan": (12346.0, float("nan")),
                     "-inf": (12347.0, float("-inf"))}

        def make(h, w):
            os.remove(os.path.join(w, "bathy.tif"))
            name = os.path.join(w, "grid.asc")
            vals = values
            if tif:
                vals = lambda r, c: (lambda v: "%g" % sentinels[v][0] if v in sentinels else v)(values(r, c))
            with open(name, "w") as f:
                f.write(asc_grid(ncols, nrows, cell, x0 if xll is None else xll,
                                 (y0 - nrows * cell) if yll is None else yll, vals, nodata,
                                 rows_written))
            if prj:
                with open(os.path.join(w, "grid.prj"), "w") as f:
                    f.write(utm31)
            if tif and shutil.which("gdal_translate"):
                g = subprocess.run(["gdal_translate", "-q", "-ot", "Float32", "-co", "COMPRESS=NONE",
                                    name, os.path.join(w, "grid.tif")], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE)
                if g.returncode != 0:  # the case cannot be built: unclassified, never "ok"
                    raise RuntimeError("gdal_translate failed: " + text(g.stderr, 200))
                with open(os.path.join(w, "grid.tif"), "rb") as f:
                    blob = f.read()
                for sentinel, value in sentinels.values():
                    blob = blob.replace(struct.pack("<f", sentinel), struct.pack("<f", value))
                with open(os.path.join(w, "grid.tif"), "wb") as f:
                    f.write(blob)
                for ext in ("asc", "prj"):
                    p = os.path.join(w, "grid." + ext)
                    if os.path.exists(p):
                        os.remove(p)
        fname = "grid.tif" if tif and shutil.which("gdal_translate") else "grid.asc"
        C("raster " + desc + (" (GeoTIFF)" if tif else " (ASCII grid)"), make, expect,
          needles=needles, fname=fname)

    flat = lambda r, c: "-20"
    for tif in (False, True):
        asc("flat 160x160 baseline", 160, 160, 0.5, flat, "valid", tif=tif)
        asc("value inf everywhere", 160, 160, 0.5, lambda r, c: "inf", "invalid", tif=tif)
        asc("value nan everywhere", 160, 160, 0.5, lambda r, c: "nan", "invalid", tif=tif)
        asc("value 1e38 everywhere", 160, 160, 0.5, lambda r, c: "1e38", "invalid", tif=tif)
        asc("value -1e38 everywhere", 160, 160, 0.5, lambda r, c: "-1e38", "invalid", tif=tif)
        asc("one nan cell under the line", 160, 160, 0.5,
            lambda r, c: "nan" if (r, c) == (80, 80) else "-20", "either", tif=tif)
        asc("one 1e38 spike under the line", 160, 160, 0.5,
            lambda r, c: "1e38" if (r, c) == (80, 80) else "-20", "either", tif=tif)
        asc("all nodata", 160, 160, 0.5, lambda r, c: "-9999", "invalid", nodata="-9999", tif=tif)
        asc("seabed above the sea surface (+20)", 160, 160, 0.5, lambda r, c: "20", "invalid", tif=tif)
        asc("1x1 grid", 1, 1, 80.0, flat, "either", tif=tif)
        asc("2x2 grid", 2, 2, 40.0, flat, "either", tif=tif)
        asc("1 um cells (line off the grid)", 160, 160, 1e-6, flat, "invalid", tif=tif)
        asc("no CRS", 160, 160, 0.5, flat, "invalid", prj=False, tif=tif, needles=("CRS", "bathy", "grid"))
        asc("another place in the zone (lines are relative to the grid centre)", 160, 160, 0.5, flat,
            "valid", xll=300000.0, yll=4000000.0, tif=tif)
    asc("wrong row count (short file)", 160, 160, 0.5, flat, "invalid", rows_written=159)
    asc("text values", 160, 160, 0.5, lambda r, c: "abc" if c == 3 else "-20", "invalid")
    asc("cellsize 0", 160, 160, 0.0, flat, "invalid")
    # GDAL reads a negative cellsize as a grid mirrored east-west and running south to north, a
    # valid geotransform: accepting it is fine if the terrain lands where the file puts it.
    asc("cellsize -0.5", 160, 160, -0.5, flat, "either")
    asc("cellsize nan", 160, 160, float("nan"), flat, "invalid")
    return cases
