# SPDX-License-Identifier: MIT
"""`pip install .`: the Python package sonarsynth built by CMake (docs/python.md, Installing).

build_ext configures the project in a temporary directory with the tests, benchmarks, examples
and fuzzers off, builds only the extension (target sonarsynth_python, which also writes its type
stubs), installs CMake's `python` component into a staging directory and takes the extension and
its stubs from there; the package's other files and the sonarsynth_*.py modules come from
python/. The version is project(sonarsynth VERSION ...) in CMakeLists.txt. Nothing is written
into the source tree: setuptools' build and egg-info directories are temporary too.

Environment: CMAKE_BUILD_PARALLEL_LEVEL (parallel jobs), SONARSYNTH_CMAKE_ARGS (more CMake
arguments, shell-quoted, e.g. "-DCMAKE_BUILD_TYPE=RelWithDebInfo"). ccache is used when it is
on the PATH, unless SONARSYNTH_CMAKE_ARGS names a compiler launcher.
"""
import atexit
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*sonarsynth\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if not match:
        raise RuntimeError(f"setup.py: no project(sonarsynth VERSION x.y.z) in {ROOT}/"
                           "CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = pathlib.Path(self.build_temp).resolve() / "cmake"
        stage = build_dir / "stage"
        extra = shlex.split(os.environ.get("SONARSYNTH_CMAKE_ARGS", ""))
        configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                     "-DSONARSYNTH_BUILD_TESTS=OFF", "-DSONARSYNTH_BUILD_BENCH=OFF",
                     "-DSONARSYNTH_BUILD_EXAMPLES=OFF", "-DSONARSYNTH_BUILD_FUZZERS=OFF",
                     "-DSONARSYNTH_WITH_OPENCV=OFF", "-DSONARSYNTH_BUILD_PYTHON=ON",
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     "-DSONARSYNTH_PYTHON_INSTALL_DIR=site"]
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        env = dict(os.environ)
        if shutil.which("ccache") and not any("COMPILER_LAUNCHER" in a for a in extra):
            configure += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache",
                          "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
            # The build directory is a new temporary one each time: with the paths under a
            # common base made relative, a second install of the same checkout hits the cache.
            base = os.path.commonpath([ROOT, build_dir])
            if base != os.sep:
                env.setdefault("CCACHE_BASEDIR", base)
        build = ["cmake", "--build", str(build_dir), "--target", "sonarsynth_python"]
        if os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL"):
            build += ["--parallel", os.environ["CMAKE_BUILD_PARALLEL_LEVEL"]]
        install = ["cmake", "--install", str(build_dir), "--component", "python", "--prefix",
                   str(stage)]
        for command in (configure + extra, build, install):
            print("setup.py:", shlex.join(command), flush=True)
            subprocess.run(command, check=True, env=env)
        built = stage / "site" / "sonarsynth"
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        extension = built / target.name
        if not extension.exists():
            raise RuntimeError(f"setup.py: CMake built no {target.name} in {built}: "
                               f"{sorted(p.name for p in built.iterdir())}")
        shutil.copy2(extension, target)
        shutil.copy2(built / "_sonarsynth.pyi", target.parent / "_sonarsynth.pyi")


# setuptools' build and egg-info directories: temporary, not build/ in the source tree (the
# CMake build directory of a checkout) nor python/sonarsynth.egg-info.
work = tempfile.mkdtemp(prefix="sonarsynth-setup-")
atexit.register(shutil.rmtree, work, ignore_errors=True)

setup(
    name="sonarsynth",
    version=project_version(),
    description="Synthetic side-scan sonar survey data",
    license="MIT",
    package_dir={"": "python"},
    packages=["sonarsynth"],
    package_data={"sonarsynth": ["py.typed", "*.pyi"]},
    py_modules=sorted(p.stem for p in (ROOT / "python").glob("sonarsynth_*.py")),
    ext_modules=[Extension("sonarsynth._sonarsynth", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    zip_safe=False,
    options={"build": {"build_base": os.path.join(work, "build")},
             "egg_info": {"egg_base": work}},
)
