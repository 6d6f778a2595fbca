# SPDX-License-Identifier: MIT
# The PyTorch datasets (docs/python.md, "PyTorch"): targets against the COCO and YOLO files and
# the label rasters of a dataset made by the CLI, read here with json and GDAL; the RLE decoder
# against hand-made masks; every image once through a 2-worker DataLoader; the on-the-fly stream
# equal to the CLI's dataset and the same for 0, 1 and 2 workers.
import collections
import json
import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

torch = pytest.importorskip("torch")
from osgeo import gdal  # noqa: E402

import sonarsynth  # noqa: E402
import sonarsynth_torch as st  # noqa: E402

from conftest import helper, tiny_dataset  # noqa: E402

gdal.UseExceptions()

# Tiny items with grey 64 px chips and every label format: a 12 m line at 3 m/s, 10 m range,
# 200 samples a side (75 pings), 1-3 rocks and boxes 2-8 m from the track.
SPEC = tiny_dataset("torch-tiny", line_length_m=12, run="""\
run:
  products:
    waterfalls: true
    truth: true
    labels: {coco: true, yolo: true, chips: {size_px: 64, stride_px: 64}, chip_color: grey}
  split: {train: 0.5, val: 0.25, test: 0.25}
""")

# Class codes of the label rasters (docs/labels.md) by COCO category id.
CLASS_OF_CATEGORY = {1: 2, 2: 3}


@pytest.fixture(scope="module")
def spec_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "torch-tiny.yaml"
    path.write_text(SPEC)
    return path


@pytest.fixture(scope="module")
def dataset(spec_path, tmp_path_factory):
    root = tmp_path_factory.mktemp("torch") / "d"
    subprocess.run([helper("SONARSYNTH_CLI"), "dataset", str(spec_path), "-o", str(root), "-q"],
                   check=True)
    return root


def read_raster(path):
    ds = gdal.Open(str(path))
    return ds.ReadAsArray()


def encode_rle(mask):
    """COCO uncompressed RLE of a 0/1 mask, written here independently of the module."""
    flat = np.asarray(mask, dtype=np.uint8).T.reshape(-1)  # column-major
    counts, value, run = [], 0, 0
    for v in flat:
        if v == value:
            run += 1
        else:
            counts.append(run)
            value, run = v, 1
    counts.append(run)
    return {"size": list(mask.shape), "counts": counts}


def test_decode_rle_hand_made_masks():
    # height 2, width 3: pixel numbers x * 2 + y; pixels 1 and 2 are (x 0, y 1) and (x 1, y 0).
    mask = st.decode_rle({"size": [2, 3], "counts": [1, 2, 3]})
    assert mask.dtype == np.uint8
    assert mask.tolist() == [[0, 1, 0], [1, 0, 0]]
    assert st.decode_rle({"size": [2, 3], "counts": [0, 6]}).tolist() == [[1, 1, 1]] * 2
    assert st.decode_rle({"size": [2, 3], "counts": [6]}).tolist() == [[0, 0, 0]] * 2
    rng = np.random.default_rng(5)
    for shape in [(1, 1), (7, 3), (64, 64), (5, 40)]:
        m = (rng.random(shape) < 0.3).astype(np.uint8)
        assert np.array_equal(st.decode_rle(encode_rle(m)), m)
    with pytest.raises(ValueError, match=r"sum to 5, not height x width = 2 x 3 = 6"):
        st.decode_rle({"size": [2, 3], "counts": [1, 2, 2]})
    with pytest.raises(ValueError, match=r"compressed RLE"):
        st.decode_rle({"size": [2, 3], "counts": "1203"})
    with pytest.raises(ValueError, match=r">= 0"):
        st.decode_rle({"size": [2, 3], "counts": [4, -1, 3]})


def check_image_set(root, set_name, split):
    """Every image of the split against the COCO file, the label rasters and the YOLO labels;
    returns the number of images and of annotations checked."""
    coco = json.loads((root / "annotations" / f"{set_name}_{split}.coco.json").read_text())
    anns = collections.defaultdict(list)
    for a in coco["annotations"]:
        anns[a["image_id"]].append(a)
    ds = st.SonarDetectionDataset(root, set=set_name, split=split)
    assert len(ds) == len(coco["images"]) > 0
    n_ann = 0
    for i, entry in enumerate(coco["images"]):
        image, target = ds[i]
        h, w = entry["height"], entry["width"]
        pixels = read_raster(root / entry["file_name"])
        if pixels.ndim == 2:
            pixels = pixels[None]
        assert image.dtype == torch.float32 and tuple(image.shape) == pixels.shape
        assert torch.equal(image, torch.from_numpy(pixels.astype(np.float32)) / 255)
        mine = anns[entry["id"]]
        n_ann += len(mine)
        assert target["image_id"].tolist() == [entry["id"]]
        assert target["item"].tolist() == [entry["item"]]
        assert target["boxes"].dtype == torch.float32 and target["boxes"].shape == (len(mine), 4)
        assert target["labels"].dtype == torch.int64
        assert target["masks"].dtype == torch.uint8 and target["masks"].shape == (len(mine), h, w)
        assert target["labels"].tolist() == [a["category_id"] for a in mine]
        assert target["iscrowd"].tolist() == [0] * len(mine)
        assert target["object_id"].tolist() == [a["object_id"] for a in mine]
        assert target["truncated"].tolist() == [a["truncated"] for a in mine]
        klass = read_raster(root / entry["class_mask"])
        instance = read_raster(root / entry["instance_mask"])
        assert klass.shape == instance.shape == (h, w)
        union = collections.defaultdict(lambda: np.zeros((h, w), dtype=bool))
        for k, a in enumerate(mine):
            x, y, bw, bh = a["bbox"]
            assert target["boxes"][k].tolist() == [x, y, x + bw, y + bh]
            mask = target["masks"][k].numpy().astype(bool)
            rows, cols = np.nonzero(mask)
            # The box is the mask's extent (pixel edges), the area its pixel count.
            assert [cols.min(), rows.min(), cols.max() + 1, rows.max() + 1] == [
                x, y, x + bw, y + bh]
            assert mask.sum() == a["area"] == target["area"][k].item()
            # The mask lies on its instance in its class in the label rasters.
            code, oid = CLASS_OF_CATEGORY[a["category_id"]], a["object_id"]
            assert np.all((klass[mask] == code) & (instance[mask] == oid))
            assert not (union[(code, oid)] & mask).any()  # pieces do not overlap
            union[(code, oid)] |= mask
        # The masks of an instance and category cover all of its pixels in the image, and every
        # object and every shadow an object casts has a box.
        labelled = np.isin(klass, (2, 3)) & (instance > 0)
        pairs = set(zip(klass[labelled].tolist(), instance[labelled].tolist()))
        assert pairs == set(union)
        for (code, oid), m in union.items():
            assert np.array_equal(m, (klass == code) & (instance == oid))
        # YOLO's labels, normalised centres and sizes, class = category id - 1.
        image_path = root / entry["file_name"]
        labels_dir = image_path.parent.parent if set_name == "chips" else image_path.parent / "yolo"
        label = labels_dir / "labels" / (image_path.stem + ".txt")
        rows = [list(map(float, line.split())) for line in label.read_text().splitlines()]
        expected = []
        for b, c in zip(target["boxes"].tolist(), target["labels"].tolist()):
            expected.append([c - 1, (b[0] + b[2]) / 2 / w, (b[1] + b[3]) / 2 / h,
                             (b[2] - b[0]) / w, (b[3] - b[1]) / h])
        assert len(rows) == len(expected)
        for got, want in zip(sorted(rows), sorted(expected)):
            assert got == pytest.approx(want, abs=1e-6)
    return len(coco["images"]), n_ann


def test_chips_and_waterfalls_match_the_coco_file_and_the_label_rasters(dataset):
    images = annotations = 0
    for split in ("train", "val", "test"):
        for set_name in ("chips", "waterfalls"):
            n_im, n_ann = check_image_set(dataset, set_name, split)
            images += n_im
            annotations += n_ann
    print("checked %d images, %d annotations" % (images, annotations))
    assert annotations >= 10  # objects and shadows were seen


def test_empty_images_and_channels(dataset):
    ds = st.SonarDetectionDataset(dataset, split="train", masks=False)
    assert ds.set == "chips"
    empty = [i for i, e in enumerate(ds.images) if not ds._annotations[e["id"]]]
    assert empty and len(empty) < len(ds)
    image, target = ds[empty[0]]
    assert image.shape == (1, 64, 64)
    assert target["boxes"].shape == (0, 4) and target["labels"].shape == (0,)
    assert "masks" not in target
    rgb = st.SonarDetectionDataset(dataset, split="train", channels=3)
    image3, target3 = rgb[empty[0]]
    assert image3.shape == (3, 64, 64) and torch.equal(image3, image.repeat(3, 1, 1))
    assert target3["masks"].shape == (0, 64, 64)
    with pytest.raises(ValueError, match=r"split = 'training'"):
        st.SonarDetectionDataset(dataset, split="training")
    with pytest.raises(FileNotFoundError, match=r"mosaic_train\.coco\.json: no such annotation"):
        st.SonarDetectionDataset(dataset, set="mosaic")
    with pytest.raises(ValueError, match=r"channels = 2"):
        st.SonarDetectionDataset(dataset, channels=2)


def test_two_worker_dataloader_yields_every_image_once(dataset):
    ds = st.SonarDetectionDataset(dataset, split="train")
    loader = torch.utils.data.DataLoader(ds, batch_size=5, num_workers=2,
                                         collate_fn=st.collate_fn)
    seen = collections.Counter()
    for images, targets in loader:
        assert len(images) == len(targets) <= 5
        for image, target in zip(images, targets):
            seen[target["image_id"].item()] += 1
            assert image.shape == (1, 64, 64)
    assert seen == collections.Counter(e["id"] for e in ds.images)


def stream_samples(stream, workers):
    loader = torch.utils.data.DataLoader(stream, batch_size=3, num_workers=workers,
                                         collate_fn=st.collate_fn)
    out = {}
    for images, targets in loader:
        for image, target in zip(images, targets):
            key = target["image_id"].item()
            assert key not in out  # every image once
            out[key] = (image, target)
    return out


def same_sample(a, b, skip=()):
    if not torch.equal(a[0], b[0]) or set(a[1]) != set(b[1]):
        return False
    return all(torch.equal(a[1][k], b[1][k]) for k in a[1] if k not in skip)


def test_stream_equals_the_cli_dataset_for_0_1_and_2_workers(spec_path, dataset, tmp_path):
    spec = sonarsynth.DatasetSpec.from_file(str(spec_path))
    stream = st.SonarStream(spec, tmp_dir=tmp_path)
    assert stream.indices == [0, 1, 2, 3]
    assert stream.worker_indices(0, 2) == [0, 2] and stream.worker_indices(1, 2) == [1, 3]
    runs = {w: stream_samples(stream, w) for w in (0, 1, 2)}
    assert os.listdir(tmp_path) == []  # the workers' directories are removed
    assert set(runs[0]) == set(runs[1]) == set(runs[2])
    for key in runs[0]:
        assert same_sample(runs[0][key], runs[1][key]) and same_sample(runs[0][key],
                                                                       runs[2][key])
    # The same images and targets as the dataset the CLI wrote, item by item in file order
    # (the image ids differ: the dataset's are renumbered over the split).
    from_cli = collections.defaultdict(list)
    for split in ("train", "val", "test"):
        ds = st.SonarDetectionDataset(dataset, split=split)
        for i in range(len(ds)):
            sample = ds[i]
            from_cli[sample[1]["item"].item()].append(sample)
    streamed = collections.defaultdict(list)
    for key in sorted(runs[2]):
        streamed[key // st.STREAM_IMAGE_ID_STRIDE].append(runs[2][key])
    assert sorted(from_cli) == sorted(streamed) == [0, 1, 2, 3]
    for item in from_cli:
        assert len(from_cli[item]) == len(streamed[item])
        for a, b in zip(from_cli[item], streamed[item]):
            assert same_sample(a, b, skip=("image_id",))


def test_stream_split_and_argument_errors(spec_path):
    spec = sonarsynth.DatasetSpec.from_file(str(spec_path))
    train = st.SonarStream(spec_path, split="train")
    assert train.indices == [i for i in range(4) if spec.item_split(i) == "train"]
    assert st.SonarStream(spec, indices=[3, 1]).worker_indices(1, 2) == [1]
    with pytest.raises(ValueError, match=r"item 4 is outside \[0, 4\)"):
        st.SonarStream(spec, indices=[0, 4])
    with pytest.raises(ValueError, match=r"threads = -1"):
        st.SonarStream(spec, threads=-1)
    no_split = sonarsynth.DatasetSpec.from_yaml(SPEC.replace(
        "  split: {train: 0.5, val: 0.25, test: 0.25}\n", ""), "no-split.yaml")
    with pytest.raises(ValueError, match=r"no run\.split"):
        st.SonarStream(no_split, split="val")
    no_chips = sonarsynth.DatasetSpec.from_yaml(SPEC.replace(
        ", chips: {size_px: 64, stride_px: 64}", ""), "no-chips.yaml")
    with pytest.raises(FileNotFoundError, match=r"item 2 has no chips/coco\.json"):
        next(iter(st.SonarStream(no_chips, indices=[2])))


def test_the_example_runs(spec_path, tmp_path):
    example = (pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" /
               "torch_dataloader.py")
    r = subprocess.run([sys.executable, str(example), "--spec", str(spec_path), "--dataset",
                        str(tmp_path / "d"), "--items", "2", "--stream-items", "2"],
                       check=True, capture_output=True, text=True, env=os.environ)
    spec = sonarsynth.DatasetSpec.from_file(str(spec_path))
    train_items = sum(spec.item_split(i) == "train" for i in range(2))
    assert train_items > 0
    assert re.search(r"map-style, 2 workers: \d+ batches, \d+ images of %d items" % train_items,
                     r.stdout), r.stdout
    assert re.search(r"on the fly, 2 workers: \d+ batches, \d+ images of 2 items", r.stdout)
    assert "worker k of 2 renders [[2], [3]]" in r.stdout
