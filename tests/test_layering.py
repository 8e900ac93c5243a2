"""Package layering: the import graph has no cycles, no layer imports a higher one, no module reaches
into another part's private names, and ``import presag_opt`` stays cheap."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import presag_opt

PACKAGE = Path(presag_opt.__file__).parent

LAYERS = {
    "errors": 0,
    "contact_force": 0,
    "runtime": 0,
    "units": 0,
    "version": 0,
    "native": 1,
    "speed": 1,
    "processes": 1,
    "cluster": 1,
    "atomic_files": 1,
    "evaluation_store": 2,
    "style": 1,
    "display": 1,
    "system": 2,
    "static": 3,
    "elasticity": 4,
    "design": 5,
    "dynamics": 5,
    "robust": 6,
    "studies": 6,
    "validation": 7,
    "pipeline": 7,
    "plotting": 8,
    "sensitivity": 8,
    "report": 9,
    "jobs": 10,
    "cli": 11,
}
"""Layer of each part of the package (its first component below ``presag_opt``): a part may import
only parts of lower layers, and parts of one layer (design and dynamics; robust and studies) not each other."""

def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> list[tuple[str, str]]:
    """(module, name) of every import of presag_opt in a file, outside ``if TYPE_CHECKING:`` blocks
    (those never run); ``name`` is empty for ``import module``."""
    tree = ast.parse(path.read_text(), filename=str(path))
    skipped = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"
        for inner in ast.walk(node)
    }
    out = []
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("presag_opt"):
            out += [(node.module, alias.name) for alias in node.names]
        elif isinstance(node, ast.Import):
            out += [(alias.name, "") for alias in node.names if alias.name.startswith("presag_opt")]
    return out


def _graph() -> dict[str, set[str]]:
    """Module -> the presag_opt modules it imports (``from package import submodule`` counts as the
    submodule)."""
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {}
    for name, path in modules.items():
        targets = set()
        for module, imported in _imports(path):
            targets.add(f"{module}.{imported}" if f"{module}.{imported}" in modules else module)
        graph[name] = targets - {name}
    return graph


def _part(module: str) -> str:
    return module.split(".")[1] if module.count(".") else ""


def test_every_part_of_the_package_has_a_layer():
    assert {_part(m) for m in _graph()} - {""} == set(LAYERS)


def test_no_import_cycles():
    graph = _graph()
    state: dict[str, int] = {}  # 1 on the current path, 2 done

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for target in sorted(graph.get(module, ())):
            if state.get(target) == 1:
                pytest.fail(f"import cycle: {' -> '.join(path[path.index(target):] + [target])}")
            if target in graph and state.get(target) is None:
                visit(target, path + [target])
        state[module] = 2

    for module in sorted(graph):
        if state.get(module) is None:
            visit(module, [module])


def test_no_part_imports_a_higher_or_a_parallel_one():
    offences = [
        f"{module} imports {target}"
        for module, targets in _graph().items()
        if _part(module)
        for target in targets
        if _part(target) != _part(module) and LAYERS[_part(target)] >= LAYERS[_part(module)]
    ]
    assert not offences


def test_lower_layers_import_nothing_from_higher_ones():
    lower, higher = {"system", "static", "elasticity"}, {"design", "robust", "validation", "dynamics", "cli"}
    graph = _graph()
    assert not [(m, t) for m, ts in graph.items() if _part(m) in lower for t in ts if _part(t) in higher]


def test_private_names_stay_inside_their_part():
    offences = [
        f"{_module_name(path)} imports {name} from {module}"
        for path in PACKAGE.rglob("*.py")
        for module, name in _imports(path)
        if name.startswith("_") and _part(module) != _part(_module_name(path))
    ]
    assert not offences


def test_the_public_api_resolves_and_covers_the_subpackages():
    """Every top-level name resolves; the jobs are the top-level names of their jobs (``recommend`` is the
    job, the Δe rule over a band stays ``presag_opt.design.recommend``); every other name of a
    sub-package is the same object at the top level."""
    import presag_opt.design
    import presag_opt.jobs
    import presag_opt.robust
    import presag_opt.validation

    for name in presag_opt.__all__:
        assert getattr(presag_opt, name) is not None, name
    jobs = set(presag_opt.jobs.__all__)
    assert all(getattr(presag_opt, n) is getattr(presag_opt.jobs, n) for n in jobs)
    for sub in (presag_opt.design, presag_opt.robust, presag_opt.validation):
        assert set(sub.__all__) - jobs <= set(presag_opt.__all__), sub.__name__
        assert all(getattr(presag_opt, n) is getattr(sub, n) for n in set(sub.__all__) - jobs)
    with pytest.raises(AttributeError, match="no attribute 'recomend'"):
        presag_opt.recomend  # noqa: B018


def test_importing_the_package_loads_neither_casadi_nor_cvxpy():
    code = "import sys, presag_opt; print(sorted(m for m in ('casadi', 'cvxpy', 'scipy.signal') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
