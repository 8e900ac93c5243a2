"""The paper's validity grid on the simple and the stitched ST 9,8/9,8 side by side: β* of the Δe
rule, the share of static forces where the rule holds at each speed ratio, and the largest
steady-arm uplift against its limit (docs/stitched.md, figure docs/stitched_validity.png).

Run the three studies first (each resumable; about 5–15 min on 2 cores):

    nice -n 10 presag sweep models/studies/paper_grid_st98_auto.toml --out STORES/grid_auto.nc --workers 2
    nice -n 10 presag sweep models/studies/paper_grid_st98_stitched.toml --out STORES/grid_stitched.nc --workers 2
    nice -n 10 presag sweep models/studies/paper_grid_st98_stitched_high.toml --out STORES/grid_stitched_high.nc --workers 2

then: python research/stitched_validity.py STORES [--figure docs/stitched_validity.png]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from presag_opt.studies.store import open_store
from presag_opt.studies.validity_analysis import validity_analysis

STORES = {"simple": ("grid_auto.nc",), "stitched": ("grid_stitched.nc", "grid_stitched_high.nc")}
CASE_FORCE_MAX = 140.0
"""Largest static force of the case-study band, for the uplift curve. [N]"""


def _rows(dataset, result):
    """Per speed: β, share of forces where the rule holds (S matters and the rule is in the band), uplift [mm]."""
    uplift = dataset["uplift_max"].sel(static_force=slice(None, CASE_FORCE_MAX + 1e-9)).max(dim=("presag", "static_force"))
    out = []
    for entry, up in zip(result.per_beta, uplift.values):
        bands = entry.bands
        share = np.mean([b.benefit and b.rule_inside for b in bands])
        out.append((entry.beta, entry.speed * 3.6, share, entry.holds, float(up) * 1e3))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("stores", type=Path, help="folder holding the three study stores")
    parser.add_argument("--figure", type=Path, help="save the side-by-side figure here (PNG)")
    args = parser.parse_args()
    curves = {}
    for system, files in STORES.items():
        rows = {}
        for name in files:
            dataset = open_store(args.stores / name)
            result = validity_analysis(dataset)
            limit = ("above the grid" if result.beta_limit is None
                     else f"{result.beta_limit:.3f} ± {result.beta_limit_uncertainty:.3f}")
            print(f"{system:8s} {name:24s} beta* = {limit}; largest uplift {result.uplift.maximum * 1e3:.1f} mm")
            rows.update({round(r[1]): r for r in _rows(dataset, result)})
        curves[system] = [rows[v] for v in sorted(rows)]
        for beta, speed, share, holds, up in curves[system]:
            print(f"  beta {beta:.3f}  {speed:5.0f} km/h  holds at {share:4.0%} of F_stat  "
                  f"{'holds' if holds else 'fails'}  uplift (F_stat <= {CASE_FORCE_MAX:g} N) {up:6.1f} mm")
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
        for system, colour in (("simple", "C0"), ("stitched", "C3")):
            data = np.array([r[:3] + (r[4],) for r in curves[system]])
            a.plot(data[:, 0], data[:, 2] * 100, "o-", color=colour, label=f"ST 9,8/9,8 {system}")
            b.plot(data[:, 0], data[:, 3], "o-", color=colour, label=f"ST 9,8/9,8 {system}")
        a.set(xlabel="β = v / c_CW", ylabel="static forces: S matters and Δe rule in band [%]",
              title="Δe rule on the paper's grid (automatic numerics)")
        b.axhline(83.5, color="k", lw=0.8, ls="--", label="uplift limit 83.5 mm")
        b.set(xlabel="β = v / c_CW", ylabel=f"largest steady-arm uplift, F_stat ≤ {CASE_FORCE_MAX:g} N [mm]",
              title="steady-arm uplift")
        for ax in (a, b):
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.figure, dpi=110)
        print(f"figure: {args.figure}")


if __name__ == "__main__":
    main()
