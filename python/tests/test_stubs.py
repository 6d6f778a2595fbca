# SPDX-License-Identifier: MIT
# The package's type stubs (docs/python.md, Type stubs): current, complete, and right about the
# module: mypy --strict accepts typed_example.py, which also runs; it rejects misuse; stubtest
# finds them consistent with the module at run time.
import ast
import os
import pathlib
import subprocess
import sys

import pytest

import sonarsynth

from conftest import helper

PACKAGE = pathlib.Path(sonarsynth.__file__).parent
HERE = pathlib.Path(__file__).parent
MAKE_STUBS = HERE.parent / "make_stubs.py"


def make_stubs(out):
    return subprocess.run([sys.executable, str(MAKE_STUBS), "--path", str(PACKAGE.parent),
                           "--out", str(out), "--strict"], capture_output=True, text=True)


def mypy(tmp_path, *args):
    """mypy with the package's stubs found as a user's checker finds them: MYPYPATH = the directory
    that holds the package (build/python), its cache in tmp_path."""
    env = dict(os.environ, MYPYPATH=str(PACKAGE.parent))
    return subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "cache"),
                           *args], capture_output=True, text=True, env=env, cwd=tmp_path)


def test_stubs_are_current_and_map_every_type(tmp_path):
    out = tmp_path / "_sonarsynth.pyi"
    run = make_stubs(out)
    assert run.returncode == 0, run.stderr  # --strict: a type make_stubs.py cannot map fails
    assert out.read_text() == (PACKAGE / "_sonarsynth.pyi").read_text()
    assert (PACKAGE / "py.typed").exists() and (PACKAGE / "__init__.pyi").exists()


def test_stubs_name_every_public_name():
    tree = ast.parse((PACKAGE / "_sonarsynth.pyi").read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    public = {n for n in dir(sonarsynth) if not n.startswith("_")}
    assert public <= names
    assert public == {n for n in dir(sonarsynth._sonarsynth) if not n.startswith("_")}


def test_typed_example_checks_and_runs(tmp_path, scene_path):
    pytest.importorskip("mypy")
    check = mypy(tmp_path, "--strict", str(HERE / "typed_example.py"))
    assert check.returncode == 0, check.stdout + check.stderr
    import typed_example

    samples_dir = pathlib.Path(helper("SONARSYNTH_SAMPLES"))
    xtf = HERE.parents[1] / "tests" / "data" / "xtf" / "golden-tiny.xtf"
    got = typed_example.use_api(scene_path, str(xtf), str(samples_dir / "datasets" / "small.yaml"))
    assert got["version"] == sonarsynth.__version__
    assert got["samples"] == 200 and got["batch_shape"] == (2, 2, 200)
    assert got["ping_shape"] == (200,)
    assert got["xtf_pings"] > 0 and "cannot open" in got["missing_error"]
    assert got["record"] and got["made"] == 1 and got["classes"] == 5
    assert got["item_dir"] == "items/000003" and got["spec_count"] > 0


# Each line is wrong; mypy must say so on that line (the stubs are not Any everywhere).
MISUSE = """\
import sonarsynth
sonarsynth.read_xtf(3)
sonarsynth.Simulation.from_file("a.yaml", seed="3")
sonarsynth.Simulation.from_file("a.yaml", 3)
sim = sonarsynth.Simulation.from_file("a.yaml")
sim.render_ping(0.0, 0.0, 0.0, heading_deg=1.0)
n: str = sim.samples_per_side
sonarsynth.no_such_function()
v: int = sonarsynth.__version__
sonarsynth.DatasetSpec.from_file("s.yaml").item_seed("0")
"""


def test_mypy_rejects_misuse(tmp_path):
    pytest.importorskip("mypy")
    (tmp_path / "misuse.py").write_text(MISUSE)
    check = mypy(tmp_path, "--strict", "misuse.py")
    flagged = {int(line.split(":")[1]) for line in check.stdout.splitlines()
               if line.startswith("misuse.py:") and ": error:" in line}
    wrong = set(range(2, MISUSE.count("\n") + 1)) - {5}
    assert flagged == wrong, check.stdout


def test_stubtest_finds_stubs_consistent(tmp_path):
    pytest.importorskip("mypy")
    # Every pybind11 class has pybind11's metaclass, and one without a constructor pybind11's
    # __init__(*args, **kwargs) that raises: neither belongs in the stubs.
    allowlist = tmp_path / "allowlist.txt"
    allowlist.write_text("sonarsynth(\\._sonarsynth)?\\.[A-Z]\\w*\n"
                         "sonarsynth(\\._sonarsynth)?\\.[A-Z]\\w*\\.__init__\n")
    env = dict(os.environ, MYPYPATH=str(PACKAGE.parent),
               PYTHONPATH=os.pathsep.join([str(PACKAGE.parent), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run(
        [sys.executable, "-c", "import sys; from mypy.stubtest import main; sys.exit(main())",
         "sonarsynth", "--allowlist", str(allowlist), "--ignore-unused-allowlist"],
        capture_output=True, text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
