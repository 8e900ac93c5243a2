"""Phenomenon check of the validity study: which assumed inputs does the σ/F_m minimum depend on?

Run: python research/phenomenon.py [--out DIR] [--workers N] [--only NAME,...]

For each study file ``research/phenomenon/phenomenon_*.toml`` (one assumed input varied at a time at
50 km/h, β ≈ 0.145, on the paper's pre-sag and static-force grid) it runs the study (resumable, into
``DIR``) and prints, per value of the varied input and per pre-sag S:

- where σ has its minimum over F_m (and whether it is distinct: interior, with a 5 % rise to both
  ends of the band — the validity analysis' criterion);
- the same for σ/F_m;
- the smallest σ over the band (the floor that does not depend on S) and how much σ changes with S
  at the middle static force.

The paper reads its validity limit from σ/F_m minima that move with S at low speed; a model whose
σ/F_m falls towards the largest force for every S has no such minima.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import open_store
from presag_opt.studies.validity_analysis import validity_analysis

STUDIES = Path(__file__).parent / "phenomenon"


def summarise(store: Path) -> None:
    dataset = open_store(store)
    name = [d for d in dataset["sigma"].dims if d not in ("presag", "speed", "static_force")][0]
    for value in dataset[name].values:
        result = validity_analysis(dataset, {name: float(value)})
        sub = dataset.sel({name: value})
        sigma = sub["sigma"].isel(speed=0)
        middle = sigma.sizes["static_force"] // 2
        spread = float(sigma.isel(static_force=middle).max() - sigma.isel(static_force=middle).min())
        print(f"\n{name} = {value:g}: σ floor {float(sigma.min()):.2f} N; σ range over S at "
              f"F_stat {float(sub.static_force[middle]):g} N: {spread:.2f} N")
        print(f"{'S [mm]':>7} {'σ-min F_m [N]':>14} {'σ-min':>7} {'σ/F_m-min F_m [N]':>18} {'σ/F_m-min':>10}")
        for optimum in result.force_optima:
            def cell(m, unit_scale=1.0):
                return f"{m.location * unit_scale:.0f}" if m.distinct else "none"
            print(f"{optimum.presag * 1e3:7.0f} {cell(optimum.sigma):>14} {optimum.sigma.value:7.2f} "
                  f"{cell(optimum.ratio):>18} {optimum.ratio.value:10.4f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="results/phenomenon", help="folder of the study stores")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--only", default=None, help="comma-separated study keys, e.g. friction,damping")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = sorted(STUDIES.glob("phenomenon_*.toml"))
    if args.only:
        keep = {f"phenomenon_{k.strip()}" for k in args.only.split(",")}
        files = [f for f in files if f.stem in keep]
    for path in files:
        study = load_study(path)
        store = out / f"{path.stem}.nc"
        started = time.perf_counter()
        run_study(study, store, workers=args.workers, progress=None)
        print(f"\n=== {study.name}: {study.run_count} runs, {time.perf_counter() - started:.0f} s", flush=True)
        summarise(store)


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
