# SPDX-License-Identifier: MIT
# The package sonarsynth (docs/python.md): every public name of its extension
# sonarsynth._sonarsynth (pybind11), its docstring and __version__, the library's version
# (project(sonarsynth VERSION ...) in CMakeLists.txt).
from ._sonarsynth import *  # noqa: F401,F403  (the extension has no __all__: every public name)
from ._sonarsynth import __doc__, __version__  # noqa: F401
