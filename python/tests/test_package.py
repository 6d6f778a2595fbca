# SPDX-License-Identifier: MIT
# The package (docs/python.md, Installing): one version everywhere, read from CMakeLists.txt's
# project(); the extension is sonarsynth._sonarsynth and the package re-exports all of it.
import pathlib
import re
import subprocess
import sys

import pytest

import sonarsynth


ROOT = pathlib.Path(__file__).resolve().parents[2]


def cmake_project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"^project\(sonarsynth VERSION (\S+) ", text, re.M).group(1)


def test_one_version_everywhere(cli):
    version = cmake_project_version()
    assert re.fullmatch(r"\d+\.\d+\.\d+", version)
    assert sonarsynth.__version__ == version
    assert sonarsynth._sonarsynth.__version__ == version
    printed = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True)
    assert printed.stdout.splitlines()[0].split() == ["sonarsynth", version]
    # pip's metadata: setup.py reads the version from CMakeLists.txt on its own.
    setup = subprocess.run([sys.executable, str(ROOT / "setup.py"), "--version"], cwd=ROOT,
                           capture_output=True, text=True, check=True)
    assert setup.stdout.strip().splitlines()[-1] == version


def test_package_re_exports_the_extension():
    ext = sonarsynth._sonarsynth
    assert ext.__name__ == "sonarsynth._sonarsynth"
    assert pathlib.Path(ext.__file__).parent == pathlib.Path(sonarsynth.__file__).parent
    public = [n for n in dir(ext) if not n.startswith("_")]
    assert public and all(getattr(sonarsynth, n) is getattr(ext, n) for n in public)
    assert sonarsynth.__doc__ == ext.__doc__
    assert sonarsynth.Simulation.__module__ == "sonarsynth._sonarsynth"


def test_simd_target_can_be_capped_and_restored():
    best = sonarsynth.simd_target()
    assert best in ("avx512", "avx2", "scalar")
    try:
        sonarsynth.set_simd_target("scalar")
        assert sonarsynth.simd_target() == "scalar"
        with pytest.raises(ValueError, match="set_simd_target = 'sse9'"):
            sonarsynth.set_simd_target("sse9")
        assert sonarsynth.simd_target() == "scalar"
    finally:
        sonarsynth.set_simd_target("auto")
    assert sonarsynth.simd_target() == best
