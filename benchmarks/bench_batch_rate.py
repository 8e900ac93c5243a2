"""The batch engine's arithmetic rate as a share of this machine's floating-point peak (issue 35).

Run from the repository root::

    python benchmarks/bench_batch_rate.py [--repeat 3]

Two batches, each timed warm (median of ``--repeat``, compiled sweeps where a C compiler is found):

- ``grid``: 10 runs of the paper's grid (S 30 mm, F_stat 95 N, 50–180 km/h, the paper's 0.5 m / 2 ms),
  as part 1 of ``bench_batch.py``;
- ``decision``: the 12 runs of one pre-sag of the case-study decision (S 45 mm, F_stat 70–140 N at
  50/70/90 km/h, automatic numerics on the band's shared discretisation), as
  ``presag robust --dynamic`` simulates each pre-sag.

The floating-point operations are counted from the batch's own arrays, per run and time step (a run
that has finished no longer counts): sweep 1, per DOF 6 + 2·(nonzeros of its row of K) + 2·(nonzeros
of its row of L) and one division; sweep 2, 2·(nonzeros of its row of Lᵀ) and one division; sweep 3,
16 per DOF (the Newmark update and predictor, the HHT residual) plus 2 per DOF for each Woodbury column
used, counted as one per pantograph (the contact force; slack droppers add columns now and then). The
Newton iterations on the few nonlinear DOFs, the set-up and the statistics are left out, so the rate is
a lower bound of the sweeps' own. It is compared with two peaks of one core: the measured rate of a
matrix product (numpy's BLAS on one thread: the practical peak) and the nominal one (clock × 16
double-precision operations per cycle for AVX2 with FMA, × 32 with AVX-512), and the bytes the
sweeps stream per step (the three bands' nonzeros with their column indices, and the run arrays) with
a measured copy bandwidth of one core. Printed with the load average before and after.

Then the cost of a batch against its number of runs (1, 4, 8, 16, 24, 32 runs of the paper's grid at
100 km/h, F_stat 60, 62, … N, one lead-in and one analysed span; each run count in one batch): how much
of a step is the traversal of the bands, whatever the number of runs, and how much each run adds.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

SWEEP1_PER_DOF = 6
"""Operations of sweep 1 per DOF and run besides the band products: d·q + m·v, g = r − s·acc. [-]"""

SWEEP3_PER_DOF = 16
"""Operations of sweep 3 per DOF and run: Newmark update, HHT residual, predictors, q. [-]"""

RUN_ARRAYS_PER_DOF = 12
"""Run arrays of (n, runs) doubles a step reads or writes per DOF, counted once each per sweep:
sweep 1 q, v, r, linear, delta; sweep 2 delta (read, write); sweep 3 delta, u, v, q, r. [-]"""


def _decision_batch():
    from presag_opt.design.band import CASE_STUDY_BAND
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH, simulated_band
    from presag_opt.robust.band_evaluation import BandEvaluator
    from presag_opt.robust.operating_grid import OperatingGrid
    from presag_opt.static.form_finding import form_find
    from presag_opt.system.loader import load_catenary

    catenary = load_catenary("st_9.8_ideal")
    grid = OperatingGrid.from_band(simulated_band(CASE_STUDY_BAND), static_points=4, speed_points=3)
    evaluator = BandEvaluator(catenary, load_pantograph(CASE_STUDY_PANTOGRAPH), grid)
    state = form_find(catenary.with_presag(45e-3 / evaluator.reference_span), evaluator.static_settings)
    return state, evaluator.pantograph, grid.points(), evaluator.settings


def _grid_batch():
    import bench_batch

    from presag_opt.dynamics.settings import OperatingPoint

    case, settings, state = bench_batch._case_and_state()
    points = [OperatingPoint(speed=v / 3.6, static_force=95.0, aero_coefficient=case.operation.aero_coefficient)
              for v in (50, 60, 70, 80, 90, 100, 120, 140, 160, 180)]
    return state, case.pantograph, points, settings


def _work(state, pantograph, points, settings) -> dict:
    """Operations and bytes of the sweeps of one batch (see the module notes)."""
    from presag_opt.dynamics.batch.system import BatchSystem
    from presag_opt.dynamics.run_plan import plan_run
    from presag_opt.dynamics.structure import structural_model

    plans = [plan_run(state, pantograph, speed=p.speed, static_force=p.static_force,
                      aero_coefficient=p.aero_coefficient, settings=settings) for p in points]
    steps = {p.settings.integrator.time_step for p in plans}
    if len(steps) != 1:
        raise SystemExit(f"the batch has {len(steps)} time steps; this count assumes one system")
    model = structural_model(state, settings=settings.structure)
    system = BatchSystem.build(model, plans[0].pantographs, plans[0].settings)
    fixed = system.fixed
    n = int(fixed["factor_band"].shape[0])
    nnz = {name: int(len(fixed[name].column)) for name in ("stiffness_rows", "lower_rows", "upper_rows")}
    per_run_step = (SWEEP1_PER_DOF * n + 2 * nnz["stiffness_rows"] + 2 * nnz["lower_rows"] + n
                    + 2 * nnz["upper_rows"] + n + SWEEP3_PER_DOF * n + 2 * n * len(plans[0].pantographs))
    dt = steps.pop()
    run_steps = int(sum(p.step_count(dt) for p in plans))
    longest = int(max(p.step_count(dt) for p in plans))
    matrix_bytes = sum(16 * k for k in nnz.values()) + 8 * (2 * n + n + 1)  # values + int64 columns, diagonals
    return dict(n=n, nnz=nnz, runs=len(plans), run_steps=run_steps, longest=longest, time_step=dt,
                flops=per_run_step * run_steps,
                bytes=matrix_bytes * longest + 8 * RUN_ARRAYS_PER_DOF * n * run_steps,
                matrix_bytes=matrix_bytes)


def _timed(state, pantograph, points, settings, repeat: int) -> float:
    from presag_opt.dynamics.batch import simulate_many

    simulate_many(state, pantograph, points[:1], settings=settings)  # compile or load the kernel
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        simulate_many(state, pantograph, points, settings=settings)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def _runs_per_batch(counts=(1, 4, 8, 16, 24, 32)) -> None:
    """Print the wall time of one batch per run count, and per run (best of two). [s]"""
    import bench_batch

    from presag_opt.dynamics.batch import simulate_many, simulation
    from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings

    case, _, state = bench_batch._case_and_state()
    settings = SimulationSettings(analysed_spans=1, lead_in_spans=1)
    aero = case.operation.aero_coefficient
    default = simulation.BATCH_SIZE
    try:
        for count in counts:
            simulation.BATCH_SIZE = max(default, count)  # every run count in one batch
            points = [OperatingPoint(speed=100 / 3.6, static_force=60.0 + 2.0 * i, aero_coefficient=aero)
                      for i in range(count)]
            simulate_many(state, case.pantograph, points[:1], settings=settings)
            wall = min(_seconds(lambda: simulate_many(state, case.pantograph, points, settings=settings))
                       for _ in range(2))
            print(f"  {count:3d} runs in one batch: {wall:.2f} s, {wall / count:.3f} s per run", flush=True)
    finally:
        simulation.BATCH_SIZE = default


def _dgemm_rate(size: int = 2000, repeat: int = 3) -> float:
    """Measured rate of a matrix product on one thread. [flop/s]"""
    from threadpoolctl import threadpool_limits

    a, b = np.random.default_rng(1).standard_normal((2, size, size))
    with threadpool_limits(1):
        a @ b
        best = min(_seconds(lambda: a @ b) for _ in range(repeat))
    return 2.0 * size**3 / best


def _copy_bandwidth(megabytes: int = 400, repeat: int = 3) -> float:
    """Measured copy bandwidth of one core (bytes read + written). [byte/s]"""
    source = np.ones(megabytes * 2**20 // 8)
    target = np.empty_like(source)
    best = min(_seconds(lambda: np.copyto(target, source)) for _ in range(repeat))
    return 2.0 * source.nbytes / best


def _seconds(fn) -> float:
    started = time.perf_counter()
    fn()
    return time.perf_counter() - started


def _nominal_peak() -> tuple[float, str]:
    """Clock × double-precision operations per cycle of one core, from /proc/cpuinfo. [flop/s]"""
    try:
        info = Path("/proc/cpuinfo").read_text()
    except OSError:
        return float("nan"), "unknown (no /proc/cpuinfo)"
    megahertz = max(float(line.split(":")[1]) for line in info.splitlines() if line.startswith("cpu MHz"))
    flags = next(line for line in info.splitlines() if line.startswith("flags")).split()
    per_cycle, unit = (32, "AVX-512 FMA, two units") if "avx512f" in flags else (16, "AVX2 FMA, two units")
    if "fma" not in flags:
        per_cycle, unit = 4, "SSE2"
    return megahertz * 1e6 * per_cycle, f"{megahertz:.0f} MHz × {per_cycle} ({unit})"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed batches per case (median)")
    args = parser.parse_args()
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from presag_opt.dynamics.batch import simulation
    from presag_opt.native import sweeps as native_sweeps

    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    print(f"sweeps: {'compiled C' if native_sweeps.available() else 'numba'}")
    dgemm, copy = _dgemm_rate(), _copy_bandwidth()
    nominal, how = _nominal_peak()
    print(f"one core: matrix product {dgemm / 1e9:.1f} Gflop/s; nominal {nominal / 1e9:.1f} Gflop/s ({how}); "
          f"copy bandwidth {copy / 1e9:.1f} GB/s")
    for name, build in (("grid", _grid_batch), ("decision", _decision_batch)):
        state, pantograph, points, settings = build()
        work = _work(state, pantograph, points, settings)
        wall = _timed(state, pantograph, points, settings, args.repeat)
        rate, traffic = work["flops"] / wall, work["bytes"] / wall
        print(f"{name}: {work['runs']} runs, {work['n']} DOFs, band nonzeros K {work['nnz']['stiffness_rows']}, "
              f"L {work['nnz']['lower_rows']}, Lᵀ {work['nnz']['upper_rows']} ({work['matrix_bytes'] / 2**20:.2f} MiB); "
              f"{work['longest']} steps of {work['time_step'] * 1e3:g} ms, {work['run_steps']} run-steps")
        print(f"  {wall:.2f} s (median of {args.repeat}): {work['flops'] / 1e9:.2f} Gflop counted -> {rate / 1e9:.2f} "
              f"Gflop/s = {100 * rate / dgemm:.1f} % of the matrix product, {100 * rate / nominal:.1f} % of nominal; "
              f"{work['bytes'] / 1e9:.2f} GB streamed -> {traffic / 1e9:.2f} GB/s = {100 * traffic / copy:.0f} % of "
              f"the copy bandwidth; {1e9 * wall / (work['run_steps'] * work['n']):.1f} ns per DOF and run-step",
              flush=True)
    print(f"one batch against its runs (100 km/h, one lead-in and one analysed span; the engine batches "
          f"up to {simulation.BATCH_SIZE} runs):")
    _runs_per_batch()
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
