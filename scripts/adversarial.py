#!/usr/bin/python3
"""Adversarial campaign against the sonarsynth CLI (docs/adversarial-testing.md).

    /usr/bin/python3 scripts/adversarial.py --cli build/tools/sonarsynth \
        [--cases N] [--seed S] [--timeout SEC] [--out report.json] [--keep-failures DIR]

Every case runs in a fresh sandbox (a valid base scene, a base XTF and raster, and "user files",
hidden ones included) that is snapshotted before and compared after the run.  Each case gets
exactly one class:

  ok            valid input, exit 0, plausible output
  clean_error   exit 1/2 with a message on stderr (flagged `generic` when it names nothing the
                case knows about: the key, flag, value or file)
  crash         exit 3 ("internal error"), a signal, an unexpected exit code, sanitizer output
  hang          ran past the timeout
  silent_wrong  exit 0 for an input known to be invalid, or exit 0 with implausible output
  data_lost     a user file (or the scene) changed or vanished, or a visible output was left
                behind by a failed run, or an interrupted run left an incomplete directory
  unclassified  anything the rules above do not decide (the reason is recorded)

`litter` (hidden .part-/.old- temporaries left by a run that ended by itself or by
SIGINT/SIGTERM) is counted in its own column, independently of the class.

Standard library only.  Deterministic for a given --seed (except for the timing of
interrupts).
"""

import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from adversarial_campaign.main import main  # noqa: E402  (the package lives beside this file)

if __name__ == "__main__":
    main(__doc__)
