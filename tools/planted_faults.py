"""Planted faults: which test tier catches each of a fixed list of faults, in two versions of the tree.

A developer tool (not a test): it answers "does the fast default tier still guard what matters?" the
way a reviewer checks it. Each fault of :data:`FAULTS` is one exact text replacement in one file (a
law's coefficient, a sign, a percentile, a branch of the decision, a unit conversion, a data file
value, ...). For each version of the tree (``--before`` and ``--after``, git revisions) the tool

1. exports the revision into ``WORK/<version>/base`` and installs it, as CI does, into a fresh
   virtual environment ``WORK/<version>/venv`` (``pip install "base[test]"``, once per version);
2. for each fault: copies the export into ``WORK/<version>/<fault>`` (no ``__pycache__``: numba and
   Python caches start empty), plants the fault (the replacement must match exactly once, else the
   fault is reported as not applicable), installs that copy in place of the package (its console
   script sees the fault too), gives it an empty ``XDG_CACHE_HOME`` (no form-found state, no
   compiled library) and runs the version's tiers in order, each ``python -m pytest -x -m TIER``
   from the copy, until one fails.

The table printed (and written with ``--json``) gives, per fault and version, the first tier that
failed and its first failing test, or "none". Usage (about 10–25 min per fault and version on a
2-core machine; run it under ``nice`` on a shared one)::

    nice -n 19 .venv/bin/python tools/planted_faults.py --before 3d2ddf8 --after HEAD --json faults.json
    nice -n 19 .venv/bin/python tools/planted_faults.py --after HEAD --faults line-per-span-low-end

See docs/testing.md ("Planted faults").
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Fault:
    """One planted fault: replace ``old`` by ``new`` (exactly one occurrence) in ``path``."""

    name: str
    path: str
    what: str
    old: str
    new: str
    later: tuple[str, str] | None = None
    """The same fault in a later version whose text differs (``old``, ``new``), tried when ``old`` is absent."""

    def replacement(self, text: str) -> tuple[str, str] | None:
        """The (old, new) pair that occurs exactly once in ``text``, or None."""
        for pair in ((self.old, self.new), self.later):
            if pair is not None and text.count(pair[0]) == 1:
                return pair
        return None


FAULTS = (
    Fault("line-per-span-low-end", "presag_opt/design/line.py",
          "per-span rule: each span's S_rel from the band's low end only (not the mean of both ends)",
          "own = dict(zip(rec.at_band_low.spans, 0.5 * (rec.at_band_low.presag_rel + rec.at_band_high.presag_rel)))",
          "own = dict(zip(rec.at_band_low.spans, rec.at_band_low.presag_rel))"),
    Fault("empirical-k", "presag_opt/design/empirical.py",
          "a law's coefficient: the empirical rule's k = 4 becomes 4.2",
          "EMPIRICAL_K = 4.0", "EMPIRICAL_K = 4.2"),
    Fault("friction-law", "presag_opt/dynamics/laws.py",
          "a law's coefficient in the compiled kernel: the pantograph's dry friction force × 0.8",
          "    return level * th, factor * level / regularisation_velocity * (1.0 - th * th)",
          "    return 0.8 * level * th, factor * level / regularisation_velocity * (1.0 - th * th)"),
    Fault("interpolation-weights", "presag_opt/design/quasi_static.py",
          "the elasticity between two force levels weighted the wrong way round",
          "elasticity=(1.0 - w) * a.elasticity + w * b.elasticity",
          "elasticity=w * a.elasticity + (1.0 - w) * b.elasticity"),
    Fault("survey-curve-sign", "presag_opt/design/line_rules.py",
          "a sign in the survey geometry: the chord of a curved span bows away from the curve's centre",
          "y = np.abs(a.stagger + (b.stagger - a.stagger) * x / length + curve)",
          "y = np.abs(a.stagger + (b.stagger - a.stagger) * x / length - curve)"),
    Fault("percentile", "presag_opt/robust/monte_carlo.py",
          "a percentile: every Monte Carlo percentile Pk reported as P(k - 5)",
          "value=float(np.percentile(values, level))", "value=float(np.percentile(values, level - 5))"),
    Fault("decision-branch", "presag_opt/design/decision.py",
          "a branch of the decision: a quasi-static answer decides even where β_max is above the trusted limit",
          "        if trusted and not issues:", "        if not issues:",
          later=("    if validity.trusted and quasi:", "    if quasi:")),
    Fault("height-error-unit", "presag_opt/cli/tolerance_mc.py",
          "a unit conversion: the command line's --height-error in cm instead of mm",
          "contact_wire_height=height * 1e-3,", "contact_wire_height=height * 1e-2,"),
    Fault("pantograph-head-mass", "models/pantographs/case_study_2mass_friction.toml",
          "a data file value: the case-study pantograph's head mass 7.2 kg becomes 7.9 kg",
          'mass = { value = 7.2, unit = "kg"', 'mass = { value = 7.9, unit = "kg"'),
    Fault("filter-cutoff", "presag_opt/dynamics/statistics.py",
          "the EN 50367 low-pass filter of the contact force at 25 Hz instead of 20 Hz",
          "CUTOFF_FREQUENCY = 20.0", "CUTOFF_FREQUENCY = 25.0"),
)

TIERS = {
    "before": ("default", "slow"),
    "after": ("default", "e2e", "notebook", "docs", "slow"),
}
"""Tiers of each version, in the order they run: ``default`` is the plain ``python -m pytest``; before
the tiers, the default run included the notebooks and the site and only ``slow`` was excluded."""


def _run(command: list[str], **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run(command, check=True, capture_output=True, text=True, **kwargs)


def prepare(version: str, revision: str, work: Path) -> tuple[Path, Path]:
    """Export ``revision`` and install it with its test dependencies into a fresh environment."""
    root = work / version
    base, venv = root / "base", root / "venv"
    if root.exists():
        shutil.rmtree(root)
    base.mkdir(parents=True)
    archive = subprocess.run(["git", "archive", revision], cwd=REPO, check=True, capture_output=True).stdout
    subprocess.run(["tar", "x"], cwd=base, input=archive, check=True)
    _run([sys.executable, "-m", "venv", str(venv)])
    _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet", f"{base}[test]"])
    return base, venv


def _install(venv: Path, copy: Path) -> None:
    """Replace the installed package by ``copy`` (the console script then runs the planted fault)."""
    site = next((venv / "lib").glob("python3*/site-packages"))
    for installed in sorted(set(site.glob("presag_opt*")) | set(site.glob("presag_opt-*"))):
        shutil.rmtree(installed) if installed.is_dir() else installed.unlink(missing_ok=True)
    _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet", "--no-deps",
          str(copy)])


def _first_failure(output: str) -> str:
    for line in output.splitlines():
        if line.startswith(("FAILED ", "ERROR ")):
            return line.split(" - ")[0]
    return output.strip().splitlines()[-1] if output.strip() else ""


def _default_sigint() -> None:
    """Start a tier with SIGINT's default action, as from a terminal: a tool started in the background
    by a non-interactive shell ignores SIGINT, and its tests that interrupt a command would inherit that."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_fault(fault: Fault | None, version: str, base: Path, venv: Path, work: Path, timeout: float,
              deselect: list[str], tiers: tuple[str, ...] | None = None) -> dict:
    """Plant one fault (None: the tree as it is) in a fresh copy and run the tiers until one fails
    (``deselect``: tests left out, e.g. ones that fail on the version without any fault)."""
    name = fault.name if fault else "control"
    copy = work / version / name
    if copy.exists():
        shutil.rmtree(copy)
    shutil.copytree(base, copy)
    if fault is not None:
        target = copy / fault.path
        text = target.read_text(encoding="utf-8")
        pair = fault.replacement(text)
        if pair is None:
            return {"fault": name, "version": version, "caught_by": "not applicable",
                    "detail": f"{fault.path}: the text to replace does not occur exactly once"}
        target.write_text(text.replace(*pair), encoding="utf-8")
    _install(venv, copy)
    cache = work / version / f"{name}-cache"
    shutil.rmtree(cache, ignore_errors=True)
    cache.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR", "PRESAG_NO_CACHE",
                                                               "PRESAG_NO_COMPILE", "CI")}
    env.update(XDG_CACHE_HOME=str(cache), PATH=f"{venv / 'bin'}:{env.get('PATH', '')}")
    result = {"fault": name, "version": version, "caught_by": "none", "detail": "", "tiers": {}}
    for tier in tiers or TIERS[version]:
        marker = [] if tier == "default" else ["-m", tier]
        started = time.monotonic()
        try:
            done = subprocess.run([str(venv / "bin" / "python"), "-m", "pytest", "-x", "-q", "-rfE",
                                   "-p", "no:cacheprovider", *marker, *(f"--deselect={d}" for d in deselect)],
                                  cwd=copy, env=env, capture_output=True, text=True, timeout=timeout,
                                  preexec_fn=_default_sigint)
            status, output = done.returncode, done.stdout + done.stderr
        except subprocess.TimeoutExpired:
            status, output = -1, f"timed out after {timeout:.0f} s"
        result["tiers"][tier] = {"status": status, "seconds": round(time.monotonic() - started)}
        if status not in (0, 5):
            result["caught_by"] = tier
            result["detail"] = _first_failure(output)
            break
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", help="git revision of the earlier version (e.g. the commit before a change)")
    parser.add_argument("--after", default="HEAD", help="git revision of the later version (default HEAD)")
    parser.add_argument("--faults", help="comma-separated names of FAULTS to plant (default all)")
    parser.add_argument("--control", action="store_true", help="also run the tiers of each version without a fault")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per tier run (default 3600)")
    parser.add_argument("--deselect-before", nargs="*", default=[], metavar="NODEID",
                        help="tests to leave out of the earlier version's runs (ones that fail there without a fault)")
    parser.add_argument("--tiers", help="comma-separated tiers to run, in order (default: each version's TIERS); "
                        "a fault none of them catches is reported as caught by none of those tiers")
    parser.add_argument("--work", type=Path, default=Path("/tmp/presag-faults"))
    parser.add_argument("--json", type=Path, help="write the results here as well (after each fault)")
    args = parser.parse_args()
    chosen = [f for f in FAULTS if not args.faults or f.name in args.faults.split(",")]
    versions = [(v, r) for v, r in (("before", args.before), ("after", args.after)) if r]
    results = []
    for version, revision in versions:
        base, venv = prepare(version, revision, args.work)
        for fault in ([None] if args.control else []) + chosen:
            deselect = args.deselect_before if version == "before" else []
            r = run_fault(fault, version, base, venv, args.work, args.timeout, deselect,
                          tuple(args.tiers.split(",")) if args.tiers else None)
            results.append(r)
            seconds = sum(t["seconds"] for t in r.get("tiers", {}).values())
            print(f"{version:6s} {r['fault']:24s} caught by {r['caught_by']:14s} ({seconds:5d} s)  {r['detail']}",
                  flush=True)
            if args.json:
                args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
