"""Bounded mutation testing of the core physics modules with mutmut (a dev tool, not a dependency).

Each module is mutated in a throw-away copy of the working tree (tracked and untracked-but-not-ignored
files), against a fast test subset, so the worktree itself is never touched and modules that are
read-only for a developer (``dynamics/structure.py``, ``dynamics/integrator.py``) can be mutated too.
A module with more mutants than ``--sample`` is scored on a deterministic sample of them (every k-th
mutant name in sorted order), so the same mutants are scored before and after a change of the tests.

Usage (see docs/testing.md)::

    nice -n 19 .venv/bin/python tools/mutation.py [GROUP ...] [--sample 24] [--time-limit 900] [--tests-from REV]

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

#: Groups of modules mutated in one mutmut project against one fast test subset (one coverage run
#: per group): group -> (modules, tests).
GROUPS: dict[str, tuple[list[str], list[str]]] = {
    "static": (
        [
            "presag_opt/static/discretisation.py",
            "presag_opt/static/potential.py",
            "presag_opt/static/equilibrium_newton.py",
            "presag_opt/static/equilibrium.py",
            "presag_opt/static/form_finding.py",
            "presag_opt/static/linearised.py",
        ],
        [
            "tests/static/test_analytic.py",
            "tests/static/test_form_finding.py",
            "tests/elasticity/test_methods.py",
            "tests/static/test_cache.py",
            "tests/robust/test_path.py",  # target_height_sensitivity
            "tests/dynamics/test_structure.py",  # TensionOnlyStructure.displacement (static_response)
        ],
    ),
    "dynamics": (
        ["presag_opt/dynamics/structure.py", "presag_opt/dynamics/integrator.py"],
        [
            "tests/dynamics/test_structure.py",
            "tests/dynamics/test_integrator.py",
            "tests/dynamics/test_wave_speed.py",
            "tests/dynamics/test_moving_load.py",
            "tests/dynamics/test_structure_parts.py",
        ],
    ),
    "design": (
        ["presag_opt/design/quasi_static.py", "presag_opt/design/empirical.py"],
        ["tests/design/test_quasi_static.py", "tests/design/test_empirical.py"],
    ),
}

KILLED = {1, 3, 24, -24, 36, 152, 255}


def _copy_tree(dest: Path, tests_from: str | None) -> None:
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
    if tests_from:
        # Score the current code against the tests of an earlier commit ("before").
        shutil.rmtree(dest / "tests")
        archive = subprocess.run(["git", "archive", tests_from, "tests"], cwd=REPO, check=True, capture_output=True)
        subprocess.run(["tar", "x"], cwd=dest, input=archive.stdout, check=True)


def _setup_cfg(dest: Path, modules: list[str], tests: list[str]) -> str:
    selection = "\n".join(f"    {t}" for t in tests if (dest / t).exists())
    only = "\n".join(f"    {m}" for m in modules)
    return (
        "[mutmut]\nsource_paths=presag_opt\nalso_copy=\n    models\n"
        f"only_mutate=\n{only}\n"
        f"pytest_add_cli_args_test_selection=\n{selection}\n"
        # -n 0: one process (the project's addopts run the suite on every core with pytest-xdist).
        "pytest_add_cli_args=\n    -x\n    -q\n    -p\n    no:cacheprovider\n    -n\n    0\n"
    )


def run_group(
    group: str, work: Path, sample: int, time_limit: float, tests_from: str | None, tests: list[str] | None = None
) -> list[dict]:
    """Mutate the modules of one group in a copy of the tree and return their counts.

    Parameters
    ----------
    group : str
        Key of :data:`GROUPS`.
    work : Path
        Scratch folder; the copy goes to a sub-folder named after the group.
    sample : int
        Largest number of mutants scored per module.
    time_limit : float
        Wall-clock limit in seconds for the group's mutant run; mutants not reached count as not
        checked and are left out of the score.
    tests_from : str or None
        Git revision whose ``tests/`` replace the working tree's.
    tests : list of str, optional
        Test files replacing the group's subset (a faster subset on a loaded machine).
    """
    modules, subset = GROUPS[group]
    tests = tests or subset
    dest = work / group
    _copy_tree(dest, tests_from)
    (dest / "setup.cfg").write_text(_setup_cfg(dest, modules, tests))
    mutmut = [str(Path(sys.executable).parent / "mutmut"), "run", "--max-children", "1"]
    # A pattern that matches no mutant: generates the mutants and collects test coverage only.
    subprocess.run([*mutmut, "no-such-mutant"], cwd=dest, capture_output=True)
    chosen: dict[str, list[str]] = {}
    for module in modules:
        meta = dest / "mutants" / (module + ".meta")
        names = sorted(json.loads(meta.read_text())["exit_code_by_key"])
        step = max(1, -(-len(names) // sample))
        chosen[module] = names[::step]
    # One mutmut run for the whole group: its clean-test and coverage runs are paid once.
    try:
        subprocess.run([*mutmut, *(n for names in chosen.values() for n in names)], cwd=dest, capture_output=True,
                       timeout=time_limit)
    except subprocess.TimeoutExpired:
        pass
    results = []
    for module, names in chosen.items():
        meta = dest / "mutants" / (module + ".meta")
        codes = json.loads(meta.read_text())["exit_code_by_key"]
        scored = [n for n in names if codes.get(n) is not None]
        killed = [n for n in scored if codes[n] in KILLED]
        results.append({
            "module": module,
            "mutants": len(codes),
            "sampled": len(names),
            "scored": len(scored),
            "killed": len(killed),
            "score": len(killed) / len(scored) if scored else float("nan"),
            "survivors": [n for n in scored if codes[n] not in KILLED],
        })
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("groups", nargs="*", default=list(GROUPS), help=f"of {', '.join(GROUPS)} (default all)")
    parser.add_argument("--sample", type=int, default=24, help="mutants scored per module (default 24)")
    parser.add_argument("--time-limit", type=float, default=900.0, help="seconds per group (default 900)")
    parser.add_argument("--tests-from", help="git revision whose tests/ to use (e.g. the commit before a change)")
    parser.add_argument("--tests", nargs="+", help="test files replacing the groups' subsets")
    parser.add_argument("--work", type=Path, default=Path("/tmp/presag-mutation"))
    parser.add_argument("--json", type=Path, help="write the results here as well")
    args = parser.parse_args()
    results = []
    for group in args.groups:
        for r in run_group(group, args.work, args.sample, args.time_limit, args.tests_from, args.tests):
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
