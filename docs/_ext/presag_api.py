"""What the documentation calls the public API of presag_opt, found at build time.

One definition serves the site (``conf.py`` lists the modules for autosummary) and the docstring test
(``tests/docs/test_docstrings.py`` checks every name listed here), so that a new module or sub-package
appears in both without an edit:

- a *public module* is every module and sub-package below ``presag_opt`` whose dotted name has no
  component starting with an underscore, except the data package ``presag_opt.builtin_models`` and
  ``presag_opt.cli.__main__`` (importing it runs the command line);
- a *public name* of a module is a class, function or documented constant defined in it (its
  ``__module__`` is the module) whose name has no leading underscore; a public class adds its public
  methods and properties defined in its own body. Names a package re-exports (its ``__all__``) are
  documented where they are defined, and listed on the package's page with a link there.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from dataclasses import dataclass
from types import ModuleType

PACKAGE = "presag_opt"

EXCLUDED = ("presag_opt.builtin_models", "presag_opt.cli.__main__")
"""Modules that are not API: the model files' data package, and the ``python -m`` entry point."""


def public_modules() -> list[str]:
    """Dotted names of the public modules, in import order (a package before its modules)."""
    root = importlib.import_module(PACKAGE)
    names = [PACKAGE]
    for info in pkgutil.walk_packages(root.__path__, prefix=PACKAGE + "."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        if info.name in EXCLUDED or info.name.startswith(tuple(e + "." for e in EXCLUDED)):
            continue
        names.append(info.name)
    return names


def top_level_parts() -> list[str]:
    """The sub-packages and modules directly below ``presag_opt`` (one API section each)."""
    return [name for name in public_modules() if name.count(".") == 1]


@dataclass(frozen=True, kw_only=True)
class PublicName:
    """One documented object: its dotted name, the object and what kind it is."""

    qualname: str
    module: str
    obj: object
    kind: str  # "class", "function", "method", "property", "constant"


def _defined_in(obj: object, module: ModuleType) -> bool:
    return getattr(obj, "__module__", None) == module.__name__


def _is_function(obj: object) -> bool:
    """A plain function, or one wrapped by numba (``py_func``) or functools (``__wrapped__``)."""
    return inspect.isfunction(obj) or (callable(obj) and not inspect.isclass(obj)
                                       and (hasattr(obj, "py_func") or hasattr(obj, "__wrapped__")))


def documented_constants(module: ModuleType) -> list[str]:
    """Module-level names with a docstring (the string right after the assignment), no underscore."""
    from sphinx.errors import PycodeError
    from sphinx.pycode import ModuleAnalyzer

    try:
        docs = ModuleAnalyzer.for_module(module.__name__).find_attr_docs()
    except PycodeError:  # a module without source (compiled) has no attribute docstrings
        return []
    return [name for (scope, name) in docs if scope == "" and not name.startswith("_")]


def public_names(module_name: str) -> list[PublicName]:
    """Every public name a module defines (classes with their public methods and properties)."""
    module = importlib.import_module(module_name)
    out = []
    for name, obj in sorted(vars(module).items()):
        if name.startswith("_"):
            continue
        if inspect.isclass(obj) and _defined_in(obj, module):
            out.append(PublicName(qualname=f"{module_name}.{name}", module=module_name, obj=obj, kind="class"))
            for member, value in sorted(vars(obj).items()):
                if member.startswith("_"):
                    continue
                if isinstance(value, property):
                    kind = "property"
                elif isinstance(value, (staticmethod, classmethod)):
                    kind, value = "method", value.__func__
                elif inspect.isfunction(value):
                    kind = "method"
                else:
                    continue
                out.append(PublicName(qualname=f"{module_name}.{name}.{member}", module=module_name,
                                      obj=value, kind=kind))
        elif _is_function(obj) and _defined_in(obj, module):
            out.append(PublicName(qualname=f"{module_name}.{name}", module=module_name, obj=obj, kind="function"))
    for name in documented_constants(module):
        if name in vars(module):
            out.append(PublicName(qualname=f"{module_name}.{name}", module=module_name, obj=vars(module)[name],
                                  kind="constant"))
    return out


def reexported(module_name: str) -> list[tuple[str, str]]:
    """(name, dotted name where it is defined) for each name of a package's ``__all__`` defined elsewhere."""
    module = importlib.import_module(module_name)
    out = []
    for name in getattr(module, "__all__", ()):
        obj = getattr(module, name)
        home = getattr(obj, "__module__", None)
        if home and home != module_name and (inspect.isclass(obj) or _is_function(obj)):
            out.append((name, f"{home}.{name}"))
        elif not (inspect.isclass(obj) or _is_function(obj)):
            home = _constant_home(name, module_name)
            if home != module_name:
                out.append((name, f"{home}.{name}"))
    return out


def _constant_home(name: str, package: str) -> str:
    """The module of ``package`` whose attribute docstrings document the constant ``name``."""
    for module_name in public_modules():
        if module_name.startswith(package + ".") or module_name == package:
            module = importlib.import_module(module_name)
            if name in documented_constants(module):
                return module_name
    return package


def summary(module_name: str) -> str:
    """The first sentence of a module's docstring (its first paragraph if it has no full stop)."""
    doc = inspect.getdoc(importlib.import_module(module_name)) or ""
    paragraph = " ".join(doc.split("\n\n")[0].split())
    head, stop, _ = paragraph.partition(". ")
    return head + "." if stop else paragraph


def members(module_name: str) -> dict[str, list[str]]:
    """The public names of a module by kind, as the API page lists them (short names)."""
    out: dict[str, list[str]] = {"classes": [], "exceptions": [], "functions": [], "attributes": []}
    for item in public_names(module_name):
        short = item.qualname[len(module_name) + 1:]
        if item.kind == "class":
            out["exceptions" if issubclass(item.obj, BaseException) else "classes"].append(short)
        elif item.kind == "function":
            out["functions"].append(short)
        elif item.kind == "constant":
            out["attributes"].append(short)
    return out
