"""Every public name has a docstring, and every documented number has a unit.

The public names are those the API reference documents (``docs/_ext/presag_api.py``: every class,
function, method, property and documented constant defined in a public module). The rule, stated for
contributors in ``docs/project/contributing.md``:

- every public class, function, method and property has a docstring;
- an entry of a Parameters, Other Parameters or Attributes section whose numpydoc type names a number
  (``float``, ``int``, ``complex``, ``number``, ``ndarray``, ``array``, ``array_like``, ``scalar``, or
  a dtype) has a unit in square brackets in its description, by house style at its end: ``[N]``,
  ``[m]``, ``[mm/N]``, ``[N/(km/h)^2]``; ``[-]`` for a dimensionless number, a count or an index. A
  bracket holding a comma or a plain number (``[0, 1]``, ``[2]``) is a range or a reference, not a unit;
- an entry whose type names no number needs no unit: flags (``bool``), text and choices (``str``,
  ``{"a", "b"}``), paths, callables, and objects of a class (``Catenary``, ``PathModel``, a
  ``casadi.Function``), which carry the units of their own fields. An entry without a type needs a
  unit (nothing says it is not a number);
- a Parameters (or Attributes) section, once written, lists every parameter of the signature (every
  field of a dataclass; fields a base class documents count);
- a public function, method or dataclass with a parameter (field) annotated as a number has a
  Parameters (Attributes) section. The
  names that had none when this rule came in are listed in ``parameters_to_document.txt`` beside this
  file; a name not on that list fails, and the list may only shrink.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import inspect
import re
import sys
import warnings
from pathlib import Path

from numpydoc.docscrape import NumpyDocString

EXT = Path(__file__).resolve().parents[2] / "docs" / "_ext"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXT / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


presag_api = _load("presag_api")

NUMERIC_TYPE = re.compile(r"\b(float|float32|float64|int|int32|int64|integer|uint8|complex|number|scalar|dtype|"
                          r"ndarray|array|array_like)\b")
"""A numpydoc type naming a number (case-sensitive: ``IntegratorSettings`` is not ``int``)."""

NOT_NUMBERS = re.compile(r"\b(ndarray|array|sequence|tuple|list) of (bool|str)\b")
"""Containers of flags or text: masks and names carry no unit."""

UNIT = re.compile(r"\[([^\[\]]+)\]")


def has_unit(description: str) -> bool:
    """Whether a description holds a unit in brackets (not a range such as ``[0, 1]`` nor a number)."""
    for match in UNIT.finditer(description):
        inside = match.group(1).strip()
        if "," in inside or re.fullmatch(r"[\d.eE+-]+", inside) and inside != "-":
            continue
        if inside:
            return True
    return False


def needs_unit(type_text: str) -> bool:
    """Whether an entry of this numpydoc type is a number (no type: assume it is)."""
    return not type_text.strip() or bool(NUMERIC_TYPE.search(NOT_NUMBERS.sub("", type_text)))


def _entries(doc: NumpyDocString, *sections: str) -> dict[str, tuple[str, str]]:
    out = {}
    for section in sections:
        for param in doc[section]:
            for name in (n.strip().lstrip("*") for n in param.name.split(",")):
                out[name] = (param.type, " ".join(param.desc))
    return out


def _variadic_parameters(obj) -> set[str]:
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return set()
    return {p.name for p in signature.parameters.values() if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}


def _signature_parameters(obj) -> list[str]:
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in signature.parameters.values()
            if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
            and not p.name.startswith("_")]


ALLOWED_WITHOUT_SECTION = Path(__file__).with_name("parameters_to_document.txt")
"""Public names whose numeric parameters had no Parameters section when the rule came in."""


def _annotation_is_number(obj, name: str) -> bool:
    try:
        annotation = inspect.signature(obj).parameters[name].annotation
    except (TypeError, ValueError, KeyError):
        return True
    if annotation is inspect.Parameter.empty:
        return True
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))
    return bool(NUMERIC_TYPE.search(text))


def _field_is_number(cls, name: str) -> bool:
    annotation = {f.name: f.type for f in dataclasses.fields(cls)}[name]
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))
    return bool(NUMERIC_TYPE.search(text))


def _documented_by_bases(cls) -> set[str]:
    """Fields a base dataclass documents (a subclass that adds fields documents only its own)."""
    out = set()
    for base in cls.__mro__[1:]:
        if dataclasses.is_dataclass(base) and inspect.getdoc(base):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                out |= set(_entries(NumpyDocString(inspect.getdoc(base)), "Parameters", "Attributes"))
    return out


def problems(item) -> list[str]:
    """What is wrong with one public name's docstring (empty when nothing is)."""
    obj = item.obj.fget if item.kind == "property" else item.obj
    text = inspect.getdoc(obj) if item.kind != "constant" else "constant"
    if not text or not text.strip():
        return [f"{item.qualname}: no docstring"]
    if item.kind in ("constant", "property"):
        return []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numpydoc warns about unknown sections; the build reports those
        doc = NumpyDocString(text)
    out = []
    if item.kind == "class":
        documented = _entries(doc, "Parameters", "Other Parameters", "Attributes")
        expected = ([f.name for f in dataclasses.fields(obj) if f.init and not f.name.startswith("_")]
                    if dataclasses.is_dataclass(obj) else [])
        inherited = _documented_by_bases(obj) if dataclasses.is_dataclass(obj) else set()
        if documented:
            out += [f"{item.qualname}: field {name!r} is not documented" for name in expected
                    if name not in documented and name not in inherited]
        elif any(_field_is_number(obj, name) for name in expected if name not in inherited):
            out.append(f"{item.qualname}: numeric parameters and no Parameters section")
    else:
        documented = _entries(doc, "Parameters", "Other Parameters")
        expected = _signature_parameters(obj)
        if documented:
            out += [f"{item.qualname}: parameter {name!r} is not documented" for name in expected
                    if name not in documented]
        elif any(_annotation_is_number(obj, name) for name in expected):
            out.append(f"{item.qualname}: numeric parameters and no Parameters section")
    variadic = _variadic_parameters(obj) if item.kind != "class" else set()
    for name, (type_text, description) in documented.items():
        if name in variadic:
            continue  # **kwargs passed on: the callee documents them
        if needs_unit(type_text) and not has_unit(description):
            out.append(f"{item.qualname}: {name} ({type_text or 'no type'}) has no unit: {description[:80]!r}")
    return out


def all_public_names():
    return [item for module in presag_api.public_modules() for item in presag_api.public_names(module)]


def test_the_rule_tells_units_from_ranges_and_numbers_from_objects():
    assert has_unit("Contact-wire tension. [N]") and has_unit("Uplift. [mm/N]") and has_unit("Ratio. [-]")
    assert has_unit("Coefficient of F_m = F_stat + α v². [N/(km/h)^2]")
    assert not has_unit("Share of the best, in [0, 1].") and not has_unit("See [2].") and not has_unit("Tension.")
    assert needs_unit("float") and needs_unit("ndarray, shape (n,)") and needs_unit("int, optional")
    assert needs_unit("") and needs_unit("Sequence[float]") and needs_unit("tuple of float")
    assert not needs_unit("bool") and not needs_unit("PathModel") and not needs_unit('{"parabola", "per-dropper"}')
    assert not needs_unit("str or Path") and not needs_unit("callable, optional") and not needs_unit("Catenary")
    assert not needs_unit("IntegratorSettings, optional") and not needs_unit("ndarray of bool, shape (n,)")
    assert needs_unit("ndarray of int") and needs_unit("float or ndarray")


def test_the_api_has_hundreds_of_public_names_in_every_part():
    items = all_public_names()
    parts = {item.module.split(".")[1] for item in items if item.module.count(".")}
    assert len(items) > 400
    assert {"system", "static", "design", "dynamics", "robust", "studies", "validation", "report"} <= parts


def allowed_without_section() -> set[str]:
    lines = ALLOWED_WITHOUT_SECTION.read_text(encoding="utf-8").splitlines()
    return {line.strip() for line in lines if line.strip() and not line.startswith("#")}


def test_every_public_name_has_a_docstring_and_every_number_a_unit():
    allowed = allowed_without_section()
    found = [line for item in all_public_names() for line in problems(item)
             if not (line.endswith("no Parameters section") and item.qualname in allowed)]
    assert not found, f"{len(found)} docstring problems:\n" + "\n".join(found)


def test_the_list_of_names_without_a_parameters_section_only_shrinks():
    """A name on the list that now has its section (or is gone) must leave the list."""
    current = {item.qualname for item in all_public_names()
               if any(line.endswith("no Parameters section") for line in problems(item))}
    stale = sorted(allowed_without_section() - current)
    assert not stale, f"remove from {ALLOWED_WITHOUT_SECTION.name}: " + ", ".join(stale)


def write_allowed_list() -> int:
    """Rewrite ``parameters_to_document.txt`` from the package as it is (after a merge or a move of
    modules: the names keep their debt, under their new paths). Returns the number of names."""
    names = sorted({item.qualname for item in all_public_names()
                    if any(line.endswith("no Parameters section") for line in problems(item))})
    header = [line for line in ALLOWED_WITHOUT_SECTION.read_text(encoding="utf-8").splitlines() if line.startswith("#")]
    ALLOWED_WITHOUT_SECTION.write_text("\n".join(header + names) + "\n", encoding="utf-8")
    return len(names)


if __name__ == "__main__":
    print(f"{write_allowed_list()} names written to {ALLOWED_WITHOUT_SECTION}")
