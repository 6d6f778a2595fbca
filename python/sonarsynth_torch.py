# SPDX-License-Identifier: MIT
"""PyTorch datasets over sonarsynth datasets (docs/python.md, "PyTorch").

``SonarDetectionDataset`` reads a dataset directory written by ``sonarsynth dataset`` (or
``sonarsynth.run_dataset``); ``SonarStream`` renders the items of a dataset spec on the fly, in
the DataLoader's workers. Both yield ``(image, target)`` in torchvision's detection convention:

- ``image``: float32 tensor (C, H, W) in [0, 1], the 8-bit image divided by 255. Grey chips
  (``chip_color: grey``) have C = 1; colour images C = 3 (a mosaic's alpha band is dropped).
  ``channels=3`` repeats a grey band three times for torchvision's detection models, which
  expect RGB.
- ``target``: ``boxes`` float32 (N, 4), ``x1, y1, x2, y2`` in pixel-edge coordinates (the COCO
  box ``[x, y, w, h]`` is ``[x, y, x + w, y + h]``); ``labels`` int64 (N,), the COCO category
  ids, 1 ``object`` and 2 ``shadow`` (docs/labels.md, Boxes); torchvision keeps 0 for the
  background, so the ids are used as they are and a model takes ``num_classes=3``;
  ``masks`` uint8 (N, H, W), 1 on the box's piece (decoded from the COCO RLE); ``image_id``
  int64 (1,); ``area`` float32 (N,), the mask's pixels; ``iscrowd`` int64 (N,), all 0; and
  sonarsynth's own ``object_id`` and ``truncated`` int64 (N,) and ``item`` int64 (1,), the
  dataset item's index. An image without objects gives ``boxes`` of shape (0, 4).

The datasets' items are tuples; ``collate_fn`` batches them as tuples of images and of targets
(images of one batch may differ in size)::

    loader = torch.utils.data.DataLoader(ds, batch_size=8, num_workers=2, collate_fn=collate_fn)
"""
import os
import shutil
import tempfile

import numpy as np
import torch
import torch.utils.data

import sonarsynth

__all__ = ["SonarDetectionDataset", "SonarStream", "collate_fn", "decode_rle"]

# COCO category ids of the label files (docs/labels.md, Boxes).
CATEGORIES = {1: "object", 2: "shadow"}

# The image sets of a dataset (docs/dataset.md, Layout): the set's COCO file inside an item.
_ITEM_COCO = {"chips": os.path.join("chips", "coco.json"), "waterfalls": "waterfalls.coco.json",
              "mosaic": "mosaic.coco.json"}
_SPLITS = ("train", "val", "test")

# SonarStream's image ids: item index times this plus the image's id in the item's COCO file,
# unique over a spec (count <= 10^7) in an int64.
STREAM_IMAGE_ID_STRIDE = 1_000_000


def collate_fn(batch):
    """Batches ``(image, target)`` pairs as ``(images, targets)``, two tuples (torchvision's
    detection references do the same): images of one batch may differ in size."""
    return tuple(zip(*batch))


def decode_rle(segmentation):
    """The mask of a COCO uncompressed RLE ``{"size": [height, width], "counts": [...]}`` as a
    uint8 numpy array (height, width), 1 inside.

    The counts are alternating runs of 0 and 1, starting with 0 (that run may be empty), over the
    pixels in column-major order (pixel (x, y) is number x * height + y), summing to height x
    width (docs/labels.md, COCO). pycocotools' compressed string counts are not read."""
    try:
        height, width = (int(v) for v in segmentation["size"])
        counts = segmentation["counts"]
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError("decode_rle: segmentation %r is not {'size': [height, width], "
                         "'counts': [...]}" % (segmentation,)) from e
    if isinstance(counts, (str, bytes)):
        raise ValueError("decode_rle: compressed RLE counts (a string) are not supported; "
                         "sonarsynth writes uncompressed counts (a list of integers)")
    counts = np.asarray(counts, dtype=np.int64)
    if height < 0 or width < 0:
        raise ValueError("decode_rle: size [%d, %d]: height and width must be >= 0"
                         % (height, width))
    if counts.ndim != 1 or (counts.size and counts.min() < 0):
        raise ValueError("decode_rle: counts must be a list of integers >= 0")
    if int(counts.sum()) != height * width:
        raise ValueError("decode_rle: counts sum to %d, not height x width = %d x %d = %d"
                         % (int(counts.sum()), height, width, height * width))
    runs = np.zeros(counts.size, dtype=np.uint8)
    runs[1::2] = 1
    column_major = np.repeat(runs, counts)
    return np.ascontiguousarray(column_major.reshape(width, height).T)


def _read_image(path):
    """The image file as a uint8 tensor (C, H, W): PNG and JPEG through torchvision, other files
    (the mosaic's GeoTIFF) through GDAL."""
    if path.lower().endswith((".png", ".jpg", ".jpeg")):
        import torchvision.io
        return torchvision.io.read_image(path, torchvision.io.ImageReadMode.UNCHANGED)
    from osgeo import gdal
    ds = gdal.Open(path)
    if ds is None:
        raise OSError("cannot read image %s" % path)
    array = ds.ReadAsArray()
    if array.ndim == 2:
        array = array[None]
    if array.dtype != np.uint8:
        raise ValueError("%s: %s pixels, expected 8-bit" % (path, array.dtype))
    return torch.from_numpy(np.ascontiguousarray(array))


def _check_channels(channels):
    if channels not in (None, 1, 3):
        raise ValueError("channels = %r: must be None (as stored), 1 or 3" % (channels,))
    return channels


def _image_tensor(path, entry, channels):
    """The image as float32 (C, H, W) in [0, 1], alpha dropped, grey repeated if channels=3."""
    pixels = _read_image(path)
    if pixels.shape[0] in (2, 4):  # grey or RGB with alpha: the alpha marks nodata only
        pixels = pixels[:-1]
    height, width = pixels.shape[1:]
    if (entry.get("height"), entry.get("width")) != (height, width):
        raise ValueError("%s: %d x %d pixels, but its COCO entry says %s x %s" % (
            path, width, height, entry.get("width"), entry.get("height")))
    if channels is not None and pixels.shape[0] != channels:
        if pixels.shape[0] == 1 and channels == 3:
            pixels = pixels.repeat(3, 1, 1)
        else:
            raise ValueError("%s has %d bands; channels = %d can only repeat a grey band" % (
                path, pixels.shape[0], channels))
    return pixels.to(torch.float32).div_(255.0)


def _mask(annotation, height, width, where):
    """The annotation's mask (height, width): its RLE, or its polygons (docs/labels.md: the
    rectangles of the piece's row runs, pixel-edge coordinates)."""
    seg = annotation.get("segmentation")
    if seg is None:
        raise ValueError("%s: annotation %s has no segmentation (labels written with "
                         "segmentation: none); give masks=False" % (where, annotation.get("id")))
    if isinstance(seg, dict):
        mask = decode_rle(seg)
        if mask.shape != (height, width):
            raise ValueError("%s: annotation %s has a %d x %d mask for a %d x %d image" % (
                where, annotation.get("id"), mask.shape[1], mask.shape[0], width, height))
        return mask
    mask = np.zeros((height, width), dtype=np.uint8)
    for poly in seg:
        xs, ys = poly[0::2], poly[1::2]
        x0, x1, y0, y1 = int(min(xs)), int(max(xs)), int(min(ys)), int(max(ys))
        if len(poly) != 8 or sorted(set(xs)) != [x0, x1] or sorted(set(ys)) != [y0, y1]:
            raise ValueError("%s: annotation %s: polygon %r is not one of sonarsynth's "
                             "rectangles" % (where, annotation.get("id"), poly))
        mask[y0:y1, x0:x1] = 1
    return mask


def _target(annotations, height, width, image_id, item, masks, where):
    """torchvision's detection target of one image's COCO annotations."""
    n = len(annotations)
    boxes = torch.zeros((n, 4), dtype=torch.float32)
    for k, a in enumerate(annotations):
        x, y, w, h = a["bbox"]
        boxes[k] = torch.tensor([x, y, x + w, y + h], dtype=torch.float32)
    target = {
        "boxes": boxes,
        "labels": torch.tensor([a["category_id"] for a in annotations], dtype=torch.int64),
        "image_id": torch.tensor([image_id], dtype=torch.int64),
        "area": torch.tensor([a["area"] for a in annotations], dtype=torch.float32),
        "iscrowd": torch.tensor([a.get("iscrowd", 0) for a in annotations], dtype=torch.int64),
        "object_id": torch.tensor([a.get("object_id", 0) for a in annotations],
                                  dtype=torch.int64),
        "truncated": torch.tensor([a.get("truncated", 0) for a in annotations],
                                  dtype=torch.int64),
        "item": torch.tensor([item], dtype=torch.int64),
    }
    if masks:
        stack = np.zeros((n, height, width), dtype=np.uint8)
        for k, a in enumerate(annotations):
            stack[k] = _mask(a, height, width, where)
        target["masks"] = torch.from_numpy(stack)
    return target


def _annotations_by_image(coco):
    by_image = {im["id"]: [] for im in coco.get("images", [])}
    for a in coco.get("annotations", []):
        by_image[a["image_id"]].append(a)
    return by_image


def _load_json(path):
    import json
    with open(path, "r", encoding="utf-8") as f:
        return json.load(f)


class SonarDetectionDataset(torch.utils.data.Dataset):
    """A map-style dataset over a dataset directory written by ``sonarsynth dataset``.

    root: the dataset directory. set: the image set, ``"chips"``, ``"waterfalls"`` or
    ``"mosaic"``; None takes chips if the dataset has them, else waterfalls (as data.yaml does).
    split: ``"train"``, ``"val"``, ``"test"``, or None for a dataset without ``run.split``. It reads
    ``annotations/<set>_<split>.coco.json`` (``<set>.coco.json`` without a split), the file the
    generator merges over the done items (docs/dataset.md); element i is the file's i-th image.
    A split without items (the generator writes no file for it while the set has files of other
    splits) gives an empty dataset.
    transforms: ``transforms(image, target) -> (image, target)``, applied last. masks: decode the
    instance masks (``target["masks"]``); False leaves them out. channels: None keeps the image's
    bands (1 for grey chips, 3 for colour), 3 repeats a grey band (torchvision's models).
    ``target["image_id"]`` is the image's id in the COCO file."""

    def __init__(self, root, set=None, split="train", transforms=None, masks=True,
                 channels=None):
        self.root = os.fspath(root)
        self.channels = _check_channels(channels)
        self.transforms = transforms
        self.masks = bool(masks)
        if split is not None and split not in _SPLITS:
            raise ValueError("split = %r: must be one of train, val, test, or None" % (split,))
        if set is None:
            has_chips = any(self._exists("chips", s) for s in (None,) + _SPLITS)
            set = "chips" if has_chips else "waterfalls"
        if set not in _ITEM_COCO:
            raise ValueError("set = %r: must be one of %s" % (set, ", ".join(_ITEM_COCO)))
        self.set, self.split = set, split
        self.annotation_file = self._coco_path(set, split)
        if not os.path.isfile(self.annotation_file) and self._split_is_empty(set, split):
            coco = {}  # the generator writes no file for a split without items
        elif not os.path.isfile(self.annotation_file):
            there = os.path.join(self.root, "annotations")
            names = sorted(os.listdir(there)) if os.path.isdir(there) else []
            raise FileNotFoundError(
                "%s: no such annotation file (set %r, split %r); %s holds %s (a dataset needs "
                "run.products.labels with coco: true, docs/dataset.md)" % (
                    self.annotation_file, set, split, there, ", ".join(names) or "nothing"))
        else:
            coco = _load_json(self.annotation_file)
        self.images = coco.get("images", [])
        self.categories = {c["id"]: c["name"] for c in coco.get("categories", [])}
        self._annotations = _annotations_by_image(coco)

    def _coco_path(self, set, split):
        name = set + ("_" + split if split else "") + ".coco.json"
        return os.path.join(self.root, "annotations", name)

    def _split_is_empty(self, set, split):
        """True if the set has files of other splits but none of this one."""
        return split is not None and any(self._exists(set, other) for other in _SPLITS)

    def _exists(self, set, split):
        return os.path.isfile(self._coco_path(set, split))

    def __len__(self):
        return len(self.images)

    def __getitem__(self, index):
        entry = self.images[index]
        path = os.path.join(self.root, entry["file_name"])
        image = _image_tensor(path, entry, self.channels)
        target = _target(self._annotations[entry["id"]], entry["height"], entry["width"],
                         entry["id"], entry.get("item", -1), self.masks, path)
        if self.transforms is not None:
            image, target = self.transforms(image, target)
        return image, target


def _item_samples(item_dir, set, index, masks, channels):
    """The (image, target) pairs of one rendered item's image set, in its COCO file's order."""
    coco_path = os.path.join(item_dir, _ITEM_COCO[set])
    if not os.path.isfile(coco_path):
        raise FileNotFoundError(
            "item %d has no %s: the spec's run.products.labels needs coco: true%s "
            "(docs/dataset.md)" % (index, _ITEM_COCO[set],
                                   " and chips" if set == "chips" else
                                   " and run.products.mosaic" if set == "mosaic" else ""))
    coco = _load_json(coco_path)
    base = os.path.dirname(coco_path)
    by_image = _annotations_by_image(coco)
    out = []
    for entry in coco.get("images", []):
        if not 0 < entry["id"] < STREAM_IMAGE_ID_STRIDE:
            raise ValueError("%s: image id %d is outside 1..%d" % (
                coco_path, entry["id"], STREAM_IMAGE_ID_STRIDE - 1))
        path = os.path.join(base, entry["file_name"])
        image = _image_tensor(path, entry, channels)
        image_id = index * STREAM_IMAGE_ID_STRIDE + entry["id"]
        out.append((image, _target(by_image[entry["id"]], entry["height"], entry["width"],
                                   image_id, index, masks, path)))
    return out


class SonarStream(torch.utils.data.IterableDataset):
    """An iterable dataset that renders the items of a dataset spec as it goes.

    spec: a ``sonarsynth.DatasetSpec`` or the path of a spec file; its ``run.products.labels``
    must ask for ``coco`` (and ``chips`` for the chips). indices: the items to render (default
    all, ``range(spec.count)``), each in [0, count). split: None (all) or ``"train"``, ``"val"``,
    ``"test"``: only the items of that split (``spec.item_split``). set, masks, channels,
    transforms: as for ``SonarDetectionDataset``. threads: rendering threads per item; None
    gives 1 in a DataLoader worker and all cores in the main process (the images do not depend
    on it). tmp_dir: where each worker's temporary directory is made (default the system's).

    Each item is rendered with ``sonarsynth.run_dataset_item`` into a temporary directory of its
    worker, its images and labels read into memory, and its files removed before the next
    item; the directory is removed when the iteration ends. Worker k of n renders the items at
    positions k, k + n, k + 2n, ... of the index list (for the default list, the items i with
    i % n == k), so every item is rendered exactly once across the workers. An item is a pure
    function of (spec, index) (docs/dataset.md, Guarantees): the pairs do not depend on the
    number of workers or threads, only their order does. Each item's images come in the order
    of its COCO file; ``target["image_id"]`` is ``item * 1,000,000 + the image's id in the
    item's file`` (unique over the spec) and ``target["item"]`` the item's index."""

    def __init__(self, spec, indices=None, split=None, set="chips", transforms=None,
                 masks=True, channels=None, threads=None, tmp_dir=None):
        super().__init__()
        if not isinstance(spec, sonarsynth.DatasetSpec):
            spec = sonarsynth.DatasetSpec.from_file(os.fspath(spec))
        self.spec = spec
        if set not in _ITEM_COCO:
            raise ValueError("set = %r: must be one of %s" % (set, ", ".join(_ITEM_COCO)))
        if split is not None and split not in _SPLITS:
            raise ValueError("split = %r: must be one of train, val, test, or None" % (split,))
        if indices is None:
            indices = range(spec.count)
        checked = []
        for i in indices:
            if isinstance(i, bool) or not isinstance(i, (int, np.integer)):
                raise TypeError("indices: %r is not an integer" % (i,))
            if not 0 <= i < spec.count:
                raise ValueError("indices: item %d is outside [0, %d), the spec's count" % (
                    i, spec.count))
            checked.append(int(i))
        if split is not None:
            if spec.item_split(0) == "":
                raise ValueError("split = %r, but the spec has no run.split" % (split,))
            checked = [i for i in checked if spec.item_split(i) == split]
        self.indices = checked
        self.set, self.split = set, split
        self.transforms = transforms
        self.masks = bool(masks)
        self.channels = _check_channels(channels)
        if threads is not None and (isinstance(threads, bool) or int(threads) != threads
                                    or threads < 0):
            raise ValueError("threads = %r: must be None or an integer >= 0 (0: all cores)"
                             % (threads,))
        self.threads = threads
        self.tmp_dir = None if tmp_dir is None else os.fspath(tmp_dir)

    def worker_indices(self, worker, workers):
        """The items worker ``worker`` of ``workers`` renders: positions worker, worker + workers,
        ... of ``indices``."""
        if not 0 <= worker < workers:
            raise ValueError("worker %d of %d: must be in [0, %d)" % (worker, workers, workers))
        return self.indices[worker::workers]

    def __iter__(self):
        info = torch.utils.data.get_worker_info()
        worker, workers = (0, 1) if info is None else (info.id, info.num_workers)
        threads = self.threads if self.threads is not None else (0 if info is None else 1)
        mine = self.worker_indices(worker, workers)
        return self._render(mine, threads)

    def _render(self, mine, threads):
        if not mine:
            return
        work = tempfile.mkdtemp(prefix="sonarsynth-stream-", dir=self.tmp_dir)
        try:
            sonarsynth.prepare_dataset_dir(self.spec, work)
            for index in mine:
                sonarsynth.run_dataset_item(self.spec, work, index, int(threads))
                item_dir = os.path.join(work, sonarsynth.dataset_item_dir(index))
                samples = _item_samples(item_dir, self.set, index, self.masks, self.channels)
                shutil.rmtree(item_dir)
                for image, target in samples:
                    if self.transforms is not None:
                        image, target = self.transforms(image, target)
                    yield image, target
        finally:
            shutil.rmtree(work, ignore_errors=True)
