"""Bounded mutation testing of the core physics modules with mutmut (a dev tool, not a dependency).

Each module is mutated in a throw-away copy of the working tree (tracked and untracked-but-not-ignored
files), against a fast test subset, so the worktree itself is never touched and modules that are
read-only for a developer (``dynamics/structure.py``, ``dynamics/integrator.py``) can be mutated too.
A module with more mutants than ``--sample`` is scored on a deterministic sample of them (every k-th
mutant name in sorted order), so the same mutants are scored before and after a change of the tests.

Usage (see docs/testing.md)::

    nice -n 19 .venv/bin/python tools/mutation.py [MODULE ...] [--sample 40] [--time-limit 900]

Score = killed (including timeouts) / scored mutants; "no tests" mutants count as survivors, because
no test of the subset reaches them.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

#: Module -> the fast test subset that is meant to guard it.
MODULES: dict[str, list[str]] = {
    "presag_opt/static/discretisation.py": ["tests/static/test_analytic.py", "tests/static/test_form_finding.py"],
    "presag_opt/static/symbolic.py": ["tests/static/test_analytic.py", "tests/static/test_form_finding.py"],
    "presag_opt/static/equilibrium.py": ["tests/static/test_analytic.py", "tests/static/test_form_finding.py"],
    "presag_opt/static/linearised.py": ["tests/static/test_elasticity.py", "tests/static/test_linearised.py"],
    "presag_opt/dynamics/structure.py": ["tests/dynamics/test_structure.py", "tests/dynamics/test_wave_speed.py"],
    "presag_opt/dynamics/integrator.py": ["tests/dynamics/test_integrator.py", "tests/dynamics/test_moving_load.py"],
    "presag_opt/design/quasi_static.py": ["tests/design/test_quasi_static.py"],
    "presag_opt/design/empirical.py": ["tests/design/test_empirical.py"],
}

KILLED = {1, 3, 24, -24, 36, 152, 255}


def _copy_tree(dest: Path) -> None:
    files = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=REPO, check=True, capture_output=True
    ).stdout.decode().split("\0")
    if dest.exists():
        shutil.rmtree(dest)
    for name in filter(None, files):
        if name.startswith(".venv") or not (REPO / name).is_file():
            continue
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / name, dest / name)


def _setup_cfg(module: str, tests: list[str]) -> str:
    selection = "\n".join(f"    {t}" for t in tests if (REPO / t).exists())
    return (
        "[mutmut]\nsource_paths=presag_opt\nalso_copy=\n    models\n"
        f"only_mutate={module}\n"
        f"pytest_add_cli_args_test_selection=\n{selection}\n"
        "pytest_add_cli_args=\n    -x\n    -q\n    -p\n    no:cacheprovider\n"
    )


def run_module(module: str, work: Path, sample: int, time_limit: float) -> dict:
    """Mutate one module in a copy of the tree and return its counts.

    Parameters
    ----------
    module : str
        Path of the module relative to the repository root.
    work : Path
        Scratch folder; the copy goes to a sub-folder named after the module.
    sample : int
        Largest number of mutants scored.
    time_limit : float
        Wall-clock limit in seconds for the run; mutants not reached count as not checked.
    """
    dest = work / module.replace("/", "_")
    _copy_tree(dest)
    (dest / "setup.cfg").write_text(_setup_cfg(module, MODULES[module]))
    mutmut = [str(Path(sys.executable).parent / "mutmut"), "run", "--max-children", "1"]
    # A pattern that matches no mutant: generates the mutants and collects test coverage only.
    subprocess.run([*mutmut, "no-such-mutant"], cwd=dest, capture_output=True, timeout=time_limit)
    meta = dest / "mutants" / (module + ".meta")
    names = sorted(json.loads(meta.read_text())["exit_code_by_key"])
    step = max(1, -(-len(names) // sample))
    chosen = names[::step]
    try:
        subprocess.run([*mutmut, *chosen], cwd=dest, capture_output=True, timeout=time_limit)
    except subprocess.TimeoutExpired:
        pass
    codes = json.loads(meta.read_text())["exit_code_by_key"]
    scored = [n for n in chosen if codes.get(n) is not None]
    killed = [n for n in scored if codes[n] in KILLED]
    survivors = [n for n in scored if codes[n] not in KILLED]
    return {
        "module": module,
        "mutants": len(names),
        "sampled": len(chosen),
        "scored": len(scored),
        "killed": len(killed),
        "score": len(killed) / len(scored) if scored else float("nan"),
        "survivors": survivors,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="*", default=list(MODULES))
    parser.add_argument("--sample", type=int, default=40, help="mutants scored per module (default 40)")
    parser.add_argument("--time-limit", type=float, default=900.0, help="seconds per module (default 900)")
    parser.add_argument("--work", type=Path, default=Path("/tmp/presag-mutation"))
    parser.add_argument("--json", type=Path, help="write the results here as well")
    args = parser.parse_args()
    results = []
    for module in args.modules:
        r = run_module(module, args.work, args.sample, args.time_limit)
        results.append(r)
        print(
            f"{r['module']:40s} mutants {r['mutants']:4d}  scored {r['scored']:3d}/{r['sampled']:3d}  "
            f"killed {r['killed']:3d}  score {100 * r['score']:5.1f} %",
            flush=True,
        )
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
