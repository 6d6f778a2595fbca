# SPDX-License-Identifier: MIT
"""Writes the type stubs of the extension sonarsynth._sonarsynth (_sonarsynth.pyi) from the
signatures pybind11 puts in its docstrings; run by the build after every link of the extension
(python/CMakeLists.txt, docs/python.md):

    python3 make_stubs.py --path build/python --out build/python/sonarsynth/_sonarsynth.pyi

Only the standard library is used (mypy's stubgen 1.0, Debian's, writes no valid stubs for this
module: it drops keyword-only signatures, static methods and C++ type names to `*args` or leaves
them invalid). pybind11's C++-flavoured names are mapped to typing: numpy.ndarray[T] to
numpy.typing.NDArray, std::filesystem::path (os.PathLike) to str | os.PathLike[str] for
arguments, List[T] to Sequence[T] for arguments (pybind11 takes any sequence). A type it cannot
map becomes Any and is reported on stderr; --strict makes that an error (the tests use it).
"""
import argparse
import ast
import importlib
import inspect
import re
import sys

MODULE = "sonarsynth._sonarsynth"
TYPING = {"Any", "Callable", "Dict", "Iterable", "Iterator", "List", "Optional", "Sequence",
          "Set", "Tuple", "Union"}
BUILTINS = {"None", "bool", "bytes", "dict", "float", "int", "list", "object", "set", "str",
            "tuple"}
# Dunder methods worth a stub when the class defines them (pickling, containers, comparison).
DUNDERS = {"__init__", "__getstate__", "__setstate__", "__len__", "__iter__", "__getitem__",
           "__contains__", "__eq__", "__ne__", "__hash__", "__repr__", "__str__", "__enter__",
           "__exit__", "__call__"}


class Mapper:
    """Turns a pybind11 type string into a stub annotation, recording what it cannot map."""

    def __init__(self, classes):
        self.classes = set(classes)
        self.unmapped = []

    def __call__(self, text, where, argument):
        t = text.strip().replace(MODULE + ".", "")
        # numpy arrays: numpy.ndarray[numpy.float32], numpy.ndarray[numpy.float64[m, 1]] (Eigen),
        # numpy.ndarray[sonarsynth::python::PoseRecord] (a structured dtype).
        t = re.sub(r"numpy\.ndarray\[numpy\.(\w+)(\[[^\]]*\])?\]",
                   r"numpy.typing.NDArray[numpy.\1]", t)
        t = re.sub(r"numpy\.ndarray\[[\w:]+\]", "numpy.typing.NDArray[numpy.void]", t)
        t = re.sub(r"\bnumpy\.ndarray\b(?!\[)", "numpy.typing.NDArray[Any]", t)
        t = re.sub(r"\b(float|int|bool|str)\[\d+\]", r"\1", t)  # std::array<float, 3>
        # py::dict, py::list, py::tuple: any contents.
        t = re.sub(r"\bdict\b(?!\[)", "Dict[Any, Any]", t)
        t = re.sub(r"\blist\b(?!\[)", "List[Any]", t)
        t = re.sub(r"\btuple\b(?!\[)", "Tuple[Any, ...]", t)
        if argument:
            t = re.sub(r"\bos\.PathLike\b", "Union[str, os.PathLike[str]]", t)
            t = re.sub(r"\bList\[", "Sequence[", t)
        else:
            t = re.sub(r"\bos\.PathLike\b", "os.PathLike[str]", t)
            if t == "object":
                t = "Any"  # a value of any type: let the caller use it without a cast
        if not self.valid(t):
            self.unmapped.append(f"{where}: {text.strip()!r}")
            return "Any"
        return t

    def valid(self, t):
        try:
            tree = ast.parse(t, mode="eval")
        except SyntaxError:
            return False
        for node in ast.walk(tree):
            if isinstance(node, ast.Name):
                if node.id not in TYPING | BUILTINS | self.classes | {"os", "numpy"}:
                    return False
            elif isinstance(node, ast.Attribute):
                root = node
                while isinstance(root, ast.Attribute):
                    root = root.value
                if not (isinstance(root, ast.Name) and root.id in ("os", "numpy")):
                    return False
            elif isinstance(node, ast.Constant) and node.value not in (None, Ellipsis):
                return False
        return True


def split_top(text, sep=","):
    """Splits at `sep` outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            if c == quote and text[i - 1] != "\\":
                quote = None
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>":
            depth -= 1
        elif c == sep and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def signatures(name, doc):
    """(arguments text, return text) of every signature line `name(...) -> ret` in a pybind11
    docstring (one, or one per overload), and the docstring's prose."""
    sigs, prose = [], []
    pattern = re.compile(r"^(?:\d+\. )?" + re.escape(name) + r"\((.*)\) -> (.+)$")
    for line in (doc or "").splitlines():
        m = pattern.match(line)
        if m and not line.startswith(f"{name}(*args, **kwargs)"):
            sigs.append((m.group(1), m.group(2)))
        elif line != "Overloaded function." and not line.startswith(f"{name}(*args, **kwargs)"):
            prose.append(line)
    return sigs, "\n".join(prose).strip()


def render_args(args_text, where, mapper, method):
    out = []
    for i, arg in enumerate(split_top(args_text)):
        if arg in ("*", "/"):
            out.append(arg)
            continue
        m = re.match(r"^(\*{0,2})(\w+)(?:\s*:\s*(.*?))?(\s*=\s*.*)?$", arg, re.S)
        if not m:
            mapper.unmapped.append(f"{where}: argument {arg!r}")
            out.append("*args: Any, **kwargs: Any")
            break
        stars, name, annotation, default = m.groups()
        if method and i == 0 and not stars:
            out.append("self")
            continue
        if annotation is None:
            annotation = "Any"
        else:
            annotation = mapper(annotation, f"{where}({name})", argument=True)
        out.append(f"{stars}{name}: {annotation}" + (" = ..." if default else ""))
    return ", ".join(out)


def docstring(text, indent):
    if not text:
        return ""
    body = text.replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    lines = body.splitlines()
    rest = [f"{indent}    {line}".rstrip() for line in lines[1:]]
    return "\n".join([f'{indent}    """{lines[0]}'] + rest + [f'{indent}    """'])


def function_stub(name, func, where, mapper, indent="", decorators=(), method=False):
    sigs, prose = signatures(name, func.__doc__)
    if not sigs:
        mapper.unmapped.append(f"{where}: no signature in the docstring")
        sigs = [("*args: Any, **kwargs: Any" if not method else "self, *args, **kwargs", "Any")]
    lines = []
    for n, (args_text, ret) in enumerate(sigs):
        for d in decorators:
            lines.append(f"{indent}@{d}")
        if len(sigs) > 1:
            lines.append(f"{indent}@overload")
        args = render_args(args_text, where, mapper, method)
        ret = mapper(ret, f"{where} return", argument=False)
        doc = docstring(prose, indent) if n == 0 else ""
        lines.append(f"{indent}def {name}({args}) -> {ret}:" + ("\n" + doc if doc else " ..."))
    return lines


def value_annotation(value):
    if type(value).__module__ == "numpy" and type(value).__name__.startswith("dtype"):
        return "numpy.dtype[numpy.void]" if value.names else "numpy.dtype[Any]"
    if isinstance(value, tuple):
        kinds = {type(v).__name__ for v in value}
        return f"Tuple[{kinds.pop()}, ...]" if len(kinds) == 1 else "Tuple[Any, ...]"
    if isinstance(value, (bool, int, float, str, bytes)):
        return type(value).__name__
    return "Any"


def class_stub(name, cls, mapper):
    bases = [b for b in cls.__bases__ if b.__module__ != "pybind11_builtins" and b is not object]
    base_text = ", ".join(b.__name__ for b in bases)
    lines = [f"class {name}" + (f"({base_text})" if base_text else "") + ":"]
    if cls.__doc__ and not issubclass(cls, BaseException):
        lines.append(docstring(cls.__doc__, ""))
    body = []
    for member, raw in cls.__dict__.items():
        if member.startswith("_") and member not in DUNDERS:
            continue
        where = f"{name}.{member}"
        kind = type(raw).__name__
        if kind == "staticmethod":
            body += function_stub(member, raw.__func__, where, mapper, "    ", ["staticmethod"])
        elif kind == "instancemethod":
            body += function_stub(member, getattr(cls, member), where, mapper, "    ", method=True)
        elif isinstance(raw, property):
            sigs, _ = signatures("", raw.fget.__doc__ or "")
            ret = mapper(sigs[0][1], where, argument=False) if sigs else "Any"
            if not sigs:
                mapper.unmapped.append(f"{where}: no signature of its getter")
            body += ["    @property", f"    def {member}(self) -> {ret}:"]
            doc = docstring(raw.__doc__ if raw.__doc__ != raw.fget.__doc__ else "", "    ")
            body[-1] += ("\n" + doc) if doc else " ..."
            if raw.fset is not None:
                setter_sigs, _ = signatures("", raw.fset.__doc__ or "")
                value = "Any"
                if setter_sigs:
                    value_text = split_top(setter_sigs[0][0])[-1].split(":", 1)[-1]
                    value = mapper(value_text, where + " setter", argument=True)
                body += [f"    @{member}.setter",
                         f"    def {member}(self, value: {value}) -> None: ..."]
        elif kind in ("wrapper_descriptor", "str"):
            continue  # pybind11's "no constructor" __init__, __doc__, __module__
        elif not callable(raw):
            body.append(f"    {member}: {value_annotation(raw)}")
        else:
            mapper.unmapped.append(f"{where}: member of type {kind}")
    if not body and len(lines) == 1:
        return [lines[0] + " ..."]
    return lines + (body or ["    ..."])


def generate(module):
    classes = [n for n, v in vars(module).items() if isinstance(v, type)]
    mapper = Mapper(classes)
    out = ["# Generated by python/make_stubs.py from the signatures in the docstrings of the",
           f"# extension {MODULE} (pybind11); do not edit.",
           "import os",
           "from typing import " + ", ".join(sorted(TYPING | {"overload"})),
           "",
           "import numpy",
           "import numpy.typing",
           ""]
    for name, value in vars(module).items():
        if name == "__version__":
            out.append("__version__: str")
        elif name.startswith("_"):
            continue
        elif isinstance(value, type):
            out += [""] + class_stub(name, value, mapper) + [""]
        elif inspect.isbuiltin(value) or callable(value):
            out += function_stub(name, value, name, mapper)
        else:
            out.append(f"{name}: {value_annotation(value)}")
    text = re.sub(r"\n{3,}", "\n\n\n", "\n".join(out).strip() + "\n")
    return text, mapper.unmapped


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--path", required=True, help="directory holding the package sonarsynth/")
    parser.add_argument("--out", required=True, help="the .pyi file to write")
    parser.add_argument("--strict", action="store_true", help="fail on a type it cannot map")
    args = parser.parse_args()
    sys.path[0] = args.path  # not this script's directory: python/sonarsynth/ has no extension
    module = importlib.import_module(MODULE)
    text, unmapped = generate(module)
    for item in unmapped:
        print(f"make_stubs: not mapped, Any in the stubs: {item}", file=sys.stderr)
    with open(args.out, "w") as f:
        f.write(text)
    return 1 if unmapped and args.strict else 0


if __name__ == "__main__":
    sys.exit(main())
