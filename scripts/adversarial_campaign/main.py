"""Command line and the campaign loop."""

import argparse
import json
import os
import random
import re
import shutil
import sys
import time

from .case import CATEGORIES
from .harness import Harness
from .process import make_removable
from .report import GENERATORS, select, summary_table


def main(doc):
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", required=True, help="the sonarsynth binary under test")
    ap.add_argument("--cases", type=int, default=400, help="number of cases (default 400)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per run (default 60)")
    ap.add_argument("--out", default="adversarial-report.json")
    ap.add_argument("--keep-failures", metavar="DIR",
                    help="copy the sandbox of every case not ok/clean_error (or with litter) here")
    ap.add_argument("--categories", default=",".join(CATEGORIES),
                    help="comma-separated subset of " + ",".join(CATEGORIES))
    ap.add_argument("--mem-mb", type=int, default=4096,
                    help="address-space limit per run, MiB (0 = none; off for ASan builds)")
    ap.add_argument("--tmp", default=None, help="where the sandboxes go (default $TMPDIR)")
    ap.add_argument("--list", action="store_true", help="list the selected cases and exit")
    ap.add_argument("--match", metavar="REGEX",
                    help="only the generated cases whose description matches (before selection)")
    ap.add_argument("--keep-sandboxes", action="store_true")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit("not an executable: " + args.cli)
    h = Harness(args)
    t0 = time.time()
    try:
        h.prepare()
        rng = random.Random(args.seed)
        cats = [c for c in args.categories.split(",") if c]
        by_cat = {}
        for cat in CATEGORIES:
            r_cat = random.Random("%d-%s" % (args.seed, cat))
            by_cat[cat] = GENERATORS[cat](h, r_cat) if cat in cats else []
            if args.match:
                by_cat[cat] = [c for c in by_cat[cat] if re.search(args.match, c.desc)]
        chosen = select(by_cat, args.cases, rng)
        universe = sum(len(v) for v in by_cat.values())
        print("sonarsynth adversarial campaign: %d of %d generated cases, seed %d, timeout %g s, cli %s"
              % (len(chosen), universe, args.seed, args.timeout, args.cli), file=sys.stderr)
        if args.list:
            for i, c in enumerate(chosen):
                print("%4d %-9s %-7s %s" % (i, c.category, c.expect, c.desc))
            return
        records = []
        for i, case in enumerate(chosen):
            try:
                rec, box = h.run_case(i, case)
            except Exception as e:  # the harness's own failure is recorded, never hidden
                rec = {"id": i, "category": case.category, "description": case.desc,
                       "command": " ".join(case.argv), "expect": case.expect, "exit": None,
                       "class": "unclassified", "reasons": ["harness error: %r" % e],
                       "litter": [], "generic_message": False, "stderr_head": ""}
                box = os.path.join(h.root, "cases", "c%05d" % i)
            records.append(rec)
            bad = rec["class"] not in ("ok", "clean_error") or rec["litter"]
            if args.verbose or bad:
                print("[%4d/%d] %-12s %-9s %s :: %s" % (i + 1, len(chosen), rec["class"], case.category,
                                                      case.desc[:70], "; ".join(rec["reasons"])[:200]),
                      file=sys.stderr)
            if bad and args.keep_failures:
                dst = os.path.join(args.keep_failures, "c%05d-%s" % (i, rec["class"]))
                if os.path.exists(box):
                    shutil.rmtree(dst, ignore_errors=True)
                    shutil.copytree(box, dst, symlinks=True, ignore_dangling_symlinks=True)
                    with open(os.path.join(dst, "case.json"), "w") as f:
                        json.dump(rec, f, indent=1)
            if not args.keep_sandboxes and os.path.exists(box):
                make_removable(box)
                shutil.rmtree(box, ignore_errors=True)
        table = summary_table(records)
        print("\n## sonarsynth adversarial campaign\n")
        print("cli `%s` (sha256 %s), %d cases (of %d generated), seed %d, timeout %g s, %.0f s\n"
              % (args.cli, h.cli_sha256[:12], len(records), universe, args.seed, args.timeout,
                 time.time() - t0))
        print(table)
        report = {"cli": args.cli, "cli_sha256": h.cli_sha256, "seed": args.seed, "cases": len(records), "generated": universe,
                  "timeout": args.timeout, "seconds": round(time.time() - t0, 1),
                  "summary_markdown": table, "records": records}
        with open(args.out, "w") as f:
            json.dump(report, f, indent=1)
        print("\ndetails: %s" % args.out)
    finally:
        if not args.keep_sandboxes:
            make_removable(h.root)
            shutil.rmtree(h.root, ignore_errors=True)
