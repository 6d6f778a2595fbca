"""Choosing the cases to run and summarising the verdicts."""

from .case import CATEGORIES, CATEGORY_WEIGHT, CLASSES
from .gen_cli import gen_cli
from .gen_raster import gen_raster
from .gen_system import gen_fs, gen_interrupt
from .gen_xtf import gen_xtf
from .gen_yaml import gen_yaml

GENERATORS = {"cli": gen_cli, "yaml": gen_yaml, "raster": gen_raster, "xtf": gen_xtf,
              "interrupt": gen_interrupt, "fs": gen_fs}


def select(cases_by_cat, n, rng):
    """A deterministic sample of n cases, spread over the categories by CATEGORY_WEIGHT."""
    total = sum(len(v) for v in cases_by_cat.values())
    if n >= total:
        return [c for cat in CATEGORIES for c in cases_by_cat[cat]]
    quota = {cat: int(round(n * CATEGORY_WEIGHT[cat])) for cat in CATEGORIES}
    spare = 0
    for cat in CATEGORIES:
        if quota[cat] > len(cases_by_cat[cat]):
            spare += quota[cat] - len(cases_by_cat[cat])
            quota[cat] = len(cases_by_cat[cat])
    while spare > 0:
        grew = False
        for cat in CATEGORIES:
            if spare and quota[cat] < len(cases_by_cat[cat]):
                quota[cat] += 1
                spare -= 1
                grew = True
        if not grew:
            break
    chosen = []
    for cat in CATEGORIES:
        pool = cases_by_cat[cat]
        idx = sorted(rng.sample(range(len(pool)), quota[cat]))
        chosen += [pool[i] for i in idx]
    return chosen


def summary_table(records):
    cols = CLASSES + ["generic_msg", "litter"]
    rows = []
    for cat in CATEGORIES + ["all"]:
        rs = [r for r in records if cat == "all" or r["category"] == cat]
        if not rs:
            continue
        row = {c: sum(1 for r in rs if r["class"] == c) for c in CLASSES}
        row["generic_msg"] = sum(1 for r in rs if r["generic_message"])
        row["litter"] = sum(1 for r in rs if r["litter"])
        rows.append([("**all**" if cat == "all" else cat), len(rs)] + [row[c] for c in cols])
    head = "| category | cases | " + " | ".join(cols) + " |"
    sep = "|" + "---|" * (len(cols) + 2)
    return "\n".join([head, sep] + ["| " + " | ".join(str(x) for x in r) + " |" for r in rows])
