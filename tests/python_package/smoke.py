# SPDX-License-Identifier: MIT
"""Checks an installed sonarsynth package as a user meets it (docs/python.md, Installing); run by
tests/python_package/run.sh from outside the source tree, with the interpreter of the install:

    python smoke.py --source SRC --site SITE [--pip]

SRC: the source tree (its CMakeLists.txt and tests/data); SITE: the directory the package must
be imported from; --pip: it was installed by pip (its metadata is checked, and mypy must find the
stubs through py.typed as it finds any installed package).

More checks: write a function check_NAME(args) below and add it to CHECKS.
"""
import argparse
import importlib.metadata
import pathlib
import re
import subprocess
import sys
import tempfile

import numpy as np


def check_import(args):
    import sonarsynth
    import sonarsynth_dask  # noqa: F401  (installed next to the package)

    package = pathlib.Path(sonarsynth.__file__).resolve().parent
    assert package == args.site.resolve() / "sonarsynth", f"imported from {package}"
    for name in ("py.typed", "__init__.pyi", "_sonarsynth.pyi"):
        assert (package / name).is_file(), f"{name} is not installed in {package}"
    print(f"sonarsynth {sonarsynth.__version__} from {package}")


def check_version(args):
    import sonarsynth

    text = (args.source / "CMakeLists.txt").read_text()
    version = re.search(r"^project\(sonarsynth VERSION (\S+) ", text, re.M).group(1)
    assert sonarsynth.__version__ == sonarsynth._sonarsynth.__version__ == version, (
        sonarsynth.__version__, version)
    if args.pip:
        metadata = importlib.metadata.version("sonarsynth")
        assert metadata == version, f"pip metadata {metadata}, CMakeLists.txt {version}"


def check_read_xtf_path(args):
    import sonarsynth

    xtf = sonarsynth.read_xtf(args.source / "tests" / "data" / "xtf" / "golden-tiny.xtf")
    assert xtf["port"].dtype == np.float32 and xtf["port"].ndim == 2 and len(xtf["port"]) > 0
    assert not xtf["anomalies"]
    print(f"read_xtf(pathlib.Path(...)): {xtf['port'].shape[0]} pings")


def check_render(args):
    import sonarsynth

    # A flat seabed 20 m down: the first return of a sensor 10 m above it is at 10 m slant range.
    heights = np.full((101, 101), -20.0, np.float32)
    sim = sonarsynth.Simulation.from_heights(heights, x0_m=-50, y0_m=50, dx_m=1, dy_m=-1,
                                             lat_deg=43.0, lon_deg=5.0)
    sim.set({"sonar.range_m": 20, "sonar.samples": 200})
    ping = sim.render_ping(0.0, 0.0, -10.0)
    classes = ping["port"]["truth_class"]
    first_seabed = int(np.argmax(classes == sonarsynth.SAMPLE_CLASSES.index("seabed")))
    assert abs((first_seabed + 0.5) * 20 / 200 - 10.0) <= 0.2, first_seabed


MYPY_GOOD = """\
import sonarsynth
sim = sonarsynth.Simulation.from_file("scene.yaml", seed=1)
n: int = sim.samples_per_side
version: str = sonarsynth.__version__
"""
MYPY_BAD = "import sonarsynth\nn: str = sonarsynth.Simulation.from_file('scene.yaml').epsg\n"


def check_stubs_found_by_mypy(args):
    """mypy --strict, with no MYPYPATH, finds the installed stubs through py.typed."""
    if not args.pip:
        return
    try:
        import mypy  # noqa: F401
    except ImportError:
        sys.exit("smoke: mypy is missing (python3-mypy; scripts/install-deps.sh)")
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in (("good.py", MYPY_GOOD), ("bad.py", MYPY_BAD)):
            (pathlib.Path(tmp) / name).write_text(text)
        run = [sys.executable, "-m", "mypy", "--strict", "--cache-dir", tmp + "/cache"]
        good = subprocess.run(run + ["good.py"], cwd=tmp, capture_output=True, text=True)
        assert good.returncode == 0, good.stdout + good.stderr
        bad = subprocess.run(run + ["bad.py"], cwd=tmp, capture_output=True, text=True)
        assert bad.returncode == 1 and "bad.py:2: error: Incompatible types" in bad.stdout, (
            bad.stdout + bad.stderr)
    print("mypy --strict: the installed stubs found and used")


CHECKS = [check_import, check_version, check_read_xtf_path, check_render,
          check_stubs_found_by_mypy]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source", type=pathlib.Path, required=True)
    parser.add_argument("--site", type=pathlib.Path, required=True)
    parser.add_argument("--pip", action="store_true")
    args = parser.parse_args()
    for check in CHECKS:
        check(args)
        print(f"smoke: {check.__name__} ok", flush=True)


if __name__ == "__main__":
    main()
