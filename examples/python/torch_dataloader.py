#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Feeds sonarsynth data to PyTorch DataLoaders with 2 workers; trains nothing
(docs/python.md, "PyTorch").

1. Generates the first items of a dataset spec into a directory (or takes a dataset already
   there) and iterates a DataLoader over its train split (SonarDetectionDataset, map-style).
2. Iterates a DataLoader over a SonarStream: further items of the spec rendered on the fly in
   the workers, each item by one worker.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/torch_dataloader.py
    PYTHONPATH=build/python /usr/bin/python3 examples/python/torch_dataloader.py \
        --dataset detector-dataset --skip-generate
"""
import argparse
import collections
import os
import pathlib
import tempfile
import time

import torch
import torch.utils.data

import sonarsynth
import sonarsynth_torch

SAMPLES = pathlib.Path(__file__).resolve().parents[2] / "samples"


def describe(name, loader):
    """Iterates the loader; prints the first batch's shapes and the counts."""
    t0 = time.perf_counter()
    batches = images = 0
    labels = collections.Counter()
    items = set()
    for batch_images, targets in loader:
        if batches == 0:
            print("  first batch: %d images %s, boxes %s, masks %s" % (
                len(batch_images), [tuple(im.shape) for im in batch_images],
                [tuple(t["boxes"].shape) for t in targets],
                [tuple(t["masks"].shape) for t in targets]))
        batches += 1
        images += len(batch_images)
        for t in targets:
            labels.update(sonarsynth_torch.CATEGORIES[c] for c in t["labels"].tolist())
            items.add(t["item"].item())
    print("  %s: %d batches, %d images of %d items, %d object and %d shadow boxes, %.1f s" % (
        name, batches, images, len(items), labels["object"], labels["shadow"],
        time.perf_counter() - t0))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--spec", default=str(SAMPLES / "datasets" / "detector.yaml"),
                   help="dataset spec (default samples/datasets/detector.yaml)")
    p.add_argument("--dataset", help="dataset directory (default: a temporary one)")
    p.add_argument("--skip-generate", action="store_true",
                   help="read --dataset as it is, generate nothing")
    p.add_argument("--items", type=int, default=6, help="items to generate (default 6)")
    p.add_argument("--stream-items", type=int, default=4,
                   help="items to render on the fly after them (default 4)")
    p.add_argument("--workers", type=int, default=2, help="DataLoader workers (default 2)")
    p.add_argument("--batch-size", type=int, default=8)
    args = p.parse_args()

    t0 = time.perf_counter()
    spec = sonarsynth.DatasetSpec.from_file(args.spec)
    with tempfile.TemporaryDirectory(prefix="sonarsynth-torch-example-") as tmp:
        root = args.dataset or os.path.join(tmp, "dataset")
        if not args.skip_generate:
            r = sonarsynth.run_dataset(spec, root, items=(0, args.items))
            print("generated items 0-%d of %s into %s: %d done, %d skipped, %.1f s" % (
                args.items - 1, args.spec, root, r["done"], r["skipped"], r["seconds"]))

        ds = sonarsynth_torch.SonarDetectionDataset(root, split="train")
        print("SonarDetectionDataset(%s, set=%r, split='train'): %d images" % (
            root, ds.set, len(ds)))
        loader = torch.utils.data.DataLoader(ds, batch_size=args.batch_size, shuffle=True,
                                             num_workers=args.workers,
                                             collate_fn=sonarsynth_torch.collate_fn)
        describe("map-style, %d workers" % args.workers, loader)

        first = args.items
        stream = sonarsynth_torch.SonarStream(spec, indices=range(first,
                                                                  first + args.stream_items))
        print("SonarStream(items %d-%d): worker k of %d renders %s" % (
            first, first + args.stream_items - 1, args.workers,
            [stream.worker_indices(k, args.workers) for k in range(args.workers)]))
        loader = torch.utils.data.DataLoader(stream, batch_size=args.batch_size,
                                             num_workers=args.workers,
                                             collate_fn=sonarsynth_torch.collate_fn)
        describe("on the fly, %d workers" % args.workers, loader)
    print("total %.1f s" % (time.perf_counter() - t0))


if __name__ == "__main__":
    main()
