#!/usr/bin/env python3
"""Writes nesshi.pyi, the type stub of the built `nesshi` module, from the module itself: each
function's and method's signature as pybind11 documents it, each property's type from its getter,
the exception classes' constructors and attributes by introspection. Run by the build after the
module is linked (python/CMakeLists.txt), so the stub never drifts from the bindings.

    PYTHONPATH=build/python python3 python/tools/write_stub.py build/python/nesshi.pyi
"""
import inspect
import re
import sys

import nesshi

TYPING = ("Any", "Dict", "List", "Optional", "Set", "Tuple", "Union")


def clean(text):
    """pybind11's type spelling as stub Python: nesshi.Machine -> Machine."""
    return text.replace("nesshi.", "")


def signature_line(obj):
    """The first line of a pybind11 docstring: 'name(args) -> ret' (overloads are not used here)."""
    doc = obj.__doc__ or ""
    first = doc.split("\n", 1)[0]
    if "(" not in first or "->" not in first:
        raise SystemExit(f"write_stub.py: no signature in the docstring of {obj!r}: {first!r}")
    return first


def summary(obj, skip_signature=True):
    lines = (obj.__doc__ or "").split("\n")
    text = "\n".join(lines[1:] if skip_signature else lines).strip()
    return text.replace('"""', "'''")


def docstring(text, indent):
    if not text:
        return ""
    pad = " " * indent
    body = text.replace("\\", "\\\\").replace("\n", "\n" + pad)
    if body.startswith('"'):
        body = " " + body
    if body.endswith('"'):
        body += " "
    return f'{pad}"""{body}"""\n'


def function(obj, indent=0, method=False):
    line = clean(signature_line(obj))
    name, rest = line.split("(", 1)
    args, ret = rest.rsplit(") -> ", 1)
    if method:  # 'self: Machine, arg0: Machine' -> 'self, arg0: Machine'
        args = re.sub(r"^self: [A-Za-z_.]+", "self", args)
    pad = " " * indent
    doc = summary(obj)
    out = f"{pad}def {name}({args}) -> {ret}:"
    return out + (" ...\n" if not doc else "\n" + docstring(doc, indent + 4) + f"{pad}    ...\n")


def property_stub(name, prop, indent):
    ret = clean(signature_line(prop.fget).rsplit(" -> ", 1)[1])
    pad = " " * indent
    doc = summary(prop, skip_signature=False) if prop.__doc__ else ""
    out = f"{pad}@property\n{pad}def {name}(self) -> {ret}:"
    return out + (" ...\n" if not doc else "\n" + docstring(doc, indent + 4) + f"{pad}    ...\n")


def exception_stub(cls):
    """A Python exception class made by the module: its constructor's signature, and its attributes'
    types from an instance built with a value of each kind."""
    base = cls.__mro__[1].__name__
    sig = inspect.signature(cls.__init__)
    sample = {"text": "t", "message": "m", "file": "f", "line": 1, "column": 2, "errors": [("f", 1, 2, "m", True)],
              "diagnostics": "d"}
    inst = cls(*[sample[p] for p in list(sig.parameters)[1:]])
    out = f"class {cls.__name__}({base}):\n" + docstring(inspect.cleandoc(cls.__doc__ or ""), 4)
    own = [a for a in vars(inst) if base == "Exception" or a not in vars(cls.__mro__[1](*["t"]))]
    for attr in own:
        value = getattr(inst, attr)
        default = sig.parameters[attr].default if attr in sig.parameters else inspect.Parameter.empty
        kind = {str: "str", int: "int", list: "List[Tuple[str, int, int, str, bool]]"}[type(value)]
        out += f"    {attr}: {'Optional[' + kind + ']' if default is None and attr == 'file' else kind}\n"
    params = []
    for p in list(sig.parameters.values())[1:]:
        kind = {"text": "str", "message": "Optional[str]", "file": "Optional[str]", "line": "int", "column": "int",
                "errors": "Any", "diagnostics": "Optional[str]"}[p.name]
        params.append(f"{p.name}: {kind}" + ("" if p.default is inspect.Parameter.empty else f" = {p.default!r}"))
    return out + f"    def __init__(self, {', '.join(params)}) -> None: ...\n"


def main():
    out = ['"""' + (nesshi.__doc__ or "").replace('"""', "'''") + '\n\nGenerated from the built module by '
           'python/tools/write_stub.py; do not edit."""\n',
           f"from typing import {', '.join(TYPING)}\n\n__version__: str\n"]
    names = [n for n in dir(nesshi) if not n.startswith("_")]
    exceptions = [getattr(nesshi, n) for n in names if isinstance(getattr(nesshi, n), type)
                  and issubclass(getattr(nesshi, n), BaseException)]
    for cls in sorted(exceptions, key=lambda c: len(c.__mro__)):  # bases first
        out.append("\n" + exception_stub(cls))
    for n in names:
        obj = getattr(nesshi, n)
        if not isinstance(obj, type) or issubclass(obj, BaseException):
            continue
        body = docstring(summary(obj, skip_signature=False), 4)
        for attr, value in obj.__dict__.items():
            if isinstance(value, property):
                body += property_stub(attr, value, 4)
            elif callable(value) and (not attr.startswith("_") or attr in ("__init__", "__eq__", "__repr__",
                                                                              "__getstate__", "__setstate__")):
                if attr == "__init__" and "->" not in (value.__doc__ or "").split("\n", 1)[0]:
                    continue  # made by a factory function, not constructed
                body += function(value, 4, method=True)
        out.append(f"\nclass {n}:\n{body}")
    for n in names:
        obj = getattr(nesshi, n)
        if callable(obj) and not isinstance(obj, type):
            out.append("\n" + function(obj))
    text = "".join(out)
    compile(text, sys.argv[1], "exec")  # a stub that does not parse is a build error
    with open(sys.argv[1], "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
