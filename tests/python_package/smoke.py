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


# Two tiny items (a 12 m line, 10 m range, 200 samples a side) with 64 px grey chips and COCO
# labels, no split.
TORCH_SPEC = """\
name: smoke-torch
seed: 5
count: 2
location: {lat_deg: 43.0, lon_deg: 5.0}
seabed: {depth_m: [10, 14], cell_m: 0.5, material: {sand: 1}}
objects:
  count: [2, 3]
  across_track_m: [2, 8]
  types: {box: {length_m: [1, 3], width_m: [0.5, 1], height_m: [0.4, 1]}}
survey: {line_length_m: 12, altitude_m: [3, 5], speed_m_s: 3}
sonar: {preset: seascan-hds-600, range_m: 10, samples: 200}
run:
  products:
    labels: {coco: true, chips: {size_px: 64, stride_px: 64}, chip_color: grey}
"""


def check_torch_dataloader(args):
    """A DataLoader with 2 workers iterates a dataset generated through the installed package:
    every image of the COCO file once, each target's boxes those of the COCO file."""
    import json

    import torch.utils.data

    import sonarsynth
    import sonarsynth_torch

    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp) / "dataset"
        spec = sonarsynth.DatasetSpec.from_yaml(TORCH_SPEC, "smoke-torch.yaml")
        sonarsynth.run_dataset(spec, root)
        data = sonarsynth_torch.SonarDetectionDataset(root, set="chips", split=None)
        loader = torch.utils.data.DataLoader(data, batch_size=4, num_workers=2,
                                             collate_fn=sonarsynth_torch.collate_fn)
        coco = json.loads((root / "annotations" / "chips.coco.json").read_text())
        boxes_by_image = {}
        for a in coco["annotations"]:
            x, y, w, h = a["bbox"]
            boxes_by_image.setdefault(a["image_id"], []).append([x, y, x + w, y + h])
        seen = []
        for images, targets in loader:
            for image, target in zip(images, targets):
                assert image.dtype == torch.float32 and image.shape[0] == 1, image.shape
                image_id = int(target["image_id"])
                seen.append(image_id)
                expected = sorted(boxes_by_image.get(image_id, []))
                got = sorted(target["boxes"].tolist())
                assert np.allclose(got, expected) if expected else not got, (image_id, got)
        assert sorted(seen) == sorted(im["id"] for im in coco["images"]), seen
        assert coco["annotations"], "the smoke dataset has no boxes"
    print(f"DataLoader, 2 workers: {len(seen)} images, {len(coco['annotations'])} boxes")


CHECKS = [check_import, check_version, check_read_xtf_path, check_render,
          check_stubs_found_by_mypy, check_torch_dataloader]


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
