"""Resolve the project's short cross-references in docstrings.

The docstrings name other objects of the package the way a reader does: ``:class:`Catenary``` from a
module that imports it, ``:func:`presag_opt.design.recommend``` by the path it is imported from,
``:attr:`settings``` for a field of the class being described. Sphinx resolves a reference only by its
full dotted name from the current module; this handler, on Sphinx's ``missing-reference`` event, tries
in order: the object the dotted name imports to (re-exports); a unique documented object whose name
ends with the reference (of several, the one nearest the referring module); a field of a documented dataclass (``Class.field``, or ``field`` of the class
being described), linked to its class. A reference none of these finds stays a warning, which the
nitpicky build turns into an error. A reference to a private name (leading underscore) is left as
code: private names are not documented.
"""

from __future__ import annotations

import dataclasses
import importlib

from docutils import nodes
from sphinx.addnodes import pending_xref
from sphinx.util.nodes import make_refnode


def _import(dotted: str) -> object | None:
    parts = dotted.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for part in parts[cut:]:
                obj = getattr(obj, part)
        except AttributeError:
            return None
        return obj
    return None


def _canonical(dotted: str) -> str | None:
    if not dotted.startswith("presag_opt."):
        return None
    obj = _import(dotted)
    module, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", None)
    return f"{module}.{qualname}" if module and qualname else None


def _field_owner(objects: dict, target: str, context_class: str | None, module: str | None) -> str | None:
    """The documented dataclass that has ``target`` (``Class.field`` or ``field``) as a field."""
    owner_name, _, field = target.rpartition(".")
    owners = []
    if owner_name:
        owners = [name for name in objects if name == owner_name or name.endswith("." + owner_name)]
    elif context_class and module:
        owners = [f"{module}.{context_class}"]
    for owner in owners:
        cls = _import(owner)
        if dataclasses.is_dataclass(cls) and field in {f.name for f in dataclasses.fields(cls)}:
            return owner
    return None


def _holder(objects: dict, target: str, context_class: str | None, module: str | None, role: str) -> str | None:
    """An undocumented constant or instance attribute, linked to the module or class that holds it."""
    owner, _, name = target.rpartition(".")
    if role == "data":
        for candidate in (owner, module):
            if candidate in objects and hasattr(_import(candidate) or object(), name):
                return candidate
    if role == "attr" and not owner and context_class and module:
        return f"{module}.{context_class}"
    return None


def _nearest(matches: list[str], module: str) -> str | None:
    """Of several documented objects of one name, the one nearest the referring module (the most leading
    dotted parts in common), if only one is nearest: ``simulate`` from ``presag_opt.dynamics.results`` is
    :func:`presag_opt.dynamics.simulate.simulate`, from ``presag_opt.jobs`` the job."""
    def shared(name: str) -> int:
        count = 0
        for a, b in zip(name.split("."), module.split(".")):
            if a != b:
                break
            count += 1
        return count

    best = max((shared(m) for m in matches), default=0)
    nearest = [m for m in matches if shared(m) == best]
    return nearest[0] if len(nearest) == 1 else None


def resolve(app, env, node: pending_xref, contnode: nodes.Element):
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~").rstrip(".")
    if target.rpartition(".")[2].startswith("_"):
        return nodes.literal(text=contnode.astext())
    domain = env.get_domain("py")
    objects = domain.objects
    found = _canonical(target)
    if found not in objects:
        kinds = set(domain.objtypes_for_role(node["reftype"]) or ())
        matches = [name for name, entry in objects.items()
                   if (name == target or name.endswith("." + target)) and (not kinds or entry.objtype in kinds)]
        found = matches[0] if len(matches) == 1 else _nearest(matches, node.get("py:module") or "")
    if found is None:
        found = _field_owner(objects, target, node.get("py:class"), node.get("py:module"))
    if found is None:
        found = _holder(objects, target, node.get("py:class"), node.get("py:module"), node["reftype"])
    if found is None or found not in objects:
        return None
    entry = objects[found]
    return make_refnode(app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, found)


def setup(app) -> dict:
    app.connect("missing-reference", resolve)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
