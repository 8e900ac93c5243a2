"""Global sensitivity of one output of a case to its assumed inputs: the job behind ``presag sensitivity``.

:func:`sensitivity_analysis` chooses the inputs (every ``assumed`` number the output can depend on,
or those named), samples them (Morris or Sobol, seeded), evaluates the output at every sample
(quasi-static outputs in worker processes, dynamic ones as reduced studies through the studies
machinery), and returns the ranked indices of each of the output's values.

Outputs (``output``):

- ``recommendation``: the case study's quasi-static recommendation on ST 9,8/9,8 ideal and mixed
  spans over F_stat 70–140 N, 0–90 km/h: S_rel of each layout (mean of its range ends), the
  recommended S_rel and the ratio mixed/ideal;
- ``robust``: the quasi-static minimax pre-sag of the case's catenary over the same band and its
  installation tolerance (10 % loss);
- ``dynamic:V1,V2,…`` (km/h): σ and σ/F_m at the case's pre-sag and static force at each speed;
- ``minima:V`` (km/h): whether σ/F_m has distinct minima over F_m that move with S at that speed;
- ``validity:V1,V2,…`` (km/h): β* of a reduced validity study over those speeds;
- ``dynamic-robust``: the dynamic robust pre-sag of the band F_stat 70–140 N × 50–90 km/h (the design
  of ``presag robust --dynamic``, at screening numerics) and its installation tolerance
  (:mod:`presag_opt.sensitivity.dynamic_robust`); each sample is one task in worker processes or on Dask.
"""

from __future__ import annotations

import re
import tempfile
import time
from collections.abc import Callable, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from presag_opt.design.recommendation import CASE_STUDY_MODELS
from presag_opt.display import data_frame, html_summary
from presag_opt.dynamics.case import SimulationCase, load_case
from presag_opt.errors import ModelError
from presag_opt.evaluation_store import Evaluation, EvaluationStore, analysis_key
from presag_opt.sensitivity.dynamic import (
    KMH,
    DynamicOutput,
    Resolution,
    base_study,
    run_definitions,
)
from presag_opt.sensitivity.dynamic_robust import (
    DYNAMIC_ROBUST_VALUES,
    DynamicRobustEvaluator,
    ScreeningNumerics,
)
from presag_opt.sensitivity.evaluation import RowEvaluations, evaluate_rows
from presag_opt.sensitivity.inputs import (
    SPAN_LIST,
    SensitivityInput,
    input_spec,
    model_inputs,
    parse_range_override,
)
from presag_opt.sensitivity.methods import (
    OutputIndices,
    morris_design,
    morris_indices,
    sobol_design,
    sobol_indices,
    spread_design,
    spread_summary,
)
from presag_opt.sensitivity.quasi_static import (
    RECOMMENDATION_VALUES,
    ROBUST_VALUES,
    RecommendationEvaluator,
    RobustEvaluator,
)
from presag_opt.static import cache
from presag_opt.system.loader import load_catenary

METHODS = ("morris", "sobol", "spread")
"""Morris screening, Sobol indices, or the spread of the output over a scrambled Sobol sample."""

QUASI_STATIC = ("recommendation", "robust")
DYNAMIC = ("dynamic", "minima", "validity")
PER_SAMPLE = ("dynamic-robust",)
"""Outputs whose samples run as one task each (:func:`~presag_opt.sensitivity.evaluation.evaluate_rows`)."""
OUTPUT_NAMES = (*QUASI_STATIC, *PER_SAMPLE, *(f"{k}:SPEEDS" for k in DYNAMIC))
"""Output names as the command line takes them."""


@dataclass(frozen=True, kw_only=True)
class SensitivityResult:
    """Indices of every value of one output.

    Attributes
    ----------
    case : str
        Case name.
    output : str
        Output as given (e.g. ``recommendation``, ``dynamic:50,90``).
    method : str
        ``"morris"`` or ``"sobol"``.
    inputs : tuple of SensitivityInput
        Inputs varied, with their ranges.
    samples : int
        Morris trajectories r, or Sobol base sample N. [-]
    seed : int
        Seed of design and bootstrap. [-]
    evaluations : int
        Evaluations of the output. [-]
    seconds : float
        Wall time of the evaluations. [s]
    seconds_first : float
        Wall time of the first evaluation alone (the cost announced). [s]
    resolution : str
        Numerics of a dynamic output ("" for quasi-static ones).
    indices : tuple of OutputIndices
        One ranked table per value of the output.
    rows : ndarray, shape (evaluations, inputs)
        The sample. [SI units of the inputs]
    values : ndarray, shape (evaluations, values)
        The output at each row, NaN where its evaluation failed. [units of the tables]
    failures : tuple of Evaluation
        The failed evaluations, each with its inputs (display units) and the one-line reason; the
        tables leave them out (``samples`` and ``dropped`` of each table say what that costs).
    solver : dict
        Counts and quantiles of the form-findings of the evaluations
        (:func:`~presag_opt.static.solver_statistics.statistics_summary`; an evaluation read back from
        the store brings those of the run that made it, so a resumed analysis reports what an
        uninterrupted one does).
    store : str
        Folder keeping every finished evaluation ("" when none is kept).
    """

    case: str
    output: str
    method: str
    inputs: tuple[SensitivityInput, ...]
    samples: int
    seed: int
    evaluations: int
    seconds: float
    seconds_first: float
    resolution: str
    indices: tuple[OutputIndices, ...]
    rows: np.ndarray = field(repr=False, compare=False)
    values: np.ndarray = field(repr=False, compare=False)
    failures: tuple[Evaluation, ...] = ()
    solver: dict = field(default_factory=dict, compare=False)
    store: str = field(default="", compare=False)

    def table(self, value: str) -> OutputIndices:
        """The indices of one value of the output, by name."""
        for item in self.indices:
            if item.output == value:
                return item
        raise ModelError(f"value {value!r} is not one of {', '.join(i.output for i in self.indices)}")

    def ranking(self) -> list[dict]:
        """Every value's inputs, most important first, as rows: μ*, its 95 % half-width and σ (Morris),
        or S1 and ST with theirs (Sobol), in the value's unit (a spread has no ranking)."""
        rows = []
        for t in self.indices:
            for e in t.morris:
                rows.append({"output": f"{t.output} [{t.unit}]", "input": e.name, "mu*": e.mu_star,
                             "mu* ±": e.mu_star_conf, "sigma": e.sigma, "mu*/max": e.relative})
            for e in t.sobol:
                rows.append({"output": f"{t.output} [{t.unit}]", "input": e.name, "S1": e.first,
                             "S1 ±": e.first_conf, "ST": e.total, "ST ±": e.total_conf})
        return rows

    def to_frame(self):
        """:meth:`ranking` as a pandas DataFrame."""
        return data_frame(self.ranking())

    def _repr_html_(self) -> str:
        firsts = [f"{t.output}: {(t.morris or t.sobol)[0].name} first" for t in self.indices if t.morris or t.sobol]
        return html_summary(f"{self.case}: {self.method} sensitivity of {self.output} over {len(self.inputs)} "
                            f"inputs ({self.evaluations} evaluations, seed {self.seed})", firsts, self.ranking())

    def to_dict(self) -> dict:
        """JSON-ready content: inputs, tables, and the design and values (inputs in display units)."""
        return {"case": self.case, "output": self.output, "method": self.method, "samples": self.samples,
                "seed": self.seed, "evaluations": self.evaluations, "seconds": self.seconds,
                "seconds_per_evaluation": self.seconds_first, "resolution": self.resolution,
                "inputs": [i.to_dict() for i in self.inputs], "indices": [i.to_dict() for i in self.indices],
                "design": (self.rows / np.array([i.factor for i in self.inputs])).tolist(),
                "values": self.values.tolist(),
                "failed": len(self.failures),
                "failures": [{"index": e.index, "inputs": e.inputs, "reason": e.failure} for e in self.failures],
                "solver": self.solver, "store": self.store}

    def failure_summary(self) -> str:
        """One line: how many evaluations failed, the first one's reason and what was left out ("" if none)."""
        if not self.failures:
            return ""
        unit = {"morris": "trajectories", "sobol": "base samples"}.get(self.method, "points")
        table = self.indices[0]
        first = self.failures[0]
        kept = f"; kept in {self.store}" if self.store else ""
        return (f"{len(self.failures)} of {self.evaluations} evaluations failed (first: evaluation {first.index}, "
                f"{first.failure}); the indices rest on {table.samples} of {table.samples + table.dropped} "
                f"{unit}{kept}")


def parse_output(text: str) -> tuple[str, tuple[float, ...]]:
    """``"dynamic:50,90"`` -> (``"dynamic"``, speeds in m/s); a quasi-static output has no speeds.

    Raises
    ------
    ModelError
        For an unknown output or a malformed speed list.
    """
    kind, sep, rest = text.partition(":")
    if kind in (*QUASI_STATIC, *PER_SAMPLE) and not sep:
        return kind, ()
    if kind not in DYNAMIC or not sep:
        raise ModelError(f"--quantity {text!r} is not one of {', '.join(OUTPUT_NAMES)} (SPEEDS in km/h, e.g. dynamic:50,90)")
    try:
        speeds = tuple(float(s) * KMH for s in rest.split(","))
    except ValueError:
        raise ModelError(f"--quantity {text!r}: the speeds must be numbers in km/h, e.g. {kind}:50,90") from None
    if any(not 0.0 < s <= 600.0 * KMH for s in speeds) or list(speeds) != sorted(set(speeds)):
        raise ModelError(f"--quantity {text!r}: speeds must be increasing and in (0, 600] km/h")
    return kind, speeds


def _roots(case: SimulationCase, kind: str) -> tuple[dict, dict]:
    """The models an output depends on and their provenance (what its inputs may be taken from)."""
    if kind == "recommendation":
        mixed = load_catenary(CASE_STUDY_MODELS[1])
        return {"catenary": mixed, "operation": case.operation}, {"catenary": mixed.provenance,
                                                                  "operation": case.provenance}
    roots = {"catenary": case.catenary, "operation": case.operation}
    provenance = {"catenary": case.catenary.provenance, "operation": case.provenance}
    if kind in DYNAMIC or kind in PER_SAMPLE:
        roots["pantograph"] = case.pantograph
        provenance["pantograph"] = case.pantograph.provenance
    return roots, provenance


def _independent(kind: str, name: str, roots: dict) -> str | None:
    """Why an output cannot depend on an input (None if it can)."""
    root = name.split(".", 1)[0]
    if root == "settings":
        return "numerical settings are not uncertain inputs (a dynamic output's resolution is fixed)"
    if root == "pantograph" and kind in QUASI_STATIC:
        return f"the {kind} output is quasi-static and has no pantograph"
    if name == "operation.static_force" and kind != "dynamic":
        return f"the {kind} output covers a band of static forces, not one"
    if name == SPAN_LIST and len(set(roots["catenary"].layout.span_lengths)) == 1:
        return f"the {kind} output's section has equal spans"
    return None


def sensitivity_analysis(
    case: str | Path | SimulationCase = "case_study_st98",
    *,
    output: str = "recommendation",
    method: str = "morris",
    inputs: Sequence[str] | None = None,
    ranges: Sequence[str] = (),
    samples: int | None = None,
    seed: int = 0,
    workers: int = 1,
    scheduler: str | None = None,
    out: str | Path | None = None,
    resolution: Resolution | None = None,
    numerics: ScreeningNumerics | None = None,
    announce: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
) -> SensitivityResult:
    """Morris screening or Sobol indices of one output of a case over its uncertain inputs.

    Parameters
    ----------
    case : str, Path or SimulationCase
        Case file or built-in case name.
    output : str
        See the module notes.
    method : {"morris", "sobol", "spread"}
        Elementary effects (screening), variance-based indices, or only the output's spread over a
        scrambled Sobol sample (``values``; tables with mean and standard deviation).
    inputs : sequence of str, optional
        Input names; default every ``assumed`` number the output can depend on.
    ranges : sequence of str
        ``NAME=LOW:HIGH`` overrides (display unit of the field); an override adds its input.
    samples : int, optional
        Morris trajectories r (default 10), Sobol base sample N (power of two, default 64) or spread
        points (power of two, default 16). [-]
    seed : int
        Seed of the design and of the bootstrap. [-]
    workers : int
        Local worker processes. [-]
    scheduler : str, optional
        Dask scheduler address (dynamic outputs).
    out : str or Path, optional
        Folder of the resumable stores: per-sample study stores (dynamic outputs), or one file per
        evaluation in ``OUT/<output>-<case>-<method>`` (quasi-static outputs). Default: a folder of the
        analysis in the cache directory when one is set (:func:`presag_opt.static.cache.evaluation_folder`;
        the command line sets it unless ``--no-cache``), else nothing is kept.
    resolution : Resolution, optional
        Numerics of dynamic outputs (default: a :class:`~presag_opt.sensitivity.dynamic.Resolution` with its defaults).
    numerics : ScreeningNumerics, optional
        Numerics of the ``dynamic-robust`` output (default: a
        :class:`~presag_opt.sensitivity.dynamic_robust.ScreeningNumerics` with its defaults).
    announce : callable, optional
        Called once with the cost estimate (first evaluation × evaluations / workers).
    progress : callable, optional
        Called with a short message (``"evaluations: done/total"``) during the evaluations.

    Raises
    ------
    ModelError
        Unknown output, method or input; an input the output cannot depend on; bad sizes or ranges.
    """
    if method not in METHODS:
        raise ModelError(f"--method {method!r} is not one of {', '.join(METHODS)}")
    kind, speeds = parse_output(output)
    case = case if isinstance(case, SimulationCase) else load_case(case)
    roots, provenance = _roots(case, kind)
    available = model_inputs(roots, provenance, assumed_only=False)
    defaults = {n: i for n, i in model_inputs(roots, provenance).items() if _independent(kind, n, roots) is None}
    overrides = {}
    for text in ranges:
        item = parse_range_override(text, roots)
        overrides[item.name] = item
    names = list(inputs) if inputs is not None else list(defaults)
    names += [n for n in overrides if n not in names]
    chosen = []
    for name in names:
        why = _independent(kind, name, roots)
        if why is not None:
            raise ModelError(f"input {name}: output {output} cannot depend on it ({why})")
        if name != SPAN_LIST:
            input_spec(name, roots)  # an unknown name is refused with the valid names at its level
        if name not in overrides and name not in available:
            raise ModelError(f"input {name} has no range in the model files of output {output}; give --range "
                             f"{name}=LOW:HIGH (inputs with ranges: {', '.join(available)})")
        chosen.append(overrides.get(name) or available[name])
    if len({i.name for i in chosen}) != len(chosen):
        raise ModelError("--inputs names an input twice")
    samples = samples or {"morris": 10, "sobol": 64, "spread": 16}[method]
    design = {"morris": morris_design, "sobol": sobol_design, "spread": spread_design}[method]
    rows = design(chosen, samples, seed)
    names = tuple(i.name for i in chosen)

    start = time.perf_counter()
    if announce:
        what = {"dynamic-robust": "one dynamic robust design (about 5 pre-sags x 12 runs) each"}.get(
            kind, "one " + ("quasi-static evaluation" if kind in QUASI_STATIC else "reduced study") + " each")
        announce(f"{len(rows)} evaluations of {output}, {what}; timing the first one to estimate the cost")
    if kind in QUASI_STATIC or kind in PER_SAMPLE:
        if kind == "recommendation":
            value_names = RECOMMENDATION_VALUES
            evaluator = RecommendationEvaluator(ideal=load_catenary(CASE_STUDY_MODELS[0]), mixed=roots["catenary"],
                                                names=names)
        elif kind == "robust":
            value_names = ROBUST_VALUES
            evaluator = RobustEvaluator(catenary=case.catenary, names=names)
        else:
            value_names = DYNAMIC_ROBUST_VALUES
            numerics = numerics or ScreeningNumerics()
            evaluator = DynamicRobustEvaluator(catenary=case.catenary, pantograph=case.pantograph,
                                               operation=case.operation, names=names, numerics=numerics)
        key = analysis_key(output, method, samples, seed, evaluator, rows.tobytes())
        with _store_folder(out, f"{kind}-{re.sub(r'[^A-Za-z0-9]+', '_', case.name)}-{method}", key) as (folder, kept):
            store = EvaluationStore.open(folder, key, f"presag sensitivity {case.name} --quantity {output} "
                                                      f"--method {method} --seed {seed}")
            labels = {"inputs": chosen, "value_names": [n for n, _ in value_names], "store": store}
            read_back = len(store.read(range(len(rows))))
            evaluate_rows(evaluator, rows[:1], **labels)  # alone: its time is the cost announced
            seconds_first = time.perf_counter() - start
            if read_back and announce:
                announce(f"{read_back} of {len(rows)} evaluations read back from {folder}; computing the other "
                         f"{len(rows) - read_back}")
            else:
                _announce(announce, len(rows), seconds_first, workers)
            # half a Morris trajectory in one process: its steps in α_ae and the span list reuse form-findings
            # (halves, not whole trajectories, keep the two workers' last tasks short)
            chunk = max(1, (len(chosen) + 1) // 2) if method == "morris" and kind == "recommendation" else 1
            evaluated = evaluate_rows(evaluator, rows, workers=workers, scheduler=scheduler, chunk=chunk,
                                      progress=progress, **labels)
        text = numerics.text() if kind in PER_SAMPLE else ""
    else:
        resolution = resolution or Resolution()
        spec = DynamicOutput(kind=kind, speeds=speeds, resolution=resolution)
        base = base_study(case)
        definitions = [spec.definition(base, roots, names, row) for row in rows]
        value_names = spec.value_names
        key = analysis_key(output, method, samples, seed, definitions)
        with _store_folder(out, f"{kind}-{re.sub(r'[^A-Za-z0-9]+', '_', case.name)}-{method}", key,
                           own_folder=False) as (folder, kept):
            run_definitions(definitions[:1], out=folder, workers=1)
            seconds_first = time.perf_counter() - start
            _announce(announce, len(rows), seconds_first, workers)
            datasets = run_definitions(definitions, out=folder, workers=workers, scheduler=scheduler,
                                       progress=progress)
        evaluated = RowEvaluations(tuple(_study_evaluation(i, row, chosen, spec, ds)
                                         for i, (row, ds) in enumerate(zip(rows, datasets))),
                                   tuple(n for n, _ in value_names))
        text = resolution.text()
    seconds = time.perf_counter() - start
    values = evaluated.values
    if method == "spread":
        tables = tuple(spread_summary(values[:, j], output=name, unit=unit) for j, (name, unit) in enumerate(value_names))
    else:
        analyse = morris_indices if method == "morris" else sobol_indices
        tables = tuple(analyse(chosen, rows, values[:, j], output=name, unit=unit, seed=seed)
                       for j, (name, unit) in enumerate(value_names))
    return SensitivityResult(case=case.name, output=output, method=method, inputs=tuple(chosen), samples=samples,
                             seed=seed, evaluations=len(rows), seconds=seconds, seconds_first=seconds_first,
                             resolution=text, indices=tables, rows=rows, values=values, failures=evaluated.failures,
                             solver=evaluated.solver_summary(), store=str(folder) if kept else "")


@contextmanager
def _store_folder(out: str | Path | None, name: str, key: str, own_folder: bool = True):
    """The folder of an analysis' store and whether it is kept: ``OUT/name`` (``OUT`` itself for the
    per-sample study stores, ``own_folder=False``), else the analysis' folder in the cache directory,
    else a temporary folder removed at the end."""
    if out is not None:
        yield (Path(out) / name if own_folder else Path(out)), True
        return
    folder = cache.evaluation_folder(f"sensitivity-{name}", key)
    if folder is not None:
        yield folder, True
        return
    with tempfile.TemporaryDirectory(prefix="presag-sensitivity-") as scratch:
        yield Path(scratch), False


def _study_evaluation(index: int, row: np.ndarray, inputs: Sequence[SensitivityInput], spec: DynamicOutput,
                      dataset) -> Evaluation:
    """One sample's reduced study as an evaluation: failed when one of its runs failed (with the first reason)."""
    shown = {i.name: float(v) / i.factor for i, v in zip(inputs, row)}
    reasons = [str(r) for r in np.ravel(dataset["failure"].values) if str(r)]
    if reasons:
        return Evaluation(index=index, inputs=shown, failure=f"{len(reasons)} run(s) failed, first: {reasons[0]}")
    values = spec.values(dataset)
    if not np.all(np.isfinite(values)):
        return Evaluation(index=index, inputs=shown, failure="the output has no finite value here")
    return Evaluation(index=index, inputs=shown, values=dict(zip((n for n, _ in spec.value_names), map(float, values))))


def _announce(announce: Callable[[str], None] | None, count: int, first: float, workers: int) -> None:
    if announce:
        total = first * count / max(1, workers)
        announce(f"{count} evaluations × {first:.1f} s (the first one) / {workers} worker(s) ≈ {total / 60:.1f} min")
